"""Whether two checkouts give `auto` the same numbers, every field, to the last bit (issue 26).

    python benchmarks/same_numbers.py --against DIR

Runs :func:`noisevar.estimate` (``auto``) on 45 seeded records, in this checkout and in the
``noisevar`` package under ``DIR`` (``PYTHONPATH``; e.g. an export of main), each in a fresh
process, and compares every field of the results (estimate, interval, notes,
diagnostics, verdict, regimes, the still stretches' R), arrays byte for byte. Records:
steps-ramps of 1,000 samples (6 seeds), the synthetic families at 20,000 (3 seeds each),
bursts of motion, glitches on fast sinusoids and level jumps (4 seeds each), two motion
records of 600,000 samples (read in chunks) and two scaled by 1e-12 and 3e9 (the scaled
path), ``speed.py``'s motion record and white noise of 1e6, Student-t(5), and five records
streamed in chunks of 2^13 and 2^15. Writes ``benchmarks/results/same_numbers.md``.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import pickle
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


def _motion(n: int, seed: int) -> np.ndarray:
    # noisevar.synth.sine_bursts's record, written here too: each child builds its records
    # with the noisevar under DIR, which may predate that function
    rng = np.random.default_rng(seed)
    x = rng.normal(size=n)
    t = np.arange(n)
    for s in range(n // 20, n, n // 5):
        b = slice(s, s + n // 30)
        x[b] += rng.uniform(3, 20) * np.sin(t[b] / rng.uniform(2, 7))
    return x


def _glitches(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    x = 5 * np.sin(2 * np.pi * t / rng.uniform(15, 80)) + rng.normal(size=n)
    k = rng.choice(n, n // 100, replace=False)
    x[k] += 10 * rng.choice([-1, 1], k.size)
    return x


def _jumps(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.normal(size=n)
    for _ in range(5):
        x[rng.integers(0, n) :] += rng.normal(0, 8)
    return x


def records() -> dict[str, np.ndarray]:
    """The seeded records."""
    import noisevar

    sys.path.insert(0, str(HERE))
    from speed import motion_record

    recs = {}
    for s in range(6):
        recs[f"steps-ramps-1000-{s}"] = noisevar.generate("steps-ramps", n=1000, seed=s).measured
    for s in range(3):
        for fam in ["fast-slow", "noise-step", "gps-circle", "random-jerk", "noise-ramp"]:
            recs[f"{fam}-20000-{s}"] = noisevar.generate(fam, n=20000, seed=s).measured
    for s in range(4):
        recs[f"motion-60000-{s}"] = _motion(60000, s)
        recs[f"glitches-6000-{s}"] = _glitches(6000, s)
        recs[f"jumps-30000-{s}"] = _jumps(30000, s)
    for s in range(2):
        recs[f"motion-600000-{s}"] = _motion(600_000, 10 + s)
    recs["motion-1e6 (speed.py)"] = motion_record(1_000_000)
    recs["motion-600000-scaled"] = _motion(600_000, 12) * 1e-12
    recs["motion-60000-scaled"] = _motion(60_000, 13) * 3e9
    rng = np.random.default_rng(99)
    recs["white-1e6"] = rng.normal(size=1_000_000)
    recs["student-t-50000"] = rng.standard_t(5, size=50000)
    return recs


def _flat(o):
    if dataclasses.is_dataclass(o):
        return {f.name: _flat(getattr(o, f.name)) for f in dataclasses.fields(o)}
    if isinstance(o, dict):
        return {k: _flat(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return type(o)(_flat(v) for v in o)
    if isinstance(o, np.ndarray):
        return ("ndarray", o.dtype.str, o.shape, o.tobytes())
    return o


def _results() -> dict:
    import noisevar
    from noisevar.stream import estimate_chunked

    recs, out = records(), {}
    for k, x in recs.items():
        try:
            out[k] = _flat(noisevar.estimate(x, method="auto"))
        except Exception as exc:  # noqa: BLE001 - a refusal is a result to compare too
            out[k] = ("error", repr(exc))
    for k in ["motion-60000-0", "motion-60000-1", "jumps-30000-0", "glitches-6000-0",
              "motion-600000-0"]:  # fmt: skip
        x = recs[k]
        for chunk in (1 << 13, 1 << 15):
            if 2 * chunk > x.size:
                continue
            try:
                r = estimate_chunked(
                    lambda a, b, x=x: x[max(a, 0) : b].copy(), x.size, chunk=chunk, method="auto"
                )
                out[f"streamed {k}, chunks of {chunk}"] = _flat(r)
            except Exception as exc:  # noqa: BLE001
                out[f"streamed {k}, chunks of {chunk}"] = ("error", repr(exc))
    return out


def _run(path: str, out: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=path)
    cmd = ["nice", "-n", "10", sys.executable, __file__, "--child", str(out)]
    subprocess.run(cmd, env=env, check=True)
    with open(out, "rb") as f:
        return pickle.load(f)


def _first_difference(a, b, path: str = "") -> str | None:
    if isinstance(a, dict) and isinstance(b, dict):
        for k in a:
            d = _first_difference(a[k], b.get(k), f"{path}.{k}")
            if d:
                return d
        return None
    if a != b:
        return f"{path}: {str(a)[:80]} / {str(b)[:80]}"
    return None


def main(argv: list[str] | None = None) -> int:
    """Compare and print Markdown; exit 1 when a record differs."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", help="a directory holding another noisevar package")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        with open(args.child, "wb") as f:
            pickle.dump(_results(), f)
        return 0
    if not args.against:
        ap.error("--against DIR is required")
    with tempfile.TemporaryDirectory() as tmp:
        mine = _run(str(HERE.parent), Path(tmp) / "this.pkl")
        theirs = _run(args.against, Path(tmp) / "against.pkl")
    same = [k for k in mine if mine[k] == theirs.get(k)]
    lines = [
        "### `auto`, this checkout against another (`python benchmarks/same_numbers.py`)",
        "",
        f"Against `{args.against}`: **{len(same)} of {len(mine)} records identical** in every "
        "field (arrays byte for byte).",
    ]
    for k in mine:
        if k not in same:
            lines.append(f"- {k}: {_first_difference(mine[k], theirs.get(k))}")
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "same_numbers.md").write_text(text + "\n")
    print(text)
    return 0 if len(same) == len(mine) else 1


if __name__ == "__main__":
    sys.exit(main())

"""Reliability (issue 29 items 1-3): batch faults and the float range of the noise models.

    nice -n 10 python benchmarks/reliability.py [--sigkills 20] [--seed 29] [--parts still]

1. **A kill at each step of the batch's commit sequence.** A table from an earlier run, one
   file changed, one no longer given, two new; the batch is killed (every later step
   refused, as a dead process would) after each step of
   :data:`noisevar.batch._output.COMMIT_STEPS` (after each file's journal line, too), then
   rerun: rows lost, rows doubled, and whether the table equals a clean run.
2. **Random SIGKILLs of ``noisevar batch``**, ``--jobs 1`` and ``--jobs 2`` in turn, at a
   seeded moment once a row is journalled, three files changed before each run; after each
   kill, the processes of its group left after 10 s (from /proc); then one run to the end
   against a clean run.
3. **Two batches on one output at once** (two ``noisevar batch`` processes started
   together): one is refused with one line, the other writes the table.
4. **The float range.** ``allan`` (phase and rate data), ``inertial_noise``,
   ``fit_coloured_noise``, ``fit_kalman`` and ``stream.estimate_file`` on one record at
   every scale of a grid (powers of two from 2^-1074 to 2^1020, 1e±154, 1e±300, 1e-160,
   subnormals), as float32 and as int64 beyond 2**53, and at rates 1e±300, 2^±64, 5e-324:
   each case is *right* (finite, and equal to the unscaled answer times the scale's power
   within the entry point's tolerance), *refused* (one NoisevarError of one line) or
   *misbehaving* (anything else).

5. **The still regimes and composite fits** (brief hostile29b): the same cases and records
   no scale makes (short, constant, NaN, +-inf, two still levels 1e12 apart, int16) through
   ``regimes='still'`` of every noise model, ``fit_imu_model``, ``fit_imu_records``,
   ``composite_fits`` and ``InertialNoise.model``, on a record with a still start.

Writes ``benchmarks/results/reliability.md``; ``--parts`` reruns some sections and keeps
the others of the existing file.
"""

from __future__ import annotations

import argparse
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import noisevar as nv  # noqa: E402
from noisevar.batch import _output, read_table  # noqa: E402
from noisevar.errors import NoisevarError  # noqa: E402
from noisevar.noise_model import (  # noqa: E402
    allan,
    fit_coloured_noise,
    fit_imu_model,
    fit_imu_records,
    fit_kalman,
    inertial_noise,
)
from noisevar.noise_model.exports.model import composite_fits  # noqa: E402
from noisevar.stream import estimate_file  # noqa: E402
from noisevar.synth import still_start  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
COLS = ["file", "channel", "variance", "ci95_low", "ci95_high", "n_total", "hash", "error"]


def _save(path: Path, seed: int, n: int = 1200) -> None:
    rng = np.random.default_rng(seed)
    np.save(path, np.cumsum(rng.normal(0, 0.05, (n, 2)), axis=0) + rng.normal(0, 1, (n, 2)))


def _fleet(root: Path, n: int) -> list[str]:
    root.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        _save(root / f"u{i:02d}.npy", i)
    (root / "broken.csv").write_text("x,y\n1.0,oops\n")
    return sorted(str(p) for p in root.iterdir())


def _table(frame: pd.DataFrame) -> pd.DataFrame:
    return frame[COLS].sort_values(["file", "channel"]).reset_index(drop=True)


def _counts(frame: pd.DataFrame, clean: pd.DataFrame) -> tuple[int, int, bool]:
    """Rows lost, rows doubled, and whether the table equals the clean run."""
    keys = set(zip(clean["file"], clean["channel"].astype(str), strict=True))
    got = list(zip(frame["file"], frame["channel"].astype(str), strict=True))
    lost = len(keys - set(got))
    doubled = len(got) - len(set(got)) + len(set(got) - keys)
    try:
        pd.testing.assert_frame_equal(_table(frame), _table(clean), check_dtype=False)
        equal = True
    except AssertionError:
        equal = False
    return lost, doubled, equal


class _Killed(BaseException):
    pass


def commit_kills() -> list[str]:
    rows = ["| killed after | runs | rows lost | rows doubled | equal to a clean run |"]
    rows.append("|---|---|---|---|---|")
    total = [0, 0, 0, 0]
    plan = [(s, 1) for s in _output.COMMIT_STEPS] + [("journalled", 2), ("journalled", 3)]
    for step, nth in plan:
        with tempfile.TemporaryDirectory() as tmp:
            root = Path(tmp) / "logs"
            files = _fleet(root, 6)
            out = Path(tmp) / "noise.parquet"
            nv.batch(files[:5], out=out, method="diff2", progress=False)
            _save(root / "u01.npy", 99)
            given = files[1:]
            seen = {"n": 0, "dead": False}

            def point(name: str, seen=seen, step=step, nth=nth) -> None:
                seen["n"] += name == step
                if seen["dead"] or (name == step and seen["n"] == nth):
                    seen["dead"] = True
                    raise _Killed(name)

            original = _output.commit_point
            _output.commit_point = point
            try:
                nv.batch(given, out=out, method="diff2", progress=False)
            except _Killed:
                pass
            finally:
                _output.commit_point = original
            rerun = nv.batch(given, out=out, method="diff2", progress=False)
            clean = nv.batch(given, method="diff2", progress=False)
            lost, doubled, equal = _counts(read_table(out), clean)
            lost2, doubled2, equal2 = _counts(rerun, clean)
        name = step if step != "journalled" else f"journalled (file {nth})"
        rows.append(f"| {name} | 1 | {lost + lost2} | {doubled + doubled2} | {equal and equal2} |")
        total = [total[0] + 1, total[1] + lost + lost2, total[2] + doubled + doubled2,
                 total[3] + (equal and equal2)]  # fmt: skip
    rows.append(f"| **all** | {total[0]} | {total[1]} | {total[2]} | {total[3]} of {total[0]} |")
    return rows


def _group(pgid: int) -> list[int]:
    pids = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat", "rb") as fh:
                    fields = fh.read().rsplit(b")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == pgid and fields[0] not in (b"Z", b"X"):
                pids.append(int(d))
    return pids


def _size(p: Path) -> int:
    try:
        return p.stat().st_size
    except OSError:
        return 0


def sigkills(k: int, seed: int) -> list[str]:
    rng = np.random.default_rng(seed)
    left, alive_at_kill, mid = 0, 0, 0
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp) / "logs"
        files = _fleet(root, 16)
        out = Path(tmp) / "noise.csv"
        journal = _output.journal_path(out)
        cmd = [sys.executable, "-m", "noisevar", "batch", str(root), "--out", str(out), "--quiet"]
        env = {**os.environ, "PYTHONWARNINGS": "ignore"}
        for i in range(k):
            for j in rng.choice(16, 3, replace=False):
                _save(root / f"u{j:02d}.npy", 1000 * (i + 1) + int(j))
            before = _size(journal)
            proc = subprocess.Popen(
                [*cmd, "--jobs", str(1 + i % 2)], start_new_session=True, env=env,
                stderr=subprocess.DEVNULL,
            )  # fmt: skip
            end = time.monotonic() + 120
            while _size(journal) <= before and proc.poll() is None and time.monotonic() < end:
                time.sleep(0.05)
            time.sleep(rng.uniform(0.0, 0.6))
            mid += proc.poll() is None
            alive_at_kill = max(alive_at_kill, len(_group(proc.pid)))
            os.kill(proc.pid, signal.SIGKILL)
            proc.wait()
            end = time.monotonic() + 10
            while _group(proc.pid) and time.monotonic() < end:
                time.sleep(0.1)
            left += len(_group(proc.pid))
        done = subprocess.run([*cmd, "--jobs", "2"], env=env, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        lost, doubled, equal = _counts(read_table(out), nv.batch(files, progress=False))
        concurrent = _concurrent(files, Path(tmp) / "both.csv", env)
    return [
        "| SIGKILLs | killed mid-run | most processes in a killed group | processes left "
        "after 10 s | rows lost | rows doubled | equal to a clean run |",
        "|---|---|---|---|---|---|---|",
        f"| {k} (--jobs 1 and 2 in turn) | {mid} | {alive_at_kill} | {left} | {lost} | "
        f"{doubled} | {equal} |",
        "",
        concurrent,
    ]


def _concurrent(files: list[str], out: Path, env: dict) -> str:
    cmd = [sys.executable, "-m", "noisevar", "batch", *files, "--out", str(out), "--quiet"]
    procs = [subprocess.Popen(cmd, env=env, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [(p.wait(), p.stderr.read()) for p in procs]
    refused = [err.strip() for code, err in results if code == 2]
    ok = sum(code == 0 for code, _ in results)
    lost, doubled, equal = _counts(read_table(out), nv.batch(files, progress=False))
    said = f" (`{refused[0][:110]}...`)" if refused else ""
    return (
        f"Two `noisevar batch` processes on one output at once: {ok} wrote it, {len(refused)} "
        f"refused with one line{said}; the table: {lost} rows lost, {doubled} doubled, equal "
        f"to a clean run: {equal}."
    )


def _base(n: int = 2000) -> np.ndarray:
    rng = np.random.default_rng(7)
    return np.cumsum(rng.normal(0, 0.05, n)) + rng.normal(0, 1, n)


#: Entry point -> (call(z, rate), numbers(result), power of the signal's unit, tolerance).
def _entries() -> dict:
    def streamed(z, rate):
        with tempfile.TemporaryDirectory() as tmp:
            np.save(Path(tmp) / "z.npy", z)
            return estimate_file(Path(tmp) / "z.npy")

    return {
        "allan (phase)": (lambda z, r: allan(z, rate=r), lambda a: a.deviation, 1, 1e-12),
        "allan (rate)": (
            lambda z, r: allan(z, rate=r, data="rate"), lambda a: a.deviation, 1, 1e-12,
        ),
        "inertial_noise": (
            lambda z, r: inertial_noise(z, r),
            lambda f: np.array([t.value for t in f.terms]), 1, 1e-9,
        ),
        "fit_coloured_noise": (
            lambda z, r: fit_coloured_noise(z, rate=r, models=("white", "white+rw")),
            lambda f: np.array([f.r]), 2, 1e-6,
        ),
        "fit_kalman": (
            lambda z, r: fit_kalman(z, "cv", rate=r), lambda t: np.array([t.q, t.r]), 2, 1e-4,
        ),
        "stream.estimate_file": (streamed, lambda e: np.array([e.variance]), 2, 1e-9),
    }  # fmt: skip


def _cases() -> list[tuple[str, object, float, float | None]]:
    """(label, record transform, rate, scale for the expected answer or None)."""
    cases = []
    for e in range(-1074, 1021, 61):
        cases.append((f"x 2^{e}", lambda z, e=e: z * 2.0**e, 100.0, 2.0**e))
    for x in (1e154, 1e-154, 1e300, 1e-300, 1e-160, 1e-310, 5e-324, 1e30):
        cases.append((f"x {x:g}", lambda z, x=x: z * x, 100.0, x))
    cases.append(("float32", lambda z: z.astype(np.float32), 100.0, None))
    cases.append(("float32 x 1e38", lambda z: (z * 1e37).astype(np.float32), 100.0, None))
    cases.append(
        ("int64 beyond 2^53", lambda z: (2**60 + np.round(z * 100)).astype(np.int64), 100.0, None)
    )
    for r in (1e300, 1e-300, 2.0**64, 2.0**-64, 5e-324):
        cases.append((f"rate {r:g}", lambda z: z, r, None))
    return cases


def _still_entries() -> dict:
    """What issue 26's last rounds added: ``regimes='still'`` on every noise model, the
    composite fits (GMWM, their K_eq), pooled records, and the Allan figure's model curve."""
    still = {"regimes": "still"}

    def gmwm(m):
        return np.array(
            [p.value for p in m.parameters if not p.name.endswith("tau_c")]
            + [m.filter_bias.random_walk]
        )

    return {
        "allan (still)": (lambda z, r: allan(z, rate=r, **still), lambda a: a.deviation, 1, 1e-12),
        "inertial_noise (still)": (
            lambda z, r: inertial_noise(z, r, **still),
            lambda f: np.array([t.value for t in f.terms]), 1, 1e-9,
        ),
        "InertialNoise.model": (lambda z, r: inertial_noise(z, r), lambda f: f.model()[1], 1, 1e-9),
        "fit_coloured_noise (still)": (
            lambda z, r: fit_coloured_noise(z, rate=r, models=("white", "white+rw"), **still),
            lambda f: np.array([f.r]), 2, 1e-6,
        ),
        "fit_kalman (still)": (
            lambda z, r: fit_kalman(z, "cv", rate=r, **still),
            lambda t: np.array([t.q, t.r]), 2, 1e-4,
        ),
        "fit_imu_model": (lambda z, r: fit_imu_model(z, r), gmwm, 1, 1e-4),
        "fit_imu_model (still)": (lambda z, r: fit_imu_model(z, r, **still), gmwm, 1, 1e-4),
        "fit_imu_records": (
            lambda z, r: fit_imu_records([z[: z.size // 3], z[z.size // 3 :]], r), gmwm, 1, 1e-4,
        ),
        "composite_fits (still)": (
            lambda z, r: composite_fits([z, z[::-1]], [r, r], **still),
            lambda fits: np.concatenate([gmwm(m) for m in fits]), 1, 1e-4,
        ),
    }  # fmt: skip


def _hostile_cases() -> list[tuple[str, object, float, float | None]]:
    """Records no scale makes: short, constant, NaN, infinite, two still levels 1e12 apart,
    int16; each right when finite (or refused with one line)."""
    cases: list[tuple[str, object, float, float | None]] = [
        (f"first {n} samples", lambda z, n=n: z[:n], 100.0, None)
        for n in (1, 2, 5, 16, 31, 63, 64, 65, 70)
    ]

    def put(z, where, value):
        z = z.copy()
        z[where] = value
        return z

    cases += [
        ("constant", lambda z: np.full_like(z, 3.0), 100.0, None),
        ("all NaN", lambda z: np.full_like(z, np.nan), 100.0, None),
        ("a NaN run", lambda z: put(z, slice(100, 300), np.nan), 100.0, None),
        ("+inf", lambda z: put(z, 5, np.inf), 100.0, None),
        ("-inf", lambda z: put(z, 5, -np.inf), 100.0, None),
        ("second half x 1e6 (levels 1e12 apart)", lambda z: put(z, slice(z.size // 2, None),
                                                              z[z.size // 2:] * 1e6), 100.0, None),
        ("int16", lambda z: np.round(z * 1000).astype(np.int16), 100.0, None),
    ]  # fmt: skip
    return cases


def still_range() -> list[str]:
    """:func:`_range_table` of the still-regime and composite entry points, on a record
    still for its first 2000 of 4000 samples (:func:`noisevar.synth.still_start`)."""
    return _range_table(
        _still_entries(), _cases() + _hostile_cases(), still_start(2000, 4000, rng=3)
    )


def float_range() -> list[str]:
    return _range_table(_entries(), _cases(), _base())


def _range_table(entries: dict, cases: list, z0: np.ndarray) -> list[str]:  # long: one table
    rows = ["| entry point | cases | right | refused (one error) | misbehaving |"]
    rows.append("|---|---|---|---|---|")
    bad_lines: list[str] = []
    totals = [0, 0, 0, 0]
    for name, (call, numbers, power, tol) in entries.items():
        ref = numbers(call(z0, 100.0))
        right = refused = bad = 0
        for label, make, rate, scale in cases:
            try:
                got = np.asarray(numbers(call(make(z0), rate)), dtype=float)
            except NoisevarError as exc:
                ok = bool(str(exc)) and "\n" not in str(exc)
                refused += ok
                if not ok:
                    bad += 1
                    bad_lines.append(f"{name}, {label}: a message of several lines")
                continue
            except Exception as exc:  # noqa: BLE001 - counted as misbehaving
                bad += 1
                bad_lines.append(f"{name}, {label}: {type(exc).__name__}: {exc}"[:200])
                continue
            fine = bool(np.all(np.isfinite(got)))
            if fine and scale is not None:
                with np.errstate(over="ignore", under="ignore"):
                    factor = np.float64(scale) ** power  # inf or 0 beyond the range
                want = ref * factor if np.isfinite(factor) and factor > 0 else None
                if want is None:  # the scale's power overflows a float: compare by logs
                    want_log = np.log(ref) + power * np.log(float(scale))
                    fine = bool(np.allclose(np.log(got), want_log, rtol=0, atol=tol))
                else:
                    fine = bool(np.allclose(got, want, rtol=tol, atol=0))
            elif fine and label.startswith("rate"):
                fine = bool(np.all(got >= 0))
            if fine:
                right += 1
            else:
                bad += 1
                bad_lines.append(f"{name}, {label}: {got[:3]} (reference {ref[:3]})")
        n = right + refused + bad
        rows.append(f"| `{name}` | {n} | {right} | {refused} | {bad} |")
        totals = [totals[0] + n, totals[1] + right, totals[2] + refused, totals[3] + bad]
    rows.append(f"| **all** | {totals[0]} | {totals[1]} | {totals[2]} | {totals[3]} |")
    if bad_lines:
        rows += ["", "Misbehaving cases:", ""] + [f"- {b}" for b in bad_lines]
    return rows


#: Sections of the results file: key -> heading (``--parts`` reruns some, keeps the rest).
SECTIONS = {
    "commit": "## A kill at each step of the commit sequence, then a rerun",
    "sigkill": "## Random SIGKILLs of `noisevar batch`",
    "float": "## The float range of the noise models and the streamed path",
    "still": "## The float range and hostile records of the still regimes and composite fits",
}
FLOAT_NOTE = (
    "Right: finite and equal to the unscaled answer times the scale's power (allan 1e-12, "
    "inertial_noise and the streamed estimate 1e-9, fit_coloured_noise 1e-6, fit_kalman "
    "1e-4: optimiser tolerances, as a non-power-of-two scale rounds the record); float32, "
    "int64 and rate cases: finite."
)
STILL_NOTE = (
    "The same cases on a record still for its first 2000 of 4000 samples "
    "(`synth.still_start`), plus records no scale makes (first 1-70 samples, constant, all "
    "NaN, a NaN run, +-inf, the second half x 1e6, int16: right when finite); the composite "
    "fits' numbers are their parameters but tau_c, and K_eq (1e-4: within 2^+-100, where "
    "the record is fitted as it is, their optimiser's answer moves up to 1.4e-5 with a power "
    "of two; beyond, exactly scaled)."
)


def _previous() -> dict[str, str]:
    """The sections of the existing results file, by key (kept when not rerun)."""
    path = RESULTS / "reliability.md"
    text = path.read_text(encoding="utf-8") if path.exists() else ""
    out = {}
    for key, heading in SECTIONS.items():
        if heading in text:
            body = text.split(heading, 1)[1]
            ends = [body.index(h) for h in SECTIONS.values() if h in body]
            out[key] = heading + (body[: min(ends)] if ends else body).rstrip("\n")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sigkills", type=int, default=20)
    ap.add_argument("--seed", type=int, default=29)
    ap.add_argument("--parts", nargs="+", choices=list(SECTIONS), default=list(SECTIONS))
    args = ap.parse_args()
    load = os.getloadavg()[0]
    runs = {
        "commit": commit_kills,
        "sigkill": lambda: sigkills(args.sigkills, args.seed),
        "float": lambda: [FLOAT_NOTE, "", *float_range()],
        "still": lambda: [STILL_NOTE, "", *still_range()],
    }
    sections = _previous()
    for key in args.parts:
        sections[key] = "\n".join([SECTIONS[key], "", *runs[key]()])
    lines = [
        "# Reliability (issue 29 items 1-3)",
        "",
        f"Command: `nice -n 10 python benchmarks/reliability.py --sigkills {args.sigkills} "
        f"--seed {args.seed} --parts {' '.join(args.parts)}` on {platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}; 1-minute load average "
        f"at start {load:.1f} (sections not in --parts are kept from the previous run).",
    ]
    lines += [part for key in SECTIONS if key in sections for part in ("", sections[key])]
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "reliability.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""Invariance of R on motion-burst records: transforms that change nothing must not move R.

    python benchmarks/invariance.py [--records 200] [--n 20000] [--seed 1] [--no-yei]
    python benchmarks/invariance.py --yei-only     # the real record alone, under a minute

Each record is white noise (σ = 1) on a slow signal, with one to three bursts of motion
(a fast oscillation, jerky steps, or taps that ring; random amplitude and length). For
each transform (reversal, dropping 1, 2 or 3 leading samples, sign flip, scale x1e3, an
offset, a linear trend) the benchmark counts the records whose transformed R lies inside
the original R's ci95 (the issue 26 target: at least 95 % for every transform).

The same on a real record: the hand-held YEI 3-Space IMU of scikit-kinematics' wheel
(fetched with ``pip download`` at run time, as ``real_records.py`` does; not committed),
6 channels x 4 transforms (reversed, drop 2, sign, scale x1e3), for the whole record's R
and for the R to use (``est.still`` when the level varies, else R), each against its own
ci95. Results go to benchmarks/results/invariance.md (``--yei-only``: invariance_yei.md).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import noisevar
from noisevar import synth

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "invariance.md"
OUT_YEI = OUT.with_name("invariance_yei.md")


def burst_record(n: int, rng: np.random.Generator) -> NDArray:
    """White noise (σ = 1) on a slow sine, with 1-3 bursts of motion (synth.motion_bursts)."""
    t = np.arange(n)
    z = 3.0 * np.sin(2 * np.pi * t / rng.uniform(2000, 8000)) + rng.normal(0.0, 1.0, n)
    return z + synth.motion_bursts(n, rng)


def transforms(n: int) -> dict[str, Callable[[NDArray], NDArray]]:
    ramp = np.linspace(0.0, 50.0, n)
    return {
        "reversed": lambda z: z[::-1],
        "drop 1": lambda z: z[1:],
        "drop 2": lambda z: z[2:],
        "drop 3": lambda z: z[3:],
        "sign": lambda z: -z,
        "scale x1e3": lambda z: 1e3 * z,
        "offset +1e4": lambda z: z + 1e4,
        "linear trend": lambda z: z + ramp[: z.size],
    }


def run(records: int, n: int, seed: int) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    inside = {k: 0 for k in transforms(n)}
    for _ in range(records):
        z = burst_record(n, rng)
        est = noisevar.estimate(z)
        lo, hi = est.ci95
        for name, f in transforms(n).items():
            scale = 1e6 if name == "scale x1e3" else 1.0
            v = noisevar.estimate(f(z)).variance / scale
            inside[name] += lo <= v <= hi
    return {k: v / records for k, v in inside.items()}


#: The YEI record's transforms (a subset of :func:`transforms`) and its channels' columns.
YEI_TRANSFORMS = ("reversed", "drop 2", "sign", "scale x1e3")
YEI_COLUMNS = {"gyr_x": 1, "gyr_y": 2, "gyr_z": 3, "acc_x": 7, "acc_y": 8, "acc_z": 9}


def yei_channels() -> dict[str, NDArray]:
    """The six IMU channels of scikit-kinematics' hand-held YEI record (110 Hz)."""
    import io

    import pandas as pd

    raw = _refdata.skinematics_file("tests/data/data_yei.txt")
    df = pd.read_csv(io.BytesIO(raw), skiprows=1, header=None)
    return {c: df[i].to_numpy(dtype=float) for c, i in YEI_COLUMNS.items()}


def _to_use(est) -> object:
    return est if est.still is None else est.still


def yei_rows() -> list[tuple[str, str, float, bool, float, bool]]:
    """Per channel and transform: R and the R to use over the original's, inside its ci95."""
    rows = []
    for ch, x in yei_channels().items():
        est = noisevar.estimate(x)
        use = _to_use(est)
        for name in YEI_TRANSFORMS:
            f = transforms(x.size)[name]
            scale = 1e6 if name == "scale x1e3" else 1.0
            again = noisevar.estimate(f(x))
            r, u = again.variance / scale, _to_use(again).variance / scale
            rows.append((ch, name, r / est.variance, bool(est.ci95[0] <= r <= est.ci95[1]),
                         u / use.variance, bool(use.ci95[0] <= u <= use.ci95[1])))  # fmt: skip
    return rows


def yei_lines(rows: list[tuple[str, str, float, bool, float, bool]]) -> list[str]:
    inside = sum(r[3] for r in rows), sum(r[5] for r in rows)
    return [
        "",
        "## The hand-held YEI record (scikit-kinematics 0.10.4), 6 channels x 4 transforms",
        "",
        f"R inside its ci95 in {inside[0]} of {len(rows)}; the R to use (still regimes when "
        f"the level varies) inside its ci95 in {inside[1]} of {len(rows)} (target: every one).",
        "",
        "| channel | transform | R / original | inside | R to use / original | inside |",
        "|---|---|---|---|---|---|",
        *(
            f"| {c} | {t} | {a:.3g} | {'yes' if ia else '**no**'} | {b:.3g} | "
            f"{'yes' if ib else '**no**'} |"
            for c, t, a, ia, b, ib in rows
        ),
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=200)
    ap.add_argument("--n", type=int, default=20000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-yei", action="store_true", help="skip the real YEI record")
    ap.add_argument("--yei-only", action="store_true", help="only the real YEI record")
    a = ap.parse_args()
    if a.yei_only:
        text = "\n".join(
            [
                "# Invariance of R on a real record",
                "",
                "`python benchmarks/invariance.py --yei-only`",
                *yei_lines(yei_rows()),
            ]
        )
        OUT_YEI.write_text(text + "\n")
        print(text)
        return
    share = run(a.records, a.n, a.seed)
    lines = [
        "# Invariance of R on motion-burst records",
        "",
        f"`python benchmarks/invariance.py --records {a.records} --n {a.n} --seed {a.seed}`",
        "",
        "| transform | R inside the original's ci95 | target | pass |",
        "|---|---|---|---|",
        *(
            f"| {k} | {v:.1%} | >= 95 % | {'yes' if v >= 0.95 else 'no'} |"
            for k, v in share.items()
        ),
        *([] if a.no_yei else yei_lines(yei_rows())),
    ]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

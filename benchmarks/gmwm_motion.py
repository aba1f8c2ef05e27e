"""``fit_imu_model`` on records with motion, and the still records it must leave alone.

Issues 26 and 30.

    python benchmarks/gmwm_motion.py                 # 2 seeds x 6 axes + 1 composite run each

Motion: real_audit.py's reproduction C (three axes of a slow random walk plus a sine, white
noise of std 0.01 at 50 Hz: N = 0.0014) and a record still for its first 1,500 of 4,000
samples then moving (seeds 0-4): N, its interval, whether the truth and the white level
sigma/sqrt(fs) are inside, the notes, and ``regimes="still"``'s N.

Still: the records of ``gmwm_choice.py`` (``imu_k_bias.py``'s 400 Hz, 3 h white noise + bias
random walk; ``imu_models.py``'s composite truths, 10 h at 200 Hz). The branch changes a fit
only when N is at its bound (``fitting.white_at_bound``), when the fit is unexplained
(``fitting.unexplained``) or the one-pass screen cannot rule motion out
(``gmwm.level_may_vary``): then the estimate's diagnostics run, or when the wavelet variance's
band is clipped (``fitting.wv_band``); each is counted. None of them: every figure of
``gmwm_choice.md`` is the same by construction.

Results: benchmarks/results/gmwm_motion.md.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model import fit_imu_model
from noisevar.noise_model.gmwm import level_may_vary
from noisevar.noise_model.gmwm.fitting import MAX_LOG_HALF_WIDTH, unexplained
from noisevar.noise_model.inertial import white_level

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests" / "noise_model"))
from imu_k_bias import RATE, _records  # noqa: E402
from imu_models import COMPOSITE, _truth, simulate_truth  # noqa: E402
from test_gmwm_motion import RATE as M_RATE  # noqa: E402
from test_gmwm_motion import TRUE_N, still_then_motion  # noqa: E402
from test_gmwm_no_warnings import moving_axes  # noqa: E402

OUT = HERE / "results" / "gmwm_motion.md"


def _row(label: str, y: np.ndarray, fit, still=None) -> str:  # noqa: ANN001
    n = fit.parameter("N")
    lo, hi = n.interval
    white = white_level(y, M_RATE)
    notes = "; ".join(t.split(":")[0][:60] for t in fit.notes) or "none"
    s = "-" if still is None else f"{still.parameter('N').value / TRUE_N - 1:+.1%}"
    return (
        f"| {label} | {fit.model} | {n.value:.3g} [{lo:.3g}, {hi:.3g}] | {white:.3g} | "
        f"{'yes' if lo <= TRUE_N <= hi else 'NO'} | {'yes' if hi >= white * (1 - 1e-9) else 'NO'}"
        f" | {s} | {notes} |"
    )


def motion() -> list[str]:
    lines = [
        "## Records with motion (true N = 0.0014)",
        "",
        "| record | model | N [interval] | white level | truth inside | white level inside "
        "| regimes='still' N error | notes (first words) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    x = moving_axes(0)
    for i, fit in enumerate(fit_imu_model(x, M_RATE)):
        lines.append(_row(f"reproduction C axis {i}", x[:, i], fit))
    for seed in range(5):
        z = still_then_motion(seed)
        whole = fit_imu_model(z, M_RATE)
        lines.append(_row(f"still 1500 then motion, seed {seed}", z, whole,
                          fit_imu_model(z, M_RATE, regimes="still")))  # fmt: skip
    return lines


def _count(fit, row: np.ndarray, cpu: float, tally: dict) -> None:  # noqa: ANN001
    tally["axes"] += 1
    tally["N at bound"] += any(t.startswith("N is at its lower bound") for t in fit.notes)
    # the diagnostics run on an unexplained fit, or where the screen cannot rule motion out
    tally["unexplained (diagnostics run)"] += unexplained(fit) or level_may_vary(row)
    tally["regime warning"] += any("noise level varies" in t for t in fit.notes)
    tally["band clipped"] += bool(
        np.any(np.isclose(fit.wv_interval[1] / fit.wv, np.exp(MAX_LOG_HALF_WIDTH)))
    )
    tally["cpu"] += cpu


def still(seeds: int, runs: int) -> list[str]:
    lines = [
        "## Still records: where the branch could change a figure",
        "",
        "| records | axes | N at bound | unexplained (diagnostics run) | regime warning "
        "| band clipped | CPU per axis (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    keys = ("axes", "N at bound", "unexplained (diagnostics run)", "regime warning")
    keys += ("band clipped", "cpu")
    tally = dict.fromkeys(keys, 0.0)
    for seed in range(seeds):
        x, _ = _records(seed)
        t0 = time.process_time()
        fits = fit_imu_model(x, RATE)
        cpu = (time.process_time() - t0) / len(fits)
        for i, fit in enumerate(fits):
            _count(fit, x[:, i], cpu, tally)
    lines.append(_line(f"imu_k_bias seeds 0-{seeds - 1} (400 Hz, 3 h)", tally))
    tally = dict.fromkeys(keys, 0.0)
    for c, base in enumerate(COMPOSITE.values()):
        rng = np.random.default_rng(7 + c)
        for r in range(runs):
            y = simulate_truth(_truth(base, rng), int(10 * 3600 * 200.0), 200.0, 5000 + 100 * c + r)
            t0 = time.process_time()
            fit = fit_imu_model(y, 200.0)
            _count(fit, y, time.process_time() - t0, tally)
    lines.append(_line(f"composite truths, {runs} run(s) each (200 Hz, 10 h)", tally))
    return lines


def _line(label: str, t: dict) -> str:
    return (
        f"| {label} | {t['axes']:.0f} | {t['N at bound']:.0f} | "
        f"{t['unexplained (diagnostics run)']:.0f} | {t['regime warning']:.0f} | "
        f"{t['band clipped']:.0f} | {t['cpu'] / max(t['axes'], 1):.2f} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--composite", type=int, default=1, help="runs per composite truth")
    a = ap.parse_args()
    t0 = time.time()
    body = motion() + [""] + still(a.seeds, a.composite)
    head = [
        "# fit_imu_model on records with motion (issues 26, 30)",
        "",
        f"`python benchmarks/gmwm_motion.py --seeds {a.seeds} --composite {a.composite}`; "
        f"{time.time() - t0:.0f} s wall, load average {os.getloadavg()[0]:.1f} on 2 cores.",
        "",
    ]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(head + body) + "\n")
    print("\n".join(head + body))


if __name__ == "__main__":
    main()

"""Could a general shape test catch the triangles and level steps the IEEE-952 misfit note
misses? (docs/algorithms.md §E4 *Misfit check*; a measurement, not a rule in noisevar)

    python benchmarks/misfit_shapes.py     # the records of benchmarks/inertial_misfit.py, ~1 min

1. **A level step is a rate random walk.** One step of size h in a record of T seconds:
   its overlapping Allan variance against ``h² tau / (3 T)``, E4.1's K term with
   ``K² = h² / T``.
2. **A ramp that flattens.** ``ln(sigma²(tau) tau)`` is convex in ``ln tau`` for every sum of
   E4.1's terms (a log-sum-exp of lines); a Gauss-Markov bias's slope never exceeds 2.
   A triangle is a rate ramp (slope 3) below its half period and flattens after. The
   candidate: between judged taus (edf >= 30) a slope above 2 by the misfit check's
   Bonferroni bound in standard errors, then a later one below 2 by the same bound. Counted
   alone and joined with the note's hump, on the motion and still records of
   ``benchmarks/inertial_misfit.py``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from scipy import stats

from noisevar.noise_model.allan import allan
from noisevar.noise_model.inertial import TERMS, _model_edf, fit_terms
from noisevar.noise_model.inertial_misfit import MISFIT, MISFIT_ALPHA, MISFIT_EDF

sys.path.insert(0, str(Path(__file__).resolve().parent))
import inertial_misfit as bench  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def ramp_then_flat(y: np.ndarray, fs: float) -> bool:
    """The candidate test on one record (see the module's docstring)."""
    res = allan(y, rate=fs, data="rate", kind="oadev", taus="octave")
    m = np.maximum(np.round(res.taus * fs), 1).astype(np.int64)
    coef, _ = fit_terms(res.taus, res.variance, res.edf, rate=fs, n_phase=y.size + 1)
    a = np.column_stack([s.coefficient(res.taus) for s in TERMS])
    edf = _model_edf(a, coef, m, y.size + 1)
    k = np.flatnonzero(edf >= MISFIT_EDF)
    if k.size < 3:
        return False
    bound = stats.norm.isf(MISFIT_ALPHA / (2.0 * k.size))
    g = np.log(res.variance[k] * res.taus[k])
    dt = np.diff(np.log(res.taus[k]))
    slope = np.diff(g) / dt
    se = np.hypot(np.sqrt(2.0 / edf[k])[1:], np.sqrt(2.0 / edf[k])[:-1]) / dt
    steep = np.flatnonzero(slope - 2.0 > bound * se)
    after = slice(steep[0] + 1, None) if steep.size else slice(0, 0)
    return bool(np.any(2.0 - slope[after] > bound * se[after]))


def main() -> None:
    start = time.perf_counter()
    lines = ["## Misfit shapes (benchmarks/misfit_shapes.py)", "", "### One level step", ""]
    n, fs, h = 20000, 50.0, 1.0
    y = np.zeros(n)
    y[n // 2 :] = h
    res = allan(y, rate=fs, data="rate", kind="oadev", taus="octave")
    ratio = res.variance / (h * h * res.taus / (3 * n / fs))
    lines += [
        "| tau (s) | " + " | ".join(f"{t:.3g}" for t in res.taus) + " |",
        "|---|" + "---|" * res.taus.size,
        "| AVAR / (h² tau / 3T) | " + " | ".join(f"{r:.3f}" for r in ratio) + " |",
        "",
        "### A ramp that flattens",
        "",
        "| records | n | ramp-then-flat | note's misfit with a hump | either |",
        "|---|---|---|---|---|",
    ]
    motion = list(bench.motion_records(60))
    still = list(bench.true_records(260)) + list(bench.gauss_markov_records(12))
    for kind in ("sine", "triangle", "steps", "still"):
        recs = still if kind == "still" else [r for r in motion if r[0] == kind]
        new = [ramp_then_flat(y, fs) for _, y, fs in recs]
        old = [MISFIT in bench.judge(y, fs)[0] for _, y, fs in recs]
        both = sum(a or b for a, b in zip(new, old, strict=True))
        lines.append(f"| {kind} | {len(recs)} | {sum(new)} | {sum(old)} | {both} |")
    lines += ["", f"{time.perf_counter() - start:.0f} s."]
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "misfit_shapes.md").write_text(text)


if __name__ == "__main__":
    main()

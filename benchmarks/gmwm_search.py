"""GMWM model search: least-squares solves and CPU per axis, and its results kept unchanged.

On the wavelet variances of the records of ``benchmarks/imu_models.py`` (the speed record's
6 axes, the ``ros`` section's first seeds, the ``composite`` section's first runs of both
truths), each axis's :func:`~noisevar.noise_model.gmwm.fitting.fit_wv` runs alone in this
process: ``scipy.optimize.least_squares`` calls, :func:`estimator.fit` calls and CPU
(``time.process_time``) per axis. With ``--save FILE`` the chosen models and parameters are
written; with ``--compare FILE`` they are checked against a saved run (models and the
models tried exactly, parameters and objectives to ``RTOL``).

Results: benchmarks/results/gmwm_search.md (``--out``). The wavelet variances are cached
in ``--cache`` (they do not depend on the search).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm.fitting import as_rows, fit_wv, wavelet_variances
from noisevar.noise_model.simulate import simulate_inertial

HERE = Path(__file__).resolve().parent
OUT = HERE / "results" / "gmwm_search.md"
#: The run of main's code before the search's memo (commit b1f98c8): ``--compare`` it.
BEFORE = HERE / "results" / "gmwm_search_before.json"
#: Relative agreement of parameters and objectives with a saved run.
RTOL = 1e-4


def _imu_models():  # noqa: ANN202
    spec = importlib.util.spec_from_file_location("imu_models", HERE / "imu_models.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _wvs(x: np.ndarray, group: str) -> list[tuple[str, float, est.WaveletVariance]]:
    return [(group, 0.0, w) for w in wavelet_variances(as_rows(x, 0), False)]


def records(seeds: int, runs: int) -> list[tuple[str, float, est.WaveletVariance]]:
    """(group, rate, wavelet variance) of each axis, as imu_models.py makes the records."""
    im = _imu_models()
    out = [("speed", 200.0, w) for *_, w in _wvs(im.speed_record(), "speed")]
    n = int(3.0 * 3600 * 400.0)
    for seed in range(seeds):
        cols = []
        for k, (nd, kd) in enumerate(im.ROS.values()):
            for a in range(3):
                s = 1000 * seed + 10 * k + a
                cols.append(
                    simulate_inertial(n, 400.0, random_walk=nd, rate_random_walk=kd, seed=s)
                )
        out += [("ros", 400.0, w) for *_, w in _wvs(np.column_stack(cols), "ros")]
    n = int(10.0 * 3600 * 200.0)
    for c, (label, base) in enumerate(im.COMPOSITE.items()):
        rng = np.random.default_rng(7 + c)
        for r in range(runs):
            t = im._truth(base, rng)
            y = simulate_inertial(
                n,
                200.0,
                quantization=t["Q"],
                random_walk=t["N"],
                rate_random_walk=t["K"],
                gauss_markov=t["GM"],
                seed=5000 + 100 * c + r,
            )
            out += [(f"composite {label}", 200.0, w) for *_, w in _wvs(y[:, None], label)]
    return out


def cached(path: Path, seeds: int, runs: int) -> list[tuple[str, float, est.WaveletVariance]]:
    """:func:`records`, read from ``path`` if it holds them (written there otherwise)."""
    if path.is_file():
        meta = json.loads(path.with_suffix(".json").read_text(encoding="utf-8"))
        if meta["seeds"] == seeds and meta["runs"] == runs:
            z = np.load(path)
            return [
                (g, r, est.WaveletVariance(z[f"tau{i}"], z[f"nu{i}"], z[f"m{i}"]))
                for i, (g, r) in enumerate(meta["axes"])
            ]
    recs = records(seeds, runs)
    arrays = {}
    for i, (_, _, w) in enumerate(recs):
        arrays |= {f"tau{i}": w.tau, f"nu{i}": w.nu, f"m{i}": w.m}
    np.savez(path, **arrays)
    meta = {"seeds": seeds, "runs": runs, "axes": [(g, r) for g, r, _ in recs]}
    path.with_suffix(".json").write_text(json.dumps(meta), encoding="utf-8")
    return recs


class Counter:
    """Counts the calls of ``estimator.least_squares`` and ``estimator.fit``."""

    def __init__(self) -> None:
        self.solves = 0
        self.fits = 0
        self._ls, self._fit = est.least_squares, est.fit

    def __enter__(self) -> Counter:
        def ls(*a, **k):  # noqa: ANN002, ANN003, ANN202
            self.solves += 1
            return self._ls(*a, **k)

        def fit(*a, **k):  # noqa: ANN002, ANN003, ANN202
            self.fits += 1
            return self._fit(*a, **k)

        est.least_squares, est.fit = ls, fit
        return self

    def __exit__(self, *exc: object) -> None:
        est.least_squares, est.fit = self._ls, self._fit


def run(recs: list) -> list[dict]:
    """Each axis's fit alone: its result, solves, fits and CPU."""
    out = []
    for group, rate, wv in recs:
        with Counter() as c:
            t0 = time.process_time()
            m = fit_wv(wv, rate)
            cpu = time.process_time() - t0
        d = m.to_dict()
        out.append(
            {
                "group": group,
                "model": m.model,
                "params": [p["value"] for p in d["parameters"]],
                "tried": sorted(r["model"] for r in d["table"]),
                "objectives": {r["model"]: r["objective"] for r in d["table"]},
                "solves": c.solves,
                "fits": c.fits,
                "cpu": cpu,
            }
        )
    return out


def compare(got: list[dict], want: list[dict]) -> list[str]:
    """Differences from a saved run (empty: the same results)."""
    bad = []
    for i, (g, w) in enumerate(zip(got, want, strict=True)):
        if (g["model"], g["tried"]) != (w["model"], w["tried"]):
            bad.append(f"axis {i} ({g['group']}): {g['model']} / {w['model']}, tried differ")
            continue
        if not np.allclose(g["params"], w["params"], rtol=RTOL, atol=0.0):
            bad.append(f"axis {i} ({g['group']}): parameters {g['params']} / {w['params']}")
        obj = g["objectives"][g["model"]], w["objectives"][w["model"]]
        if not np.isclose(*obj, rtol=RTOL, atol=0.05):
            bad.append(f"axis {i} ({g['group']}): chosen objective {obj[0]} / {obj[1]}")
    return bad


def table(res: list[dict], before: list[dict] | None) -> list[str]:
    lines = [
        "| records | axes | least_squares calls per axis, median [min, max] | "
        "estimator.fit calls per axis, median | CPU per axis (s), median | total CPU (s) |",
        "|---|---|---|---|---|---|",
    ]
    for label, rows in [
        ("all", res),
        *((g, [r for r in res if r["group"] == g]) for g in dict.fromkeys(r["group"] for r in res)),
    ]:
        s = np.array([r["solves"] for r in rows])
        f = np.array([r["fits"] for r in rows])
        c = np.array([r["cpu"] for r in rows])
        cell = f"{np.median(s):.0f} [{s.min()}, {s.max()}]"
        cpu = f"{c.sum():.2f}"
        if before is not None:
            old = [r for r in before if label == "all" or r["group"] == label]
            b = np.array([r["solves"] for r in old])
            cell += f" (before {np.median(b):.0f} [{b.min()}, {b.max()}])"
            cpu += f" (before {sum(r['cpu'] for r in old):.2f})"
        lines.append(
            f"| {label} | {len(rows)} | {cell} | {np.median(f):.0f} | {np.median(c):.3f} | {cpu} |"
        )
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3, help="ros seeds (6 axes each)")
    ap.add_argument("--runs", type=int, default=5, help="composite runs per truth")
    ap.add_argument("--cache", type=Path, default=Path("/tmp/gmwm_search_wv.npz"))
    ap.add_argument("--save", type=Path, help="write the results (JSON) here")
    ap.add_argument(
        "--compare", type=Path, help="check against a saved run (JSON), e.g. " + BEFORE.name
    )
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    recs = cached(args.cache, args.seeds, args.runs)
    res = run(recs)
    if args.save:
        args.save.write_text(json.dumps(res, indent=1), encoding="utf-8")
    before = json.loads(args.compare.read_text(encoding="utf-8")) if args.compare else None
    bad = compare(res, before) if before is not None else []
    lines = [
        "### GMWM model search: `python benchmarks/gmwm_search.py`",
        "",
        f"Each axis's fit_wv alone in one process (load {os.getloadavg()[0]:.1f}): the speed "
        f"record's 6 axes, {args.seeds} ros seeds x 6 axes, {args.runs} composite runs per "
        "truth (imu_models.py's records).",
        "",
        *table(res, before),
    ]
    if before is not None:
        lines += [
            "",
            f"Against {args.compare.name}: "
            + (
                "same models, models tried and parameters (rtol 1e-4) on every axis."
                if not bad
                else f"{len(bad)} differences:"
            ),
            *(f"- {b}" for b in bad),
        ]
    args.out.parent.mkdir(exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()

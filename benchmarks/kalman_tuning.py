"""Benchmark of issue 14 (part 2): Q and R together, coloured-noise models, speed.

    python benchmarks/kalman_tuning.py          # writes benchmarks/results/kalman_tuning.md
    python benchmarks/kalman_tuning.py --runs 5 --coloured-runs 3 --peer-runs 2
    (the pykalman section needs ``pip install pykalman``; without it, it says so)

1. statsmodels' Nile data: ``fit_kalman(model="rw")`` against Durbin and Koopman's
   sigma2_eps = 15099, sigma2_eta = 1469.1 (target: within 0.5 %).
2. Simulated constant-velocity and constant-acceleration tracks (r = 4 known,
   q over three decades, n = 2e4): median r and q errors, the share of runs whose
   NIS mean is inside its 95 % band, ALS against MLE; statsmodels' MLE (an
   ``MLEModel`` with the same F, H, Q and exact diffuse start) and Shumway-Stoffer
   EM (ours, compiled, benchmark only) on fewer runs; pykalman's EM timed per
   iteration (at about 12 s per iteration it cannot be run to convergence).
3. Coloured noise: white + AR(1) (phi 0.5, 0.9, 0.99), white + random walk and
   white alone at n = 2e4: parameters within 10 %, model choice by BIC.
4. Speed: ``fit_kalman`` on 1e5 samples (target < 2 s).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.signal
import statsmodels.api as sm

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from noisevar.kalman.kernels import _cov_into  # noqa: E402
from noisevar.noise_model import evaluate_kalman, fit_coloured_noise, fit_kalman  # noqa: E402
from noisevar.noise_model._steady import diffuse_start  # noqa: E402
from noisevar.noise_model.kalman_fit import MODELS, kinematic_model  # noqa: E402
from noisevar.numeric.jit import inline, jit  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
RATE, R_TRUE, N = 10.0, 4.0, 20000
H_VALUES = {"cv": (1e-4, 1e-3, 1e-2, 1e-1), "ca": (1e-5, 1e-4, 1e-3, 1e-2)}
EM_MAX_ITER = 2000
#: Log-likelihood left to gain (Aitken) below which EM stops.
EM_TOL = 1e-4


def track(model: str, n: int, q: float, r: float, rng: np.random.Generator) -> np.ndarray:
    F, _, Q1 = kinematic_model(model, 1.0 / RATE)
    w = rng.standard_normal((n, F.shape[0])) @ np.linalg.cholesky(q * Q1).T
    x = np.zeros(F.shape[0])
    pos = np.empty(n)
    for k in range(n):  # simulation only
        x = F @ x + w[k]
        pos[k] = x[0]
    return pos + rng.normal(0.0, np.sqrt(r), n)


# ------------------------------------------------------------------ peers
class Kinematic(sm.tsa.statespace.MLEModel):
    """The kinematic model in statsmodels: parameters (q, r), exact diffuse start."""

    def __init__(self, z: np.ndarray, model: str) -> None:
        F, h, Q1 = kinematic_model(model, 1.0 / RATE)
        n = F.shape[0]
        super().__init__(z, k_states=n, k_posdef=n, initialization="diffuse")
        self.Q1 = Q1
        self["design"] = h[None, :]
        self["transition"] = F
        self["selection"] = np.eye(n)
        self.k = MODELS[model][1]

    @property
    def param_names(self) -> list[str]:
        return ["q", "r"]

    @property
    def start_params(self) -> np.ndarray:
        r0 = float(np.var(np.diff(self.endog[:, 0]))) / 2
        return np.array([1e-2 * r0 * RATE**self.k, r0])

    def transform_params(self, u: np.ndarray) -> np.ndarray:
        return np.exp(u)

    def untransform_params(self, p: np.ndarray) -> np.ndarray:
        return np.log(p)

    def update(self, params, **kwargs):  # noqa: ANN001, ANN201
        params = super().update(params, **kwargs)
        self["state_cov"] = params[0] * self.Q1
        self["obs_cov", 0, 0] = params[1]


def statsmodels_fit(z: np.ndarray, model: str) -> tuple[float, float]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = Kinematic(z, model).fit(disp=False, maxiter=500)
    return float(res.params[0]), float(res.params[1])


@inline
def _abt(A, B, out):  # pragma: no cover - compiled
    # out = A B'
    m = A.shape[0]
    for i in range(m):
        for j in range(m):
            acc = 0.0
            for t in range(m):
                acc += A[i, t] * B[j, t]
            out[i, j] = acc


@inline
def _ab(A, B, out):  # pragma: no cover - compiled
    # out = A B
    m = A.shape[0]
    for i in range(m):
        for j in range(m):
            acc = 0.0
            for t in range(m):
                acc += A[i, t] * B[t, j]
            out[i, j] = acc


@inline
def _av(A, v, out):  # pragma: no cover - compiled
    m = A.shape[0]
    for i in range(m):
        acc = 0.0
        for t in range(m):
            acc += A[i, t] * v[t]
        out[i] = acc


@inline
def _chol_solve_t(P, B, L, out):  # pragma: no cover - compiled
    # out = B P^-1 for symmetric positive definite P (Cholesky), B (m, m)
    m = P.shape[0]
    for j in range(m):
        s = P[j, j]
        for t in range(j):
            s -= L[j, t] * L[j, t]
        L[j, j] = np.sqrt(s)
        for i in range(j + 1, m):
            s = P[i, j]
            for t in range(j):
                s -= L[i, t] * L[j, t]
            L[i, j] = s / L[j, j]
    for row in range(m):  # solve X P = B row by row: P x' = b'
        for i in range(m):  # L y = b
            s = B[row, i]
            for t in range(i):
                s -= L[i, t] * out[row, t]
            out[row, i] = s / L[i, i]
        for i in range(m - 1, -1, -1):  # L' x = y
            s = out[row, i]
            for t in range(i + 1, m):
                s -= L[t, i] * out[row, t]
            out[row, i] = s / L[i, i]


@jit
def em_step(z, F, h, Q1, q, r, x0, P0):  # pragma: no cover - compiled
    # long: one E-step (filter, RTS smoother with lag-one covariances) written out in loops
    N, m = z.size, x0.size
    xf = np.empty((N + 1, m))
    Pf = np.empty((N + 1, m, m))
    xp = np.empty((N + 1, m))
    Pp = np.empty((N + 1, m, m))
    xf[0] = x0
    Pf[0] = P0
    T1 = np.empty((m, m))
    T2 = np.empty((m, m))
    J = np.empty((m, m))
    L = np.empty((m, m))
    ph = np.empty(m)
    K = np.empty(m)
    d = np.empty(m)
    ll = 0.0
    Q = q * Q1
    for k in range(1, N + 1):
        # x- = F x,  P- = F P F' + Q
        _av(F, xf[k - 1], xp[k])
        _cov_into(F, Pf[k - 1], Q, Pp[k], T1, m)
        S = r
        e = z[k - 1]
        for i in range(m):
            acc = 0.0
            for j in range(m):
                acc += Pp[k, i, j] * h[j]
            ph[i] = acc
            S += h[i] * acc
            e -= h[i] * xp[k, i]
        # l += -1/2 (log 2 pi S + e^2 / S)
        ll += -0.5 * (np.log(2.0 * np.pi * S) + e * e / S)
        for i in range(m):
            K[i] = ph[i] / S
            xf[k, i] = xp[k, i] + K[i] * e
        # P = P- - K S K'
        for i in range(m):
            for j in range(m):
                Pf[k, i, j] = Pp[k, i, j] - K[i] * S * K[j]
    xs = xf[N].copy()
    Ps = Pf[N].copy()
    xs_prev = np.empty(m)
    Ps_prev = np.empty((m, m))
    W = np.empty((m, m))
    M = np.empty((m, m))
    eye = np.eye(m)
    sq = 0.0
    sr = 0.0
    for k in range(N - 1, -1, -1):
        # W = Pp^-1;  J = Pf F' W
        _chol_solve_t(Pp[k + 1], eye, L, W)
        _abt(Pf[k], F, T1)
        _ab(T1, W, J)
        # r: (z - h xs)^2 + h Ps h' at state k+1
        e = z[k]
        v = 0.0
        for i in range(m):
            e -= h[i] * xs[i]
            for j in range(m):
                v += h[i] * Ps[i, j] * h[j]
        sr += e * e + v
        # w = x_k+1 - F x_k:  E[w] = Q W d,  Var[w] = Q - Q W (Pp - Ps) W Q  (d = xs - xp)
        # so  tr(Q1^-1 E[w w']) / q = m + q (d' M d - tr(M (Pp - Ps))),  M = W Q1 W
        _ab(W, Q1, T1)
        _ab(T1, W, M)
        for i in range(m):
            d[i] = xs[i] - xp[k + 1, i]
        acc = 0.0
        for i in range(m):
            for j in range(m):
                acc += M[i, j] * (d[i] * d[j] - Pp[k + 1, j, i] + Ps[j, i])
        sq += acc
        # xs_k = xf + J d,  Ps_k = Pf + J (Ps_k+1 - Pp_k+1) J'
        for i in range(m):
            acc = xf[k, i]
            for j in range(m):
                acc += J[i, j] * d[j]
            xs_prev[i] = acc
        for i in range(m):
            for j in range(m):
                T1[i, j] = Ps[i, j] - Pp[k + 1, i, j]
        _ab(J, T1, T2)
        _abt(T2, J, T1)
        for i in range(m):
            for j in range(m):
                Ps_prev[i, j] = Pf[k, i, j] + T1[i, j]
        xs[:] = xs_prev
        Ps[:, :] = Ps_prev
    # q' = q + q^2 / (N m) sum(...),  r' = mean((z - h xs)^2 + h Ps h')
    return q + q * q * sq / (N * m), sr / N, ll, xs


def em_fit(z: np.ndarray, model: str, tol: float = EM_TOL, max_iter: int = EM_MAX_ITER) -> tuple:
    """Shumway-Stoffer EM for ``(q, r)`` with ``Q = q Q1`` (F, H known).

    The first ``d`` samples give the prior of ``x_(d-1)`` (exact diffuse start at the
    starting values); its covariance stays fixed and its mean is re-estimated (the
    smoothed ``x_(d-1)``), so that each iteration cannot lower the likelihood of
    ``z[d:]``. Start: ``r`` from the variance of the d-th difference, ``h = 1e-2``.
    Stops when Aitken's extrapolation of the log-likelihood says less than ``tol``
    is left to gain.

    Returns
    -------
    q, r, iterations, converged, min_increase
        ``min_increase`` is the smallest change of the log-likelihood between
        iterations (>= 0 when the likelihood rose at every iteration).
    """
    F, h, Q1 = kinematic_model(model, 1.0 / RATE)
    d = F.shape[0]
    zc = z - z[0]
    r = float(np.var(np.diff(zc, d))) / math.comb(2 * d, d)
    q = 1e-2 * r * RATE ** MODELS[model][1]
    x0, P0, start = diffuse_start(zc, F, h, q * Q1, r)
    obs = np.ascontiguousarray(zc[start:])
    lls: list[float] = []
    converged = False
    while len(lls) < max_iter:
        q, r, ll, x0 = em_step(obs, F, h, Q1, q, r, x0, P0)
        lls.append(ll)
        if len(lls) >= 3:
            d1, d0 = lls[-1] - lls[-2], lls[-2] - lls[-3]
            c = d1 / d0 if d0 > 0 else 0.0
            # l_inf - l_k = (l_k - l_k-1) / (1 - c)   (Aitken)
            if 0.0 <= c < 1.0 and d1 / (1.0 - c) < tol:
                converged = True
                break
    return q, r, len(lls), converged, float(np.min(np.diff(lls)))


def pykalman_iteration_time(z: np.ndarray, model: str, iters: int = 2) -> float:
    """Seconds per EM iteration of pykalman (full Q and R; it cannot hold Q = q Q1)."""
    from pykalman import KalmanFilter

    F, h, Q1 = kinematic_model(model, 1.0 / RATE)
    kf = KalmanFilter(transition_matrices=F, observation_matrices=h[None, :])
    t0 = time.perf_counter()
    kf.em(z, n_iter=iters, em_vars=["transition_covariance", "observation_covariance"])
    return (time.perf_counter() - t0) / iters


# ------------------------------------------------------------------ sections
def nile_section() -> list[str]:
    y = sm.datasets.nile.load_pandas().data["volume"].to_numpy(float)
    lines = [
        "### statsmodels' Nile data: the local-level model",
        "",
        '`fit_kalman(nile, model="rw")` (rate 1/year): sigma2_eps = r, sigma2_eta = q T. '
        "Durbin and Koopman: 15099 and 1469.1. Target: within 0.5 %.",
        "",
        "| method | sigma2_eps | error | sigma2_eta | error | within 0.5 % | time (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for method in ("mle", "als"):
        t0 = time.perf_counter()
        t = fit_kalman(y, model="rw", method=method)
        dt = time.perf_counter() - t0
        e1, e2 = t.r / 15099 - 1, t.q / 1469.1 - 1
        ok = abs(e1) <= 5e-3 and abs(e2) <= 5e-3
        lines.append(
            f"| {method} | {t.r:.1f} | {e1:+.3%} | {t.q:.2f} | {e2:+.3%} | **{ok}** | {dt:.2f} |"
        )
    return [*lines, ""]


def _cell(errs_r, errs_q, inband, times) -> str:
    return (
        f"{np.median(np.abs(errs_r)):.2%} | {np.median(np.abs(errs_q)):.2%} | "
        f"{np.mean(inband):.0%} | {np.median(times):.2f}"
    )


def _statsmodels_peer(z: np.ndarray, model: str) -> tuple[float, float, dict]:
    return (*statsmodels_fit(z, model), {})


def _em_peer(z: np.ndarray, model: str) -> tuple[float, float, dict]:
    q, r, iters, converged, min_inc = em_fit(z, model)
    return q, r, {"iterations": iters, "converged": converged, "min_increase": min_inc}


#: Peers of the joint table: label, function (z, model) -> (q, r, extra), argument giving runs.
PEERS = (
    ("statsmodels MLE", _statsmodels_peer, "peer_runs"),
    ("EM (ours, Shumway-Stoffer)", _em_peer, "em_runs"),
)


def _fit_cell(records, fit, model, q_true) -> dict:
    """Errors, NIS-in-band flags, times and extras of one method on the records."""
    out: dict = {"r": [], "q": [], "band": [], "time": [], "q_fit": [], "extra": []}
    for z in records:
        t0 = time.perf_counter()
        q, r, extra = fit(z, model)
        out["time"].append(time.perf_counter() - t0)
        out["r"].append(r / R_TRUE - 1)
        out["q"].append(q / q_true - 1)
        out["q_fit"].append(q)
        out["band"].append(evaluate_kalman(z, model, q, r, rate=RATE).nis_consistent)
        out["extra"].append(extra)
    return out


def _ours(method: str):
    def fit(z: np.ndarray, model: str) -> tuple[float, float, dict]:
        t = fit_kalman(z, model=model, rate=RATE, method=method)
        return t.q, t.r, {}

    return fit


def _em_notes(em: list[tuple[str, dict, list]]) -> list[str]:
    """Iterations, convergence, monotonicity, and EM's q against our MLE's on the same records."""
    lines = []
    for cell, res, q_mle in em:
        ex = res["extra"]
        its = [e["iterations"] for e in ex]
        gap = np.abs(np.array(res["q_fit"]) / np.array(q_mle[: len(ex)]) - 1)
        lines.append(
            f"- EM {cell}: iterations median {np.median(its):.0f} (range {min(its)}-{max(its)}); "
            f"converged in {sum(e['converged'] for e in ex)}/{len(ex)}; log-likelihood rose at "
            f"every iteration: {all(e['min_increase'] >= 0 for e in ex)} "
            f"(smallest rise {min(e['min_increase'] for e in ex):.2g}); "
            f"median |q_EM / q_mle - 1| on the same records {np.median(gap):.2%}."
        )
    return lines


def joint_section(  # long: one table
    runs: int, peer_runs: int, em_runs: int
) -> tuple[list[str], dict, list[str]]:
    lines = [
        f"### Joint q and r on simulated tracks (n = {N}, {RATE:g} Hz, r = {R_TRUE:g})",
        "",
        f"{runs} seeded runs per cell for ours; statsmodels' MLE and the EM fit on the "
        "first runs of each cell (the same records; 'mle, the peers' records' is ours on them). "
        "Errors are medians of |relative error|; 'NIS in band' is the share of runs whose "
        "mean NIS (filter run with the fitted q and r) lies in its 95 % chi-square band; "
        "time is the median per fit.",
        "",
        "| model | h = qT^k/r | method | runs | r error | q error | NIS in band | time (s) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    n_runs = {"peer_runs": peer_runs, "em_runs": em_runs}
    names = ["mle", "als"] + [p[0] for p in PEERS]
    summary: dict = {m: {"r": [], "q": [], "band": []} for m in names}
    em_cells: list = []
    for model, hs in H_VALUES.items():
        k = MODELS[model][1]
        for hv in hs:
            q_true = hv * R_TRUE * RATE**k
            rng = np.random.default_rng(1000 + int(-np.log10(hv)) + 10 * k)
            records = [track(model, N, q_true, R_TRUE, rng) for _ in range(runs)]
            methods = [(m, _ours(m), runs) for m in ("mle", "als")]
            methods += [(name, fn, n_runs[arg]) for name, fn, arg in PEERS]
            mle: dict = {}
            for name, fn, n in methods:
                if n <= 0:
                    continue
                if mle and n < runs and n not in mle:  # ours on the peers' records
                    mle[n] = _cell(*(mle["res"][key][:n] for key in ("r", "q", "band", "time")))
                    lines.append(f"| {model} | {hv:g} | mle, the peers' records | {n} | {mle[n]} |")
                res = _fit_cell(records[:n], fn, model, q_true)
                mle = {"res": res} if name == "mle" else mle
                for key in ("r", "q", "band"):
                    summary[name][key] += res[key]
                if name.startswith("EM"):
                    em_cells.append((f"{model} h={hv:g}", res, mle["res"]["q_fit"]))
                cell = _cell(res["r"], res["q"], res["band"], res["time"])
                lines.append(f"| {model} | {hv:g} | {name} | {n} | {cell} |")
            print(f"  joint {model} h={hv:g} done", file=sys.stderr, flush=True)
    return [*lines, ""], summary, _em_notes(em_cells)


def pykalman_section(iters: int) -> list[str]:
    """pykalman's EM: seconds per iteration on one record per model (it is too slow to run)."""
    try:
        import pykalman  # noqa: F401
    except ImportError:
        return [
            "### pykalman's EM",
            "",
            "Not measured: pykalman is not installed (`pip install pykalman`).",
            "",
        ]
    lines = [
        "### pykalman's EM: time per iteration (n = 20000)",
        "",
        f"`KalmanFilter.em(z, n_iter={iters}, em_vars=[transition_covariance, "
        "observation_covariance])` (full Q: pykalman cannot hold Q = q Q1), one record "
        "per model; our EM's iteration count on the same record for scale.",
        "",
        "| model | h | pykalman s / iteration | our EM: iterations | our EM: s / iteration |",
        "|---|---|---|---|---|",
    ]
    for model, hv in (("cv", 1e-3), ("ca", 1e-4)):
        q_true = hv * R_TRUE * RATE ** MODELS[model][1]
        z = track(model, N, q_true, R_TRUE, np.random.default_rng(77))
        t_pk = pykalman_iteration_time(z, model, iters)
        t0 = time.perf_counter()
        its = em_fit(z, model)[2]
        t_em = (time.perf_counter() - t0) / its
        lines.append(f"| {model} | {hv:g} | {t_pk:.2f} | {its} | {t_em:.4f} |")
    return [*lines, ""]


def coloured_section(runs: int) -> list[str]:  # long: one table
    cases = [
        ("white+ar1", {"phi": 0.5, "s2": 1.0, "r": 0.5}),
        ("white+ar1", {"phi": 0.9, "s2": 1.0, "r": 0.5}),
        ("white+ar1", {"phi": 0.99, "s2": 1.0, "r": 0.5}),
        ("white+rw", {"q": 0.01, "r": 1.0}),
        ("white", {"r": 1.0}),
    ]
    lines = [
        f"### Coloured noise: white + AR(1), white + random walk, white (n = {N})",
        "",
        f"{runs} seeded runs per case; `fit_coloured_noise(z)` with its default models "
        "(white, white+ar1, white+rw) and BIC. Errors are medians of |relative error| "
        "over the runs that chose the right model. Target: right model in >= 90 % of "
        "runs, parameters within 10 %.",
        "",
        "| truth | right model | r error | phi error | q error | within 10 % | time (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for i, (name, p) in enumerate(cases):
        rng = np.random.default_rng(500 + i)
        right, er, ephi, eq, times = [], [], [], [], []
        for _ in range(runs):
            z = rng.normal(0.0, np.sqrt(p["r"]), N)
            q_true = None
            if name == "white+ar1":
                q_true = p["s2"] * (1 - p["phi"] ** 2)
                drive = rng.normal(0, np.sqrt(q_true), N)
                z += scipy.signal.lfilter([1.0], [1.0, -p["phi"]], drive)
            elif name == "white+rw":
                q_true = p["q"]
                z += np.cumsum(rng.normal(0.0, np.sqrt(q_true), N))
            t0 = time.perf_counter()
            f = fit_coloured_noise(z)
            times.append(time.perf_counter() - t0)
            right.append(f.model == name)
            if f.model == name:
                er.append(f.r / p["r"] - 1)
                if name == "white+ar1":
                    ephi.append(f.phi[0] / p["phi"] - 1)
                if q_true is not None:
                    eq.append(f.q[0] / q_true - 1)
        med = {
            k: float(np.median(np.abs(v))) if v else None
            for k, v in (("r", er), ("phi", ephi), ("q", eq))
        }
        ok = all(v is None or v <= 0.10 for v in med.values())
        label = name + (f" phi={p['phi']}" if "phi" in p else "")
        cells = " | ".join("–" if med[k] is None else f"{med[k]:.2%}" for k in ("r", "phi", "q"))
        lines.append(
            f"| {label} | {np.mean(right):.0%} | {cells} | **{ok}** | {np.median(times):.2f} |"
        )
        print(f"  coloured {label} done", file=sys.stderr, flush=True)
    return [*lines, ""]


def speed_section() -> list[str]:
    rng = np.random.default_rng(7)
    lines = [
        "### Speed: fit_kalman on 1e5 samples (target < 2 s)",
        "",
        "After one warm-up call (the compiled kernel's first call loads it from numba's cache). "
        "Median of 3 calls.",
        "",
        "| model | method | time (s) | < 2 s |",
        "|---|---|---|---|",
    ]
    for model, hv in (("rw", 1e-2), ("cv", 1e-3), ("ca", 1e-4)):
        q = hv * R_TRUE * RATE ** MODELS[model][1]
        z = track(model, 100_000, q, R_TRUE, rng)
        for method in ("mle", "als"):
            fit_kalman(z[:1000], model=model, rate=RATE, method=method)
            ts = []
            for _ in range(3):
                t0 = time.perf_counter()
                fit_kalman(z, model=model, rate=RATE, method=method)
                ts.append(time.perf_counter() - t0)
            t = float(np.median(ts))
            lines.append(f"| {model} | {method} | {t:.2f} | **{t < 2}** |")
    return [*lines, ""]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--peer-runs", type=int, default=5)
    ap.add_argument("--em-runs", type=int, default=5)
    ap.add_argument("--pykalman-iters", type=int, default=2)
    ap.add_argument("--coloured-runs", type=int, default=20)
    ap.add_argument("--out", default=str(RESULTS / "kalman_tuning.md"))
    ap.add_argument("--skip", nargs="*", default=[], help="speed nile joint pykalman coloured")
    args = ap.parse_args()
    load = os.getloadavg()[0]
    t_start = time.perf_counter()
    lines = [
        "## Kalman tuning: Q and R together, coloured noise (issue 14)",
        "",
        f"Measured with `python benchmarks/kalman_tuning.py {' '.join(sys.argv[1:])}` on "
        f"{platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}; 1-minute load average "
        f"at start {load:.1f} (shared machine: timings vary with load).",
        "",
    ]
    if "speed" not in args.skip:
        lines += speed_section()
    if "nile" not in args.skip:
        lines += nile_section()
    if "joint" not in args.skip:
        joint, s, em_notes = joint_section(args.runs, args.peer_runs, args.em_runs)
        lines += joint
        for m in (m for m in s if s[m]["r"]):
            lines.append(
                f"- {m}, all cells: median r error {np.median(np.abs(s[m]['r'])):.2%} "
                f"(target <= 3 %), median q error {np.median(np.abs(s[m]['q'])):.2%} "
                f"(target <= 15 %), NIS in band {np.mean(s[m]['band']):.0%} (target >= 90 %)."
            )
        lines += ["", *em_notes, ""]
    if "pykalman" not in args.skip:
        lines += pykalman_section(args.pykalman_iters)
    if "coloured" not in args.skip:
        lines += coloured_section(args.coloured_runs)
    lines.append(f"Total wall time {time.perf_counter() - t_start:.0f} s.")
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(exist_ok=True)
    Path(args.out).write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()

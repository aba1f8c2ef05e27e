"""Kalman filter core: linear KF and EKF, batched over Monte Carlo runs.

One core serves every R-adaptation strategy (:mod:`noisevar.kalman.strategies`)
and the robust Huber update (spec B3): a strategy is a small object the core
asks for ``R`` (and optionally ``Q``) at each step, never a copy of the filter.

Conventions
-----------
* The filter always carries a leading **batch axis** ``B`` (independent Monte
  Carlo runs filtered in lock-step, so numpy's per-call overhead is paid once
  per step, not once per run per step). A single run is ``B = 1``:
  ``filt.x`` has shape ``(1, n)``. :func:`run_filter` drops the axis again
  when it was given a single record.
* ``x0, P0`` are the estimate **one step before the first measurement**; each
  step is ``predict()`` then ``update(z_k)`` (as in ``filterpy``'s loop).
* Model functions take the batched state and the step index:
  ``f(x, k) -> (B, n)``, ``F_jacobian(x, k) -> (B, n, n)`` or ``(n, n)``,
  ``h(x, k) -> (B, m)``, ``H_jacobian(x, k) -> (B, m, n)`` or ``(m, n)``.
  A linear model gives the matrices ``F`` and ``H`` instead.

The equations, at step ``k`` (``H``, ``F`` the Jacobians for an EKF)::

    x(k|k-1) = f(x(k-1|k-1))            P(k|k-1) = F P Fᵀ + Q_k
    d_k = z_k - h(x(k|k-1))             S_k = H P(k|k-1) Hᵀ + R_k
    K_k = P(k|k-1) Hᵀ S_k⁻¹             x(k|k) = x(k|k-1) + K_k d_k
    P(k|k) = (I - K H) P(k|k-1) (I - K H)ᵀ + K R_k Kᵀ      (Joseph form)
    r_k = z_k - h(x(k|k))               NIS_k = d_kᵀ S_k⁻¹ d_k

``P`` is symmetrised after every update. Components listed in
``angle_measurements`` have their innovation and residual wrapped to
``[-π, π)``.

Step-by-step use (for example a local filter of a distributed fusion, which
needs ``x_pred, P_pred, x, P`` of every step)::

    filt = KalmanFilter(model, strategy=VariationalBayesR())
    for k in range(n_steps):
        filt.predict()
        filt.update(z[k])          # or filt.skip_update() for a faulty sensor
        use(filt.x_pred[0], filt.P_pred[0], filt.x[0], filt.P[0])

Whole record: :func:`run_filter` returns a
:class:`~noisevar.kalman.result.FilterResult`.

Speed
-----
The per-step arithmetic (prediction, innovation, gain, Joseph update,
residual, angle wrapping) runs in compiled kernels
(:mod:`noisevar.kalman._kernels`, numba, cached on disk after the first
compilation) that loop over the batch axis: one call per step and stage
instead of a few dozen numpy calls on tiny arrays. The hooks are unchanged:
strategies are still Python objects called at every step (the built-in ones
call small kernels of their own), and a model's ``f``, ``F_jacobian``,
``h``, ``H_jacobian`` are still plain numpy functions (a model may add a
compiled ``transition``, as gps-circle does). :data:`USE_COMPILED` ``=
False`` selects the plain-numpy path below, which gives the same results to
rounding (tested to 1e-10); with the robust Huber update the numpy path is
always used.

On the numpy path every step costs a few dozen numpy calls whatever ``B``
is, so a batch of runs is much cheaper per run than separate calls. :func:`run_filter` lets
the filter write each step's ``x, P, d, r, S`` (and ``x_pred, P_pred``)
straight into its records (no copies) and records ``R`` / ``Q`` only when
they differ from the model's. For batches of :data:`_CLOSED_FORM_FROM` runs
or more, ``S⁻¹`` of a small innovation covariance (``m <= 4``) comes from
closed-form cofactors over the whole batch (:func:`_inv_closed_form`)
instead of a LAPACK call per run; results agree with the LAPACK path to
rounding. NIS and NEES are computed after the loop over the stored arrays
(:func:`quadratic_form_inverse`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from noisevar.errors import NoisevarError
from noisevar.kalman.result import FilterResult, wrap_angle

try:  # compiled per-step kernels (numba); the numpy path below is the reference
    from noisevar.kalman import _kernels
except ImportError:  # pragma: no cover - numba not installed
    _kernels = None

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.strategies import RStrategy

ModelFunction = Callable[[NDArray, int], NDArray]
TransitionFunction = Callable[[NDArray, int, NDArray, NDArray], None]

#: Filters constructed while this is true run their per-step arithmetic in the
#: compiled kernels of :mod:`noisevar.kalman._kernels` (when numba is
#: installed); false selects the plain-numpy reference path (same results to
#: rounding, several times slower for small batches).
USE_COMPILED: bool = _kernels is not None

_SYM_TOL = 1e-9

try:  # the gufunc behind np.linalg.inv, without its per-call checks (~5 us saved per step)
    from numpy.linalg import _umath_linalg

    def _inv(a: NDArray) -> NDArray:
        return _umath_linalg.inv(a, signature="d->d")

except (ImportError, AttributeError):  # pragma: no cover - other numpy builds

    def _inv(a: NDArray) -> NDArray:
        try:
            return np.linalg.inv(a)
        except np.linalg.LinAlgError:
            return np.full(np.broadcast_shapes(np.shape(a)), np.nan)


_matvec = getattr(np, "matvec", None)  # numpy >= 2.2: stacked matrix @ stacked vector

if _matvec is None:  # pragma: no cover - older numpy

    def _matvec(a: NDArray, v: NDArray) -> NDArray:
        return np.matmul(a, v[..., None])[..., 0]


#: Batch size from which a transposed operand of a batched matmul is copied
#: to contiguous memory first (strided operands make numpy's stacked matmul
#: ~2x slower for large batches, while the copy costs a call for small ones).
_CONTIGUOUS_FROM = 16

_TWO_PI = 2.0 * np.pi

#: Batch size from which the inverse of a small (m <= 4) innovation
#: covariance is computed in closed form over the whole batch
#: (:func:`_inv_closed_form`): LAPACK costs ~0.4 us per 4 x 4 member (its
#: per-call overhead), the closed form ~15 element-wise numpy calls in all.
_CLOSED_FORM_FROM = 32


def _adjugate_tables_4() -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Index tables of the 4 x 4 adjugate through the twelve 2 x 2 minors of rows (0, 1), (2, 3).

    With ``s_p`` the minors of rows 0, 1 and ``c_p`` those of rows 2, 3 over
    the column pairs ``(0,1), (0,2), (0,3), (1,2), (1,3), (2,3)``, every
    cofactor is a signed sum of three products ``a_rc * minor`` and
    ``det = s0 c5 - s1 c4 + s2 c3 + s3 c2 - s4 c1 + s5 c0`` (the Laplace
    expansion along the first two rows). Minors are indexed in
    ``[s, c, -s, -c]`` (24 rows) so that the signs are gathered, not multiplied.
    """
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    minors = np.array(
        [
            [4 * r0 + i for r0, _ in ((0, 1), (2, 3)) for i, _ in pairs],
            [4 * r1 + j for _, r1 in ((0, 1), (2, 3)) for _, j in pairs],
            [4 * r0 + j for r0, _ in ((0, 1), (2, 3)) for _, j in pairs],
            [4 * r1 + i for _, r1 in ((0, 1), (2, 3)) for i, _ in pairs],
        ]
    )  # minor p = g[0] g[1] - g[2] g[3]

    def a(r: int, c: int) -> int:
        return 4 * r + c

    s = list(range(6))
    c = list(range(6, 12))
    neg = 12  # offset of the negated minors
    # inv[i, j] * det = sum of (sign, entry, minor), row-major over (i, j)
    terms = [
        [(+1, a(1, 1), c[5]), (-1, a(1, 2), c[4]), (+1, a(1, 3), c[3])],
        [(-1, a(0, 1), c[5]), (+1, a(0, 2), c[4]), (-1, a(0, 3), c[3])],
        [(+1, a(3, 1), s[5]), (-1, a(3, 2), s[4]), (+1, a(3, 3), s[3])],
        [(-1, a(2, 1), s[5]), (+1, a(2, 2), s[4]), (-1, a(2, 3), s[3])],
        [(-1, a(1, 0), c[5]), (+1, a(1, 2), c[2]), (-1, a(1, 3), c[1])],
        [(+1, a(0, 0), c[5]), (-1, a(0, 2), c[2]), (+1, a(0, 3), c[1])],
        [(-1, a(3, 0), s[5]), (+1, a(3, 2), s[2]), (-1, a(3, 3), s[1])],
        [(+1, a(2, 0), s[5]), (-1, a(2, 2), s[2]), (+1, a(2, 3), s[1])],
        [(+1, a(1, 0), c[4]), (-1, a(1, 1), c[2]), (+1, a(1, 3), c[0])],
        [(-1, a(0, 0), c[4]), (+1, a(0, 1), c[2]), (-1, a(0, 3), c[0])],
        [(+1, a(3, 0), s[4]), (-1, a(3, 1), s[2]), (+1, a(3, 3), s[0])],
        [(-1, a(2, 0), s[4]), (+1, a(2, 1), s[2]), (-1, a(2, 3), s[0])],
        [(-1, a(1, 0), c[3]), (+1, a(1, 1), c[1]), (-1, a(1, 2), c[0])],
        [(+1, a(0, 0), c[3]), (-1, a(0, 1), c[1]), (+1, a(0, 2), c[0])],
        [(-1, a(3, 0), s[3]), (+1, a(3, 1), s[1]), (-1, a(3, 2), s[0])],
        [(+1, a(2, 0), s[3]), (-1, a(2, 1), s[1]), (+1, a(2, 2), s[0])],
    ]
    entries = np.array([[e for _, e, _ in row] for row in terms]).T  # (3, 16)
    signed = np.array([[mi + (neg if sg < 0 else 0) for sg, _, mi in row] for row in terms]).T
    det = np.array([c[5], neg + c[4], c[3], c[2], neg + c[1], c[0]])  # times s0..s5
    return minors, entries, signed, det


_ADJ4_MINORS, _ADJ4_ENTRIES, _ADJ4_SIGNED, _ADJ4_DET = _adjugate_tables_4()
# 3 x 3: inv[i, j] * det = a[j+1, i+1] a[j+2, i+2] - a[j+1, i+2] a[j+2, i+1] (indices mod 3)
_ADJ3 = np.array(
    [
        [3 * ((j + 1) % 3) + (i + 1) % 3 for i in range(3) for j in range(3)],
        [3 * ((j + 2) % 3) + (i + 2) % 3 for i in range(3) for j in range(3)],
        [3 * ((j + 1) % 3) + (i + 2) % 3 for i in range(3) for j in range(3)],
        [3 * ((j + 2) % 3) + (i + 1) % 3 for i in range(3) for j in range(3)],
    ]
)
_SIGN2 = np.array([1.0, -1.0, -1.0, 1.0])[:, None]


def _inv_closed_form(a: NDArray) -> NDArray:
    """Inverses of a stack of small matrices by the adjugate, ``m <= 4``.

    The entries are laid out one row per matrix entry (batch axis last), so
    each step of the cofactor formulas is one element-wise numpy call over
    the whole batch (about fifteen calls for ``m = 4``) instead of a LAPACK
    call per member. No pivoting is needed (there is no elimination); the
    accuracy is that of LAPACK's LU to a few ulp for the well-conditioned
    innovation covariances of a filter. A singular member gives inf/NaN,
    like :func:`_inv`, which the divergence checks report.

    Parameters
    ----------
    a : ndarray, shape (B, m, m)

    Returns
    -------
    ndarray, shape (B, m, m)
    """
    B, m, _ = a.shape
    if m == 1:
        return 1.0 / a
    e = a.reshape(B, m * m).T  # (m*m, B): row m*i + j is entry (i, j) of every member
    if m == 2:
        det = e[0] * e[3] - e[1] * e[2]
        adj = e[[3, 1, 2, 0]] * _SIGN2
    elif m == 3:
        g = e[_ADJ3]  # (4, 9, B)
        adj = g[0] * g[1]
        adj -= g[2] * g[3]
        det = np.add.reduce(e[:3] * adj[[0, 3, 6]], axis=0)  # first row x its cofactors
    else:
        g = e[_ADJ4_MINORS]  # (4, 12, B)
        minors = g[0] * g[1]
        minors -= g[2] * g[3]
        signed = np.concatenate([minors, -minors])
        det = np.add.reduce(minors[:6] * signed[_ADJ4_DET], axis=0)
        terms = e[_ADJ4_ENTRIES] * signed[_ADJ4_SIGNED]  # (3, 16, B)
        adj = terms[0] + terms[1]
        adj += terms[2]
    adj /= det
    return np.ascontiguousarray(adj.T).reshape(B, m, m)


def _index_or_slice(idx: tuple[int, ...]) -> slice | list[int] | None:
    """A basic slice for consecutive indices (views are cheaper than fancy indexing)."""
    if not idx:
        return None
    idx = tuple(sorted(idx))
    if idx == tuple(range(idx[0], idx[-1] + 1)):
        return slice(idx[0], idx[-1] + 1)
    return list(idx)


def _wrap_in_place(a: NDArray, cols: slice | list[int]) -> None:
    """Wrap columns ``cols`` of ``a`` (shape (B, m)) to ``[-π, π)`` in place."""
    if isinstance(cols, slice):
        if a.shape[0] == 1 and cols.stop - cols.start == 1:
            # one angle of one run: scalar arithmetic is ~5x cheaper than three
            # ufunc calls, and Python's float % is the same floored fmod as np.mod
            row = a[0]
            j = cols.start
            row[j] = (float(row[j]) + np.pi) % _TWO_PI - np.pi
            return
        # on a contiguous temporary: in-place ufuncs on the strided column
        # cost about twice as much
        t = a[:, cols] + np.pi
        np.mod(t, _TWO_PI, out=t)
        t -= np.pi
        a[:, cols] = t
    else:
        a[:, cols] = wrap_angle(a[:, cols])


# --------------------------------------------------------------------------- validation
def _as_matrix(a: ArrayLike, name: str, shape: tuple[int, int] | None = None) -> NDArray:
    try:
        arr = np.array(a, dtype=float)
    except (TypeError, ValueError):
        raise NoisevarError(f"{name} must be a numeric matrix, got {type(a).__name__}") from None
    if arr.ndim == 0 or arr.ndim == 1 and name in ("Q", "R", "P0"):
        # a scalar or a vector of variances: accept as a diagonal
        arr = np.diag(np.atleast_1d(arr))
    if arr.ndim != 2:
        raise NoisevarError(f"{name} must be a 2-D matrix, got shape {arr.shape}")
    if shape is not None and arr.shape != shape:
        raise NoisevarError(
            f"{name} has shape {arr.shape} but the model needs {shape}: "
            "check the state and measurement dimensions"
        )
    if not np.all(np.isfinite(arr)):
        raise NoisevarError(f"{name} contains NaN or infinite values")
    return arr


def check_covariance(a: ArrayLike, name: str, definite: bool = True) -> NDArray:
    """Validate a covariance matrix: square, finite, symmetric, positive (semi)definite.

    Parameters
    ----------
    a : array_like, shape (k, k), (k,) or scalar
        The matrix; a vector or scalar is taken as a diagonal.
    name : str
        Name used in the error message (``"R"``, ``"Q"``, ...).
    definite : bool
        Require positive definite (True) or only positive semidefinite.

    Returns
    -------
    ndarray, shape (k, k)
        The matrix, exactly symmetric.

    Raises
    ------
    NoisevarError
        With a message saying which property fails.
    """
    arr = _as_matrix(a, name)
    if arr.shape[0] != arr.shape[1]:
        raise NoisevarError(f"{name} must be square, got shape {arr.shape}")
    scale = max(float(np.max(np.abs(arr))), 1e-300)
    if np.max(np.abs(arr - arr.T)) > _SYM_TOL * scale:
        raise NoisevarError(
            f"{name} is not symmetric (max |{name} - {name}ᵀ| = "
            f"{np.max(np.abs(arr - arr.T)):.3g}): a covariance matrix must equal its transpose"
        )
    arr = 0.5 * (arr + arr.T)
    eig_min = float(np.linalg.eigvalsh(arr)[0])
    if definite and eig_min <= 0:
        raise NoisevarError(
            f"{name} is not positive definite (smallest eigenvalue {eig_min:.3g}): "
            "give every component a positive variance"
        )
    if not definite and eig_min < -_SYM_TOL * scale:
        raise NoisevarError(
            f"{name} is not positive semidefinite (smallest eigenvalue {eig_min:.3g}): "
            "variances cannot be negative"
        )
    return arr


# --------------------------------------------------------------------------- model
@dataclass(frozen=True)
class StateSpaceModel:
    """A discrete-time state-space model, linear or extended (EKF).

    Give either matrices (``F``, ``H``) or functions with Jacobians
    (``f`` + ``F_jacobian``, ``h`` + ``H_jacobian``); the two halves may be
    mixed (linear transition, nonlinear measurement). Everything is checked
    once, at construction, so a bad model fails with a clear
    :class:`~noisevar.errors.NoisevarError` instead of a numpy traceback.

    Parameters
    ----------
    Q : array_like, shape (n, n)
        Process-noise covariance (symmetric, positive semidefinite). A vector
        is read as a diagonal.
    R : array_like, shape (m, m)
        Nominal measurement-noise covariance (symmetric, positive definite);
        the strategies start from it.
    x0 : array_like, shape (n,)
        State estimate one step before the first measurement.
    P0 : array_like, shape (n, n)
        Its covariance (positive definite).
    F : array_like, shape (n, n), optional
        Transition matrix of a linear model.
    H : array_like, shape (m, n), optional
        Measurement matrix of a linear model.
    f, F_jacobian : callable, optional
        ``f(x, k) -> (B, n)`` and its Jacobian ``(B, n, n)`` (or ``(n, n)``),
        with ``x`` of shape ``(B, n)`` and ``k`` the step index.
    h, H_jacobian : callable, optional
        ``h(x, k) -> (B, m)`` and its Jacobian ``(B, m, n)`` (or ``(m, n)``).
    dt : float
        Sample period (only used for the time axis of results).
    angle_states, angle_measurements : tuple of int
        Components that are angles in radians: their errors, innovations and
        residuals are wrapped to ``[-π, π)``.
    state_names, measurement_names : tuple of str, optional
        Labels for tables and figures.
    name : str
        A label for the model.
    transition : callable, optional
        A fused, in-place form of ``f`` and ``F_jacobian`` for speed:
        ``transition(x, k, x_out, F_out)`` writes ``f(x, k)`` into ``x_out``
        (shape ``(B, n)``) and ``F_jacobian(x, k)`` into ``F_out``
        (``(B, n, n)``), for example a compiled kernel. The compiled filter
        path uses it instead of ``f`` and ``F_jacobian`` (which are still
        required, and checked to agree with it on ``x0``).
    """

    Q: NDArray
    R: NDArray
    x0: NDArray
    P0: NDArray
    F: NDArray | None = None
    H: NDArray | None = None
    f: ModelFunction | None = None
    F_jacobian: ModelFunction | None = None
    h: ModelFunction | None = None
    H_jacobian: ModelFunction | None = None
    dt: float = 1.0
    angle_states: tuple[int, ...] = ()
    angle_measurements: tuple[int, ...] = ()
    state_names: tuple[str, ...] = ()
    measurement_names: tuple[str, ...] = ()
    name: str = ""
    transition: TransitionFunction | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        x0 = np.array(self.x0, dtype=float)
        if x0.ndim != 1 or x0.size == 0:
            raise NoisevarError(f"x0 must be a non-empty 1-D state vector, got shape {x0.shape}")
        if not np.all(np.isfinite(x0)):
            raise NoisevarError("x0 contains NaN or infinite values")
        n = x0.size
        Q = check_covariance(self.Q, "Q", definite=False)
        R = check_covariance(self.R, "R", definite=True)
        P0 = check_covariance(self.P0, "P0", definite=True)
        m = R.shape[0]
        if Q.shape != (n, n):
            raise NoisevarError(f"Q has shape {Q.shape} but the state has {n} components")
        if P0.shape != (n, n):
            raise NoisevarError(f"P0 has shape {P0.shape} but the state has {n} components")
        set_(self, "x0", x0)
        set_(self, "Q", Q)
        set_(self, "R", R)
        set_(self, "P0", P0)

        if self.f is None:
            if self.F is None:
                raise NoisevarError("give either a transition matrix F or a function f")
            set_(self, "F", _as_matrix(self.F, "F", (n, n)))
        else:
            if not callable(self.f) or not callable(self.F_jacobian):
                raise NoisevarError("an extended model needs callables f and F_jacobian")
            if self.F is not None:
                raise NoisevarError("give either F or f, not both")
        if self.transition is not None and (self.f is None or not callable(self.transition)):
            raise NoisevarError("transition must be a callable, given together with f")
        if self.h is None:
            if self.H is None:
                raise NoisevarError("give either a measurement matrix H or a function h")
            set_(self, "H", _as_matrix(self.H, "H", (m, n)))
        else:
            if not callable(self.h) or not callable(self.H_jacobian):
                raise NoisevarError("an extended model needs callables h and H_jacobian")
            if self.H is not None:
                raise NoisevarError("give either H or h, not both")
        for name, idx, size in (
            ("angle_states", self.angle_states, n),
            ("angle_measurements", self.angle_measurements, m),
        ):
            idx = tuple(int(i) for i in idx)
            if any(i < 0 or i >= size for i in idx):
                raise NoisevarError(f"{name} {idx} out of range for dimension {size}")
            set_(self, name, idx)
        set_(self, "dt", float(self.dt))
        if not (np.isfinite(self.dt) and self.dt > 0):
            raise NoisevarError(f"dt must be a positive number, got {self.dt}")
        set_(self, "state_names", tuple(self.state_names) or tuple(f"x{i}" for i in range(n)))
        set_(
            self,
            "measurement_names",
            tuple(self.measurement_names) or tuple(f"z{i}" for i in range(m)),
        )
        if len(self.state_names) != n or len(self.measurement_names) != m:
            raise NoisevarError("state_names / measurement_names do not match the dimensions")
        self._check_functions(n, m)

    def _check_functions(self, n: int, m: int) -> None:
        xb = self.x0[None, :]
        checks = []
        if self.f is not None:
            checks += [("f", self.f, (1, n)), ("F_jacobian", self.F_jacobian, (1, n, n))]
        if self.h is not None:
            checks += [("h", self.h, (1, m)), ("H_jacobian", self.H_jacobian, (1, m, n))]
        for name, fun, shape in checks:
            try:
                out = np.asarray(fun(xb.copy(), 0), dtype=float)
            except Exception as exc:  # noqa: BLE001 - report the user's function failure
                raise NoisevarError(
                    f"model function {name} failed on x0 with a (1, {n}) batch: {exc!r}; "
                    f"it must accept x of shape (B, {n}) and the step index k"
                ) from exc
            ok = out.shape == shape or (len(shape) == 3 and out.shape == shape[1:])
            if not ok:
                raise NoisevarError(
                    f"model function {name} returned shape {out.shape} for a (1, {n}) batch, "
                    f"expected {shape}"
                )
        if self.transition is not None:
            x_out, F_out = np.empty((1, n)), np.empty((1, n, n))
            try:
                self.transition(xb.copy(), 0, x_out, F_out)
            except Exception as exc:  # noqa: BLE001 - report the user's function failure
                raise NoisevarError(
                    f"model function transition failed on x0 with a (1, {n}) batch: {exc!r}"
                ) from exc
            f0 = np.asarray(self.f(xb.copy(), 0), dtype=float)
            F0 = np.broadcast_to(np.asarray(self.F_jacobian(xb.copy(), 0), dtype=float), (1, n, n))
            scale = 1.0 + np.max(np.abs(f0)) + np.max(np.abs(F0))
            if not (
                np.allclose(x_out, f0, rtol=1e-9, atol=1e-12 * scale)
                and np.allclose(F_out, F0, rtol=1e-9, atol=1e-12 * scale)
            ):
                raise NoisevarError("transition disagrees with f / F_jacobian on x0")

    @property
    def n_states(self) -> int:
        """State dimension ``n``."""
        return int(self.x0.size)

    @property
    def n_measurements(self) -> int:
        """Measurement dimension ``m``."""
        return int(self.R.shape[0])

    @property
    def measured_states(self) -> tuple[int, ...] | None:
        """State indices a linear ``H`` picks out, when ``H`` is a selection matrix.

        ``H`` with a single 1 in each row (distinct columns) and zeros
        elsewhere measures states directly; the filter then indexes instead
        of multiplying (much faster for batched runs). ``None`` otherwise.
        """
        H = self.H
        if self.h is not None or H is None:
            return None
        if not np.all((H == 0) | (H == 1)) or not np.all(H.sum(axis=1) == 1):
            return None
        idx = tuple(int(i) for i in np.argmax(H, axis=1))
        return idx if len(set(idx)) == len(idx) else None

    @property
    def is_linear(self) -> bool:
        """True when both the transition and the measurement are matrices."""
        return self.f is None and self.h is None


# --------------------------------------------------------------------------- robust update
@dataclass(frozen=True)
class HuberUpdate:
    """Huber M-estimation measurement update (spec B3), usable with any strategy.

    The update is written as a regression: the prediction and the
    (linearised) measurement are stacked and whitened by
    ``blockdiag(P(k|k-1), R)^(-1/2)`` (Cholesky factors) to give
    ``y = M x + τ``; then, iteratively reweighted least squares::

        ψ_i = 1 if |τ_i| <= κ else κ / |τ_i|        (Huber weight)
        x̂ = (Mᵀ Ψ M)⁻¹ Mᵀ Ψ y,   P = (Mᵀ Ψ M)⁻¹

    With ``κ = inf`` every ``ψ_i = 1`` and the result is the Kalman update
    (in information form). For an EKF the measurement is linearised at the
    prediction: ``z - h(x(k|k-1)) + H x(k|k-1) ≈ H x + v``.

    The core still computes ``S`` and ``K`` of the plain update (for NIS and
    for strategies that use the gain); only ``x(k|k)`` and ``P(k|k)`` come
    from the robust regression.

    Parameters
    ----------
    kappa : float
        Huber threshold on whitened residuals (1.345: 95 % efficiency at the
        Gaussian; the paper's value).
    iterations : int
        Maximum IRLS iterations (the paper uses 10).
    tol : float
        Stop early when no state component moves by more than ``tol`` times
        its standard deviation.
    """

    kappa: float = 1.345
    iterations: int = 10
    tol: float = 1e-10

    def __post_init__(self) -> None:
        if not (self.kappa > 0):
            raise NoisevarError(f"kappa must be positive (or inf), got {self.kappa}")
        if int(self.iterations) < 1:
            raise NoisevarError(f"iterations must be at least 1, got {self.iterations}")


# --------------------------------------------------------------------------- divergence
@dataclass(frozen=True)
class DivergenceCheck:
    """How a run is judged to have diverged (reported, never hidden).

    A run is flagged when

    * its state or covariance becomes NaN/infinite, or the innovation
      covariance is singular;
    * a diagonal element of ``P`` exceeds ``covariance_limit`` (default:
      ``1e6`` times the largest diagonal element of ``P0`` and of ``R``) —
      an exploding covariance;
    * the mean NIS over a window of ``window`` steps exceeds
      ``nis_factor · m``: the innovations are far larger than the filter
      believes (chi-square mean is ``m``);
    * with truth, the mean NEES over a window exceeds ``nis_factor · n``.

    Parameters
    ----------
    covariance_limit : float, optional
        Absolute limit on any diagonal element of ``P``.
    nis_factor : float
        How far above its chi-square mean a windowed NIS / NEES may go.
    window : int
        Window length for the NIS / NEES test.
    check_every : int
        How often (in steps) :func:`run_filter` checks finiteness and size
        of ``P`` while running.
    """

    covariance_limit: float | None = None
    nis_factor: float = 10.0
    window: int = 100
    check_every: int = 50


# --------------------------------------------------------------------------- the filter
@dataclass
class KalmanFilter:
    """A linear / extended Kalman filter over a batch of runs, step by step.

    Parameters
    ----------
    model : StateSpaceModel
        The model.
    strategy : RStrategy, optional
        R-adaptation strategy (default: fixed ``model.R``).
    robust : HuberUpdate, optional
        Use the Huber M-estimation update instead of the plain one.
    batch_size : int
        Number of runs ``B`` filtered in lock-step.
    x0 : array_like, shape (n,) or (B, n), optional
        Initial state per run (default ``model.x0`` for every run), for
        example each run's first measurement.

    Attributes
    ----------
    k : int
        Index of the current step (``-1`` before the first ``predict``).
    x, P : ndarray, shapes (B, n), (B, n, n)
        Latest estimate ``x̂(k|k)`` and covariance (after ``update``).
    x_pred, P_pred : ndarray
        Prediction ``x̂(k|k-1)``, ``P(k|k-1)`` of the current step.
    z, z_pred, innovation, residual : ndarray, shape (B, m)
        Measurement, predicted measurement ``h(x̂(k|k-1))``, innovation
        ``d = z - z_pred`` and residual ``r = z - h(x̂(k|k))``.
    F_used, H_used : ndarray
        Transition / measurement Jacobians of the current step.
    Q, R : ndarray
        Covariances used at the current step (broadcastable to ``(B, n, n)``
        and ``(B, m, m)``).
    S, S_inv, K : ndarray
        Innovation covariance, its inverse, and the Kalman gain.
    PHt, HPHt : ndarray
        ``P(k|k-1) Hᵀ`` and ``H P(k|k-1) Hᵀ`` of the current step (what
        innovation-based strategies need before the update).
    failed : ndarray of bool, shape (B,)
        Runs whose ``P(k|k-1)`` or ``R`` lost positive definiteness in the
        Huber update (reported as diverged by :func:`run_filter`).

    Notes
    -----
    All these arrays are the filter's own: treat them as read-only (when
    ``H`` is the identity, ``PHt`` and ``HPHt`` *are* ``P_pred``). Strategies
    return new arrays instead of modifying them. On the compiled path
    ``S_inv``, ``K`` and ``F_used`` live in buffers the filter reuses two
    steps later (and the intermediate iterations of an iterative strategy
    write scratch memory): copy them to keep them; ``x``, ``P``,
    ``x_pred``, ``P_pred``, ``innovation``, ``residual`` and ``S`` are new
    memory at every step.
    """

    model: StateSpaceModel
    strategy: RStrategy | None = None
    robust: HuberUpdate | None = None
    batch_size: int = 1
    x0: ArrayLike | None = None
    k: int = field(init=False, default=-1)

    def __post_init__(self) -> None:
        from noisevar.kalman.strategies import FixedR

        if not isinstance(self.model, StateSpaceModel):
            raise NoisevarError("model must be a noisevar.kalman.StateSpaceModel")
        if int(self.batch_size) < 1:
            raise NoisevarError(f"batch_size must be at least 1, got {self.batch_size}")
        if self.robust is not None and not isinstance(self.robust, HuberUpdate):
            raise NoisevarError("robust must be a HuberUpdate (or None)")
        self.batch_size = int(self.batch_size)
        if self.strategy is None:
            self.strategy = FixedR()
        m, n, B = self.model.n_measurements, self.model.n_states, self.batch_size
        self.n, self.m = n, m
        self._eye = np.eye(n)
        if self.x0 is None:
            self.x = np.repeat(self.model.x0[None, :], B, axis=0)
        else:
            x0 = np.asarray(self.x0, dtype=float)
            if x0.shape not in ((n,), (B, n)) or not np.all(np.isfinite(x0)):
                raise NoisevarError(
                    f"x0 must be finite with shape ({n},) or ({B}, {n}), got {x0.shape}"
                )
            self.x = np.array(np.broadcast_to(x0, (B, n)))
        self.P = np.repeat(self.model.P0[None, :, :], B, axis=0)
        self.x_pred = self.x.copy()
        self.P_pred = self.P.copy()
        self.z = np.zeros((B, m))
        self.z_pred = np.zeros((B, m))
        self.innovation = np.zeros((B, m))
        self.residual = np.zeros((B, m))
        self.F_used: NDArray = self.model.F if self.model.F is not None else self._eye
        self.H_used: NDArray = self.model.H if self.model.H is not None else np.zeros((m, n))
        self.Q: NDArray = self.model.Q
        self.R: NDArray = self.model.R
        self.S = np.repeat(self.model.R[None], B, axis=0)
        self.S_inv = np.linalg.inv(self.S)
        self.K = np.zeros((B, n, m))
        self.failed = np.zeros(B, dtype=bool)  # runs whose S became singular / non-finite
        self._angle_z = _index_or_slice(self.model.angle_measurements)
        sel = self.model.measured_states
        self._identity_H = sel is not None and sel == tuple(range(n)) and m == n
        self._sel = None if sel is None else list(sel)
        # constant operands of the step, precomputed once
        self._copy_t = B >= _CONTIGUOUS_FROM
        self._closed_form = B >= _CLOSED_FORM_FROM and m <= 4
        self._Ft = None if self.model.F is None else np.ascontiguousarray(self.model.F.T)
        self._Ht = None if self.model.H is None else np.ascontiguousarray(self.model.H.T)
        # operands of the compiled kernels (see _kernels: shared operands are 3-D)
        self._fast = bool(USE_COMPILED and _kernels is not None and self.robust is None)
        if self._identity_H:
            self._kind = 0
        elif self._sel is not None:
            self._kind = 1
        elif self.model.h is None:
            self._kind = 2
        else:
            self._kind = 3
        if _kernels is not None:
            self._cfg = _kernels.config(self._kind, self.model.angle_measurements, self._sel)
            self._work = np.empty(_kernels.work_shape(n, m))
        self._nt = (None,) * n  # the dimensions, as compile-time constants of the kernels
        self._shape_x, self._shape_z = (B, n), (B, m)
        self._shape_P, self._shape_R, self._shape_K = (B, n, n), (B, m, m), (B, n, m)
        self._scratch_buf: tuple[NDArray, ...] | None = None
        self._F_buf = (np.empty((B, n, n)), np.empty((B, n, n)))
        self._SK = (self._sk_buffer(), self._sk_buffer())
        self._mt = (None,) * m
        self._H3 = (
            np.ascontiguousarray(self.model.H[None])
            if self.model.H is not None
            else np.zeros((1, m, n))
        )
        self._F3 = None if self.model.F is None else np.ascontiguousarray(self.model.F[None])
        self._Q3 = self.model.Q[None]
        self._R3 = self.model.R[None]
        self.strategy.start(self)

    # ------------------------------------------------------------------ steps
    def predict(self) -> None:
        """Time update: ``x(k|k-1) = f(x)``, ``P(k|k-1) = F P Fᵀ + Q_k``."""
        self._predict(None, None)

    def _predict(self, x_out: NDArray | None, P_out: NDArray | None) -> None:
        """:meth:`predict`, writing ``x(k|k-1)``, ``P(k|k-1)`` into ``x_out``, ``P_out``.

        :func:`run_filter` passes the slices of its records for this step, so
        nothing is copied afterwards; ``None`` allocates fresh arrays. Either
        way every step's arrays are new memory (a caller may keep them).
        """
        if self._fast:
            self._predict_compiled(x_out, P_out)
            return
        k = self.k + 1
        self.k = k
        model = self.model
        Q = self.strategy.process_covariance(self)
        if Q is None:
            Q = model.Q
        self.Q = Q
        x = self.x
        if model.f is None:
            F = model.F
            Ft = self._Ft
            x_pred = np.matmul(x, Ft, out=x_out)
        else:
            F = model.F_jacobian(x, k)
            x_pred = model.f(x, k)
            if x_out is not None:
                x_out[...] = x_pred
                x_pred = x_out
            Ft = F.mT
            if self._copy_t and F.ndim == 3:
                Ft = Ft.copy()  # a strided operand slows large batched matmuls down
        P_pred = np.matmul(np.matmul(F, self.P), Ft, out=P_out)
        P_pred += Q
        self.x_pred = x_pred
        self.P_pred = P_pred
        self.F_used = F

    def _stack3(self, a: ArrayLike, rows: int, cols: int, name: str) -> NDArray:
        """``a`` as a float array of shape (1 or B, rows, cols) for the kernels."""
        if type(a) is not np.ndarray or a.dtype != np.float64:
            a = np.asarray(a, dtype=float)
        if a.ndim == 2 and a.shape == (rows, cols):
            return a[None]
        if a.ndim == 3 and a.shape[1:] == (rows, cols) and a.shape[0] in (1, self.batch_size):
            return a
        try:
            return np.broadcast_to(a, (self.batch_size, rows, cols))
        except ValueError:
            raise NoisevarError(
                f"{name} has shape {a.shape}; expected ({rows}, {cols}) or "
                f"({self.batch_size}, {rows}, {cols})"
            ) from None

    def _predict_compiled(self, x_out: NDArray | None, P_out: NDArray | None) -> None:
        """:meth:`_predict` in the compiled kernels (same arithmetic, same hook)."""
        k = self.k + 1
        self.k = k
        model = self.model
        Q = self.strategy.process_covariance(self)
        if Q is None:
            Q = model.Q
        self.Q = Q
        x = self.x
        if Q is model.Q:
            Q3 = self._Q3
        elif type(Q) is np.ndarray and Q.shape == self._shape_P:
            Q3 = Q
        else:
            Q3 = self._stack3(Q, self.n, self.n, "Q")
        if x_out is None:
            x_out = np.empty(self._shape_x)
        if P_out is None:
            P_out = np.empty(self._shape_P)
        if model.f is None:
            F = model.F
            _kernels.predict_linear(self._F3, x, self.P, Q3, x_out, P_out, self._nt)
        else:
            if model.transition is not None:
                # two alternating buffers: F_used stays valid for a step after
                F = F3 = self._F_buf[k & 1]
                model.transition(x, k, x_out, F)
            else:
                F = model.F_jacobian(x, k)
                x_out[...] = model.f(x, k)
                F3 = self._stack3(F, self.n, self.n, "F_jacobian")
            _kernels.predict_cov(F3, self.P, Q3, P_out, self._nt)
        self.x_pred = x_out
        self.P_pred = P_out
        self.F_used = F

    def _sk_buffer(self) -> tuple[NDArray, NDArray, NDArray]:
        """One ``(B, m + n, m)`` array holding ``S⁻¹`` and ``K``, and those two views."""
        SK = np.empty((self.batch_size, self.m + self.n, self.m))
        return SK, SK[:, : self.m], SK[:, self.m :]

    def _scratch(self) -> tuple[NDArray, ...]:
        """``x, P, r, S, SK, S_inv, K`` buffers of the intermediate update iterations."""
        buf = self._scratch_buf
        if buf is None:
            B, n, m = self.batch_size, self.n, self.m
            buf = self._scratch_buf = (
                np.empty((B, n)),
                np.empty((B, n, n)),
                np.empty((B, m)),
                np.empty((B, m, m)),
                *self._sk_buffer(),
            )
        return buf

    def _update_compiled(self, z: NDArray, out: tuple[NDArray, ...] | None = None) -> None:
        """:meth:`_update` in the compiled kernels (same arithmetic, same hooks)."""
        model = self.model
        kind = self._kind
        self.z = z
        x_pred, P_pred = self.x_pred, self.P_pred
        cfg = self._cfg
        if out is None:
            d = np.empty(self._shape_z)
        else:
            x_o, P_o, d, r_o, S_o = out
        if kind == 0:
            H, H3 = model.H, self._H3
            z_pred = x_pred
            PHt = HPHt = P_pred
            _kernels.innovation(z, x_pred, cfg, d)
        else:
            if kind == 3:
                H = model.H_jacobian(x_pred, self.k)
                H3 = self._stack3(H, self.m, self.n, "H_jacobian")
                z_pred = np.asarray(model.h(x_pred, self.k), dtype=float)
            else:
                H, H3 = model.H, self._H3
                z_pred = np.empty(self._shape_z)
            PHt = np.empty(self._shape_K)
            HPHt = np.empty(self._shape_R)
            _kernels.measure(z, x_pred, P_pred, H3, cfg, z_pred, d, PHt, HPHt, self._nt, self._mt)
        self.PHt = PHt
        self.HPHt = HPHt
        self.z_pred = z_pred
        self.H_used = H
        self.innovation = d
        strategy = self.strategy
        R = strategy.measurement_covariance(self)
        n_it = strategy.iterations
        shape_R = self._shape_R
        gain = _kernels.gain_update
        work, nt, mt = self._work, self._nt, self._mt
        for it in range(n_it):
            if it:
                R = strategy.refine(self)
            self.R = R
            if R is model.R:
                R3 = self._R3
            elif type(R) is np.ndarray and R.shape == shape_R:
                R3 = R
            else:
                R3 = self._stack3(R, self.m, self.m, "R")
            if it + 1 < n_it:  # feeds only the strategy's next R: scratch memory
                x, P, r, S, SK, S_inv, K = self._scratch()
                final = False
            else:
                final = True
                if out is None:
                    x = np.empty(self._shape_x)
                    P = np.empty(self._shape_P)
                    r = np.empty(self._shape_z)
                    S = np.empty(shape_R)
                else:
                    x, P, r, S = x_o, P_o, r_o, S_o
                # S⁻¹ and K: two alternating buffers (valid until the update after next)
                SK, S_inv, K = self._SK[self.k & 1]
            gain(x_pred, P_pred, R3, d, H3, cfg, z, final, S, SK, x, P, r, work, nt, mt)
            self.S = S
            self.S_inv = S_inv
            self.K = K
            self.x = x
            self.P = P
            if kind == 3:
                self._residual(r)
            else:
                self.residual = r
        strategy.observe(self)

    def update(self, z: ArrayLike) -> None:
        """Measurement update with ``z`` of shape ``(B, m)`` (or ``(m,)`` when ``B = 1``).

        Raises
        ------
        NoisevarError
            When ``z`` has the wrong shape or contains NaN.
        """
        z = np.asarray(z, dtype=float)
        if z.ndim == 1:
            z = z[None, :]
        if z.shape != (self.batch_size, self.m):
            raise NoisevarError(
                f"measurement has shape {z.shape}, expected ({self.batch_size}, {self.m})"
            )
        if not np.all(np.isfinite(z)):
            raise NoisevarError(
                f"measurement at step {self.k} contains NaN or infinite values: "
                "drop or interpolate missing samples (or call skip_update())"
            )
        self._update(z)

    def skip_update(self) -> None:
        """No measurement this step: ``x(k|k) = x(k|k-1)``, ``P(k|k) = P(k|k-1)``.

        Used for a missing sample, or by a fusion centre for a local filter
        flagged faulty (it then adds nothing to the fused information).
        """
        self.x = self.x_pred
        self.P = self.P_pred
        self.innovation = np.full_like(self.innovation, np.nan)
        self.residual = np.full_like(self.residual, np.nan)

    def _update(self, z: NDArray, out: tuple[NDArray, ...] | None = None) -> None:
        """Measurement update with a validated ``z`` of shape ``(B, m)``.

        ``out`` is ``None`` (fresh arrays) or the record slices
        ``(x, P, innovation, residual, S)`` of this step, which the final
        update iteration writes into (see :meth:`_predict`).
        """
        if self._fast:
            self._update_compiled(z, out)
            return
        model = self.model
        self.z = z
        x_pred = self.x_pred
        if self._sel is not None:  # H selects states: index instead of multiplying
            H = model.H
            if self._identity_H:
                z_pred = x_pred
                self.PHt = self.HPHt = self.P_pred
            else:
                sel = self._sel
                z_pred = x_pred[:, sel]
                self.PHt = self.P_pred[:, :, sel]
                self.HPHt = self.PHt[:, sel, :]
        else:
            if model.h is None:
                H = model.H
                z_pred = np.matmul(x_pred, self._Ht)
                Ht = self._Ht
            else:
                H = model.H_jacobian(x_pred, self.k)
                z_pred = model.h(x_pred, self.k)
                Ht = H.mT
            self.PHt = self.P_pred @ Ht
            self.HPHt = H @ self.PHt
        self.z_pred = z_pred
        self.H_used = H
        d = np.subtract(z, z_pred, out=None if out is None else out[2])
        if self._angle_z is not None:
            _wrap_in_place(d, self._angle_z)
        self.innovation = d
        strategy = self.strategy
        R = strategy.measurement_covariance(self)
        n_it = strategy.iterations
        if n_it == 1:
            self.R = R
            self._gain_and_update(H, d, R, True, out)
        else:
            last = n_it - 1
            for it in range(n_it):
                if it:
                    R = strategy.refine(self)
                self.R = R
                self._gain_and_update(H, d, R, it == last, out if it == last else None)
        strategy.observe(self)

    def _gain_and_update(
        self,
        H: NDArray,
        d: NDArray,
        R: NDArray,
        final: bool = True,
        out: tuple[NDArray, ...] | None = None,
    ) -> None:
        """Kalman (or Huber) update with ``R``.

        Intermediate iterations of an iterative strategy (``final=False``)
        only feed the strategy's next ``R``: they use the short form
        ``P = P(k|k-1) - K H P(k|k-1)``; the final one uses the Joseph form.
        ``out`` as in :meth:`_update`.
        """
        x_out = P_out = S_out = r_out = None
        if out is not None:
            x_out, P_out, _, r_out, S_out = out
        S = np.add(self.HPHt, R, out=S_out)
        # NaN/inf (no exception) for a singular member: caught by the checks
        S_inv = _inv_closed_form(S) if self._closed_form else _inv(S)
        self.S = S
        self.S_inv = S_inv
        K = np.matmul(self.PHt, S_inv)
        self.K = K
        if self.robust is None:
            self.x = np.add(self.x_pred, _matvec(K, d), out=x_out)
            if self._identity_H:
                A = np.subtract(self._eye, K)
            elif self._sel is not None:
                A = np.repeat(self._eye[None], self.batch_size, axis=0)
                A[:, :, self._sel] -= K
            else:
                A = self._eye - K @ H
            P_pred = self.P_pred
            if not final:
                self.P = np.matmul(A, P_pred)
                self._residual(None)
                return
            # Joseph form, then exactly symmetric
            At, Kt = A.mT, K.mT
            if self._copy_t:
                At, Kt = At.copy(), Kt.copy()
            P = np.matmul(np.matmul(A, P_pred), At)
            P += np.matmul(np.matmul(K, R), Kt)
            P_sym = np.add(P, P.mT, out=P_out)
            P_sym *= 0.5
            self.P = P_sym
        else:
            self._huber_update(H, d, R)
            if x_out is not None:
                x_out[...] = self.x
                P_out[...] = self.P
                self.x, self.P = x_out, P_out
        self._residual(r_out)

    def _residual(self, out: NDArray | None = None) -> None:
        """``r = z - h(x(k|k))`` (angles wrapped), into ``out`` when given."""
        if self._identity_H:
            r = np.subtract(self.z, self.x, out=out)
        elif self._sel is not None:
            r = np.subtract(self.z, self.x[:, self._sel], out=out)
        elif self.model.h is None:
            r = np.subtract(self.z, np.matmul(self.x, self._Ht), out=out)
        else:
            r = np.subtract(self.z, self.model.h(self.x, self.k), out=out)
        if self._angle_z is not None:
            _wrap_in_place(r, self._angle_z)
        self.residual = r

    def _huber_update(self, H: NDArray, d: NDArray, R: NDArray) -> None:
        rob = self.robust
        B, n, m = self.batch_size, self.n, self.m
        H = np.broadcast_to(H, (B, m, n))
        R = np.broadcast_to(R, (B, m, m))
        Lp_inv = _inv(self._cholesky(self.P_pred))
        Lr_inv = _inv(self._cholesky(R))
        # regression y = M x + tau, whitened
        M = np.concatenate([Lp_inv, Lr_inv @ H], axis=1)  # (B, n+m, n)
        z_lin = d + (H @ self.x_pred[:, :, None])[:, :, 0]  # linearised measurement
        y = np.concatenate(
            [(Lp_inv @ self.x_pred[:, :, None])[:, :, 0], (Lr_inv @ z_lin[:, :, None])[:, :, 0]],
            axis=1,
        )
        x = self.x_pred
        psi = np.ones((B, n + m))
        for _ in range(int(rob.iterations)):
            if np.isfinite(rob.kappa):
                tau = np.abs(y - (M @ x[:, :, None])[:, :, 0])
                psi = np.minimum(1.0, rob.kappa / np.maximum(tau, 1e-300))
            MtW = M.mT * psi[:, None, :]
            A = MtW @ M
            P = _inv(A)
            x_new = (P @ (MtW @ y[:, :, None]))[:, :, 0]
            step = np.max(np.abs(x_new - x) / np.sqrt(np.diagonal(P, axis1=1, axis2=2)))
            x = x_new
            if not np.isfinite(rob.kappa) or step < rob.tol:
                break
        self.huber_weights = psi
        self.x = x
        self.P = 0.5 * (P + P.mT)

    def project(self, P: NDArray) -> NDArray:
        """``H P Hᵀ`` with the current measurement Jacobian (e.g. ``H P(k|k) Hᵀ``).

        Parameters
        ----------
        P : ndarray, shape (B, n, n)

        Returns
        -------
        ndarray, shape (B, m, m)
        """
        if self._identity_H:
            return P
        if self._sel is not None:
            return P[:, self._sel][:, :, self._sel]
        H = self.H_used
        return H @ P @ H.mT

    def _cholesky(self, a: NDArray) -> NDArray:
        """Batched Cholesky factor; members that are not positive definite are flagged."""
        try:
            return np.linalg.cholesky(a)
        except np.linalg.LinAlgError:
            a = np.array(a)
            finite = np.all(np.isfinite(a), axis=(1, 2))
            bad = ~finite
            bad[finite] = np.linalg.eigvalsh(a[finite])[:, 0] <= 0
            self.failed |= bad
            a[bad] = np.eye(a.shape[-1])
            L = np.linalg.cholesky(a)
            L[bad] = np.nan
            return L

    # ------------------------------------------------------------------ health
    def reset_runs(self, runs: NDArray) -> None:
        """Put diverged runs back to ``x0, P0`` so the batch's linear algebra stays finite.

        Parameters
        ----------
        runs : ndarray of bool, shape (B,)
            Runs to reset (their results are reported as diverged by the caller).
        """
        self.x = np.array(self.x)
        self.P = np.array(self.P)
        self.x[runs] = (
            self.model.x0
            if self.x0 is None
            else np.broadcast_to(np.asarray(self.x0, dtype=float), self.x.shape)[runs]
        )
        self.P[runs] = self.model.P0
        self.strategy.reset_runs(self, runs)


# --------------------------------------------------------------------------- whole record
def _as_record(z: ArrayLike, m: int, name: str) -> tuple[NDArray, bool]:
    try:
        arr = np.asarray(z, dtype=float)
    except (TypeError, ValueError):
        raise NoisevarError(f"{name} must be numeric") from None
    if arr.ndim == 1 and m == 1:
        arr = arr[:, None]
    if arr.ndim == 2:
        if arr.shape[1] != m:
            raise NoisevarError(
                f"{name} has shape {arr.shape}; expected (n_steps, {m}) for this model"
            )
        return arr[None], False
    if arr.ndim == 3:
        if arr.shape[2] != m:
            raise NoisevarError(
                f"{name} has shape {arr.shape}; expected (runs, n_steps, {m}) for this model"
            )
        return arr, True
    raise NoisevarError(
        f"{name} must have shape (n_steps, {m}) or (runs, n_steps, {m}), got {arr.shape}"
    )


def run_filter(
    model: StateSpaceModel,
    z: ArrayLike,
    strategy: RStrategy | None = None,
    robust: HuberUpdate | None = None,
    truth: ArrayLike | None = None,
    store_predicted: bool = True,
    divergence: DivergenceCheck | None = None,
    x0: ArrayLike | None = None,
) -> FilterResult:
    """Run the filter over a whole record (or a batch of Monte Carlo records).

    Parameters
    ----------
    model : StateSpaceModel
        The model.
    z : array_like, shape (N, m) or (B, N, m)
        Measurements; a leading axis runs ``B`` independent records in
        lock-step (much faster than ``B`` separate calls).
    strategy : RStrategy, optional
        R-adaptation strategy (default :class:`~noisevar.kalman.strategies.FixedR`).
        A strategy object keeps state: use a fresh one per call.
    robust : HuberUpdate, optional
        Huber M-estimation update (spec B3).
    truth : array_like, shape (N, n) or (B, N, n), optional
        True states; enables NEES, RMSE and the NEES divergence test.
    store_predicted : bool
        Also record ``x_pred`` and ``P_pred`` at every step (``P`` is always
        recorded; ``P_pred`` costs another ``B N n²`` floats).
    divergence : DivergenceCheck, optional
        Divergence criteria (default :class:`DivergenceCheck`).
    x0 : array_like, shape (n,) or (B, n), optional
        Initial state per run (default ``model.x0``).

    Returns
    -------
    FilterResult
        Per-step records, NIS/NEES, and an honest divergence report.

    Raises
    ------
    NoisevarError
        For bad shapes, NaN measurements, or an invalid strategy.
    """
    from noisevar.kalman.strategies import FixedR, RStrategy

    if not isinstance(model, StateSpaceModel):
        raise NoisevarError("model must be a noisevar.kalman.StateSpaceModel")
    n, m = model.n_states, model.n_measurements
    zb, batched = _as_record(z, m, "z")
    if not np.all(np.isfinite(zb)):
        bad = np.argwhere(~np.isfinite(zb))[0]
        raise NoisevarError(
            f"measurements contain NaN or infinite values (first at step {bad[1]}, "
            f"channel {bad[2]}): drop or interpolate missing samples first"
        )
    B, N, _ = zb.shape
    if N == 0:
        raise NoisevarError("the measurement record is empty")
    truth_b = None
    if truth is not None:
        truth_b, _ = _as_record(truth, n, "truth")
        if truth_b.shape[1] != N or truth_b.shape[0] not in (1, B):
            raise NoisevarError(
                f"truth has shape {np.shape(truth)} but the measurements are {zb.shape[:2]} "
                "(runs, steps)"
            )
        truth_b = np.broadcast_to(truth_b, (B, N, n))
    if strategy is None:
        strategy = FixedR()
    if not isinstance(strategy, RStrategy):
        raise NoisevarError(
            f"strategy must be an RStrategy instance, got {type(strategy).__name__}"
        )
    div = divergence or DivergenceCheck()
    cov_limit = div.covariance_limit
    if cov_limit is None:
        cov_limit = 1e6 * max(float(np.max(np.diag(model.P0))), float(np.max(np.diag(model.R))))

    strategy.prepare(zb, model)
    filt = KalmanFilter(model, strategy=strategy, robust=robust, batch_size=B, x0=x0)

    x_rec = np.empty((N, B, n))
    d_rec = np.empty((N, B, m))
    r_rec = np.empty((N, B, m))
    S_rec = np.empty((N, B, m, m))
    R_rec: NDArray | None = None  # allocated when the strategy's R is not model.R
    Q_rec: NDArray | None = None  # allocated when a strategy first changes Q
    P_rec = np.empty((N, B, n, n))
    xp_rec = np.empty((N, B, n)) if store_predicted else None
    Pp_rec = np.empty((N, B, n, n)) if store_predicted else None
    z_steps = np.ascontiguousarray(np.moveaxis(zb, 1, 0))

    div_step = np.full(B, -1)
    reasons = [""] * B
    check_every = max(1, int(div.check_every))
    next_check = min(check_every, N)
    last_check = 0
    if filt._fast:
        predict, update = filt._predict_compiled, filt._update_compiled
    else:
        predict, update = filt._predict, filt._update
    # predictions that are not recorded go to two alternating buffers (a
    # hook may still read the previous step's)
    pred_buf = [(np.empty((B, n)), np.empty((B, n, n))) for _ in range(2)]
    model_R, model_Q = model.R, model.Q
    # a singular S or a NaN state gives NaN (no exception, no warning) and is
    # reported by the divergence checks below
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for k in range(N):
            # the filter writes this step's results straight into the records
            # (no copies); a hook that replaced an array is copied in below
            if store_predicted:
                xp_k, Pp_k = xp_rec[k], Pp_rec[k]
                predict(xp_k, Pp_k)
            else:
                predict(*pred_buf[k & 1])
            x_k, P_k, d_k, r_k, S_k = x_rec[k], P_rec[k], d_rec[k], r_rec[k], S_rec[k]
            update(z_steps[k], (x_k, P_k, d_k, r_k, S_k))
            if filt.x is not x_k:
                x_k[...] = filt.x
            if filt.P is not P_k:
                P_k[...] = filt.P
            if filt.innovation is not d_k:
                d_k[...] = filt.innovation
            if filt.residual is not r_k:
                r_k[...] = filt.residual
            if filt.S is not S_k:
                S_k[...] = filt.S
            if store_predicted:
                if filt.x_pred is not xp_k:
                    xp_k[...] = filt.x_pred
                if filt.P_pred is not Pp_k:
                    Pp_k[...] = filt.P_pred
            R = filt.R
            if R_rec is not None:
                R_rec[k] = R
            elif R is not model_R:
                R_rec = np.empty((N, B, m, m))
                R_rec[:k] = model_R
                R_rec[k] = R
            Q = filt.Q
            if Q_rec is not None:
                Q_rec[k] = Q
            elif Q is not model_Q:
                Q_rec = np.empty((N, B, n, n))
                Q_rec[:k] = model_Q
                Q_rec[k] = Q
            if k + 1 == next_check:
                _check_block(filt, x_rec, last_check, k + 1, cov_limit, div_step, reasons)
                last_check = k + 1
                next_check = min(k + 1 + check_every, N)

    # R / Q never changed: read-only views, no copies
    if R_rec is None:
        R_rec = np.broadcast_to(model_R, (N, B, m, m))
    if Q_rec is None:
        Q_rec = np.broadcast_to(model_Q, (N, B, n, n))

    def to_batch(a: NDArray | None) -> NDArray | None:
        return None if a is None else np.moveaxis(a, 0, 1)

    # NIS / NEES on the (step, run) layout the records were written in
    nis = quadratic_form_inverse(S_rec, d_rec).T
    nees = None
    if truth_b is not None:
        err = x_rec - np.moveaxis(truth_b, 1, 0)
        for i in model.angle_states:
            err[..., i] = wrap_angle(err[..., i])
        nees = quadratic_form_inverse(P_rec, err).T
    x_out = to_batch(x_rec)
    P_out = to_batch(P_rec)
    d_out = to_batch(d_rec)
    S_out = to_batch(S_rec)
    _check_consistency(nis, m, div, div_step, reasons, "NIS", "innovations")
    if nees is not None:
        _check_consistency(nees, n, div, div_step, reasons, "NEES", "estimation errors")

    outs = {
        "x": x_out,
        "x_pred": to_batch(xp_rec),
        "P": P_out,
        "P_pred": to_batch(Pp_rec),
        "innovation": d_out,
        "innovation_cov": S_out,
        "residual": to_batch(r_rec),
        "R": to_batch(R_rec),
        "Q": to_batch(Q_rec),
        "nis": nis,
        "nees": nees,
    }
    # NaN out what a run computed after it blew up (not after a NIS/NEES flag:
    # those values are finite, only inconsistent)
    blown = np.array(
        [
            s >= 0 and not r.startswith(("NIS", "NEES"))
            for s, r in zip(div_step, reasons, strict=True)
        ]
    )
    for b in np.flatnonzero(blown):
        for key in (
            "x",
            "x_pred",
            "P",
            "P_pred",
            "innovation",
            "innovation_cov",
            "residual",
            "nis",
            "nees",
        ):
            if outs[key] is not None:
                outs[key][b, div_step[b] :] = np.nan

    name = strategy.name + ("+huber" if robust is not None else "")
    diverged = div_step >= 0
    truth_out = None if truth_b is None else np.array(truth_b)
    if not batched:
        outs = {k: (None if v is None else v[0]) for k, v in outs.items()}
        truth_out = None if truth_out is None else truth_out[0]
    return FilterResult(
        strategy=name,
        time=np.arange(N) * model.dt,
        truth=truth_out,
        diverged=diverged if batched else bool(diverged[0]),
        divergence_step=div_step if batched else int(div_step[0]),
        divergence_reason=reasons if batched else reasons[0],
        batched=batched,
        state_names=model.state_names,
        measurement_names=model.measurement_names,
        angle_states=model.angle_states,
        **outs,
    )


#: Matrix entries per chunk in :func:`quadratic_form_inverse` (~2 MB of float64).
_QF_CHUNK = 1 << 18


def quadratic_form_inverse(A: NDArray, v: NDArray) -> NDArray:
    """``vᵀ A⁻¹ v`` for stacks of symmetric positive-definite ``A`` (NIS, NEES).

    A Cholesky factorisation and forward substitution written element-wise
    over the stack, so that a million 4 x 4 matrices take milliseconds
    instead of a LAPACK call each. Non-finite or non-positive-definite
    members give NaN.

    Parameters
    ----------
    A : ndarray, shape (..., k, k)
        Symmetric positive-definite matrices.
    v : ndarray, shape (..., k)
        Vectors.

    Returns
    -------
    ndarray, shape (...)
    """
    lead = A.shape[:-2]
    if len(lead) >= 1 and lead[0] > 1 and A.size > _QF_CHUNK:
        # chunks along the first axis that fit in cache: the entries are
        # gathered with a stride of k*k, so cold memory would cost k*k passes
        step = max(1, _QF_CHUNK // A[0].size)
        return np.concatenate(
            [
                _quadratic_form_inverse(A[i : i + step], v[i : i + step])
                for i in range(0, lead[0], step)
            ]
        )
    return _quadratic_form_inverse(A, v)


def _quadratic_form_inverse(A: NDArray, v: NDArray) -> NDArray:
    k = A.shape[-1]
    # each matrix entry as its own contiguous array: element-wise arithmetic
    # without reductions over tiny axes
    a = {(i, j): np.ascontiguousarray(A[..., i, j]) for i in range(k) for j in range(i + 1)}
    L: dict[tuple[int, int], NDArray] = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for j in range(k):
            d = a[j, j].copy()
            for p in range(j):
                d -= L[j, p] * L[j, p]
            L[j, j] = np.sqrt(np.where(d > 0, d, np.nan))
            for i in range(j + 1, k):
                e = a[i, j].copy()
                for p in range(j):
                    e -= L[i, p] * L[j, p]
                L[i, j] = e / L[j, j]
        total = np.zeros(A.shape[:-2])
        y: list[NDArray] = []
        for i in range(k):
            e = np.array(v[..., i], dtype=float)
            for p in range(i):
                e -= L[i, p] * y[p]
            y.append(e / L[i, i])
            total += y[i] * y[i]
    return total


def _check_block(
    filt: KalmanFilter,
    x_rec: NDArray,
    start: int,
    stop: int,
    cov_limit: float,
    div_step: NDArray,
    reasons: list[str],
) -> None:
    """Flag runs that went non-finite or whose covariance exploded in steps [start, stop)."""
    block = x_rec[start:stop]  # (k, B, n)
    nonfinite = ~np.all(np.isfinite(block), axis=2)  # (k, B)
    pdiag = np.diagonal(filt.P, axis1=1, axis2=2)
    bad_now = ~np.all(np.isfinite(pdiag), axis=1) | filt.failed
    big = np.any(np.abs(pdiag) > cov_limit, axis=1)
    newly = (nonfinite.any(axis=0) | bad_now | big) & (div_step < 0)
    if not np.any(newly):
        return
    for b in np.flatnonzero(newly):
        if nonfinite[:, b].any():
            div_step[b] = start + int(np.argmax(nonfinite[:, b]))
            reasons[b] = f"state became NaN/infinite at step {div_step[b]}"
        elif bad_now[b]:
            div_step[b] = stop - 1
            reasons[b] = f"covariance became NaN/infinite or S singular by step {div_step[b]}"
        else:
            div_step[b] = stop - 1
            reasons[b] = (
                f"covariance exploded: max diag(P) = {np.max(pdiag[b]):.3g} > "
                f"{cov_limit:.3g} by step {div_step[b]}"
            )
    filt.failed &= ~newly
    filt.reset_runs(newly)


def _check_consistency(
    stat: NDArray,
    dof: int,
    div: DivergenceCheck,
    div_step: NDArray,
    reasons: list[str],
    label: str,
    what: str,
) -> None:
    """Flag runs whose windowed mean NIS/NEES is far above its chi-square mean."""
    B, N = stat.shape
    w = max(1, min(int(div.window), N))
    finite = np.where(np.isfinite(stat), stat, 0.0)
    c = np.cumsum(np.concatenate([np.zeros((B, 1)), finite], axis=1), axis=1)
    mean_w = (c[:, w:] - c[:, :-w]) / w  # window ending at step j + w - 1
    limit = div.nis_factor * dof
    hi = stats.chi2.ppf(0.999, w * dof) / w
    for b in range(B):
        if div_step[b] >= 0:
            continue
        over = np.flatnonzero(mean_w[b] > limit)
        if over.size:
            j = int(over[0]) + w - 1
            div_step[b] = j
            reasons[b] = (
                f"{label} diverged: {what} far larger than the filter's covariance says "
                f"(mean {label} over {w} steps = {mean_w[b, over[0]]:.3g} at step {j}; "
                f"chi-square mean {dof}, 99.9 % bound {hi:.3g})"
            )


def nis_band(dof: int, window: int = 1, coverage: float = 0.95) -> tuple[float, float]:
    """Two-sided chi-square band for a mean of ``window`` NIS (or NEES) values.

    Parameters
    ----------
    dof : int
        Degrees of freedom of one value (``m`` for NIS, ``n`` for NEES).
    window : int
        Number of values averaged.
    coverage : float
        Probability inside the band.

    Returns
    -------
    (low, high) : tuple of float
    """
    a = (1.0 - coverage) / 2.0
    return (
        float(stats.chi2.ppf(a, dof * window) / window),
        float(stats.chi2.ppf(1.0 - a, dof * window) / window),
    )

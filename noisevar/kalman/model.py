"""The state-space model and its validation: :class:`StateSpaceModel`, :class:`HuberUpdate`.

Everything a filter is given is checked here, once, so a bad model fails with a
:class:`~noisevar.errors.NoisevarError` instead of a numpy traceback.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError

ModelFunction = Callable[[NDArray, int], NDArray]
TransitionFunction = Callable[[NDArray, int, NDArray, NDArray], None]

_SYM_TOL = 1e-9


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
        self._check_labels(n, m)
        self._check_functions(n, m)

    def _check_labels(self, n: int, m: int) -> None:
        """Angle indices, ``dt`` and names."""
        set_ = object.__setattr__
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
    """Huber M-estimation measurement update (docs/algorithms.md §G5), with any strategy.

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

"""Seeded test signals: a clean signal plus a known measurement-noise model.

Every generator returns a :class:`GeneratedSignal`; ``runs > 1`` stacks
independent noise realisations of the same clean signal (Monte Carlo), shape
``(runs, n)``. Families:

``fast-slow``
    The paper's Fig. 1 style: slow drifts and ramps with a fast oscillating
    burst and a sharp turn, white noise of standard deviation 5.
``gps-circle``
    One channel (east, north, speed, heading) of the vehicle of docs/algorithms.md §A9:
    radius 300 m, angular rate π/100 rad/s, sample period 0.5 s.
``random-jerk``
    Position of a target driven by white jerk (a random smooth trajectory).
``steps-ramps``
    Piecewise ramps with jumps (steps), where difference estimators suffer.
``noise-step``, ``noise-ramp``
    A smooth signal whose noise standard deviation steps (ramps) up 3-fold
    mid-record; the "true" variance is the record's mean variance.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.table import SAMPLE_PERIOD_RANGE
from noisevar.params import ParamSpec, by_name, validate_params


@dataclass
class GeneratedSignal:
    """A clean signal, its noise model and the measured samples.

    Attributes
    ----------
    name : str
        Family name.
    t : ndarray, shape (n,)
        Sample times (s).
    clean : ndarray, shape (n,)
        The noise-free signal.
    noise_std : ndarray, shape (n,)
        Noise standard deviation at each sample.
    measured : ndarray, shape (n,) or (runs, n)
        ``clean + noise``.
    seed : int
        Seed of the noise (and of any random clean signal).
    params : dict
        Parameters the generator was called with.
    """

    name: str
    t: NDArray
    clean: NDArray
    noise_std: NDArray
    measured: NDArray
    seed: int
    params: dict = field(default_factory=dict)

    @property
    def true_variance(self) -> float:
        """Mean noise variance over the record (the estimators' target)."""
        return float(np.mean(self.noise_std**2))

    @property
    def sample_period(self) -> float:
        """Sample period (s)."""
        return float(self.t[1] - self.t[0]) if self.t.size > 1 else 1.0


def _noise(rng: np.random.Generator, std: NDArray, runs: int) -> NDArray:
    shape = (runs, std.size) if runs > 1 else (std.size,)
    noise = rng.standard_normal(shape)
    noise *= std
    return noise


def _noisy(clean: NDArray, rng: np.random.Generator, std: NDArray, runs: int) -> NDArray:
    """``clean + noise`` (in the noise's array: the same numbers, one array fewer)."""
    noise = _noise(rng, std, runs)
    noise += clean
    return noise


def _finish(name, t, clean, std, seed, runs, params, rng) -> GeneratedSignal:
    std = np.broadcast_to(np.asarray(std, dtype=float), clean.shape).copy()
    return GeneratedSignal(
        name=name,
        t=t,
        clean=clean,
        noise_std=std,
        measured=_noisy(clean, rng, std, runs),
        seed=seed,
        params=params,
    )


#: The paper's Fig. 1 signal: the family a page or a Monte Carlo run starts from.
PAPER_SIGNAL = "fast-slow"


def fast_slow(
    n: int = 6000, noise_std: float = 5.0, seed: int = 0, runs: int = 1
) -> GeneratedSignal:
    """Paper Fig. 1 style: slow drifts and ramps, a fast burst, a sharp turn."""
    rng = np.random.default_rng(seed)
    k = np.arange(n, dtype=float)
    u = k / n
    # in place, operation for operation (the same numbers, fewer arrays):
    # clean = 400 sin(2π 0.6 u) + 150 u  +  60 sin(2π k / 60) exp(-((u - 0.45) / 0.04)²)
    #         + 300 max(0, u - 0.75) [u < 0.85] + 30 [u >= 0.85]
    clean = np.sin(2 * np.pi * 0.6 * u)
    clean *= 400.0
    clean += 150.0 * u
    burst = np.multiply(2 * np.pi, k, out=k)
    burst /= 60.0
    burst = np.sin(burst, out=burst)
    burst *= 60.0
    bump = np.subtract(u, 0.45)
    bump /= 0.04
    np.square(bump, out=bump)
    np.negative(bump, out=bump)
    burst *= np.exp(bump, out=bump)
    clean += burst
    turn = np.subtract(u, 0.75, out=bump)
    np.maximum(turn, 0.0, out=turn)
    turn *= 300.0
    turn *= u < 0.85
    turn += 30.0 * (u >= 0.85)
    clean += turn
    k = np.arange(n, dtype=float)
    params = {"n": n, "noise_std": noise_std, "seed": seed}
    return _finish(PAPER_SIGNAL, k, clean, noise_std, seed, runs, params, rng)


GPS_CHANNELS = {"east": 5.0, "north": 5.0, "speed": np.sqrt(2.0), "heading": 0.01}


def gps_circle(
    n: int = 6000,
    channel: str = "east",
    noise_std: float | None = None,
    seed: int = 0,
    runs: int = 1,
    radius: float = 300.0,
    omega: float = np.pi / 100.0,
    sample_period: float = 0.5,
) -> GeneratedSignal:
    """One channel of the vehicle on a circle (docs/algorithms.md §A9; radius 300 m, ω = π/100).

    Default noise standard deviations are the paper's: 5 m (east, north),
    √2 m/s (speed), 0.01 rad (heading).
    """
    if channel not in GPS_CHANNELS:
        raise NoisevarError(f"channel must be one of {sorted(GPS_CHANNELS)}, got {channel!r}")
    rng = np.random.default_rng(seed)
    t = np.arange(n) * sample_period
    theta = omega * t + np.pi / 2
    speed = radius * omega
    clean = {
        "east": radius * np.cos(theta - np.pi / 2),
        "north": radius * np.sin(theta - np.pi / 2),
        "speed": np.full(n, speed),
        "heading": theta,
    }[channel]
    std = GPS_CHANNELS[channel] if noise_std is None else noise_std
    params = {"n": n, "channel": channel, "noise_std": std, "seed": seed}
    return _finish("gps-circle", t, clean, std, seed, runs, params, rng)


def random_jerk(
    n: int = 6000, noise_std: float = 5.0, seed: int = 0, runs: int = 1, jerk_std: float = 5e-6
) -> GeneratedSignal:
    """Position of a target driven by white jerk (triple integration, per-sample units)."""
    rng = np.random.default_rng(seed)
    jerk = rng.standard_normal(n) * jerk_std
    clean = np.cumsum(np.cumsum(np.cumsum(jerk)))
    params = {"n": n, "noise_std": noise_std, "seed": seed, "jerk_std": jerk_std}
    return _finish(
        "random-jerk", np.arange(n, dtype=float), clean, noise_std, seed, runs, params, rng
    )


def steps_ramps(
    n: int = 6000, noise_std: float = 5.0, seed: int = 0, runs: int = 1, n_steps: int = 8
) -> GeneratedSignal:
    """Piecewise ramps with ``n_steps`` jumps of 10-40 noise standard deviations."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    edges = np.sort(rng.choice(np.arange(n // 20, n - n // 20), size=n_steps, replace=False))
    jumps = rng.choice([-1.0, 1.0], n_steps) * rng.uniform(10, 40, n_steps) * noise_std
    slopes = rng.uniform(-0.3, 0.3, n_steps + 1) * noise_std
    seg = np.searchsorted(edges, k, side="right")
    clean = np.cumsum(slopes[seg]) + np.concatenate([[0.0], np.cumsum(jumps)])[seg]
    params = {"n": n, "noise_std": noise_std, "seed": seed, "n_steps": n_steps}
    return _finish("steps-ramps", k.astype(float), clean, noise_std, seed, runs, params, rng)


def _smooth_base(n: int) -> NDArray:
    u = np.arange(n) / n
    return 200.0 * np.sin(2 * np.pi * 1.5 * u) + 80.0 * u**2


def noise_step(
    n: int = 6000, noise_std: float = 5.0, seed: int = 0, runs: int = 1, factor: float = 3.0
) -> GeneratedSignal:
    """Smooth signal whose noise std steps from ``noise_std`` to ``factor * noise_std`` mid-run."""
    rng = np.random.default_rng(seed)
    std = np.where(np.arange(n) < n // 2, noise_std, factor * noise_std)
    params = {"n": n, "noise_std": noise_std, "seed": seed, "factor": factor}
    return _finish(
        "noise-step", np.arange(n, dtype=float), _smooth_base(n), std, seed, runs, params, rng
    )


def noise_ramp(
    n: int = 6000, noise_std: float = 5.0, seed: int = 0, runs: int = 1, factor: float = 3.0
) -> GeneratedSignal:
    """Smooth signal whose noise std ramps from ``noise_std`` to ``factor * noise_std``."""
    rng = np.random.default_rng(seed)
    std = noise_std * np.linspace(1.0, factor, n)
    params = {"n": n, "noise_std": noise_std, "seed": seed, "factor": factor}
    return _finish(
        "noise-ramp", np.arange(n, dtype=float), _smooth_base(n), std, seed, runs, params, rng
    )


#: Most samples per realisation, and in all realisations together (memory grows with both).
MAX_N = 10_000_000
MAX_TOTAL = 50_000_000
#: Largest magnitude of any other numeric parameter (noise std, factors...).
MAX_MAGNITUDE = 1e100

#: The parameters every family takes (their defaults are each generator's own).
COMMON_PARAMS = (
    ParamSpec("n", "int", help="samples per realisation", lo=100, hi=MAX_N, lo_closed=True),
    ParamSpec(
        "noise_std",
        "float",
        help="noise standard deviation",
        lo=0.0,
        hi=MAX_MAGNITUDE,
        lo_closed=True,
    ),
    ParamSpec("seed", "int", help="seed of the noise", lo=0, hi=2**63 - 1, lo_closed=True),
    ParamSpec(
        "runs",
        "int",
        help="independent noise realisations",
        lo=1,
        hi=MAX_TOTAL // 100,
        lo_closed=True,
    ),
)


@dataclass(frozen=True)
class SignalSpec:
    """A signal family, declared once: its generator and the parameters it takes.

    Attributes
    ----------
    name : str
        Family name, as in ``generate(name)``.
    func : callable
        The generator; it returns a :class:`GeneratedSignal`.
    params : tuple of ParamSpec
        Every parameter of ``func``: :data:`COMMON_PARAMS` first, then the family's own
        (:attr:`extras`). Each default is the generator's own (its signature).
    """

    name: str
    func: Callable[..., GeneratedSignal]
    params: tuple[ParamSpec, ...]

    @property
    def param_specs(self) -> dict[str, ParamSpec]:
        """Name to spec of every parameter."""
        return by_name(self.params)

    @property
    def extras(self) -> tuple[ParamSpec, ...]:
        """The family's own parameters (beyond :data:`COMMON_PARAMS`)."""
        common = {p.name for p in COMMON_PARAMS}
        return tuple(p for p in self.params if p.name not in common)

    def validate(self, params: Mapping[str, Any]) -> dict[str, Any]:
        """Checked and converted parameters, or one :class:`NoisevarError` naming the bad one."""
        specs = self.param_specs
        out = validate_params(f"signal {self.name!r}", specs, params)
        n, runs = out.get("n") or specs["n"].default, out.get("runs") or specs["runs"].default
        if n * runs > MAX_TOTAL:
            raise NoisevarError(
                f"n x runs = {n * runs:,} samples is over the limit of {MAX_TOTAL:,}: "
                "use fewer runs or a shorter signal"
            )
        return out


def _family(name: str, func: Callable[..., GeneratedSignal], *extras: ParamSpec) -> SignalSpec:
    """The spec of a family, each parameter's default read from ``func``'s signature."""
    signature = inspect.signature(func).parameters
    specs = by_name((*COMMON_PARAMS, *extras))
    if set(signature) != set(specs):
        raise TypeError(f"{name}: parameters {sorted(signature)} but specs {sorted(specs)}")
    params = tuple(replace(p, default=signature[p.name].default) for p in specs.values())
    return SignalSpec(name, func, params)


def _non_negative(name: str, help: str) -> ParamSpec:
    return ParamSpec(name, "float", help=help, lo=0.0, hi=MAX_MAGNITUDE, lo_closed=True)


_FACTOR = _non_negative("factor", "noise std at the end over noise std at the start")

#: Every signal family, in the order :func:`signal_names` lists them.
SIGNALS: dict[str, SignalSpec] = {
    s.name: s
    for s in (
        _family(PAPER_SIGNAL, fast_slow),
        _family(
            "gps-circle",
            gps_circle,
            ParamSpec("channel", "str", help="measured channel", choices=tuple(GPS_CHANNELS)),
            _non_negative("radius", "radius of the circle (m)"),
            ParamSpec(
                "omega",
                "float",
                help="angular rate (rad/s)",
                lo=-MAX_MAGNITUDE,
                hi=MAX_MAGNITUDE,
                lo_closed=True,
            ),
            ParamSpec(
                "sample_period",
                "float",
                help="sample period (s)",
                lo=SAMPLE_PERIOD_RANGE[0],
                hi=SAMPLE_PERIOD_RANGE[1],
                lo_closed=True,
            ),
        ),
        _family("random-jerk", random_jerk, _non_negative("jerk_std", "jerk std per sample")),
        _family(
            "steps-ramps",
            steps_ramps,
            ParamSpec("n_steps", "int", help="number of jumps", lo=0, hi=MAX_N, lo_closed=True),
        ),
        _family("noise-step", noise_step, _FACTOR),
        _family("noise-ramp", noise_ramp, _FACTOR),
    )
}


def signal_names() -> list[str]:
    """Names of the signal families, for :func:`generate`."""
    return list(SIGNALS)


def signal_spec(name: str) -> SignalSpec:
    """The spec of the family ``name``, or a :class:`NoisevarError` listing the families."""
    if name not in SIGNALS:
        raise NoisevarError(f"unknown signal {name!r}; choose one of {signal_names()}")
    return SIGNALS[name]


def generate(name: str, **params: Any) -> GeneratedSignal:
    """Generate a signal of the family ``name`` (see module docstring).

    Parameters
    ----------
    name : str
        One of :func:`signal_names`.
    **params
        ``n``, ``noise_std``, ``seed``, ``runs`` and the family's own parameters
        (:attr:`SignalSpec.extras`), checked against their specs.

    Returns
    -------
    GeneratedSignal
    """
    spec = signal_spec(name)
    checked = spec.validate(params)
    try:
        return spec.func(**checked)
    except (TypeError, ValueError) as exc:
        raise NoisevarError(f"bad parameter for signal {name!r}: {exc}") from None

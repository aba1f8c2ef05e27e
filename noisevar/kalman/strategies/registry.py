"""The strategy registry: names, defaults and :func:`make_strategy`."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

from numpy.typing import ArrayLike

from noisevar.errors import NoisevarError
from noisevar.kalman.strategies.base import RStrategy
from noisevar.kalman.strategies.fixed import FixedR, OracleR
from noisevar.kalman.strategies.sage_husa import SageHusaR
from noisevar.kalman.strategies.somd import SomdOnlineR
from noisevar.kalman.strategies.vb import VariationalBayesR
from noisevar.kalman.strategies.windowed import InnovationR, ResidualQR, ResidualR
from noisevar.params import ParamSpec


@dataclass(frozen=True)
class StrategySpec:
    """A registered strategy: its class, its user-facing parameters and what it needs to know.

    Parameters
    ----------
    name : str
        Registry name (``"sage-husa"``).
    cls : type
        The :class:`RStrategy` subclass.
    help : str
        One line for lists, ``--help`` and the dashboard.
    params : tuple of ParamSpec
        Tunable parameters with their defaults.
    fixed : dict
        Constructor arguments that define this entry (``method="somd-paper"``).
    needs : tuple of str
        Context it must be given: ``"h_smooth"`` (SOMD) or ``"R_true"`` (oracle).
    featured : bool
        Among the strategies a comparison shows at first (the dashboard's default pick).
    """

    name: str
    cls: type[RStrategy]
    help: str
    params: tuple[ParamSpec, ...] = ()
    fixed: dict[str, Any] = field(default_factory=dict)
    needs: tuple[str, ...] = ()
    featured: bool = False

    def defaults(self) -> dict[str, Any]:
        """Default value of every tunable parameter."""
        return {p.name: p.default for p in self.params}


_WINDOW = ParamSpec("window", "int", 50, "moving window N (steps)", lo=1, lo_closed=True)
_SOMD_EVERY = ParamSpec("every", "int", 100, "re-estimate R every N steps", lo=1, lo_closed=True)
_SOMD_WINDOW = ParamSpec(
    "window",
    "int",
    None,
    "trailing window (steps; default: all samples so far)",
    lo=1,
    lo_closed=True,
)
_FORGETTING = ParamSpec("forgetting", "float", 0.98, "Sage-Husa forgetting factor b", lo=0, hi=1)
_RHO = ParamSpec("rho", "float", 0.99, "VB forgetting factor rho", lo=0, hi=1)

STRATEGIES: dict[str, StrategySpec] = {
    s.name: s
    for s in (
        StrategySpec("fixed", FixedR, "the model's nominal R"),
        StrategySpec(
            "oracle",
            OracleR,
            "the true R (simulations only): the lower bound",
            needs=("R_true",),
            featured=True,
        ),
        StrategySpec(
            "somd",
            SomdOnlineR,
            "SOMD on a trailing window per channel (bias-corrected)",
            (_SOMD_EVERY, _SOMD_WINDOW),
            needs=("h_smooth",),
            featured=True,
        ),
        StrategySpec(
            "somd-paper",
            SomdOnlineR,
            "SOMD on a trailing window, the paper's factor 1/2",
            (_SOMD_EVERY, _SOMD_WINDOW),
            {"method": "somd-paper"},
            ("h_smooth",),
        ),
        StrategySpec("rae", ResidualR, "residual-based moving-window R", (_WINDOW,), featured=True),
        StrategySpec("iae", InnovationR, "innovation-based moving-window R", (_WINDOW,)),
        StrategySpec("rae-q", ResidualQR, "residual-based R and Q = K C_d K'", (_WINDOW,)),
        StrategySpec(
            "sage-husa",
            SageHusaR,
            "Sage-Husa recursion with forgetting",
            (_FORGETTING,),
            featured=True,
        ),
        StrategySpec(
            "vb", VariationalBayesR, "variational Bayes, inverse-gamma R", (_RHO,), featured=True
        ),
    )
}

#: Former names, still accepted by :func:`make_strategy` with a DeprecationWarning.
ALIASES = {"somd-online": "somd", "somd-paper-online": "somd-paper"}


def strategy_spec(name: str) -> StrategySpec:
    """The registry entry of ``name`` (former names accepted with a DeprecationWarning)."""
    if name in ALIASES:
        warnings.warn(
            f"strategy {name!r} is now called {ALIASES[name]!r}", DeprecationWarning, stacklevel=3
        )
        name = ALIASES[name]
    if name not in STRATEGIES:
        raise NoisevarError(f"unknown strategy {name!r}; choose one of: {', '.join(STRATEGIES)}")
    return STRATEGIES[name]


def make_strategy(
    name: str,
    *,
    h_smooth: float | ArrayLike | None = None,
    R_true: ArrayLike | None = None,
    **params: Any,
) -> RStrategy:
    """Build a strategy by name with the registry's defaults.

    Parameters
    ----------
    name : str
        One of ``STRATEGIES``.
    h_smooth : float or sequence of float, optional
        Smoothing ``h`` per channel, for the SOMD strategies.
    R_true : array_like, optional
        The true ``R``, for ``oracle``.
    **params
        Tunable parameters of that strategy (see ``STRATEGIES[name].params``); ``None`` keeps
        the default.

    Returns
    -------
    RStrategy
        A fresh strategy object.
    """
    spec = strategy_spec(name)
    context = {"h_smooth": h_smooth, "R_true": R_true}
    for need in spec.needs:
        if context[need] is None:
            raise NoisevarError(f"strategy {spec.name!r} needs {need}")
    specs = {p.name: p for p in spec.params}
    given = {k: v for k, v in params.items() if v is not None}
    unknown = sorted(set(given) - set(specs))
    if unknown:
        raise NoisevarError(
            f"bad parameters for strategy {spec.name!r}: {', '.join(unknown)} "
            f"(its parameters: {', '.join(specs) or 'none'})"
        )
    kwargs = {**spec.defaults(), **{k: specs[k].validate(v) for k, v in given.items()}}
    kwargs.update(spec.fixed)
    kwargs.update({need: context[need] for need in spec.needs})
    return spec.cls(**kwargs)

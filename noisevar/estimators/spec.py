"""The declaration of an estimator: :class:`MethodSpec`, with what is special to the method.

Whatever one method needs beyond ``func`` (a second sensor, parameters for coloured
noise, a path for records read in chunks, a finishing step) is a field here, so that
:func:`noisevar.estimate`, :mod:`noisevar.estimators.pipeline`, the CLI and the
dashboard ask the spec, never the method's name.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from numpy.typing import NDArray

from noisevar.estimators.params import COMMON_PARAMS, PARAMS
from noisevar.params import ParamSpec, by_name, validate_params


@dataclass(frozen=True)
class MethodSpec:
    """A registered estimator, declared once.

    Parameters
    ----------
    name : str
        Method name, as in ``estimate(z, method=name)``.
    description : str
        One line for ``noisevar methods`` and the dashboard.
    kind : {"ours", "somd", "peer"}
        Family.
    func : callable
        ``func(z, notes, **params)``. With ``vectorised=False``, ``z`` is one validated
        signal, shape ``(n,)``, and it returns one
        :class:`~noisevar.estimators.results.VarianceEstimate`; with ``vectorised=True``,
        ``z`` has shape ``(k, n)`` (``k`` validated channels) and it returns a list of ``k``.
    params : tuple of (str or ParamSpec)
        The parameters it takes: names in
        :data:`~noisevar.estimators.params.PARAMS`, or new specs. ``drop_nonfinite`` is
        always accepted.
    vectorised : bool
        Whether ``func`` takes many channels at once.
    assumes : tuple of str
        What the method needs of the noise, as keys of
        :data:`noisevar.diagnostics.ASSUMPTIONS`; each estimate says which hold.
    coloured_params : dict, optional
        Parameters to use instead of the defaults when the noise is not white (``auto``:
        its shortest span, which lets the least of a coloured part in).
    moment : bool
        The estimate is a mean of squared residuals, whose interval
        :func:`~noisevar.estimators.estimate` widens for the measured kurtosis and
        correlation (docs/algorithms.md §E1).
    slow : bool
        Seconds on a long record: a comparison of methods leaves it out of its defaults
        there (:func:`noisevar.estimators.compare.default_methods`).
    needs_reference : bool
        The method takes a second sensor's record as ``reference=`` (one channel at a
        time; the CLI asks for ``--reference-column``).
    chunked : callable, optional
        ``chunked(read, n, *, probe=None, chunk=None, workers=2, note="streamed",
        notes=())``: the method's engine for a record read in chunks (``read(a, b)``
        gives samples ``a .. b``; ``notes`` are carried in front of its own), a
        :class:`~noisevar.estimators.pipeline.Record` that
        :func:`~noisevar.estimators.pipeline.run_record` takes through the same steps as
        a record in memory; ``None`` when it has none. A long record in memory and a
        file too large for it go this way (:func:`~noisevar.estimators.estimate_chunked`).
    residual : callable, optional
        ``residual(result.params)``: the residual filter whose white-noise normalisation
        the estimate makes (``mean(e²) / Σd²``). With it, the pipeline corrects an estimate
        of differenced (MA(1)) noise to the variance per sample (docs/algorithms.md §E2).
    finish : callable, optional
        ``finish(result, diagnostics, record)``: a finishing step applied to the method's
        result on one record before its interval and verdict are written (``auto``: the
        rounding correction of a quantised record, §E3). ``record(a, b)`` gives samples
        ``a .. b`` of a record in one uniform segment (``None`` for a record in several).
    """

    name: str
    description: str
    kind: str
    func: Callable[..., Any]
    params: tuple[str | ParamSpec, ...] = ()
    vectorised: bool = False
    assumes: tuple[str, ...] = ("white", "identifiable", "unsmoothed")
    moment: bool = True
    coloured_params: Mapping[str, Any] | None = None
    needs_reference: bool = False
    slow: bool = False
    chunked: Callable[..., Any] | None = None
    finish: Callable[..., Any] | None = None
    residual: Callable[[Mapping[str, Any]], NDArray] | None = None

    @property
    def param_specs(self) -> dict[str, ParamSpec]:
        """Name to spec of every parameter this method takes (``drop_nonfinite`` included)."""
        specs = [p if isinstance(p, ParamSpec) else PARAMS[p] for p in self.params]
        names = {s.name for s in specs}
        specs += [PARAMS[c] for c in COMMON_PARAMS if c not in names]
        return by_name(specs)

    def validate(self, params: Mapping[str, Any]) -> dict[str, Any]:
        """Validated parameters; a name this method does not take is a :class:`NoisevarError`."""
        return validate_params(f"method {self.name!r}", self.param_specs, params)

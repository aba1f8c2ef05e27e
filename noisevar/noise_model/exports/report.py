"""The HTML report of an IMU noise model and its consumer files (docs/algorithms.md §E7.5).

One page, from results only: the record's verdict per axis (the Estimator page's answer),
which values were exported (best fit or conservative, and the default), the units each axis
was read in and the conversions made (by pint), the fitted terms per axis with their
units, the exported model, then every consumer file's values with their unit, their kind
(continuous-time density or discrete std at a stated rate) and their conversion line.
The style and the escaping are :mod:`noisevar.report`'s.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from noisevar import report, units
from noisevar.estimators.answer import REGIME_WARNING, RecordAnswer
from noisevar.format import eng
from noisevar.noise_model.exports.base import CONTINUOUS, ExportFile, number
from noisevar.noise_model.exports.model import ImuModel
from noisevar.noise_model.inertial import InertialNoise

#: The kind of B (a level, not a density), as :func:`~.base.density` says it.
_LEVEL = "continuous-time (not a density)"
#: The file name the CLI writes beside the consumer files, and the page's download name.
REPORT_FILENAME = "report.html"


@dataclass(frozen=True)
class Axis:
    """One fitted column of the model: its sensor, its fit and the record's answer.

    Attributes
    ----------
    column : str
        The column (or log field) name.
    sensor : {"gyroscope", "accelerometer"}
    fit : InertialNoise
        Its IEEE-952 fit (in the unit the data were read in, ``fit.unit``).
    answer : RecordAnswer or None
        The record's answer (method auto) whose verdict is quoted; None: not computed.
    """

    column: str
    sensor: str
    fit: InertialNoise
    answer: RecordAnswer | None = None


def _summary(model: ImuModel, axes: Sequence[Axis]) -> list[str]:
    said = model.header("")[1]  # "values: BEST FIT ...; default of noisevar: best"
    lines = [said[0].upper() + said[1:]]
    for a in axes:
        if a.answer is None:
            continue
        ans = a.answer
        if ans.verdict:
            lines.append(f"Verdict, {a.column} ({a.sensor}): {ans.verdict}")
        lines.append(f"Record's answer, {a.column}: {ans.sentence(a.fit.unit)}")
        if ans.level_varies:
            lines.append(f"Regime warning, {a.column}: {REGIME_WARNING}")
        if ans.still_levels:
            lines.append(f"Other still levels, {a.column}: {ans.still_levels_text(a.fit.unit)}")
    return lines


def _axes_table(axes: Sequence[Axis]) -> str:
    rows = []
    for a in axes:
        u = a.fit.unit or "no unit declared"
        for t in a.fit.terms:
            lo, hi = t.interval
            rows.append(
                (a.column, a.sensor, u, f"{t.symbol} ({t.name.replace('_', ' ')})", eng(t.value))
                + (t.unit, f"{eng(lo)} .. {eng(hi)}", f"{eng(t.discrete)} {t.discrete_unit}")
            )
    header = ("column", "sensor", "read in", "term", "value", "unit", "interval", "per sample")
    return report.table(rows, header)


def _model_table(model: ImuModel) -> str:
    rows = []
    for name in ("gyroscope", "accelerometer"):
        s = model.sensor(name)
        for term, kind in (("N", CONTINUOUS), ("K", CONTINUOUS), ("B", _LEVEL)):
            factor = s.factors.get(term)
            rows.append(
                (name, term, number(getattr(s, term)), units.term_unit(s.unit, term), kind)
                + (f"x{factor:.4g}" if factor is not None else "",)
            )
    header = ("sensor", "term", "value", "unit", "kind", "factor over the best fit")
    return report.table(rows, header)


def _file_blocks(f: ExportFile, title: str) -> list[str]:
    rows = [
        (v.name, number(v.value), v.unit, v.kind, v.how + (f"; NOT IDENTIFIED: {v.withheld}"
                                                           if v.withheld else ""))
        for v in f.values
    ]  # fmt: skip
    header = ("parameter", "value", "unit", "kind", "conversion")
    return [report.heading(f"{f.filename}: {title}", 3), report.table(rows, header)]


def imu_report(
    model: ImuModel,
    files: Sequence[ExportFile],
    axes: Sequence[Axis],
    *,
    source: str = "",
    command: str = "",
    figures: Sequence[Any] = (),
) -> str:
    """The HTML report of ``model``, its consumer ``files`` and the fitted ``axes``.

    Parameters
    ----------
    model : ImuModel
        The exported model (:func:`~noisevar.noise_model.exports.imu_model`).
    files : sequence of ExportFile
        The consumer files written from it (:func:`~noisevar.noise_model.exports.export`).
    axes : sequence of Axis
        Each fitted column, its sensor, fit and the record's answer (the verdict).
    source : str
        What was read (a log and its topic), in the title.
    command : str
        The command line that repeats it, shown at the end.
    figures : sequence of plotly Figure
        The Allan fits, drawn after the tables.

    Returns
    -------
    str
        A self-contained HTML page (every string escaped).
    """
    from noisevar.noise_model.exports import consumer

    blocks = [
        report.paragraphs(_summary(model, axes), strong=True),
        report.heading("Units and conversions"),
        report.paragraphs(
            [
                f"IMU sample rate {model.rate:g} Hz; fitted on regimes={model.regimes}.",
                "Exported in SI: gyroscope rad/s, accelerometer m/s^2. N and K are "
                "continuous-time densities; each file's discrete values are converted at "
                "the stated rate (docs/algorithms.md §E7).",
                *model.notes,
            ]
        ),
        report.heading("Fitted terms per axis (IEEE 952, in the unit each axis was read in)"),
        _axes_table(axes),
        report.heading("The exported model (largest over the axes, SI)"),
        _model_table(model),
        report.heading("Consumer files"),
    ]
    for f in files:
        blocks += _file_blocks(f, consumer(f.consumer).title)
    if command:
        blocks.append(report.pre(command))
    title = "noisevar: IMU noise model" + (f" of {source}" if source else "")
    return report.page(title, blocks, figures)

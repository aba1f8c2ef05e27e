"""``noisevar imu ... --export ... --out DIR`` also writes DIR/report.html (§E7.5).

The report (:func:`noisevar.noise_model.exports.report.imu_report`) quotes each gyroscope
and accelerometer column's verdict: the record's answer of :func:`noisevar.estimate`
(method auto, as the Estimator page and ``noisevar estimate``), computed here per column
(every exported file's header says it too), and draws each column's Allan fit.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.estimators.answer import RecordAnswer
from noisevar.estimators.results import VarianceEstimate
from noisevar.noise_model.exports import ExportFile, ImuModel
from noisevar.noise_model.inertial import InertialNoise

#: A column's estimate, or why it has none.
Estimated = VarianceEstimate | NoisevarError


def column_estimates(
    args: argparse.Namespace,
    data: dict[str, np.ndarray],
    scales: dict[str, float],
    times: dict[str, np.ndarray | None],
) -> tuple[dict[str, Estimated], dict[str, Estimated]]:
    """Each gyroscope and accelerometer column's :func:`noisevar.estimate` (method auto, as
    the Estimator page) of the scaled column the fits see, for the IEEE-952 fits' regimes
    (``inertial_noise(estimates=)``), and for the answers (:func:`column_answers`); the
    error instead when there is none (the fit then estimates, and says, as before).

    Notes
    -----
    The answer is the record's, split at the gaps in its times as on every other path
    (:func:`noisevar.io.record_times`); the fits run on the samples end to end (an Allan
    variance needs one uniform record), so a column whose times have a gap is estimated
    twice, once each way; otherwise once, for both.
    """
    from noisevar.diagnostics.segments import split_times
    from noisevar.estimators import estimate

    def one(c: str, t: np.ndarray | None) -> Estimated:
        try:
            return estimate(data[c] * scales[c], t=t)
        except NoisevarError as exc:  # raised where the answer is needed, as before
            return exc

    named = list(dict.fromkeys([*args.gyro, *args.accel]))
    gapped = {
        c for c in named if times.get(c) is not None and len(split_times(times[c]).segments) > 1
    }
    work = [(c, None) for c in named] + [(c, times[c]) for c in sorted(gapped, key=named.index)]
    # the columns' estimates in threads, as inertial_noise fits the axes
    with ThreadPoolExecutor(max(1, min(len(work), os.cpu_count() or 1))) as pool:
        ests = list(pool.map(lambda w: one(*w), work))
    fits = dict(zip(named, ests[: len(named)], strict=True))
    split = dict(zip(sorted(gapped, key=named.index), ests[len(named) :], strict=True))
    return fits, {**fits, **split}


def column_answers(
    args: argparse.Namespace, estimates: dict[str, VarianceEstimate | NoisevarError]
) -> list[tuple[str, str, RecordAnswer]]:
    """Each gyroscope and accelerometer column's record answer (method auto, as the
    Estimator page): ``(sensor, column, answer)``, for the files' headers and the report.

    ``estimates``: :func:`column_estimates`."""
    from noisevar.estimators.answer import record_answer
    from noisevar.estimators.regimes import DEFAULT_REGIMES

    regimes = args.regimes or DEFAULT_REGIMES
    named = [
        (sensor, c)
        for sensor, columns in (("gyroscope", args.gyro), ("accelerometer", args.accel))
        for c in dict.fromkeys(columns)
    ]
    for _, c in named:
        if isinstance(estimates[c], NoisevarError):
            raise estimates[c]
    return [(sensor, c, record_answer(estimates[c], regimes)) for sensor, c in named]


def write_report(
    args: argparse.Namespace,
    model: ImuModel,
    files: list[ExportFile],
    fits: dict[str, InertialNoise],
    answers: list[tuple[str, str, RecordAnswer]],
) -> str:
    """Write ``report.html`` into ``--out``; its path."""
    from noisevar.figures.noise_model import allan_figure
    from noisevar.noise_model.exports.report import REPORT_FILENAME, Axis, imu_report

    axes = [Axis(c, sensor, fits[c], ans) for sensor, c, ans in answers]
    figures = [
        allan_figure(a.fit.allan, fit=a.fit, title=f"Allan deviation of {a.column}", unit=u)
        for a in axes
        for u in [a.fit.unit]
    ]
    topics = list(dict.fromkeys(args.topic or []))
    said = "topics" if len(topics) > 1 else "topic"
    source = Path(args.file).name + (f", {said} {', '.join(topics)}" if topics else "")
    command = shlex.join(["noisevar", *sys.argv[1:]]) if sys.argv[1:] else ""
    text = imu_report(model, files, axes, source=source, command=command, figures=figures)
    path = Path(args.out) / REPORT_FILENAME
    path.write_text(text, encoding="utf-8")
    return str(path)

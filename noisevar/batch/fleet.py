"""Fleet statistics of a batch table: per channel, which sensors are unusually noisy or quiet.

Each file of a batch is one sensor. Per channel, the noise standard deviations of the
fleet are compared on a log scale (twice as noisy and half as noisy are equally far
from typical) with a robust z-score: the distance from the fleet's median in units of
its median absolute deviation (MAD), so the outliers being looked for do not widen the
yardstick. A sensor is flagged when ``|z|`` exceeds the threshold (3.5, the usual
cut-off of the modified z-score of Iglewicz and Hoaglin).
"""

from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from noisevar.batch.channels import left_out_rows
from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import (
    DEFAULT_REGIMES,
    check_regimes,
    choose_variances,
    no_still_rows,
)
from noisevar.estimators.results import FLAG_PREFIX

if TYPE_CHECKING:
    import pandas as pd

#: ``|z|`` above which a sensor is flagged.
DEFAULT_THRESHOLD = 3.5
#: Fewer sensors than this in a channel: no fleet to compare with.
MIN_SENSORS = 3
#: MAD of a normal sample over its standard deviation (``Φ⁻¹(3/4)``).
MAD_TO_SD = 0.6744897501960817
#: Mean absolute deviation of a normal sample over its standard deviation (``sqrt(2/π)``).
MEAN_AD_TO_SD = 0.7978845608028654
#: The batch table's column of each row's ``level_varies`` flag.
LEVEL_VARIES = FLAG_PREFIX + "level_varies"


def _json_float(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


@dataclass(frozen=True)
class ChannelSpread:
    """The fleet's noise on one channel.

    Attributes
    ----------
    channel : str
        Channel name.
    n_sensors : int
        Sensors with an estimate on this channel.
    median_std : float
        The fleet's typical noise standard deviation (median).
    low, high : float
        The normal range: standard deviations with ``|z| <= threshold``.
    n_flagged : int
        Sensors outside it.
    """

    channel: str
    n_sensors: int
    median_std: float
    low: float
    high: float
    n_flagged: int


@dataclass(frozen=True)
class SensorScore:
    """One sensor (file) on one channel.

    Attributes
    ----------
    file : str
        The file (the sensor).
    channel : str
        Channel name.
    std : float
        Its noise standard deviation.
    z : float or None
        Robust z-score of ``log std`` within the channel (None: too few sensors).
    flagged : bool
        ``|z|`` over the threshold.
    sentence : str
        What that means, in words.
    """

    file: str
    channel: str
    std: float
    z: float | None
    flagged: bool
    sentence: str


@dataclass(frozen=True)
class FleetReport:
    """Per-channel spread of a fleet's noise and the sensors outside it.

    Attributes
    ----------
    threshold : float
        ``|z|`` above which a sensor is flagged.
    channels : tuple of ChannelSpread
        One per channel with an estimate.
    sensors : tuple of SensorScore
        One per file x channel with an estimate, most unusual first.
    n_errors : int
        Rows of the table without an estimate (their ``error`` says why), but the
        columns ``--columns all`` left out (a note counts them).
    notes : tuple of str
        Plain-language remarks.
    regimes : {"all", "still"}
        Each row's R: its whole record's, or its still regimes' (``still_variance``)
        where it has one (:func:`~noisevar.estimators.regimes.choose_variances`).
    warnings : tuple of str
        What makes the files not comparable as they stand: byte-identical files
        (:func:`identical_files`), sample rates that differ (:func:`rate_notes`).
    """

    threshold: float
    channels: tuple[ChannelSpread, ...]
    sensors: tuple[SensorScore, ...]
    n_errors: int
    notes: tuple[str, ...] = ()
    regimes: str = DEFAULT_REGIMES
    warnings: tuple[str, ...] = ()

    @property
    def flagged(self) -> list[SensorScore]:
        """The sensors outside the fleet's normal range."""
        return [s for s in self.sensors if s.flagged]

    def to_frame(self) -> pd.DataFrame:
        """One row per sensor x channel: file, channel, std, z, flagged, sentence."""
        import pandas as pd

        cols = ["file", "channel", "std", "z", "flagged", "sentence"]
        return pd.DataFrame([asdict(s) for s in self.sensors], columns=cols)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (no NaN: missing numbers are None)."""
        return {
            "threshold": self.threshold,
            "channels": [
                {k: _json_float(v) if isinstance(v, float) else v for k, v in asdict(c).items()}
                for c in self.channels
            ],
            "sensors": [
                {
                    **asdict(s),
                    "std": _json_float(s.std),
                    "z": None if s.z is None else _json_float(s.z),
                }
                for s in self.sensors
            ],
            "n_errors": self.n_errors,
            "notes": list(self.notes),
            "warnings": list(self.warnings),
            "regimes": self.regimes,
        }


def robust_z(x: NDArray) -> tuple[NDArray, float, float]:
    """Robust z-scores of ``x``, its median and the scale used.

    Returns
    -------
    z : ndarray
        ``(x - median) / scale``; zeros when the scale is zero (all equal).
    median, scale : float
        ``scale = MAD / 0.6745`` (falls back to the mean absolute deviation / 0.7979
        when more than half the values are equal).
    """
    med = float(np.median(x))
    dev = np.abs(x - med)
    # scale = MAD / Φ⁻¹(3/4): the standard deviation of normal data, robustly
    scale = float(np.median(dev)) / MAD_TO_SD
    if scale == 0.0:
        # mean absolute deviation / sqrt(2/π), when the MAD is zero
        scale = float(np.mean(dev)) / MEAN_AD_TO_SD
    if scale == 0.0:
        return np.zeros_like(x), med, 0.0
    # z = (x - median) / scale
    return (x - med) / scale, med, scale


def _sentence(file: str, channel: str, std: float, z: float, median: float, cut: float) -> str:
    flagged = abs(z) > cut
    name = f"{os.path.basename(file)} · {channel}"
    ratio = std / median if median > 0 else float("inf")
    if not flagged:
        return f"{name}: noise std {std:.3g}, within the fleet's normal range (z = {z:+.1f})."
    how = f"{ratio:.1f} times noisier than" if ratio >= 1 else f"{1 / ratio:.1f} times quieter than"
    return (
        f"{name}: noise std {std:.3g} is {how} the fleet's typical {median:.3g} "
        f"(robust z = {z:+.1f}, beyond ±{cut:g}): check this sensor."
    )


def _channel(
    name: str, files: list[str], std: NDArray, threshold: float
) -> tuple[ChannelSpread, list[SensorScore]]:
    logs = np.log10(std)
    z, med, scale = robust_z(logs)
    median = float(10.0**med)
    flagged = np.abs(z) > threshold
    # normal range: log10 std = median ± threshold · scale
    low, high = 10.0 ** (med - threshold * scale), 10.0 ** (med + threshold * scale)
    scores = [
        SensorScore(
            f,
            name,
            float(s),
            float(zz),
            bool(fl),
            _sentence(f, name, float(s), float(zz), median, threshold),
        )
        for f, s, zz, fl in zip(files, std, z, flagged, strict=True)
    ]
    spread = ChannelSpread(name, len(files), median, float(low), float(high), int(flagged.sum()))
    return spread, scores


def _stds(frame: pd.DataFrame, regimes: str) -> tuple[NDArray, NDArray]:
    """Each row's noise std for the regime choice (its ``std``, or its still regimes'),
    and the rows with no still R (NaN there: never their whole record's in its place)."""
    std = frame["std"].to_numpy(dtype=float, na_value=np.nan)
    if regimes == DEFAULT_REGIMES or "still_variance" not in frame.columns:
        return std, np.zeros(std.shape, dtype=bool)
    still = frame["still_variance"].to_numpy()
    varies = frame[LEVEL_VARIES].to_numpy() if LEVEL_VARIES in frame.columns else None
    chosen = choose_variances(std**2, still, regimes, varies)
    return np.sqrt(chosen), no_still_rows(still, varies)


def identical_files(frame: pd.DataFrame) -> list[str]:
    """One note per group of byte-identical files (the same ``hash``): one record counted twice.

    Parameters
    ----------
    frame : DataFrame
        A batch table (its ``file`` and ``hash`` columns; none without ``hash``).

    Returns
    -------
    list of str
    """
    if "hash" not in frame.columns:
        return []
    pairs = frame[["file", "hash"]].dropna().drop_duplicates()
    notes = []
    for _, group in pairs.groupby("hash", sort=False):
        files = sorted({os.path.basename(str(f)) for f in group["file"]})
        if len(set(group["file"])) > 1:
            notes.append(
                f"{', '.join(files)} are byte-identical (the same content hash): one record "
                "counted as several sensors; compare only one of them"
            )
    return notes


def rate_notes(frame: pd.DataFrame) -> list[str]:
    """A note when the files' sample rates differ (``sample_rate_hz``): their per-sample noise
    std are then not comparable (a white noise's std grows with the square root of the rate).

    Parameters
    ----------
    frame : DataFrame
        A batch table.

    Returns
    -------
    list of str
    """
    if "sample_rate_hz" not in frame.columns:
        return []
    rates = frame[["file", "sample_rate_hz"]].dropna().drop_duplicates("file")
    values = rates["sample_rate_hz"].astype(float).round(6)
    if values.nunique() < 2:
        return []
    counts = values.value_counts()
    said = ", ".join(f"{r:g} Hz ({n} file{'s' if n > 1 else ''})" for r, n in counts.items())
    return [
        f"sample rates differ: {said}; a sensor's noise std per sample depends on its rate "
        "(white noise: std ∝ √rate), so compare files of one rate or their noise densities"
    ]


def fleet_report(
    table: pd.DataFrame | str | os.PathLike,
    threshold: float = DEFAULT_THRESHOLD,
    regimes: str = DEFAULT_REGIMES,
) -> FleetReport:
    """Fleet statistics of a batch table (:func:`noisevar.batch`'s rows, or its file).

    Parameters
    ----------
    table : DataFrame, str or path
        Rows with ``file``, ``channel``, ``std`` (and ``error``), or a ``.parquet`` /
        ``.csv`` batch table.
    threshold : float
        ``|z|`` above which a sensor is flagged (> 0).
    regimes : {"all", "still"}
        Compare the whole records' noise, or each record's still regimes'
        (``still_variance``, where the level varies; else its whole record's).

    Returns
    -------
    FleetReport
    """
    from noisevar.batch._output import read_table

    if not (isinstance(threshold, int | float) and math.isfinite(threshold) and threshold > 0):
        raise NoisevarError(f"the threshold must be a positive number, got {threshold!r}")
    check_regimes(regimes)
    frame = table if not isinstance(table, str | os.PathLike) else read_table(table)
    missing = {"file", "channel", "std"} - set(frame.columns)
    if missing:
        raise NoisevarError(
            f"not a batch table: no {', '.join(sorted(missing))} column (run noisevar batch)"
        )
    std, no_still = _stds(frame, regimes)
    ok = np.isfinite(std) & (std > 0)
    good = frame[ok].assign(std=std[ok])
    channels, sensors, notes = [], [], []
    said = left_out_rows(frame["error"]) if "error" in frame else [False] * len(frame)
    left = np.array(said, dtype=bool)
    if left.any():
        notes.append(
            f"{int(left.sum())} columns left out by --columns all (flags, codes, clock "
            "times: their rows say which)"
        )
    if no_still.any():
        notes.append(
            f"{int(no_still.sum())} rows have no still R (their level varies and their still "
            "stretches are too short for R's method, or absent): left out of the still "
            "comparison; compare them with regimes='all'"
        )
    for name in dict.fromkeys(str(c) for c in good["channel"]):
        part = good[good["channel"].astype(str) == name]
        files = [str(f) for f in part["file"]]
        values = part["std"].to_numpy(dtype=float)
        if len(files) < MIN_SENSORS:
            notes.append(
                f"channel {name}: {len(files)} sensors, too few to compare (need {MIN_SENSORS})"
            )
            sensors += [
                SensorScore(
                    f,
                    name,
                    float(s),
                    None,
                    False,
                    f"{os.path.basename(f)} · {name}: noise std {s:.3g}.",
                )
                for f, s in zip(files, values, strict=True)
            ]
            continue
        spread, scores = _channel(name, files, values, float(threshold))
        channels.append(spread)
        sensors += scores
    sensors.sort(key=lambda s: -abs(s.z) if s.z is not None else 0.0)
    return FleetReport(
        float(threshold),
        tuple(channels),
        tuple(sensors),
        int((~ok & ~no_still & ~left).sum()),
        tuple(notes),
        regimes,
        tuple(identical_files(frame) + rate_notes(frame)),
    )

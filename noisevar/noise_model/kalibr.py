"""Kalibr's ``imu.yaml``: the continuous-time noise densities of an IMU (docs/algorithms.md §E4).

Kalibr takes, per sensor, the white-noise density N (``*_noise_density``) and the bias
random walk K (``*_random_walk``), both continuous-time, and the update rate it
discretises them with. Written by hand (a flat file); read with PyYAML when it is
installed, else with a small reader of ``key: value`` lines.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import DEFAULT_REGIMES, check_regimes
from noisevar.noise_model.gmwm.model import HORIZON
from noisevar.noise_model.inertial import InertialNoise
from noisevar.noise_model.inertial_resolve import axis_warnings
from noisevar.noise_model.inertial_white import why_below_white

if TYPE_CHECKING:
    from noisevar.noise_model.gmwm.model import ImuModel as CompositeModel

#: Keys of the file, in Kalibr's order, with their comments.
FIELDS = {
    "accelerometer_noise_density": "m/s^2/sqrt(Hz): white noise (continuous time)",
    "accelerometer_random_walk": "m/s^3/sqrt(Hz): bias random walk",
    "gyroscope_noise_density": "rad/s/sqrt(Hz): white noise (continuous time)",
    "gyroscope_random_walk": "rad/s^2/sqrt(Hz): bias random walk",
    "rostopic": "the IMU's ROS topic",
    "update_rate": "Hz (for the discretisation of the values above)",
}


#: Prefix of the comment lines that carry the notes.
NOTE = "# note: "
#: Prefix of the comment line that says which of the records' regimes were fitted.
REGIMES_LINE = "# regimes: "


@dataclass(frozen=True)
class KalibrImu:
    """The values of a Kalibr ``imu.yaml``.

    ``regimes`` (``"all"`` or ``"still"``) is which of the records' regimes the terms were
    fitted on, written as a comment line; ``notes`` as ``# note:`` lines.
    """

    accelerometer_noise_density: float
    accelerometer_random_walk: float
    gyroscope_noise_density: float
    gyroscope_random_walk: float
    update_rate: float
    rostopic: str = "/imu0"
    notes: tuple[str, ...] = field(default_factory=tuple)
    regimes: str = DEFAULT_REGIMES

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary of the file's values (the notes are in ``notes``)."""
        return {k: v for k, v in asdict(self).items() if k not in ("notes", "regimes")}

    def to_yaml(self) -> str:
        """The file's text (the regimes and the notes as comment lines at the top)."""
        values = self.to_dict()
        lines = ["# Kalibr IMU noise model, written by noisevar (docs/algorithms.md §E4)"]
        said = "the whole records" if self.regimes == DEFAULT_REGIMES else "still stretches"
        lines.append(f"{REGIMES_LINE}{self.regimes} (the terms were fitted on {said})")
        lines += [f"{NOTE}{note}" for note in self.notes]
        for key, comment in FIELDS.items():
            v = values[key]
            if isinstance(v, str):
                text = v
            elif key == "update_rate":
                text = f"{v:g}"
            else:
                text = f"{v:.10e}"
            lines.append(f"{key + ':':<30} {text:<14} # {comment}")
        return "\n".join(lines) + "\n"


def _axes(fits: InertialNoise | Sequence[InertialNoise]) -> list[InertialNoise]:
    axes = [fits] if isinstance(fits, InertialNoise) else list(fits)
    if not axes:
        raise NoisevarError("No axis given: pass the InertialNoise of at least one axis.")
    return axes


def _regimes(
    gyro: InertialNoise | Sequence[InertialNoise], accel: InertialNoise | Sequence[InertialNoise]
) -> tuple[str, list[str]]:
    """The regime choice of every axis (one for all), and each still stretch's note."""
    axes = {"gyroscope": _axes(gyro), "accelerometer": _axes(accel)}
    chosen = {a.regimes for fits in axes.values() for a in fits}
    if len(chosen) != 1:
        raise NoisevarError(
            "The axes were fitted on different regimes (some on the whole record, some on "
            "still stretches): fit them all with the same regimes."
        )
    notes = [
        f"{sensor} axis {i}: {note}"
        for sensor, fits in axes.items()
        for i, a in enumerate(fits)
        for note in a.notes
        if note.startswith("regimes=")
    ]
    return chosen.pop(), notes


def _worst(fits: InertialNoise | Sequence[InertialNoise], name: str) -> float:
    """The largest value of term ``name`` over the axes (the conservative choice)."""
    return max(a.term(name).value for a in _axes(fits))


def composite_k(
    fits: InertialNoise | Sequence[InertialNoise], bias: Sequence[CompositeModel], name: str
) -> float:
    """The largest over the axes of the composite fits' bias as one random walk
    (``FilterBias.random_walk``: K itself for a WN+RW model, else K_eq over the fit's
    horizon); ``bias`` holds one composite fit per axis of ``fits``, of the same data."""
    if len(bias) != len(_axes(fits)):
        raise NoisevarError(
            f"{name}: {len(bias)} composite fits for {len(_axes(fits))} axes: give one per "
            "axis, of the same data in the same order"
        )
    return max(b.filter_bias.random_walk for b in bias)


def k_rule(fits: Sequence[InertialNoise], bias: Sequence[CompositeModel] | None = None) -> str:
    """Why K is not identified at the horizon the bias is modelled over, or ``""``.

    Parameters
    ----------
    fits : sequence of InertialNoise
        The sensor's axes' IEEE-952 fits (their Allan variances' taus).
    bias : sequence of noisevar.noise_model.gmwm.ImuModel, optional
        Their composite fits: the horizon is theirs (``FilterBias.horizon``), else
        :data:`~noisevar.noise_model.gmwm.model.HORIZON`.

    Returns
    -------
    str
        The reason, when the longest tau fitted on some axis is shorter than the horizon.

    Notes
    -----
    docs/algorithms.md §E7.7 (K and the record's length). An Allan variance at tau needs
    2 tau of record; K (slope +1/2) is seen only at the taus fitted, so a record whose
    longest tau is below the horizon T extrapolates the bias to T from what dominated
    its short taus (vibration, a warm-up): pymavlink's 0.9 s ArduPlane log gave
    ``EK2_GBIAS_P_NSE`` 8.9e3x the flight's. One rule for every consumer.
    """
    horizon = max((b.filter_bias.horizon for b in bias), default=HORIZON) if bias else HORIZON
    reach = min(float(np.max(a.allan.taus)) for a in fits)
    if reach >= horizon:
        return ""
    k = max(a.rate_random_walk for a in fits)
    hi = max(a.term("K").interval[1] for a in fits)
    return (
        f"the fitted record reaches tau {reach:.3g} s, short of the {horizon:g} s horizon "
        f"the bias is modelled over (the Allan variance at tau needs 2 tau of record), so K "
        f"(the Allan fit's {k:.3g}, interval up to {hi:.3g}, in the data's unit) is "
        "extrapolated, not measured; record the sensor still for 2x the horizon"
    )


def composite_k_note(bias: dict[str, Sequence[CompositeModel]]) -> str:
    """Where a K taken from the composite fits comes from, in words (files' headers)."""
    models = "; ".join(
        f"{name} {', '.join(dict.fromkeys(b.model for b in fits))}" for name, fits in bias.items()
    )
    horizons = ", ".join(
        dict.fromkeys(f"{b.filter_bias.horizon:g}" for fits in bias.values() for b in fits)
    )
    return (
        f"the composite fit (GMWM, noisevar.fit_imu_model; models: {models}): its bias as "
        "one random walk, the largest over the axes: K itself for a WN+RW model, else "
        f"K_eq = sqrt(3 AVAR_bias(T) / T) over T = {horizons} s"
    )


def _density(fits: InertialNoise | Sequence[InertialNoise], key: str) -> tuple[float, list[str]]:
    """The white-noise density: the largest of N and of the white level over the axes.

    Kalibr has no quantisation or bias-instability field, so short-tau noise the fit put
    into Q or B would be lost: the density is at least the white level
    ``sigma(tau0) sqrt(tau0)`` of every axis (docs/algorithms.md §E4), with a note when
    that raises it above N, naming the terms that took it.
    """
    axes = _axes(fits)
    n = max(a.random_walk for a in axes)
    i = int(max(range(len(axes)), key=lambda j: axes[j].white_level))
    white = axes[i].white_level
    if not white > n:
        return n, []
    note = (
        f"{key}: raised from N = {n:.4g} (IEEE-952 fit, largest axis) to the white level "
        f"sigma(tau0) sqrt(tau0) = {white:.4g} of axis {i}, before inflation: "
        f"{why_below_white(axes[i].tau0_holders)} (on a short record or one with motion, "
        "they are hard to tell from white noise)"
    )
    return white, [note]


def imu_rate(
    gyro: Sequence[InertialNoise], accel: Sequence[InertialNoise]
) -> tuple[float, list[str]]:
    """The one IMU rate a consumer's file states: the gyroscope's; a note when the
    accelerometer was sampled at another rate (two topics of a log: PX4's FIFOs).

    Raises
    ------
    NoisevarError
        One sensor's axes fitted at different rates.
    """
    for name, axes in (("gyroscope", gyro), ("accelerometer", accel)):
        rates = {x.rate for x in axes}
        if len(rates) != 1:
            raise NoisevarError(
                f"the {name} axes were fitted at different rates ({sorted(rates)} Hz)"
            )
    rate, a_rate = gyro[0].rate, accel[0].rate
    if a_rate == rate:
        return rate, []
    return rate, [
        f"the gyroscope was sampled at {rate:g} Hz, the accelerometer at {a_rate:g} Hz: each "
        "sensor's N and K are densities fitted at its own rate (they do not depend on it); "
        f"a file that states one IMU rate states the gyroscope's {rate:g} Hz (set it to your "
        "filter's IMU rate if that differs); the accelerometer's std per sample at its own "
        f"rate is N·√{a_rate:g}"
    ]


def kalibr_imu(
    gyro: InertialNoise | Sequence[InertialNoise],
    accel: InertialNoise | Sequence[InertialNoise],
    *,
    inflation: float = 1.0,
    rostopic: str = "/imu0",
    gyro_bias: Sequence[CompositeModel] | None = None,
    accel_bias: Sequence[CompositeModel] | None = None,
) -> KalibrImu:
    """Kalibr's values from the fitted terms of the gyroscope and accelerometer axes.

    Parameters
    ----------
    gyro, accel : InertialNoise or sequence of them
        Fits of the gyroscope axes (rad/s) and accelerometer axes (m/s^2).
    inflation : float
        Factor on every density (Kalibr's authors advise inflating Allan-derived
        values, e.g. by 10, for the unmodelled effects of a moving IMU).
    rostopic : str
        The IMU's topic.
    gyro_bias, accel_bias : sequence of noisevar.noise_model.gmwm.ImuModel, optional
        Composite fits of the same axes (same data, order): the random walks are then
        their bias as one random walk (:func:`composite_k`), as the consumer exports'.

    Returns
    -------
    KalibrImu

    Notes
    -----
    Over several axes the largest N and K are kept. The noise density is at least
    each axis's white level ``sigma(tau0) sqrt(tau0)`` (Kalibr has no quantisation or
    bias-instability term to hold what the fit put into Q or B at tau0); ``notes`` says
    when that raised it, and why.
    """
    if not (math.isfinite(inflation) and inflation > 0):
        raise NoisevarError(f"The inflation must be a positive number, not {inflation}.")
    rate, rate_notes = imu_rate(_axes(gyro), _axes(accel))
    regimes, regime_notes = _regimes(gyro, accel)
    accel_n, accel_notes = _density(accel, "accelerometer_noise_density")
    gyro_n, gyro_notes = _density(gyro, "gyroscope_noise_density")
    walks = {
        name: _worst(fits, "rate_random_walk") if b is None else composite_k(fits, b, name)
        for name, fits, b in (("gyroscope", gyro, gyro_bias), ("accelerometer", accel, accel_bias))
    }
    bias = {n: list(b) for n, b in (("gyroscope", gyro_bias), ("accelerometer", accel_bias)) if b}
    k_notes = [f"random walks from: {composite_k_note(bias)}"] if bias else []
    k_notes += [
        f"{name}_random_walk NOT IDENTIFIED: {why}; kept (Kalibr needs every key): do not use "
        "it as measured"
        for name, fits, b in (("gyroscope", gyro, gyro_bias), ("accelerometer", accel, accel_bias))
        for why in [k_rule(_axes(fits), b)]
        if why
    ]
    return KalibrImu(
        accelerometer_noise_density=inflation * accel_n,
        accelerometer_random_walk=inflation * walks["accelerometer"],
        gyroscope_noise_density=inflation * gyro_n,
        gyroscope_random_walk=inflation * walks["gyroscope"],
        update_rate=rate,
        rostopic=rostopic,
        notes=tuple(
            axis_warnings({"gyroscope": _axes(gyro), "accelerometer": _axes(accel)})
            + rate_notes
            + regime_notes
            + accel_notes
            + gyro_notes
            + k_notes
        ),
        regimes=regimes,
    )


def write_kalibr(imu: KalibrImu, path: str | os.PathLike) -> None:
    """Write ``imu`` as Kalibr's ``imu.yaml`` at ``path``."""
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(imu.to_yaml())


def _flat_yaml(text: str) -> dict[str, str]:
    """``key: value`` lines of a flat YAML file (comments and blank lines skipped)."""
    out = {}
    for line in text.splitlines():
        body = line.split("#", 1)[0].strip()
        if body and ":" in body:
            key, value = body.split(":", 1)
            out[key.strip()] = value.strip().strip("'\"")
    return out


def parse_kalibr(text: str) -> KalibrImu:
    """A Kalibr ``imu.yaml`` from its text.

    Parameters
    ----------
    text : str

    Returns
    -------
    KalibrImu
    """
    try:
        import yaml

        raw = yaml.safe_load(text)
    except ImportError:
        raw = _flat_yaml(text)
    except yaml.YAMLError as exc:
        raise NoisevarError(f"Not a YAML file: {exc}".splitlines()[0]) from exc
    if not isinstance(raw, dict):
        raise NoisevarError("Not a Kalibr imu.yaml: expected 'key: value' lines.")
    missing = [k for k in FIELDS if k not in raw and k != "rostopic"]
    if missing:
        raise NoisevarError(f"Not a Kalibr imu.yaml: {', '.join(missing)} missing.")
    try:
        values = {k: float(raw[k]) for k in FIELDS if k != "rostopic"}
    except (TypeError, ValueError) as exc:
        raise NoisevarError(f"A Kalibr value is not a number: {exc}.") from exc
    lines = text.splitlines()
    notes = tuple(line[len(NOTE) :] for line in lines if line.startswith(NOTE))
    return KalibrImu(
        **values,
        rostopic=str(raw.get("rostopic", "/imu0")),
        notes=notes,
        regimes=_regimes_of(lines),
    )


def _regimes_of(lines: list[str]) -> str:
    """The regime choice a file's ``# regimes:`` line names (``"all"`` without one)."""
    for line in lines:
        if line.startswith(REGIMES_LINE):
            words = line[len(REGIMES_LINE) :].split()
            try:
                return check_regimes(words[0] if words else None)
            except NoisevarError as exc:
                raise NoisevarError(f"Not a noisevar imu.yaml regimes line: {exc}.") from None
    return DEFAULT_REGIMES


def read_kalibr(path: str | os.PathLike) -> KalibrImu:
    """Read a Kalibr ``imu.yaml``."""
    with open(path, encoding="utf-8") as fh:
        return parse_kalibr(fh.read())

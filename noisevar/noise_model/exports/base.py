"""What every consumer's writer returns: the file's text and each value with its meaning."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from noisevar import units
from noisevar.noise_model.exports.model import ImuModel

#: Kind of a value: a continuous-time density, or a discrete std at a stated rate.
CONTINUOUS = "continuous-time density"


def discrete(rate: float) -> str:
    """The kind of a value that is a discrete std (or variance) at ``rate`` Hz."""
    return f"discrete at {rate:g} Hz"


@dataclass(frozen=True)
class Value:
    """One exported value, its unit, its kind and how it was converted from the model.

    ``withheld``: why the value is not identified (a K, ``SensorTerms.k_withheld``),
    empty when it is; a merged file (:attr:`Consumer.merged`) writes it commented out.
    """

    name: str
    value: float
    unit: str
    kind: str
    how: str
    withheld: str = ""

    def comment(self) -> str:
        """``unit; kind; how`` for the file's comment."""
        return f"{self.unit}; {self.kind}; {self.how}"

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "name": self.name,
            "value": self.value,
            "unit": self.unit,
            "kind": self.kind,
            "how": self.how,
            "withheld": self.withheld,
        }

    def line(self, text: str) -> str:
        """``text``, the value's line of a merged file, commented out when it is withheld
        (the config keeps its own value; :attr:`Consumer.merged`)."""
        return f"# WITHHELD ({self.withheld}): {text}" if self.withheld else text


@dataclass(frozen=True)
class ExportFile:
    """A consumer's file: its name, its text and the values it holds."""

    consumer: str
    filename: str
    text: str
    values: tuple[Value, ...]

    def value(self, name: str) -> float:
        """The value called ``name``."""
        return next(v.value for v in self.values if v.name == name)


@dataclass(frozen=True)
class Consumer:
    """A registered consumer: its key, title, default file name, writer and reader.

    ``filename`` is the name of the file written without a flight log; a writer may name
    its file after what it holds (ArduPilot's after the EKF it writes): take the name of
    the :class:`ExportFile` written.

    ``write(model, **options)`` returns an :class:`ExportFile`; ``parse(text)`` reads the
    file back into ``{name: value}`` through the consumer's own format. ``log_params``: the
    flight-log parameters the writer takes as ``params=`` (the EKF's step: PX4's
    ``EKF2_PREDICT_US``, ArduPilot's ``SCHED_LOOP_RATE``), empty for a writer that takes none.
    ``merged``: the file's lines are merged into the user's config (a parameter file, a
    settings block), so a line left out keeps the config's own value: a value not
    identified (:attr:`Value.withheld`) is written commented out with its reason. A
    complete file (``merged`` False: its reader needs every key) keeps the value, and its
    header says it is not identified (docs/algorithms.md §E7).
    """

    key: str
    title: str
    filename: str
    write: Callable[..., ExportFile]
    parse: Callable[[str], dict[str, float]]
    log_params: tuple[str, ...] = ()
    merged: bool = False


def density(model: ImuModel, sensor: str, term: str, name: str) -> Value:
    """A continuous-time term of ``sensor`` written as it is."""
    s = model.sensor(sensor)
    kind = CONTINUOUS if term in ("N", "K") else "continuous-time (not a density)"
    return Value(
        name,
        getattr(s, term),
        units.term_unit(s.unit, term),
        kind,
        f"{term} of the {sensor} as fitted (no conversion)",
        s.k_withheld if term == "K" else "",
    )


def white_sigma(model: ImuModel, sensor: str, name: str, rate: float, what: str) -> Value:
    """The white noise's std per step at ``rate``: ``N √rate``."""
    s = model.sensor(sensor)
    return Value(
        name,
        units.sigma_at(s.N, rate),
        s.unit,
        discrete(rate),
        f"N sqrt(f) = {s.N:.6g} x sqrt({rate:g}), {what}",
    )


def walk_sigma(model: ImuModel, sensor: str, name: str, rate: float, what: str) -> Value:
    """A bias walk's per-step change over the step time at ``rate``: ``K √rate``."""
    s = model.sensor(sensor)
    return Value(
        name,
        units.walk_rate_sigma(s.K, rate),
        units.term_unit(s.unit, "R"),
        discrete(rate),
        f"K sqrt(f) = {s.K:.6g} x sqrt({rate:g}), {what}",
        s.k_withheld,
    )


def ekf_step_values(
    model: ImuModel, rate: float, at: str, imu: tuple[str, str, str, str], gnss: tuple[str, str]
) -> list[Value]:
    """An EKF's IMU noise stds at its prediction ``rate``, and its GNSS stds when measured.

    ``imu`` names gyro noise, accel noise, gyro bias, accel bias; ``gnss`` position and
    velocity. PX4's EKF2 and ArduPilot's EKF3 both add ``(dt·value)²`` per prediction step
    (their modules cite the lines), so both take E7.1 and E7.2 at that step's rate.
    """
    gyro, acc, gyro_b, acc_b = imu
    values = [
        white_sigma(model, "gyroscope", gyro, rate, f"rate std over one {at}"),
        white_sigma(model, "accelerometer", acc, rate, f"std over one {at}"),
        walk_sigma(model, "gyroscope", gyro_b, rate, f"bias step / dt, {at}"),
        walk_sigma(model, "accelerometer", acc_b, rate, f"bias step / dt, {at}"),
    ]
    for key, name, unit in zip(("position", "velocity"), gnss, ("m", "m/s"), strict=True):
        if key in model.gnss:
            what = f"sqrt(R) of the GNSS {key} record"
            values.append(Value(name, model.gnss[key], unit, "measurement std", what))
    return values


def range_warning(name: str, value: float, bounds: tuple[float | None, float | None]) -> str | None:
    """The warning line (without its comment character) for ``value`` outside a consumer's
    documented ``bounds`` (``(lo, hi)``, None: no bound), or None inside them."""
    lo, hi = bounds
    if not ((lo is not None and value < lo) or (hi is not None and value > hi)):
        return None
    bound = f"minimum {lo}" if hi is None else f"maximum {hi}" if lo is None else ""
    return (
        f"WARNING: {name} is outside the documented {bound or f'range [{lo}, {hi}]'}"
        ": the ground station may refuse it or the EKF clip it; written as computed"
    )


def number(v: float) -> str:
    """A value as written in every file: 10 significant digits, exponent form."""
    return f"{v:.9e}"


_ASCII = {"√": "sqrt", "²": "^2", "³": "^3", "⁴": "^4", "§": "section ", "µ": "u", "·": "*"}


def ascii_text(text: str) -> str:
    """``text`` in ASCII (``√Hz`` as ``sqrtHz``...): for readers that may not take UTF-8
    (OpenCV's FileStorage YAML, ground stations' parameter files, older MATLAB)."""
    for k, v in _ASCII.items():
        text = text.replace(k, v)
    return text

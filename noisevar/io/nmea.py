"""NMEA 0183 logs (GGA/RMC) to local east/north/up metres, speed and course."""

from __future__ import annotations

import datetime
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.io.table import LoadedTable, _period_from_time

_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_KNOT = 1852.0 / 3600.0


def _looks_like_nmea(text: str) -> bool:
    for ln in text.splitlines()[:20]:
        s = ln.strip()
        if not s:
            continue
        return bool(re.match(r"^[$!][A-Z]{2}[A-Z]{3},", s))
    return False


def geodetic_to_enu(lat_deg: ArrayLike, lon_deg: ArrayLike, alt_m: ArrayLike) -> NDArray:
    """WGS-84 latitude, longitude, height to local east/north/up metres from the first point.

    Parameters
    ----------
    lat_deg, lon_deg : array_like
        Geodetic latitude and longitude (degrees).
    alt_m : array_like
        Height (metres; zeros when unknown).

    Returns
    -------
    ndarray, shape (n, 3)
        East, north, up of each point in the local tangent frame at the first.
    """
    lat = np.radians(np.asarray(lat_deg, dtype=float))
    lon = np.radians(np.asarray(lon_deg, dtype=float))
    h = np.asarray(alt_m, dtype=float)
    e2 = _WGS84_F * (2.0 - _WGS84_F)
    nrad = _WGS84_A / np.sqrt(1.0 - e2 * np.sin(lat) ** 2)
    xyz = np.column_stack(
        [
            (nrad + h) * np.cos(lat) * np.cos(lon),
            (nrad + h) * np.cos(lat) * np.sin(lon),
            (nrad * (1.0 - e2) + h) * np.sin(lat),
        ]
    )
    d = xyz - xyz[0]
    sl, cl = np.sin(lat[0]), np.cos(lat[0])
    so, co = np.sin(lon[0]), np.cos(lon[0])
    rot = np.array([[-so, co, 0.0], [-sl * co, -sl * so, cl], [cl * co, cl * so, sl]])
    return d @ rot.T


@dataclass
class _Scan:
    """What one pass over an NMEA log found: epochs by (day, second of day), and the problems."""

    epochs: dict[tuple[int, float], dict[str, Any]] = field(default_factory=dict)
    order: list[tuple[int, float]] = field(default_factory=list)
    day: int = 0
    last_sod: float | None = None
    checksum_errors: list[str] = field(default_factory=list)
    missing_checksum: list[int] = field(default_factory=list)
    parse_errors: list[str] = field(default_factory=list)
    n_sentences: int = 0
    n_invalid: int = 0

    def epoch(self, ts: Any) -> dict[str, Any]:
        """The record of the epoch of timestamp ``ts`` (created on first sight)."""
        sod = ts.hour * 3600 + ts.minute * 60 + ts.second + ts.microsecond / 1e6
        if self.last_sod is not None and sod < self.last_sod - 43200:
            self.day += 1  # midnight roll-over
        self.last_sod = sod
        key = (self.day, round(sod, 3))
        if key not in self.epochs:
            self.epochs[key] = {}
            self.order.append(key)
        return self.epochs[key]


def _parse_sentence(scan: _Scan, line_no: int, s: str) -> Any:
    """The parsed GGA/RMC sentence, or None (recording why in ``scan``)."""
    import pynmea2

    try:
        return pynmea2.parse(s, check=True)
    except pynmea2.ChecksumError as exc:
        detail = exc.args[0] if exc.args else "checksum"
        detail = str(detail[0] if isinstance(detail, tuple) else detail)
        if "missing" in detail:
            scan.missing_checksum.append(line_no)
        else:
            scan.checksum_errors.append(f"line {line_no} ({detail})")
    except pynmea2.ParseError:
        scan.parse_errors.append(f"line {line_no} cannot be parsed")
    return None


def _fill(rec: dict[str, Any], kind: str, msg: Any) -> bool:
    """Copy a sentence's fix into its epoch record; False when it has no valid fix."""
    if kind == "GGA":
        if int(msg.gps_qual or 0) == 0 or not msg.lat:
            return False
        rec["lat"], rec["lon"] = float(msg.latitude), float(msg.longitude)
        rec["alt"] = float(msg.altitude) if msg.altitude is not None else np.nan
        return True
    if msg.status != "A" or not msg.lat:
        return False
    rec.setdefault("lat", float(msg.latitude))
    rec.setdefault("lon", float(msg.longitude))
    spd = msg.spd_over_grnd
    rec["speed"] = float(spd) * _KNOT if spd not in (None, "") else np.nan
    crs = msg.true_course
    rec["course"] = float(crs) if crs not in (None, "") else np.nan
    return True


def _fill_epoch(scan: _Scan, line_no: int, kind: str, msg: Any, ts: datetime.time) -> None:
    """Add a sentence's fix to its epoch; a malformed or impossible position is skipped."""
    epoch = scan.epoch(ts)
    rec: dict[str, Any] = {}
    try:
        if not _fill(rec, kind, msg):
            scan.n_invalid += 1
            return
    except (TypeError, ValueError, AttributeError):
        scan.parse_errors.append(f"line {line_no} has a malformed field")
        return
    if not (abs(rec["lat"]) <= 90.0 and abs(rec["lon"]) <= 180.0):
        scan.parse_errors.append(
            f"line {line_no} has an impossible position (latitude {rec['lat']:.6g}, "
            f"longitude {rec['lon']:.6g})"
        )
        return
    if kind == "GGA":
        epoch.update(rec)
    else:
        for key, val in rec.items():
            epoch[key] = val if key in ("speed", "course") else epoch.get(key, val)


def _scan(text: str) -> _Scan:
    scan = _Scan()
    for line_no, ln in enumerate(text.splitlines(), start=1):
        s = ln.strip()
        if not s:
            continue
        if not s.startswith(("$", "!")):
            scan.parse_errors.append(f"line {line_no} is not an NMEA sentence")
            continue
        kind = s[3:6]
        if kind not in ("GGA", "RMC"):
            continue
        scan.n_sentences += 1
        msg = _parse_sentence(scan, line_no, s)
        if msg is None:
            continue
        try:
            ts = msg.timestamp
        except (AttributeError, TypeError, ValueError):
            scan.parse_errors.append(f"line {line_no} has an invalid time")
            continue
        if ts is None:
            scan.n_invalid += 1
            continue
        if not isinstance(ts, datetime.time):
            scan.parse_errors.append(f"line {line_no} has an invalid time")
            continue
        _fill_epoch(scan, line_no, kind, msg, ts)
    return scan


def _valid_fixes(scan: _Scan, name: str) -> list[tuple[int, float]]:
    """Epochs with a fix, after refusing corrupted or too short logs."""
    if scan.checksum_errors:
        n = len(scan.checksum_errors)
        more = f" and {n - 1} more" if n > 1 else ""
        raise NoisevarError(
            f"{name}: NMEA checksum error at {scan.checksum_errors[0]}{more}: the log is "
            "corrupted; repair or drop those lines before loading"
        )
    if scan.n_sentences == 0:
        raise NoisevarError(f"{name}: no GGA or RMC sentences found (positions come from those)")
    if scan.missing_checksum:
        scan.parse_errors.append(f"line {scan.missing_checksum[0]} has no checksum (truncated?)")
    fixes = [k for k in scan.order if "lat" in scan.epochs[k]]
    if not fixes and scan.missing_checksum:
        raise NoisevarError(
            f"{name}: {len(scan.missing_checksum)} GGA/RMC sentences have no checksum (*hh), so "
            "they cannot be verified: log with checksums on"
        )
    if len(fixes) < 2:
        raise NoisevarError(
            f"{name}: only {len(fixes)} GGA/RMC epochs with a valid fix: give a longer log"
        )
    return fixes


#: The columns of a position turned into local metres (:func:`geodetic_to_enu`).
ENU_NAMES = ("east_m", "north_m", "up_m")
#: Units of the columns an NMEA log gives (pint syntax).
NMEA_UNITS = {**dict.fromkeys(ENU_NAMES, "m"), "speed_mps": "m/s", "course_deg": "deg"}


def _columns(recs: list[dict[str, Any]], t: NDArray) -> dict[str, NDArray]:
    lat = np.array([r["lat"] for r in recs])
    lon = np.array([r["lon"] for r in recs])
    alt = np.array([r.get("alt", np.nan) for r in recs])
    has_alt = np.all(np.isfinite(alt))
    enu = geodetic_to_enu(lat, lon, alt if has_alt else np.zeros_like(lat))
    columns: dict[str, NDArray] = {"time": t, **dict(zip(ENU_NAMES[:2], enu.T[:2], strict=True))}
    if has_alt:
        columns[ENU_NAMES[2]] = enu[:, 2]
    speed = np.array([r.get("speed", np.nan) for r in recs])
    course = np.array([r.get("course", np.nan) for r in recs])
    if np.any(np.isfinite(speed)):
        columns["speed_mps"] = speed
    if np.any(np.isfinite(course)):
        columns["course_deg"] = course
    return columns


def _read_nmea(text: str, name: str) -> LoadedTable:
    scan = _scan(text)
    fixes = _valid_fixes(scan, name)
    t = np.array([k[0] * 86400.0 + k[1] for k in fixes])
    columns = _columns([scan.epochs[k] for k in fixes], t - t[0])
    notes = [f"{len(fixes)} epochs from {scan.n_sentences} GGA/RMC sentences"]
    if scan.n_invalid:
        notes.append(f"{scan.n_invalid} sentences without a valid fix were skipped")
    if scan.parse_errors:
        notes.append(f"{len(scan.parse_errors)} lines skipped ({scan.parse_errors[0]})")
    period = _period_from_time(columns["time"], notes)
    units = {c: u for c, u in NMEA_UNITS.items() if c in columns}
    return LoadedTable(name, columns, "nmea", "time", period, notes, units)

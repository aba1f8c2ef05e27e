"""RTKLIB solution files (``.pos``, as RTKPOST, RTKNAVI and rnx2rtkp write them): ``%``
header lines, the last of which names the columns, a time of two fields (a date and a clock,
or a GPS week and its seconds), then the position: latitude, longitude, height (degrees,
or degrees, minutes and seconds), ECEF x/y/z or a baseline's east/north/up (m), the
quality flag Q, the satellite count and the solution's own standard deviations."""

from __future__ import annotations

import datetime
import re

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.header_units import header_unit
from noisevar.io.limits import echo
from noisevar.io.nmea import _WGS84_A, _WGS84_F, ENU_NAMES
from noisevar.io.table import LoadedTable

#: The column line of a solution file: ``%`` then its time system, then the first column
#: (searched in a header line: a line end lost runs it on the line above).
_COLUMNS = re.compile(r"%\s+(GPST|UTC|JST)\s+[a-z]", re.IGNORECASE)
#: Lines of the head searched for the column line (a header block is about 25 lines).
_HEAD_LINES = 60
#: Characters of the head searched for it (its header lines are under 200 characters).
_HEAD_CHARS = 200 * _HEAD_LINES
#: The GPS time's origin and a week's seconds.
_GPS_EPOCH, _WEEK = datetime.datetime(1980, 1, 6), 604800.0
NOTE = (
    "read as an RTKLIB solution file: its '%' header skipped, the time's two fields joined "
    "({system}; the quality flag Q and the solution's own standard deviations kept as "
    "columns){geo}"
)
_GEO = (
    "; latitude, longitude and height turned into east, north and up metres from the first "
    "point (each scaled at that point, so that each keeps its stored digits' grid)"
)


def is_rtklib(text: str) -> bool:
    """Whether ``text`` (a file's head) is an RTKLIB solution file."""
    return _column_line(text[:_HEAD_CHARS].splitlines()) is not None


def _column_line(lines: list[str]) -> tuple[int, str] | None:
    """The last column line of the head (its index, and the line from its ``%``), or None."""
    found = [(i, ln[m.start() :]) for i, ln in enumerate(lines[:_HEAD_LINES])
             if ln.startswith("%") and (m := _COLUMNS.search(ln))]  # fmt: skip
    return found[-1] if found else None


def _time(a: str, b: str) -> str:
    """The ISO date-time of a row's two time fields (``2021/03/22 15:20:44.000``, or a GPS
    week and its seconds ``2168 284819.000``)."""
    if "/" in a:
        iso = f"{a.replace('/', '-')}T{b}"
        datetime.datetime.fromisoformat(iso)  # a date that is none raises here, with its row
        return iso
    moment = _GPS_EPOCH + datetime.timedelta(seconds=float(a) * _WEEK + float(b))
    return moment.isoformat()


def _angle(cells: list[str]) -> float:
    """Degrees of an angle written as degrees, or as degrees, minutes and seconds."""
    if len(cells) == 1:
        return float(cells[0])
    d, m, s = (float(c) for c in cells)
    sign = -1.0 if cells[0].startswith("-") else 1.0
    return sign * (abs(d) + m / 60.0 + s / 3600.0)


def local_metres(lat: np.ndarray, lon: np.ndarray, h: np.ndarray) -> np.ndarray:
    """East, north, up metres from the first point, each column scaled at that point.

    Parameters
    ----------
    lat, lon : ndarray
        WGS-84 latitude and longitude (degrees).
    h : ndarray
        Ellipsoidal height (m).

    Returns
    -------
    ndarray, shape (n, 3)

    Notes
    -----
    Each axis is one stored column times a constant (the meridian and prime-vertical radii
    at the first point), so a column's grid (RTKLIB's 1e-9 degree, 0.1 mm) stays a grid
    and the held-values and grid rules still read it; the full rotation
    (:func:`noisevar.io.nmea.geodetic_to_enu`) mixes the columns and smears it. The scale
    drifts by 2e-4 per km of latitude: a smooth distortion, no noise.
    """
    e2 = _WGS84_F * (2.0 - _WGS84_F)
    phi = np.radians(lat[0])
    w = 1.0 - e2 * np.sin(phi) ** 2
    north = np.radians(lat - lat[0]) * (_WGS84_A * (1.0 - e2) / w**1.5 + h[0])
    east = np.radians(lon - lon[0]) * (_WGS84_A / np.sqrt(w) + h[0]) * np.cos(phi)
    return np.column_stack([east, north, h - h[0]])


def _rows(lines: list[str], width: int, dms: bool, name: str) -> list[list[str]]:
    """The data rows' cells (time joined, a latitude and longitude in degrees, minutes and
    seconds turned into degrees)."""
    rows = []
    for i, ln in enumerate(lines):
        cells = ln.split()
        if not cells or ln.startswith("%"):
            continue
        if len(cells) != width + (4 if dms else 0) + 2:
            raise NoisevarError(
                f"{echo(name)}: row {i + 1} of the RTKLIB solution has {len(cells)} fields, "
                f"its column line names {width + 1}: give the file as RTKLIB wrote it"
            )
        try:
            if dms:
                cells = [*cells[:2], str(_angle(cells[2:5])), str(_angle(cells[5:8])), *cells[8:]]
            rows.append([_time(*cells[:2]), *cells[2:]])
        except (ValueError, OverflowError) as exc:  # an untrusted row: one line, its number
            raise NoisevarError(
                f"{echo(name)}: row {i + 1} of the RTKLIB solution has a time or an angle that "
                f"is not one ({echo(' '.join(cells[:8]), 60)!r}): give the file as RTKLIB "
                "wrote it"
            ) from exc
    return rows


def _positions(rows: list[list[str]], name: str) -> np.ndarray:
    """Each row's latitude, longitude and height as numbers, refused in one line where one is
    not a finite latitude (within ±90°), longitude or height."""
    try:
        cells = np.asarray([r[1:4] for r in rows], float)
    except ValueError as exc:
        raise NoisevarError(
            f"{echo(name)}: a latitude, longitude or height of the RTKLIB solution is not a "
            "number: give the file as RTKLIB wrote it"
        ) from exc
    bad = ~np.isfinite(cells).all(axis=1) | (np.abs(cells[:, 0]) > 90.0)
    if bad.any():
        raise NoisevarError(
            f"{echo(name)}: solution {int(np.argmax(bad)) + 1} of the RTKLIB file has no finite "
            "latitude (within ±90°), longitude and height: remove it, or give the file as "
            "RTKLIB wrote it"
        )
    return cells


def rtklib_csv(text: str, name: str) -> tuple[str, str]:
    """The solution file ``text`` as a CSV table (a ``time`` column of ISO date-times, then
    the columns the file names, a row of their units) and the note saying how it was read.

    Notes
    -----
    Read as a table, the ``%`` lines were refused as an unknown comment marker, or, with
    only the column line, ``%`` was taken for a date column and the position read in
    degrees (tracklib's RTKLIB files); a column line run on the line above (tracklib's
    ``sol.pos``) named columns ``%``, ``pos``, ``:`` and numbers. Geodetic positions
    become local east/north/up metres (:func:`local_metres`), so that R is in m².
    """
    lines = text.splitlines()
    at, columns = _column_line(lines) or (0, "")
    system, *names = columns[1:].split()
    dms = bool(names) and names[0].startswith("latitude(d'")
    rows = _rows(lines[at + 1 :], len(names), dms, name)
    if not rows:
        raise NoisevarError(f"{echo(name)}: an RTKLIB solution file without solutions")
    units = [header_unit(n) or "" for n in names]
    geo = len(names) >= 3 and names[0].startswith("latitude") and names[1].startswith("longitude")
    if geo:
        cells = _positions(rows, name)
        enu = local_metres(cells[:, 0], cells[:, 1], cells[:, 2])
        rows = [[r[0], *map(repr, map(float, e)), *r[4:]] for r, e in zip(rows, enu, strict=True)]
        names, units = [*ENU_NAMES, *names[3:]], ["m", "m", "m", *units[3:]]
    out = [",".join(["time", *names]), ",".join(["", *units])]
    out += [",".join(r) for r in rows]
    return "\n".join(out) + "\n", NOTE.format(system=system, geo=_GEO if geo else "")


#: What an RTKLIB solution's columns other than its position (and velocity) are, by name
#: without the unit: none is a measured signal.
SIDE = {
    "Q": "the solution's quality flag (1 fix, 2 float, 5 single...)",
    "ns": "the number of satellites used",
    "age": "the age of the differential corrections",
    "ratio": "the ambiguity ratio test's value",
}


def with_side_columns(table: LoadedTable) -> LoadedTable:
    """A table read from :func:`rtklib_csv` with the solution's columns other than its
    position (and velocity) named as side columns: :data:`SIDE`, and ``sd*``, the
    solution's own standard deviations and covariances.

    Notes
    -----
    They were read as signals: the Signal page's channels and the Two sensors page's sensors
    opened on ``sdn(m)``, ``sde(m)``, ``sdne(m)``, and ``--columns all`` estimated the noise
    of a satellite count. The standard deviations are not paired with R as a ROS message's
    covariance is: a GNSS solution's covers slow errors (multipath, the geometry) that the
    sample-to-sample R does not see (docs/algorithms.md, *Declared noise*).
    """
    side = {}
    for c in table.data_columns:
        stem = c.split("(")[0]
        if stem in SIDE:
            side[c] = SIDE[stem]
        elif stem.startswith("sd"):
            side[c] = "the solution's own standard deviation or covariance"
    table.side_columns = side
    return table

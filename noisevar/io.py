"""Loading measured signals from files: CSV/TSV, ``.npy`` and NMEA 0183 (GGA/RMC).

One entry point, :func:`load_table`, turns a file (a path or its bytes) into a
:class:`LoadedTable`: named float columns, the time column if there is one,
and the sample period it implies. :func:`pick_column` then gives one signal
for :func:`noisevar.estimate`. The CLI and the dashboard share these two
functions, so a file that loads in one loads in the other.

Every failure raises :class:`~noisevar.errors.NoisevarError` with one message
that says what is wrong and where (row, column, line), never a parser
traceback.

Formats
-------
CSV / TSV / whitespace-separated text
    The delimiter is detected (tab, comma, semicolon, else whitespace). The
    first row is a header when any of its fields is not a number; otherwise
    the columns are named ``col0, col1, ...``. Lines starting with ``#`` are
    comments. A cell that is not a number is refused with its row and column;
    an empty cell or ``NaN`` becomes NaN (refused later by
    :func:`pick_column` for the column actually used, unless asked to drop).
    A column named like a time (``t``, ``time``, ``time_s``, ``timestamp``,
    ``seconds``...) gives the sample period (median step); ISO date-times in
    it are converted to seconds from the first.
``.npy``
    Read with ``np.load(allow_pickle=False)`` only (a pickled object array is
    refused: loading it could run code). A 1-D array is one column
    ``value``; a 2-D array ``(n, k)`` gives columns ``col0..``; a structured
    array gives one column per field.
NMEA 0183
    GGA and RMC sentences (any talker: GP, GN, GL...) with a valid fix are
    merged by epoch. Positions become local east/north/up metres from the
    first fix (WGS-84, exact ECEF to local ENU rotation); RMC gives speed
    (m/s) and course (degrees). A sentence with a wrong or missing checksum
    makes the whole file refused, naming the line: a corrupted log should not
    silently feed an estimator. Other sentence types are ignored.
"""

from __future__ import annotations

import csv
import hashlib
import io
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError

#: Names (lower case, units in brackets stripped) recognised as a time column.
TIME_NAMES = ("t", "time", "time_s", "times", "timestamp", "seconds", "sec", "secs", "s", "epoch")
#: File extensions read as text tables.
TABLE_EXTENSIONS = (".csv", ".tsv", ".txt", ".dat", ".tab")
#: File extensions read as NMEA 0183 logs (content is also sniffed).
NMEA_EXTENSIONS = (".nmea", ".nma", ".gps", ".log", ".ubx.nmea")
#: Relative spread of the time steps above which the sampling counts as not uniform.
UNIFORM_TOLERANCE = 0.01
_NPY_MAGIC = b"\x93NUMPY"
_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_KNOT = 1852.0 / 3600.0
_NA_TOKENS = ["", "nan", "NaN", "NAN", "na", "NA", "n/a", "N/A", "null", "NULL", "None", "-"]


@dataclass
class LoadedTable:
    """Columns of numbers read from one file.

    Attributes
    ----------
    name : str
        File name (for messages and titles).
    columns : dict of str to ndarray
        Column name to float samples, all of the same length; NaN marks an
        empty cell.
    kind : {"csv", "tsv", "text", "npy", "nmea", "generated"}
        The format the file was read as.
    time_column : str or None
        The column holding the sample times (seconds), if any.
    sample_period : float or None
        Median time step of ``time_column`` (seconds), if any.
    notes : list of str
        Plain-language remarks (non-uniform sampling, skipped sentences...).
    """

    name: str
    columns: dict[str, NDArray]
    kind: str
    time_column: str | None = None
    sample_period: float | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def n_rows(self) -> int:
        """Number of samples per column."""
        return int(next(iter(self.columns.values())).size) if self.columns else 0

    @property
    def data_columns(self) -> list[str]:
        """Column names other than the time column (the candidate signals)."""
        return [c for c in self.columns if c != self.time_column]

    def time(self) -> NDArray | None:
        """The time column (seconds) or None."""
        return self.columns.get(self.time_column) if self.time_column else None

    def digest(self) -> str:
        """Content hash of all columns (names and values): a cache key."""
        h = hashlib.blake2b(digest_size=16)
        for name, col in self.columns.items():
            h.update(name.encode())
            h.update(np.ascontiguousarray(col, dtype=float).tobytes())
        return h.hexdigest()

    def to_csv(self) -> str:
        """The table as CSV text with a header row."""
        names = list(self.columns)
        data = np.column_stack([self.columns[c] for c in names]) if names else np.empty((0, 0))
        buf = io.StringIO()
        buf.write(",".join(names) + "\n")
        np.savetxt(buf, data, delimiter=",", fmt="%.10g")
        return buf.getvalue()


# --------------------------------------------------------------------------- helpers
def content_digest(data: bytes | ArrayLike) -> str:
    """Short content hash of bytes or of an array's values (a cache key).

    Parameters
    ----------
    data : bytes or array_like
        File bytes, or samples (hashed as contiguous float64 plus shape).

    Returns
    -------
    str
        32 hex characters (BLAKE2b, 16 bytes).
    """
    h = hashlib.blake2b(digest_size=16)
    if isinstance(data, (bytes, bytearray, memoryview)):
        h.update(bytes(data))
    else:
        arr = np.ascontiguousarray(np.asarray(data, dtype=float))
        h.update(str(arr.shape).encode())
        h.update(arr.tobytes())
    return h.hexdigest()


def _is_time_name(name: str) -> bool:
    base = re.sub(r"[\[\(].*?[\]\)]", "", name).strip().lower().replace(" ", "_")
    return base in TIME_NAMES or base.startswith("time_") or base.endswith("_time")


def _period_from_time(t: NDArray, notes: list[str]) -> float | None:
    if t.size < 2 or not np.all(np.isfinite(t)):
        notes.append("the time column has missing values: sample period not taken from it")
        return None
    dt = np.diff(t)
    if np.any(dt <= 0):
        first = int(np.argmax(dt <= 0)) + 1
        notes.append(
            f"the time column is not strictly increasing (row {first}): "
            "sample period not taken from it"
        )
        return None
    period = float(f"{float(np.median(dt)):.12g}")  # 0.1, not 0.09999999999999787
    spread = float((dt.max() - dt.min()) / period)
    if spread > UNIFORM_TOLERANCE:
        notes.append(
            f"sampling is not uniform: steps from {dt.min():.4g} s to {dt.max():.4g} s "
            f"(median {period:.4g} s); the estimators assume uniform sampling"
        )
    return period


def _check_binary(raw: bytes, name: str) -> str:
    head = raw[:65536]
    if b"\x00" in head:
        raise NoisevarError(
            f"{name} looks like a binary file (it contains NUL bytes): give a CSV/TSV text "
            "table, an NMEA 0183 log, or a .npy array"
        )
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
        ctrl = sum(1 for ch in text[:65536] if ord(ch) < 32 and ch not in "\r\n\t")
        if ctrl > 0.01 * min(len(text), 65536):
            raise NoisevarError(
                f"{name} looks like a binary file (not UTF-8 text): give a CSV/TSV text table, "
                "an NMEA 0183 log, or a .npy array"
            ) from None
    return text


def _read_source(source: str | os.PathLike | bytes, name: str | None) -> tuple[bytes, str]:
    if isinstance(source, (bytes, bytearray, memoryview)):
        return bytes(source), name or "upload"
    path = Path(source)
    if not path.is_file():
        raise NoisevarError(f"no such file: {path}")
    try:
        return path.read_bytes(), name or path.name
    except OSError as exc:
        raise NoisevarError(f"cannot read {path}: {exc.strerror or exc}") from None


# ------------------------------------------------------------------------------ text
def _sniff_delimiter(lines: list[str]) -> str | None:
    sample = lines[:50]
    if any("\t" in ln for ln in sample):
        return "\t"
    for cand in (",", ";", "|"):
        counts = {ln.count(cand) for ln in sample}
        if len(counts) == 1 and counts != {0}:
            return cand
    for cand in (",", ";"):
        if any(cand in ln for ln in sample):
            return cand
    return None  # whitespace


def _split(line: str, delim: str | None) -> list[str]:
    if delim is None:
        return line.split()
    return next(csv.reader([line], delimiter=delim))


def _is_number(cell: str) -> bool:
    s = cell.strip()
    if s == "":
        return True
    try:
        float(s)
    except ValueError:
        return False
    return True


def _unique_names(raw: list[str]) -> list[str]:
    names: list[str] = []
    for i, r in enumerate(raw):
        base = r.strip().strip('"').strip() or f"col{i}"
        candidate, k = base, 1
        while candidate in names:
            k += 1
            candidate = f"{base}_{k}"
        names.append(candidate)
    return names


def _parse_time_strings(values: list[str]) -> NDArray | None:
    """ISO date-times to seconds from the first; None when they are not date-times."""
    try:
        t = np.array(values, dtype="datetime64[ns]")
    except (ValueError, TypeError):
        return None
    if np.any(np.isnat(t)):
        return None
    return (t - t[0]).astype("timedelta64[ns]").astype(float) / 1e9


def _meaningful(line: str) -> bool:
    s = line.strip()
    return bool(s) and not s.startswith("#")


def _data_line_number(text: str, header_line: int, row: int) -> int:
    """File line number (1-based) of data row ``row`` (0-based) after line ``header_line``."""
    count = -1
    for i, ln in enumerate(text.splitlines(), start=1):
        if i <= header_line or not _meaningful(ln):
            continue
        count += 1
        if count == row:
            return i
    return header_line + row + 1


def _read_text_table(text: str, name: str) -> LoadedTable:
    head: list[tuple[int, str]] = []
    for i, ln in enumerate(text[:1_000_000].splitlines(), start=1):
        if _meaningful(ln):
            head.append((i, ln))
            if len(head) >= 60:
                break
    if not head:
        raise NoisevarError(f"{name} is empty: no data rows (only blank or # comment lines)")
    delim = _sniff_delimiter([ln for _, ln in head])
    first = _split(head[0][1], delim)
    header = not all(_is_number(c) for c in first)
    if header:
        names = _unique_names(first)
        header_line = head[0][0]
        if len(head) < 2:
            raise NoisevarError(f"{name} has a header but no data rows")
    else:
        names = [f"col{i}" for i in range(len(first))]
        header_line = head[0][0] - 1
    ncol = len(names)
    time_idx = next((i for i, c in enumerate(names) if _is_time_name(c)), None)
    columns = _parse_body(text, header_line, names, delim, name, time_idx)
    notes: list[str] = []
    kind = "tsv" if delim == "\t" else ("csv" if delim else "text")
    time_col = names[time_idx] if time_idx is not None else None
    period = _period_from_time(columns[time_col], notes) if time_col else None
    empty = [c for c in names if np.all(np.isnan(columns[c]))]
    if len(empty) == ncol:
        raise NoisevarError(f"{name} has no numbers: every cell is empty or NaN")
    for c in empty:
        notes.append(f"column {c!r} is empty")
    return LoadedTable(name, columns, kind, time_col, period, notes)


def _parse_body(
    text: str,
    header_line: int,
    names: list[str],
    delim: str | None,
    name: str,
    time_idx: int | None,
) -> dict[str, NDArray]:
    import pandas as pd

    ncol = len(names)
    sep = r"\s+" if delim is None else delim
    try:
        df = pd.read_csv(
            io.StringIO(text),
            sep=sep,
            header=None,
            names=list(range(ncol)),
            skiprows=header_line,
            comment="#",
            skip_blank_lines=True,
            na_values=_NA_TOKENS,
            keep_default_na=True,
            engine="c",
            skipinitialspace=True,
            on_bad_lines="error",
            quotechar='"',
            index_col=False,
        )
    except Exception as exc:  # noqa: BLE001 - pandas raises several parser types
        msg = str(exc)
        m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", msg)
        if m:
            raise NoisevarError(
                f"{name}: line {m.group(2)} has {m.group(3)} fields but the "
                f"table has {m.group(1)}: every row must have the same columns"
            ) from None
        if "No columns to parse" in msg:
            raise NoisevarError(f"{name} has a header but no data rows") from None
        first = msg.splitlines()[0] if msg else type(exc).__name__
        raise NoisevarError(f"{name}: cannot parse the table ({first})") from None
    if len(df) == 0:
        raise NoisevarError(f"{name} has a header but no data rows")
    columns: dict[str, NDArray] = {}
    for i, cname in enumerate(names):
        col = df[i]
        if pd.api.types.is_numeric_dtype(col.dtype) and not pd.api.types.is_bool_dtype(col.dtype):
            # a writable copy: pandas may hand out read-only views (copy-on-write), which
            # some numerical libraries (PyWavelets) refuse
            columns[cname] = np.array(col.to_numpy(dtype=float, na_value=np.nan), dtype=float)
            continue
        coerced = pd.to_numeric(col, errors="coerce")
        bad = (coerced.isna() & col.notna()).to_numpy()
        if bad.any():
            if i == time_idx:
                times = _parse_time_strings([str(v).strip() for v in col.tolist()])
                if times is not None:
                    columns[cname] = times
                    continue
            j = int(np.argmax(bad))
            raise NoisevarError(
                f"{name}: line {_data_line_number(text, header_line, j)}, column {cname!r}: "
                f"{str(col.iloc[j])!r} is not a number (only numeric columns can be loaded)"
            )
        columns[cname] = np.array(coerced.to_numpy(dtype=float, na_value=np.nan), dtype=float)
    return columns


# ------------------------------------------------------------------------------- npy
def _read_npy(raw: bytes, name: str) -> LoadedTable:
    try:
        arr = np.load(io.BytesIO(raw), allow_pickle=False)
    except ValueError as exc:
        if "pickle" in str(exc).lower():
            raise NoisevarError(
                f"{name} holds Python objects (a pickled array), which are refused for safety: "
                "save a numeric array with np.save"
            ) from None
        raise NoisevarError(f"{name} is not a valid .npy file ({exc})") from None
    except Exception as exc:  # noqa: BLE001 - np.load raises several types on corrupt files
        raise NoisevarError(f"{name} is not a valid .npy file ({type(exc).__name__})") from None
    if not isinstance(arr, np.ndarray):  # pragma: no cover - .npz is read by np.load too
        raise NoisevarError(f"{name} is not a single .npy array")
    notes: list[str] = []
    if arr.dtype.names:
        if arr.ndim != 1:
            raise NoisevarError(f"{name}: a structured array must be 1-D, got shape {arr.shape}")
        columns = {}
        for fname in arr.dtype.names:
            try:
                columns[fname] = np.asarray(arr[fname], dtype=float)
            except (TypeError, ValueError):
                raise NoisevarError(f"{name}: field {fname!r} is not numeric") from None
    else:
        if arr.dtype.kind not in "biuf":
            raise NoisevarError(
                f"{name}: the array has dtype {arr.dtype}, not real numbers "
                "(give int or float samples)"
            )
        if arr.ndim == 0 or arr.size == 0:
            raise NoisevarError(f"{name} is empty or a single number: give a 1-D or 2-D array")
        if arr.ndim == 1:
            columns = {"value": arr.astype(float)}
        elif arr.ndim == 2:
            if arr.shape[0] < arr.shape[1] and arr.shape[0] <= 16:
                notes.append(f"array of shape {arr.shape} read as {arr.shape[0]} rows of signals")
                arr = arr.T
            columns = {f"col{i}": arr[:, i].astype(float) for i in range(arr.shape[1])}
        else:
            raise NoisevarError(
                f"{name} has shape {arr.shape}: give a 1-D signal or a 2-D (samples, columns) array"
            )
    time_col = next((c for c in columns if _is_time_name(c)), None)
    period = _period_from_time(columns[time_col], notes) if time_col else None
    return LoadedTable(name, columns, "npy", time_col, period, notes)


# ------------------------------------------------------------------------------ NMEA
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


def _read_nmea(text: str, name: str) -> LoadedTable:
    import pynmea2

    epochs: dict[tuple[int, float], dict[str, Any]] = {}
    order: list[tuple[int, float]] = []
    day = 0
    last_sod: float | None = None
    checksum_errors: list[str] = []
    missing_checksum: list[int] = []
    parse_errors: list[str] = []
    n_sentences = 0
    n_invalid = 0
    for line_no, ln in enumerate(text.splitlines(), start=1):
        s = ln.strip()
        if not s:
            continue
        if not s.startswith(("$", "!")):
            parse_errors.append(f"line {line_no} is not an NMEA sentence")
            continue
        kind = s[3:6]
        if kind not in ("GGA", "RMC"):
            continue
        n_sentences += 1
        try:
            msg = pynmea2.parse(s, check=True)
        except pynmea2.ChecksumError as exc:
            detail = exc.args[0] if exc.args else "checksum"
            detail = str(detail[0] if isinstance(detail, tuple) else detail)
            if "missing" in detail:
                missing_checksum.append(line_no)
            else:
                checksum_errors.append(f"line {line_no} ({detail})")
            continue
        except pynmea2.ParseError:
            parse_errors.append(f"line {line_no} cannot be parsed")
            continue
        ts = getattr(msg, "timestamp", None)
        if ts is None:
            n_invalid += 1
            continue
        sod = ts.hour * 3600 + ts.minute * 60 + ts.second + ts.microsecond / 1e6
        if last_sod is not None and sod < last_sod - 43200:
            day += 1  # midnight roll-over
        last_sod = sod
        key = (day, round(sod, 3))
        rec = epochs.get(key)
        if rec is None:
            rec = epochs[key] = {}
            order.append(key)
        try:
            if kind == "GGA":
                if int(msg.gps_qual or 0) == 0 or not msg.lat:
                    n_invalid += 1
                    continue
                rec["lat"], rec["lon"] = float(msg.latitude), float(msg.longitude)
                rec["alt"] = float(msg.altitude) if msg.altitude is not None else np.nan
            else:
                if msg.status != "A" or not msg.lat:
                    n_invalid += 1
                    continue
                rec.setdefault("lat", float(msg.latitude))
                rec.setdefault("lon", float(msg.longitude))
                spd = msg.spd_over_grnd
                rec["speed"] = float(spd) * _KNOT if spd not in (None, "") else np.nan
                crs = msg.true_course
                rec["course"] = float(crs) if crs not in (None, "") else np.nan
        except (TypeError, ValueError):
            parse_errors.append(f"line {line_no} has a malformed field")
    if checksum_errors:
        more = f" and {len(checksum_errors) - 1} more" if len(checksum_errors) > 1 else ""
        raise NoisevarError(
            f"{name}: NMEA checksum error at {checksum_errors[0]}{more}: the log is corrupted; "
            "repair or drop those lines before loading"
        )
    if n_sentences == 0:
        raise NoisevarError(f"{name}: no GGA or RMC sentences found (positions come from those)")
    if missing_checksum:
        parse_errors.append(f"line {missing_checksum[0]} has no checksum (truncated?)")
    fixes = [k for k in order if "lat" in epochs[k]]
    if not fixes and missing_checksum:
        raise NoisevarError(
            f"{name}: {len(missing_checksum)} GGA/RMC sentences have no checksum (*hh), so they "
            "cannot be verified: log with checksums on"
        )
    if len(fixes) < 2:
        raise NoisevarError(
            f"{name}: only {len(fixes)} GGA/RMC epochs with a valid fix: give a longer log"
        )
    recs = [epochs[k] for k in fixes]
    t = np.array([k[0] * 86400.0 + k[1] for k in fixes])
    t = t - t[0]
    lat = np.array([r["lat"] for r in recs])
    lon = np.array([r["lon"] for r in recs])
    alt = np.array([r.get("alt", np.nan) for r in recs])
    has_alt = np.all(np.isfinite(alt))
    enu = geodetic_to_enu(lat, lon, alt if has_alt else np.zeros_like(lat))
    columns: dict[str, NDArray] = {"time": t, "east_m": enu[:, 0], "north_m": enu[:, 1]}
    if has_alt:
        columns["up_m"] = enu[:, 2]
    speed = np.array([r.get("speed", np.nan) for r in recs])
    course = np.array([r.get("course", np.nan) for r in recs])
    if np.any(np.isfinite(speed)):
        columns["speed_mps"] = speed
    if np.any(np.isfinite(course)):
        columns["course_deg"] = course
    notes = [f"{len(fixes)} epochs from {n_sentences} GGA/RMC sentences"]
    if n_invalid:
        notes.append(f"{n_invalid} sentences without a valid fix were skipped")
    if parse_errors:
        notes.append(f"{len(parse_errors)} lines skipped ({parse_errors[0]})")
    period = _period_from_time(t, notes)
    return LoadedTable(name, columns, "nmea", "time", period, notes)


# ------------------------------------------------------------------------------- API
def load_table(
    source: str | os.PathLike | bytes,
    name: str | None = None,
    *,
    max_bytes: int | None = None,
) -> LoadedTable:
    """Read a CSV/TSV text table, a ``.npy`` array or an NMEA 0183 log.

    Parameters
    ----------
    source : str, path or bytes
        A file path, or the file's bytes (an upload).
    name : str, optional
        File name; its extension picks the format (``.npy``; ``.nmea`` and
        friends; anything else is sniffed: ``.npy`` magic bytes, NMEA
        sentences, else a text table). Default: the path's name.
    max_bytes : int, optional
        Refuse larger files with a clear message.

    Returns
    -------
    LoadedTable

    Raises
    ------
    NoisevarError
        Missing, empty, binary or malformed files (with the line and column),
        NMEA checksum errors, pickled ``.npy`` arrays, files over ``max_bytes``.

    Examples
    --------
    >>> tab = load_table(b"t,x\\n0,1.0\\n0.5,1.2\\n1.0,0.9\\n", "demo.csv")
    >>> tab.data_columns, tab.sample_period
    (['x'], 0.5)
    """
    raw, name = _read_source(source, name)
    if max_bytes is not None and len(raw) > max_bytes:
        raise NoisevarError(
            f"{name} is {len(raw) / 1e6:.1f} MB, over the {max_bytes / 1e6:.0f} MB limit: "
            "give a shorter record or raise the limit"
        )
    if len(raw) == 0 or not raw.strip():
        raise NoisevarError(f"{name} is empty")
    lower = name.lower()
    if raw.startswith(_NPY_MAGIC) or lower.endswith(".npy"):
        if not raw.startswith(_NPY_MAGIC):
            raise NoisevarError(f"{name} is not a valid .npy file (no NumPy header)")
        return _read_npy(raw, name)
    if lower.endswith(".npz"):
        raise NoisevarError(f"{name}: .npz archives are not supported; save one array as .npy")
    text = _check_binary(raw, name)
    if lower.endswith(NMEA_EXTENSIONS) or _looks_like_nmea(text):
        return _read_nmea(text, name)
    return _read_text_table(text, name)


def pick_column(
    table: LoadedTable, column: str | int | None = None, *, drop_nonfinite: bool = False
) -> NDArray:
    """One column of a table as a signal for :func:`noisevar.estimate`.

    Parameters
    ----------
    table : LoadedTable
        A loaded file.
    column : str or int, optional
        Column name, or index among :attr:`LoadedTable.data_columns`
        (default: the first data column).
    drop_nonfinite : bool
        Drop empty/NaN cells instead of refusing them.

    Returns
    -------
    ndarray of float, shape (n,)

    Raises
    ------
    NoisevarError
        Unknown column, or a column with empty/NaN cells (unless dropped).
    """
    data_cols = table.data_columns
    if not data_cols:
        raise NoisevarError(f"{table.name} has no data column (only a time column)")
    if column is None:
        cname = data_cols[0]
    elif isinstance(column, (int, np.integer)) and not isinstance(column, bool):
        if not 0 <= int(column) < len(data_cols):
            raise NoisevarError(
                f"column index {column} is out of range: {table.name} has {len(data_cols)} "
                f"data columns ({', '.join(data_cols)})"
            )
        cname = data_cols[int(column)]
    else:
        cname = str(column)
        if cname not in table.columns:
            if cname.isdigit() and int(cname) < len(data_cols):
                cname = data_cols[int(cname)]
            else:
                raise NoisevarError(
                    f"no column {column!r} in {table.name}; columns: {', '.join(table.columns)}"
                )
    z = np.asarray(table.columns[cname], dtype=float)
    bad = ~np.isfinite(z)
    if bad.any():
        if not drop_nonfinite:
            first = int(np.argmax(bad))
            raise NoisevarError(
                f"column {cname!r} of {table.name} has {int(bad.sum())} empty or NaN values "
                f"(the first at data row {first + 1}): clean the file, or drop them "
                "(CLI: --drop-nonfinite)"
            )
        z = z[~bad]
    return z


def signal_summary(z: ArrayLike, sample_period: float | None = None) -> dict[str, float]:
    """A short description of a signal: size, duration, level and spread.

    Parameters
    ----------
    z : array_like, shape (n,)
        Samples.
    sample_period : float, optional
        Seconds per sample (duration is NaN without it).

    Returns
    -------
    dict
        ``n``, ``duration_s``, ``mean``, ``std``, ``min``, ``max``,
        ``n_nonfinite``.
    """
    z = np.asarray(z, dtype=float)
    fin = z[np.isfinite(z)]
    if fin.size == 0:
        raise NoisevarError("the signal has no finite sample")
    return {
        "n": int(z.size),
        "duration_s": float((z.size - 1) * sample_period) if sample_period else float("nan"),
        "mean": float(fin.mean()),
        "std": float(fin.std()),
        "min": float(fin.min()),
        "max": float(fin.max()),
        "n_nonfinite": int(z.size - fin.size),
    }


def table_from_arrays(
    name: str,
    columns: dict[str, ArrayLike],
    sample_period: float | None = None,
    kind: str = "generated",
    notes: list[str] | None = None,
) -> LoadedTable:
    """Wrap arrays already in memory (a generated signal) as a :class:`LoadedTable`.

    Parameters
    ----------
    name : str
        Title of the table.
    columns : dict of str to array_like
        Equal-length columns.
    sample_period : float, optional
        Seconds per sample.
    kind : str
        Recorded in :attr:`LoadedTable.kind`.
    notes : list of str, optional
        Remarks.

    Returns
    -------
    LoadedTable
    """
    cols = {k: np.asarray(v, dtype=float).ravel() for k, v in columns.items()}
    sizes = {v.size for v in cols.values()}
    if len(sizes) != 1:
        raise NoisevarError(f"columns of {name} have different lengths: {sorted(sizes)}")
    return LoadedTable(name, cols, kind, None, sample_period, list(notes or []))

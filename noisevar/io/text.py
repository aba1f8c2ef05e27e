"""CSV / TSV / whitespace-separated text tables."""

from __future__ import annotations

import csv
import io
import re

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.table import _NA_TOKENS, LoadedTable, _is_time_name, _period_from_time


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

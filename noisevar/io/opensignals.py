"""OpenSignals text files (PLUX, BITalino): the column names of their JSON header."""

from __future__ import annotations

import json

#: The first line of an OpenSignals text file (PLUX, BITalino); its second holds the header
#: as JSON (``# {"<device>": {"column": [...], "sampling rate": 1000, ...}}``).
OPENSIGNALS = "# OpenSignals Text File Format"


def opensignals_names(text: str, width: int) -> list[str] | None:
    """The column names an OpenSignals file's JSON header gives, or None for any other file.

    Parameters
    ----------
    text : str
        The file's head.
    width : int
        Fields in its first data row.

    Returns
    -------
    list of str or None
        Its first device's ``column`` (``nSeq, I1, I2, O1, O2, A2``), then an empty name
        for each field past them: the device writes a tab after each row's last value.
    """
    if not text.startswith(OPENSIGNALS):
        return None
    line = next((ln for ln in text.splitlines()[1:4] if ln.startswith("# {")), None)
    try:
        devices = json.loads(line[2:]) if line else None
    except ValueError:
        return None
    device = next(iter(devices.values()), None) if isinstance(devices, dict) else None
    cols = device.get("column") if isinstance(device, dict) else None
    if not isinstance(cols, list) or not 0 < len(cols) <= width:
        return None
    if not all(isinstance(c, str) and c.strip() for c in cols):
        return None
    return [*cols, *[""] * (width - len(cols))]

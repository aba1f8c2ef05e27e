"""A text DataFlash log's units (its UNIT, MULT and FMTU lines), as in autoflpy's test log.

pymavlink's text index parses only the first line of each message type, so its unit table
held the first UNIT line alone; the units must come from the formats of the full pass
(issue 26, real_audit4: every field of a 17 MB ArduPlane text log was without a unit).
"""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.io import load_table
from noisevar.io.logs import list_topics

HEAD = [
    "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns",
    "FMT, 203, 76, UNIT, QbZ, TimeUS,Id,Label",
    "FMT, 202, 44, FMTU, QBNN, TimeUS,FmtType,UnitIds,MultIds",
    "FMT, 204, 20, MULT, Qbd, TimeUS,Id,Mult",
    "FMT, 130, 29, GPS, QBLLe, TimeUS,Status,Lat,Lng,Alt",
    "FMT, 133, 35, IMU, Qffff, TimeUS,GyrX,GyrY,AccZ,T",
    "UNIT, 1000, 45, ",
    "UNIT, 1000, 68, deglatitude",
    "UNIT, 1000, 85, deglongitude",
    "UNIT, 1000, 69, rad/s",
    "UNIT, 1000, 109, m",
    "UNIT, 1000, 111, m/s/s",
    "UNIT, 1000, 79, degC",
    "UNIT, 1000, 115, s",
    "MULT, 1000, 45, 0",
    "MULT, 1000, 70, 1E-06",
    "MULT, 1000, 48, 1",
    "MULT, 1000, 66, 0.01",
    "MULT, 1000, 71, 1E-07",
    "FMTU, 1000, 130, s-DUm, F-GGB",
    "FMTU, 1000, 133, sEEoO, F0000",
]


def test_text_log_units_from_its_unit_lines(tmp_path):
    rng = np.random.default_rng(0)
    lines = list(HEAD)
    for i in range(60):
        us = 2_000_000 + 20_000 * i
        g = rng.normal(size=4)
        lines.append(f"IMU, {us}, {1e-3 * g[0]:.7g}, {1e-3 * g[1]:.7g}, {-9.81 + g[2]:.7g}, 23")
        if i % 5 == 0:
            lines.append(f"GPS, {us}, 6, {49.95 + 1e-7 * i:.7f}, -6.3688301, {8.4 + g[3]:.2f}")
    path = tmp_path / "flight.log"
    path.write_text("\n".join(lines) + "\n")
    topics = {t.name: t for t in list_topics(path)}
    assert topics["IMU"].units == {"GyrX": "rad/s", "GyrY": "rad/s", "AccZ": "m/s**2", "T": "degC"}
    assert topics["GPS"].units == {"Lat": "deg", "Lng": "deg", "Alt": "m"}
    tab = load_table(path, topic="GPS", fields=["Lat", "Alt"])
    assert tab.units == {"Lat": "deg", "Alt": "m"}
    assert tab.columns["Lat"][3] == pytest.approx(49.95 + 1.5e-6, abs=1e-9)  # i = 15

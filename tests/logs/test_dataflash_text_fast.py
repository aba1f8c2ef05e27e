"""A DataFlash text log is read in one pass, with pymavlink's values (issue 26, polish).

pymavlink's text reader made a message object per line: 2.5-3.6 s per CLI call on
autoflpy's 17 MB ArduPlane log. The log is now split and converted by type; these check
the values against pymavlink's message-by-message parse, and that its text reader is not
used.
"""

from __future__ import annotations

import numpy as np
import pytest
from pymavlink import DFReader
from test_dataflash_text_units import HEAD

from noisevar.errors import NoisevarError
from noisevar.io.logs import list_topics, read_topic

#: An instance field (FMTU ``#``), a mode, lines the reader must skip.
EXTRA = [
    "FMT, 140, 30, BARO, QBff, TimeUS,I,Alt,Press",
    "FMT, 141, 20, MODE, QMB, TimeUS,Mode,ModeNum",
    "UNIT, 1000, 35, instance",
    "UNIT, 1000, 80, Pa",
    "FMTU, 1000, 140, s#mP, F-00",
]


def _log(tmp_path, mode: str = "10"):
    rng = np.random.default_rng(26)
    early = "IMU, 1000, 0.5, 0.5, 0.5, 20"  # before its FMT line: pymavlink reads it
    lines = [HEAD[0], early, *HEAD[1:], *EXTRA]
    for i in range(300):
        us = 2_000_000 + 20_000 * i
        g = rng.normal(size=4)
        lines.append(f"IMU, {us}, {1e-3 * g[0]:.7g}, {1e-3 * g[1]:.7g}, {-9.81 + g[2]:.7g}, 23")
        lines.append(f"BARO, {us + 7}, {i % 2}, {100 + g[3]:.5f}, {101325 + 10 * g[0]:.3f}")
        if i % 5 == 0:
            lines.append(f"GPS, {us}, 6, {49.95 + 1e-7 * i:.7f}, -6.3688301, {8.4 + g[3]:.2f}")
        if i == 100:
            lines += ["IMU, 5, 1", "NOPE, 1, 2, 3", f"MODE, {us}, {mode}, 10"]  # short, unknown
    path = tmp_path / "flight.log"
    path.write_text("\r\n".join(lines) + "\r\n")
    return path


class _Text(DFReader.DFReader_text):
    """pymavlink's text reader without its GPS clock search (the log's GPS has no week)."""

    def init_clock(self) -> None:
        self.clock = DFReader.DFReaderClock_usec()
        self._rewind(keep_messages=True)


def _pymavlink(path, name, fields, inst=None):
    """Each message of ``name`` (of instance ``inst``), parsed by pymavlink one by one."""
    log = _Text(str(path))
    rows = []
    while (m := log.recv_match(type=name)) is not None:
        if inst is None or int(m.I) == inst:
            rows.append([m.TimeUS / 1e6, *(float(getattr(m, f)) for f in fields)])
    return np.asarray(rows)


def _ours(path, topic, fields):
    chunks = list(read_topic(path, topic, fields))
    times = np.concatenate([c.times for c in chunks])
    values = [np.concatenate([c.values[f] for c in chunks]) for f in fields]
    return np.column_stack([times, *values])


@pytest.mark.parametrize(
    ("topic", "name", "fields", "inst"),
    [
        ("IMU", "IMU", ["GyrX", "GyrY", "AccZ", "T"], None),
        ("GPS", "GPS", ["Status", "Lat", "Lng", "Alt"], None),
        ("BARO[1]", "BARO", ["Alt", "Press"], 1),
        ("MODE", "MODE", ["Mode", "ModeNum"], None),
    ],
)
def test_text_log_values_are_pymavlinks(tmp_path, monkeypatch, topic, name, fields, inst):
    path = _log(tmp_path)
    want = _pymavlink(path, name, fields, inst)

    def refuse(*_a, **_k):
        raise AssertionError("pymavlink's text reader used")

    monkeypatch.setattr(DFReader.DFReader_text, "init_arrays", refuse)
    np.testing.assert_array_equal(_ours(path, topic, fields), want)
    topics = {t.name: t for t in list_topics(path)}
    assert topics[topic].count == len(want)
    assert set(topics) == {"IMU", "GPS", "BARO[0]", "BARO[1]", "MODE"}
    assert topics["BARO[0]"].units == {"Alt": "m", "Press": "Pa"}


def test_a_text_field_that_is_not_a_number_is_one_clear_error(tmp_path):
    path = _log(tmp_path, mode="Manual")
    with pytest.raises(NoisevarError, match="message MODE field 'Mode' holds 'Manual', not a"):
        list(read_topic(path, "MODE", ["Mode"]))

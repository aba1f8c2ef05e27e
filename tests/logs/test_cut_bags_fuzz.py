"""Bags cut short and then damaged (bytes flipped, seeded): listing and reading give a table
or one NoisevarError, never another exception, whatever the repair meets."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from logfiles import imu_values, rechunked_mcap, write_bag, write_ros1_chunked

from noisevar.errors import NoisevarError
from noisevar.io.logs import list_topics, load_log


@pytest.fixture(scope="module")
def bags(tmp_path_factory) -> dict[str, bytes]:
    d = tmp_path_factory.mktemp("fuzz")
    z = imu_values(600, seed=9)  # small chunks: a cut leaves whole chunks before it
    mcap = next(write_bag(d / "m", z, "mcap").glob("*.mcap"))
    mcap = rechunked_mcap(mcap, d / "c.mcap", "LZ4", chunk=8_000).read_bytes()
    ros1 = write_ros1_chunked(d / "r.bag", z, "BZ2", chunk=8_000).read_bytes()
    return {"cut.mcap": mcap, "cut.bag": ros1}


@settings(
    max_examples=80,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    name=st.sampled_from(["cut.mcap", "cut.bag"]),
    keep=st.floats(0.05, 0.999),
    flips=st.lists(st.tuples(st.floats(0, 1), st.integers(1, 255)), max_size=3),
)
def test_damaged_cut_bags_read_or_refuse(bags, tmp_path, name, keep, flips):
    data = bytearray(bags[name][: max(16, int(keep * len(bags[name])))])
    for where, xor in flips:
        data[min(int(where * len(data)), len(data) - 1)] ^= xor
    path = tmp_path / name
    path.write_bytes(bytes(data))
    try:
        topics = list_topics(path)
        if any(t.name == "/imu" for t in topics):
            table = load_log(path, "/imu", ["angular_velocity.x"])
            assert np.all(np.isfinite(table.columns["time"]))
    except NoisevarError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 800

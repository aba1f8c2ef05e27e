"""The noise a ROS message declares (its covariance) against the R measured (issue 26: real logs).

robot_localization takes a message's covariance as its measurement noise R: a driver that
declares too small a covariance makes the filter overconfident. The covariance elements
were not read; now each field's declared variance comes with the table, and the CLI says
how the measured R stands against it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from logfiles import imu_values, write_bag

from noisevar.cli import main
from noisevar.io import load_table
from noisevar.io.logs import list_topics


@pytest.fixture(scope="module")
def bag(tmp_path_factory) -> Path:
    # the fixture declares a covariance diagonal (0, 0.5, 0): y known, x and z unknown (0)
    return write_bag(tmp_path_factory.mktemp("declared") / "b", imu_values(400), "mcap")


def test_declared_variances_come_with_the_table(bag: Path) -> None:
    tab = load_table(bag, topic="/imu")
    assert tab.declared_variance == {"angular_velocity.y": 0.5, "linear_acceleration.y": 0.5}
    assert not any("covariance" in c for c in tab.columns)  # read for the note only
    (imu,) = [t for t in list_topics(bag) if t.name == "/imu"]
    assert imu.declared["angular_velocity.z"] == "angular_velocity_covariance.8"
    named = load_table(bag, topic="/imu", fields=["angular_velocity_covariance.4"])
    np.testing.assert_array_equal(named.columns["angular_velocity_covariance.4"], 0.5)


def test_cli_compares_the_measured_r_with_the_declared(bag: Path, capsys) -> None:
    argv = ["estimate", str(bag), "--topic", "/imu", "--column", "angular_velocity.y"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "the log declares a variance of 0.5 (rad/s)² for this field" in out
    assert "x the declared value: a filter given the declared value trusts this sensor more" in out
    assert main([*argv, "--unit-out", "deg/s"]) == 0
    out = capsys.readouterr().out
    assert f"declares a variance of {0.5 * (180 / np.pi) ** 2:,.0f} (deg/s)²" in out
    assert main(["estimate", str(bag), "--topic", "/imu", "--column", "angular_velocity.x"]) == 0
    assert "declares" not in capsys.readouterr().out  # 0: ROS's "unknown"


def test_signal_page_says_it(bag: Path) -> None:
    from streamlit.testing.v1 import AppTest

    at = AppTest.from_file(str(Path(__file__).parents[2] / "app.py"), default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value(
        ("robot.mcap", next(bag.glob("*.mcap")).read_bytes(), "")
    ).run()
    box = next(s for s in at.selectbox if s.label == "Signal column")
    box.set_value("angular_velocity.y").run()
    assert not at.exception, [e.value for e in at.exception]
    said = [i.value for i in at.info if "declares a variance of 0.5" in i.value]
    assert said and "trusts this sensor more than it should" in said[0]

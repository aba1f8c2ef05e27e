"""Fleet: byte-identical files and differing sample rates are said (issue 28 item 7)."""

from __future__ import annotations

import shutil

import numpy as np

import noisevar as nv
from noisevar.batch.example import write_example_fleet
from noisevar.batch.fleet import fleet_report
from noisevar.figures.fleet import flagged_sensors


def test_identical_files_and_rates_are_noted(tmp_path):
    paths = write_example_fleet(tmp_path / "f", n_sensors=4, n=800, seed=3)
    twin = tmp_path / "f" / "twin_of_first.csv"
    shutil.copyfile(paths[0], twin)
    rng = np.random.default_rng(0)
    fast = tmp_path / "f" / "fast.csv"
    t = np.arange(800) / 200.0
    np.savetxt(
        fast,
        np.column_stack([t, *(rng.normal(0, 0.02, (3, 800)))]),
        delimiter=",",
        header="time,ax,ay,az",
        comments="",
    )
    table = nv.batch([str(p) for p in [*paths, twin, fast]], columns="all", progress=False)
    assert set(table["sample_rate_hz"].dropna()) == {100.0, 200.0}
    notes = fleet_report(table).warnings
    (same,) = [n for n in notes if "byte-identical" in n]
    assert paths[0].name in same and "twin_of_first.csv" in same
    (rates,) = [n for n in notes if n.startswith("sample rates differ")]
    assert "100 Hz (5 files)" in rates and "200 Hz (1 file)" in rates


def test_one_rate_and_distinct_files_say_nothing(tmp_path):
    paths = write_example_fleet(tmp_path / "g", n_sensors=4, n=800, seed=4)
    notes = fleet_report(nv.batch([str(p) for p in paths], progress=False)).warnings
    assert not any("byte-identical" in n or "sample rates" in n for n in notes)


def test_unusual_sensor_labels_are_whole_and_the_margin_fits_them(tmp_path):
    paths = write_example_fleet(tmp_path / "h", n_sensors=5, n=800, seed=5)
    fig = flagged_sensors(fleet_report(nv.batch([str(p) for p in paths], progress=False)))
    labels = list(fig.data[0].y)
    assert all(" · " in lab and lab.split(" · ")[0].endswith(".csv") for lab in labels)
    assert fig.layout.yaxis.automargin
    assert fig.layout.margin.l >= 7 * max(len(lab) for lab in labels)

"""One series of a file that stacks several (the long format), by its label: ``load_table(
series=)``, ``--series``, the config key ``series`` (:data:`noisevar.io.series_option.SERIES`).

Before: such a file was refused ("give one series, e.g. the rows of one 'id' saved as their
own file") with no way to read one but to split the file by hand."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.config import config_to_json, parse_config, validate_config
from noisevar.errors import NoisevarError, StackedSeries
from noisevar.io import channel_record, load_table
from noisevar.io.series_option import LISTED, MAX_LABELS

TURBINES = ("T1", "T2", "T3")


def _blocks(labels, n: int = 50, seed: int = 0) -> tuple[bytes, dict[str, np.ndarray]]:
    """Each label's record one after the other, its time starting again at 0."""
    rng = np.random.default_rng(seed)
    rows, values = ["id,time,gl"], {}
    for k, label in enumerate(labels):
        values[label] = np.round(100 + (k + 1) * rng.normal(size=n), 6)
        rows += [f"{label},{i * 300},{v!r}" for i, v in enumerate(values[label].tolist())]
    return ("\n".join(rows) + "\n").encode(), values


def _scada(n: int = 60, seed: int = 1) -> tuple[bytes, dict[str, np.ndarray]]:
    """Three turbines' rows interleaved: each time stamp three times."""
    rng = np.random.default_rng(seed)
    values = {t: np.round(rng.normal(size=n) * (k + 1), 6) for k, t in enumerate(TURBINES)}
    rows = ["Date_time,Wind_turbine_name,Ba_avg"]
    for i in range(n):
        rows += [f"{i * 600},{t},{float(values[t][i])!r}" for t in TURBINES]
    return ("\n".join(rows) + "\n").encode(), values


def test_the_rows_of_one_series_are_read_in_file_order_with_a_note():
    raw, values = _blocks(["Subject 1", "Subject 2", "Subject 3"])
    table = load_table(raw, "cgm.csv", series="Subject 2")
    z, t = channel_record(table, "gl")
    assert np.array_equal(z, values["Subject 2"])
    assert table.sample_period == 300.0 and np.all(np.diff(t) > 0)
    note = "read the rows of id = 'Subject 2' (1 of 3 series, 50 of 150 rows), in file order"
    assert note in table.notes, table.notes


def test_interleaved_turbines_each_time_three_times():
    raw, values = _scada()
    with pytest.raises(StackedSeries) as err:
        load_table(raw, "scada.csv")
    assert err.value.column == "Wind_turbine_name" and err.value.labels == TURBINES
    table = load_table(raw, "scada.csv", series="T2")
    z, t = channel_record(table, "Ba_avg")
    assert np.array_equal(z, values["T2"]) and table.sample_period == 600.0
    assert np.all(np.diff(t) > 0)


def test_the_refusal_names_the_option_and_carries_the_labels_bounded():
    labels = [f"s{i:03d}" for i in range(MAX_LABELS + 50)]
    raw, _ = _blocks(labels, n=3)
    with pytest.raises(StackedSeries) as err:
        load_table(raw, "many.csv")
    e = err.value
    assert isinstance(e, NoisevarError) and "\n" not in str(e)
    assert "--series 's000' (Signal page: Series to read)" in str(e), str(e)
    assert e.column == "id" and e.n_labels == len(labels)
    assert e.labels == tuple(labels[:MAX_LABELS])
    # a label past the kept ones is read all the same
    assert load_table(raw, "many.csv", series=labels[-1]).n_rows == 3


def test_an_unknown_label_is_refused_listing_some_present():
    labels = [f"unit {i}" for i in range(25)]
    raw, _ = _blocks(labels, n=3)
    with pytest.raises(NoisevarError, match="no row has 'id' = 'unit 99'") as err:
        load_table(raw, "units.csv", series="unit 99")
    msg = str(err.value)
    assert "\n" not in msg and "its 25 series: 'unit 0'" in msg and msg.endswith(", ...")
    assert msg.count("'unit ") == 1 + LISTED
    long = "x" * 5000
    with pytest.raises(NoisevarError) as err:
        load_table(raw, "units.csv", series=long)
    assert len(str(err.value)) < 600  # the label echoed bounded


def test_a_file_of_one_series_refuses_the_option():
    raw = b"t,x\n0,1.0\n1,1.2\n2,0.9\n3,1.1\n"
    with pytest.raises(NoisevarError, match=r"one.csv holds one series: leave --series"):
        load_table(raw, "one.csv", series="A")
    buf = io.BytesIO()
    np.save(buf, np.arange(5.0))
    with pytest.raises(NoisevarError, match="holds one series"):
        load_table(buf.getvalue(), "a.npy", series="A")
    assert load_table(raw, "one.csv", series="  ").n_rows == 4  # empty: not given


def test_cli_refusals_are_one_line_exit_2(tmp_path, capsys):
    raw, _ = _blocks(["a", "b"])
    p = tmp_path / "two.csv"
    p.write_bytes(raw)
    one = tmp_path / "one.csv"
    one.write_text("t,x\n0,1.0\n1,1.2\n2,0.9\n3,1.1\n")
    for argv in (
        ["estimate", str(p)],
        ["estimate", str(p), "--series", "c"],
        ["estimate", str(one), "--series", "a"],
        ["estimate", str(p), "--series", "a", "--stream"],
        ["allan", str(p), "--series", "zz"],
        ["fit", str(p), "--series", "zz"],
    ):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err, (argv, err)
    assert main(["estimate", str(p), "--series", "b", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["n_total"] == 50 and any("id = 'b'" in n for n in out["notes"])


def test_batch_applies_the_label_to_every_file(tmp_path, capsys):
    raw, _ = _blocks(["a", "b"])
    (tmp_path / "two.csv").write_bytes(raw)
    (tmp_path / "other.csv").write_bytes(_blocks(["c", "d"])[0])
    out = tmp_path / "rows.csv"
    assert main(["batch", str(tmp_path), "--series", "b", "--out", str(out), "--quiet"]) == 0
    import pandas as pd

    rows = pd.read_csv(out)
    ok = rows[rows["file"].str.endswith("two.csv") & (rows["channel"] == "gl")]
    assert len(ok) == 1 and ok["n_total"].iloc[0] == 50
    bad = rows[rows["file"].str.endswith("other.csv")]
    assert bad["error"].str.contains("no row has 'id' = 'b'").all(), bad["error"].tolist()


def test_config_round_trip_reads_the_same_series(tmp_path, capsys):
    raw, values = _blocks(["a", "b"])
    p = tmp_path / "two.csv"
    p.write_bytes(raw)
    cfg = config_to_json({"method": "auto"}, column="gl", series="b")
    assert parse_config(cfg)["series"] == "b"
    assert validate_config({"method": "auto", "series": "b"})["series"] == "b"
    with pytest.raises(NoisevarError, match="series"):
        validate_config({"method": "auto", "series": 3})
    path = tmp_path / "cfg.json"
    path.write_text(cfg)
    assert main(["estimate", str(p), "--config", str(path), "--format", "json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    import noisevar

    z, t = channel_record(load_table(p, series="b"), "gl")
    assert np.array_equal(z, values["b"])
    assert cli["variance"] == pytest.approx(noisevar.estimate(z, t=t).variance, rel=1e-12)


def test_a_tuned_filters_config_carries_the_series_and_fit_reads_it(tmp_path, capsys):
    raw, _ = _blocks(["a", "b"], n=300)
    p = tmp_path / "two.csv"
    p.write_bytes(raw)
    saved = tmp_path / "tuned.json"
    argv = ["fit", str(p), "--series", "b", "--model", "rw", "--column", "gl"]
    assert main([*argv, "--save-config", str(saved), "--format", "json"]) == 0
    fitted = json.loads(capsys.readouterr().out)
    assert json.loads(saved.read_text())["series"] == "b"
    assert main(["fit", str(p), "--config", str(saved), "--format", "json"]) == 0
    applied = json.loads(capsys.readouterr().out)
    assert applied["r"] == pytest.approx(fitted["r"], rel=1e-9)

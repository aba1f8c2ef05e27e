"""Files of the ninth real-record audit (benchmarks/real_audit9.py) as navigation users have
them: traffic's ``json.gz`` samples were refused as "a binary file (NUL bytes)" and its
readsb and Flightradar24 JSON files blaming thousands separators; OpenOA's La Haute Borne
SCADA file (four turbines' 10-minute rows interleaved, a turbine-name column) was answered
as one record; a CSV of ten aircraft (traffic's ``to_csv``) was refused blaming the hex
``icao24`` codes and "lines above the header"."""

import gzip
import json

import numpy as np
import pandas as pd
import pytest

from noisevar import NoisevarError
from noisevar.cli import main
from noisevar.io import load_table


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    return err


def _track(n: int, seed: int) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    t = pd.date_range("2019-11-05 11:26:32", periods=n, freq="s", tz="UTC")
    return pd.DataFrame({"timestamp": t, "altitude": 25.0 * np.round(rng.normal(1400, 40, n) / 25),
                         "groundspeed": np.round(rng.normal(140, 2, n))})  # fmt: skip


def test_a_gzip_file_is_named_and_told_to_decompress(tmp_path, capsys):
    path = tmp_path / "fuelflow_a320.json.gz"
    path.write_bytes(gzip.compress(_track(300, 1).to_json(date_format="iso").encode()))
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "gzip" in err and "decompress" in err and "binary" not in err


@pytest.mark.parametrize("lines", [False, True])
def test_a_json_file_is_named_and_told_to_convert(tmp_path, capsys, lines):
    """readsb's trace and Flightradar24's export (one object over many lines) and rs1090's
    JSON lines: one line saying JSON and how to make a CSV, not thousands separators."""
    frame = _track(200, 2)
    if lines:
        text = frame.to_json(orient="records", lines=True, date_format="iso")
        path = tmp_path / "full_flight.jsonl"
    else:
        rows = frame.assign(timestamp=frame.timestamp.astype(str)).to_numpy().tolist()
        text = json.dumps({"icao": "ac671b", "trace": rows}, indent=2)
        path = tmp_path / "trace_full_ac671b.json"
    path.write_text(text)
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "JSON" in err and "CSV" in err and "thousands" not in err


def test_interleaved_series_are_refused(tmp_path):
    """La Haute Borne: four turbines' rows interleaved, each time stamp four times."""
    rng = np.random.default_rng(3)
    t = pd.date_range("2014-01-01 01:00", periods=200, freq="10min", tz="+01:00")
    rows = [(name, str(s), round(float(v), 2)) for s, vs in zip(t, rng.normal(7, 1, (200, 4)),
            strict=True) for name, v in zip(["R80736", "R80721", "R80790", "R80711"], vs,
            strict=True)]  # fmt: skip
    path = tmp_path / "la-haute-borne.csv"
    pd.DataFrame(rows, columns=["Wind_turbine_name", "Date_time", "Ws_avg"]).to_csv(
        path, index=False
    )
    with pytest.raises(NoisevarError, match=r"4 series.*'Wind_turbine_name'.*one series"):
        load_table(path)
    one = tmp_path / "R80711.csv"
    pd.DataFrame(rows[3::4], columns=["Wind_turbine_name", "Date_time", "Ws_avg"]).to_csv(
        one, index=False
    )
    assert load_table(one).sample_period == pytest.approx(600.0)
    # one series with a status column and a time stamp repeated inside it: read
    frame = _track(300, 4)
    frame["status"] = np.where(np.arange(300) % 50 < 25, "OK", "WARN")
    frame.loc[120, "timestamp"] = frame.loc[119, "timestamp"]
    status = tmp_path / "status.csv"
    frame.to_csv(status, index=False)
    assert load_table(status).columns["altitude"].size == 300


def test_aircraft_stacked_with_hex_codes_are_refused_as_stacked(tmp_path):
    """traffic's ``to_csv`` of ten aircraft: ``icao24`` hex codes, some all digits."""
    parts = [_track(120, s).assign(icao24=code, callsign=f"SWR{s}")
             for s, code in enumerate(["4b18b8", "440170", "4b1a2c"])]  # fmt: skip
    parts[1]["timestamp"] -= pd.Timedelta("3D")  # another day: time goes back
    path = tmp_path / "zurich_airport.csv"
    pd.concat(parts).to_csv(path)
    with pytest.raises(NoisevarError, match=r"stacks 3 series.*one series"):
        load_table(path)

"""Files of the nineteenth real-record audit (benchmarks/real_audit19.py) as users have them:
vallenae's Vallen acoustic-emission databases (``.tradb`` waveforms as blobs, ``.pridb``,
``.trfdb``) were refused as "an SQLite database (an ActiGraph .agd file is one)" to be
exported with ``pandas.read_sql``, which gives no samples from a blob."""

import json
import sqlite3

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_table

#: a Vallen database's tables (vallenae's schema templates, cut to a few columns)
_SCHEMAS = {
    "tradb": ["tr_params (ID INTEGER, TR_mV REAL)", "tr_globalinfo (Key TEXT, Value TEXT)",
              "tr_data (SetID INTEGER, TRAI INTEGER, Chan INTEGER, Data BLOB)"],
    "pridb": ["ae_params (ID INTEGER)", "ae_globalinfo (Key TEXT, Value TEXT)",
              "ae_data (SetID INTEGER, SetType INTEGER, Time INTEGER)"],
    "trfdb": ["trf_globalinfo (Key TEXT, Value TEXT)", "trf_data (TRAI INTEGER, FFT_CoG REAL)"],
}  # fmt: skip


def _database(path, tables: list[str]) -> None:
    con = sqlite3.connect(path)
    for t in tables:
        con.execute(f"CREATE TABLE {t}")
    if any(t.startswith("tr_data") for t in tables):
        blob = np.random.default_rng(0).integers(-300, 300, 1024).astype("<i2").tobytes()
        con.execute("INSERT INTO tr_data VALUES (1, 1, 1, ?)", (blob,))
    con.commit()
    con.close()


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    return err


@pytest.mark.parametrize("ext", sorted(_SCHEMAS))
def test_a_vallen_ae_database_is_named_with_vallenae_as_the_way_out(tmp_path, capsys, ext):
    path = tmp_path / f"sample.{ext}"
    _database(path, _SCHEMAS[ext])
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "Vallen acoustic-emission" in err and f".{ext}" in err and "vallenae" in err
    assert "SQLite" in err and "ActiGraph" not in err and "pandas.read_sql" not in err


def test_another_sqlite_database_names_its_tables(tmp_path, capsys):
    """An SQLite file of no known kind: the generic refusal, with the tables to export."""
    path = tmp_path / "logger.db"
    _database(path, ["samples (t REAL, x REAL)", "settings (k TEXT)"])
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    said = err.partition("its tables: ")[2]
    assert "SQLite" in err and "samples" in said and "settings" in said


def test_a_damaged_sqlite_schema_still_gives_one_refusal(tmp_path):
    """Untrusted bytes after the SQLite magic (a schema with odd names, truncation, flipped
    bytes): only the one-line NoisevarError, the names said as written or not at all."""
    rng = np.random.default_rng(7)
    good = tmp_path / "a.tradb"
    _database(good, _SCHEMAS["tradb"])
    raw = good.read_bytes()
    with pytest.raises(NoisevarError, match="vallenae"):
        load_table(good)
    for i in range(40):
        damaged = bytearray(raw[: int(rng.integers(17, len(raw)))])
        for j in rng.integers(16, len(damaged), 8):
            damaged[j] = int(rng.integers(0, 256))
        if i % 2:
            damaged += b"CREATE TABLE \xff\xfe" + b"x" * 500 + b'CREATE TABLE "\n'
        path = tmp_path / f"d{i}.tradb"
        path.write_bytes(bytes(damaged))
        with pytest.raises(NoisevarError) as exc:
            load_table(path)
        assert "\n" not in str(exc.value) and len(str(exc.value)) < 1000


def test_a_count_above_a_one_column_file_is_its_header(tmp_path, capsys):
    """vallenae's ``signal.txt``: its period, the count of its samples, then the samples."""
    z = np.random.default_rng(11).uniform(-1.0, 1.0, 1024)
    path = tmp_path / "signal.txt"
    path.write_text("100.000000\n1024\n" + "\n".join(f"{v:.6f}" for v in z) + "\n")
    table = load_table(path)
    got = table.columns["col0"]
    np.testing.assert_allclose(got, np.round(z, 6))
    assert any("1024 counts the values below" in n for n in table.notes)
    assert main(["estimate", str(path), "--format", "json"]) == 0
    said = json.loads(capsys.readouterr().out)
    assert said["n_total"] == 1024 and said["variance"] < 1.0
    for lead in ([], [5.0], [1023.0, 7.0]):  # values that count nothing stay samples
        plain = np.concatenate([lead, z])
        path.write_text("\n".join(f"{v:.6f}" for v in plain) + "\n")
        assert load_table(path).columns["col0"].size == plain.size

"""Files of the seventeenth real-record audit (benchmarks/real_audit17.py) as users have
them: pyphysio's ``.ph`` files are xarray netCDF4 (HDF5) files, a 3-D ``signal`` (time x 26
fNIRS channels x 2 components) beside its coordinates ``channel``, ``component`` and ``time``
(dimension scales). The HDF5 reader skipped the 3-D dataset and read the coordinate
``channel`` (0 .. 25) as the signal, refused as "a counter or a clock"."""

import numpy as np
import pytest

import noisevar as nv
from noisevar.cli import main
from noisevar.io import channel_record, load_table

h5py = pytest.importorskip("h5py")


def _netcdf_like(path, n: int = 2000, seed: int = 0) -> np.ndarray:
    """A netCDF4-style file: ``signal`` (n, 3, 2) on the scales ``time``, ``channel`` and
    ``component``; returns the signal (white noise of std 0.01 plus a slow wave)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 10.0
    sig = np.sin(0.05 * t)[:, None, None] + rng.normal(0.0, 0.01, (n, 3, 2))
    with h5py.File(path, "w") as f:
        for name, values in (("time", t), ("channel", np.arange(3)), ("component", [0, 1])):
            f[name] = np.asarray(values)
            f[name].make_scale(name)
        f["signal"] = sig
        for i, name in enumerate(("time", "channel", "component")):
            f["signal"].dims[i].attach_scale(f[name])
    return sig


def test_a_netcdf_coordinate_is_not_the_signal(tmp_path, capsys):
    path = tmp_path / "fnirs.h5"
    sig = _netcdf_like(path)
    table = load_table(path)
    assert "channel" not in table.signals and "component" not in table.signals
    assert table.signals == ["col0_0", "col0_1", "col1_0", "col1_1", "col2_0", "col2_1"]
    z = np.asarray(channel_record(table, "col1_1")[0], float)
    np.testing.assert_array_equal(z, sig[:, 1, 1])
    assert table.time_column is not None and table.sample_period == pytest.approx(0.1)
    assert nv.estimate(z).variance == pytest.approx(1e-4, rel=0.2)
    assert main(["estimate", str(path), "--format", "json"]) == 0
    assert '"column": "col0_0"' in capsys.readouterr().out

    # a 1-D signal on its ``time`` coordinate (pyphysio's fnirs_tapping.ph) keeps its
    # times, a 2-D dataset its ``col0 ..`` fields
    path = tmp_path / "tap.h5"
    with h5py.File(path, "w") as f:
        f["time"] = 100.0 + np.arange(500) / 10.0
        f["time"].make_scale("time")
        f["signal"] = np.random.default_rng(1).normal(size=500)
        f["signal"].dims[0].attach_scale(f["time"])
        f["two"] = np.random.default_rng(2).normal(size=(70, 2))
    table = load_table(path, topic="/")
    assert table.signals == ["signal"] and table.sample_period == pytest.approx(0.1)
    assert load_table(path, topic="/two").signals == ["col0", "col1"]


#: the first bytes of bioread's ``physio-5.0.1.acq`` (a version number, no signature)
_ACQ_HEAD = bytes.fromhex("00000000008400000" + "96e0004000000013fe0") + bytes(200)


def test_an_acqknowledge_file_is_named_with_a_way_to_export_it(tmp_path, capsys):
    """bioread's BIOPAC recordings were refused as "a binary file (it contains NUL bytes)"."""
    (tmp_path / "physio.acq").write_bytes(_ACQ_HEAD)
    assert main(["estimate", str(tmp_path / "physio.acq")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "BIOPAC AcqKnowledge" in err and "acq2txt" in err
    (tmp_path / "physio.dat").write_bytes(_ACQ_HEAD)  # another suffix: as before
    assert main(["estimate", str(tmp_path / "physio.dat")]) == 2
    assert "binary file" in capsys.readouterr().err


def test_a_side_file_of_settings_is_called_one(tmp_path, capsys):
    """pyphysio's ``info_medical`` beside its recording was refused blaming thousands
    separators."""
    path = tmp_path / "info_medical"
    path.write_text("fsamp:      1024\nsignals:    ecg,eda,bvp,resp\nlength:     120 s\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "side file of settings" in err and "thousands" not in err


def test_a_dataset_of_huge_slices_lists_only_the_first_fields(tmp_path):
    """An untrusted file's shape is not enumerated whole: (4, 1e5, 1e4) has 1e9 slices, of
    which the reader names the first MAX_FIELDS (it listed every index before cutting)."""
    import time

    from noisevar.io.logs.spec import MAX_FIELDS

    path = tmp_path / "huge.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("signal", shape=(4, 10**5, 10**4), dtype="f4", chunks=(4, 10, 10))
    t0 = time.perf_counter()
    with pytest.raises(nv.NoisevarError):  # 4 samples: too short, refused in one line
        nv.estimate(channel_record(load_table(path), "col0_0")[0])
    assert time.perf_counter() - t0 < 30
    assert len(load_table(path).signals) <= MAX_FIELDS

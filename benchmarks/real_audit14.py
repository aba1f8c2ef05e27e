"""A fourteenth audit, for gait, physiology and vehicle-bus engineers: three body-worn
accelerometers (Daphnet, in mg, with millisecond time stamps of a 64 Hz clock), a UCR anomaly
benchmark's physiological record with its labelled anomaly, a NIST reference series with a
certified residual deviation, and the files a user of these fields brings (a NIST report
above its table, Vector ASC CAN logs, EDF, BDF, BLF, .ts, .tsf) (issue 26).

    python benchmarks/real_audit14.py                    # every record, a few minutes
    python benchmarks/real_audit14.py --records enso     # records whose name has it; prints only

Measured data shipped in aeon's wheel (``_refdata.AEON``, BSD-3-Clause), lmfit's sdist
(``_refdata.LMFIT``: NIST's Statistical Reference Datasets, public domain), python-can's
sdist (``_refdata.PYTHON_CAN``, LGPL-3.0) and pyedflib's wheel (``_refdata.PYEDFLIB``,
BSD-2-Clause), which no earlier audit reads (``real_records``, ``real_audit`` ..
``real_audit13``, ``real_noise``, ``workbooks``: see their docstrings), fetched with ``pip
download --no-deps`` at run time into ``benchmarks/.cache`` and never committed; the
packages are never installed or imported:

- ``daphnet`` (aeon; ``Daphnet_S06R02E0/S06R02E0.csv``): the Daphnet freezing-of-gait set's
  subject 6, run 2: three 3-axis accelerometers (ankle, thigh, trunk) in mg on a ~9.8 mg
  grid, 64 Hz, its time stamps written to the millisecond (steps of 15 and 16 ms), walking
  with stops, and an ``is_anomaly`` label column (all 0 here);
- ``bleeding`` (aeon; ``KDD-TSAD_135/..._InternalBleeding16_TEST.csv``): the UCR anomaly
  archive's (KDD Cup 2021) InternalBleeding16, a physiological record of 7,501 samples with
  an integer ``timestamp`` and its labelled anomaly (rows 4187-4198);
- ``wiimote`` (aeon; ``PickupGestureWiimoteZ_TEST.ts``): the UCR archive's Wii remote
  gestures, Z acceleration (g, on a 1/26 g grid written to 3 decimals), its first case (a
  pick-up, 267 samples), written as a CSV column as the refusal of ``.ts`` says;
- ``enso`` (lmfit; ``NIST_STRD/ENSO.dat``): NIST StRD ENSO, the monthly pressure difference
  between Easter Island and Darwin over 168 months, below NIST's 60-line report with its
  certified residual standard deviation 2.2269642403 (a 9-parameter cyclic model).

The NIST file is cut as users cut it after the product's refusal (its 60 report lines
skipped, names given), the ``.ts`` file's first case written as a column; the refusals
themselves are checked in check 4.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks: these
   are accelerometers without a gyroscope): finite; R and the R to use inside the original's
   ci95 under reversal, dropping 1-3 leading samples, sign flip, scale x1e3, offset, linear
   trend, the verdict's finding kept (``real_audit8.finding_kept``); CLI ``--columns all`` =
   Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: (a) NIST's certified residual variance (2.2269642403²) inside ENSO's
   R's ci95; (b) grids: no R and no R to use under lsb²/12 / 4 (``real_audit8
   .grid_reference``, the grid each channel's values sit on); (c) the labelled anomaly:
   the estimator's outlying samples in the bleeding record fall inside the label's rows;
   (d) time stamps: Daphnet's millisecond stamps read as the set's documented 64 Hz
   (its clock's step, 15.625 ms), not as 62.5 Hz, and not called non-uniform sampling;
   (e) units: ``--unit mg --unit-out m/s^2`` gives (9.80665e-3)² R; (f) glitches
   (``real_audit9.glitch_reference``); (g) ``noisevar fit`` (the Kalman fit) on the pages'
   channels: r inside the estimate's ci95, or one line;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do, never a traceback nor a warning
   (``real_audit13._file_checks``); a report above a table not blamed on thousands
   separators; a format named (ASC, BLF, EDF, BDF, .ts, .tsf); with no ``--column``, a
   measured column is read (not a time stamp, not a label).

Results: benchmarks/results/real_audit14.md.
"""

from __future__ import annotations

import json
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
    ref_row,
)
from real_audit3 import fit_row, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import _file_checks, file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit14.md"
_AE = "aeon/datasets/data/"
_BLEED = _AE + "KDD-TSAD_135/135_UCR_Anomaly_InternalBleeding16_"
#: record -> (requirement, path inside the wheel or sdist, what it is)
RECORDS = {
    "daphnet": (_refdata.AEON, _AE + "Daphnet_S06R02E0/S06R02E0.csv",
                "Daphnet freezing of gait, subject 6: ankle, thigh, trunk accelerometers "
                "(mg), 64 Hz, millisecond stamps"),
    "bleeding": (_refdata.AEON, _BLEED + "TEST.csv",
                 "UCR anomaly archive InternalBleeding16: 7,501 samples, a labelled anomaly"),
    "wiimote": (_refdata.AEON, _AE + "PickupGestureWiimoteZ/PickupGestureWiimoteZ_TEST.ts",
                "a Wii remote's Z acceleration (g, 3 decimals of a 1/26 g grid), one pick-up "
                "gesture, 267 samples"),
    "enso": (_refdata.LMFIT, "NIST_STRD/ENSO.dat",
             "NIST StRD ENSO: monthly pressure difference, 168 months, certified residual SD "
             "(a 60-line report above the table)"),
}  # fmt: skip
_AXES = [f"{s}_{a}" for s in ("ankle", "leg", "trunk")
         for a in ("horiz_fwd", "vert", "horiz_lateral")]  # fmt: skip
#: channels per record (the product's column names)
#: (Daphnet's ``is_anomaly`` label, all 0, is no measured channel: check 4 opens the file)
CHANNELS = {"daphnet": _AXES, "bleeding": ["value"], "wiimote": ["acc_z"], "enso": ["y"]}
#: NIST's file cut as the refusal says: (pandas skiprows, names)
ENSO_CUT = (60, ["y", "x"])
#: NIST's certified residual standard deviation of ENSO (ENSO.dat, line 51)
ENSO_SD = 2.2269642403
#: channels shown on the pages (AppTest is slow): Two sensors pairs each with the next
PAGES = {"daphnet": ["trunk_vert", "trunk_horiz_fwd"], "bleeding": ["value"], "wiimote": ["acc_z"],
         "enso": ["y"]}  # fmt: skip
#: records whose values sit on a grid (Daphnet's ~9.8 mg steps, the Wii remote's 1/26 g written
#: to 3 decimals, NIST's 0.1); the bleeding
#: record's five decimals are a float's
GRIDS = ("daphnet", "wiimote", "enso")
#: the Daphnet set's documented rate (Hz)
DAPHNET_HZ = 64.0
#: standard gravity (m/s² per g), for the mg -> m/s² check
G0 = 9.80665


# ---------------------------------------------------------------- the files
def raw(name: str) -> Path:
    """The record's file as published."""
    req, rel, _ = RECORDS[name]
    if req == _refdata.AEON:
        return _refdata.wheel_path(req, rel)
    return _refdata.sdist_path(req, rel)


def user_file(name: str) -> Path:
    """The file a user gives: NIST's report cut as the refusal says, the Wii remote's first
    case written as a CSV column as the refusal of ``.ts`` says, the others as shipped."""
    if name == "wiimote":
        out = raw(name).with_name("wiimote_case1.csv")
        if not out.exists():
            case = raw(name).read_text().split("@data", 1)[1].split()[0]
            values = [float(v) for v in case.rsplit(":", 1)[0].split(",")]
            pd.DataFrame({"acc_z": values}).to_csv(out, index=False)
        return out
    if name != "enso":
        return raw(name)
    out = raw(name).with_name("ENSO_user.csv")
    if not out.exists():
        skip, names = ENSO_CUT
        pd.read_csv(raw(name), sep=r"\s+", skiprows=skip, header=None,
                    names=names).to_csv(out, index=False)  # fmt: skip
    return out


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples as the product reads them from the user's file."""
    table = load_table(user_file(name))
    out = {}
    for col in CHANNELS[name]:
        z, _t = channel_record(table, col, drop_nonfinite=True)
        out[col] = np.asarray(z, float)[np.isfinite(z)]
    return out


def rate_of(name: str) -> float:
    """The record's sample rate (Hz) as the product reads its time column (1 without one)."""
    table = load_table(user_file(name))
    return 1.0 / table.sample_period if table.sample_period else 1.0


# ---------------------------------------------------------------- check 3: references
def enso_reference(z: np.ndarray) -> dict:
    """3a: NIST's certified residual variance inside R's ci95."""
    est, ref = nv.estimate(z), ENSO_SD**2
    fail = [] if est.ci95[0] <= ref <= est.ci95[1] else [
        f"R x{est.variance / ref:.3g} NIST's certified residual variance, outside its ci95"
    ]  # fmt: skip
    return ref_row("enso", "y", "NIST's certified residual SD² (9-parameter model)", ref, est,
                   fail)  # fmt: skip


def grid_step(z: np.ndarray) -> float:
    """The grid a channel's values sit on: its smallest step between distinct values."""
    return float(np.min(np.diff(np.unique(z))))


def anomaly_reference() -> dict:
    """3c: the bleeding record's outlying samples fall inside its labelled anomaly."""
    df = pd.read_csv(raw("bleeding"))
    z = df["value"].to_numpy(float)
    rows = np.flatnonzero(df["is_anomaly"].to_numpy() == 1)
    est = nv.estimate(z)
    out = np.asarray([] if est.outliers is None else est.outliers, int)  # sample indices
    outside = [int(i) for i in out if not rows[0] <= i <= rows[-1]]
    fail = [] if out.size and not outside else (
        [f"outlying samples at {outside[:5]} outside the label"] if outside
        else ["no outlying sample in the labelled anomaly"])  # fmt: skip
    return ref_row("bleeding", "value", f"labelled anomaly rows {rows[0]}-{rows[-1]} "
                   f"({out.size} outlying: {', '.join(map(str, out[:4]))})", float(rows[0]),
                   est, fail)  # fmt: skip


def rate_reference() -> dict:
    """3d: Daphnet's millisecond stamps give its documented 64 Hz, said as uniform."""
    table = load_table(raw("daphnet"))
    z, _t = channel_record(table, "trunk_vert")
    rate = 1.0 / table.sample_period if table.sample_period else float("nan")
    fail = [] if abs(rate / DAPHNET_HZ - 1) < 1e-3 else [
        f"read as {rate:.6g} Hz, the set's rate is {DAPHNET_HZ:g} Hz"
    ]  # fmt: skip
    if any("not uniform" in n for n in table.notes):
        fail.append("millisecond stamps of a 64 Hz clock called non-uniform sampling")
    return ref_row("daphnet", "timestamp (rate, Hz)", "the set's documented 64 Hz", DAPHNET_HZ,
                   nv.estimate(z), fail)  # fmt: skip


def unit_reference() -> dict:
    """3e: ``--unit mg --unit-out m/s^2`` gives (9.80665e-3)² R."""
    path, col = raw("daphnet"), "trunk_vert"
    z, _t = channel_record(load_table(path), col)
    est, k = nv.estimate(z), (G0 * 1e-3) ** 2
    rc, out, err = process("estimate", path, "--column", col, "--unit", "mg", "--unit-out",
                           "m/s^2", "--format", "json")  # fmt: skip
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    if rc == 0 and abs(json.loads(out)["variance"] / (k * est.variance) - 1) > 1e-6:
        fail.append(f"R in m/s^2 x{json.loads(out)['variance'] / est.variance:.6g} R")
    return ref_row("daphnet", f"{col} mg -> m/s^2", "(9.80665e-3)² R", k * est.variance, est,
                   fail)  # fmt: skip


def fit_reference(name: str, col: str) -> dict:
    """3g: ``noisevar fit`` gives an r inside the estimate's ci95 or names the assumption the
    record breaks, or refuses in one line (`real_audit3.fit_said`)."""
    path = user_file(name)
    z, t = channel_record(load_table(path), col, drop_nonfinite=True)
    est = nv.estimate(z, t=t)
    return fit_row(name, path, col, est)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = [grid_reference(name, c, z, grid_step(z)) for c, z in chans.items() if name in GRIDS]
    if name == "enso":
        out.append(enso_reference(chans["y"]))
    if name == "bleeding":
        out.append(anomaly_reference())
    if name == "daphnet":
        out += [rate_reference(), unit_reference()]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, col) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: a time stamp, a label
_NOT_SIGNALS = {"timestamp", "is_anomaly", "x"}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"ASC": "ASC file", "BLF": "BLF file", "EDF": "EDF file", "BDF": "BDF file",
            ".tsf": ".tsf file", "(.ts)": ".ts file"}  # fmt: skip


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13._file_checks``, with this audit's formats and non-signals."""
    fail = _file_checks(what, rc, out, err)
    for word, name in _FORMATS.items():
        if word in what and rc == 2 and name not in err:
            fail.append(f"refused without naming the format ({name!r})")
    if rc == 0 and "no --column" in what:
        row = json.loads(out)
        row = row.get("channels", [row])[0]
        if row.get("column") in _NOT_SIGNALS:
            fail.append(f"opened on {row.get('column')!r}, not a measured column")
    return fail


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    nist = lambda f: _refdata.sdist_path(_refdata.LMFIT, "NIST_STRD/" + f)  # noqa: E731
    can = lambda f: _refdata.sdist_path(_refdata.PYTHON_CAN, "test/data/" + f)  # noqa: E731
    edf = lambda f: _refdata.wheel_path(_refdata.PYEDFLIB, "pyedflib/tests/data/" + f)  # noqa: E731
    ae = lambda f: _refdata.wheel_path(_refdata.AEON, _AE + f)  # noqa: E731
    cases = {
        "Daphnet CSV (ms time stamps, a label column), no --column": (raw("daphnet"), []),
        "Daphnet CSV, --columns all": (raw("daphnet"), ["--columns", "all"]),
        "UCR anomaly CSV (integer timestamp, a label), no --column": (raw("bleeding"), []),
        "UCR anomaly CSV, its TRAIN part, no --column": (ae(_BLEED[len(_AE):] + "TRAIN.csv"), []),
        "NIST StRD ENSO as shipped (a report above the table), refused": (raw("enso"), []),
        "NIST StRD Hahn1 as shipped (a report above the table), refused": (nist("Hahn1.dat"), []),
        "NIST StRD ENSO, cut as the refusal says, no --column": (user_file("enso"), []),
        "Vector ASC CAN log (a CAN bus trace, 2014), refused": (can("issue_1256.asc"), []),
        "Vector ASC CAN log (error frames, German day name), refused":
            (can("logfile.asc"), []),
        "Vector BLF CAN log, refused": (can("test_CanMessage.blf"), []),
        "EDF (pyedflib's generator), refused": (edf("test_generator.edf"), []),
        "BDF (pyedflib's generator), refused": (edf("test_generator.bdf"), []),
        "UCR archive's Wiimote gestures (.ts), refused":
            (ae("PickupGestureWiimoteZ/PickupGestureWiimoteZ_TEST.ts"), []),
        "Monash forecasting archive file (.tsf), refused":
            (ae("UnitTest/UnitTest_Tsf_Loader.tsf"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A fourteenth audit, for gait, physiology and vehicle-bus engineers: body-worn "
        "accelerometers, a labelled anomaly, a NIST certified series and the files these "
        "fields bring (issue 26)",
        "real_audit14.py", f"`{_refdata.AEON}`'s and `{_refdata.PYEDFLIB}`'s wheels and "
        f"`{_refdata.LMFIT}`'s and `{_refdata.PYTHON_CAN}`'s sdists", RECORDS,
        [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rows = audited_rows(name, chans, rate_of(name))
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

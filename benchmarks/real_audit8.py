"""An eighth audit on real records nobody here wrote: a smartwatch IMU, appliance power, an
ECG, solar generation, economic and market series, sunspots and weather (issue 26).

    python benchmarks/real_audit8.py                     # every record, a few minutes
    python benchmarks/real_audit8.py --records msft      # records whose name has it; prints only

Measured data shipped in three wheels no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit7``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; the packages are never installed or imported (``_refdata.SKTIME``, ``PMDARIMA``,
``VEGA``):

- ``basicmotions`` (sktime, BSD-3-Clause; the UEA archive's BasicMotions): a smartwatch's
  accelerometer and gyroscope at 10 Hz, 10-s cases labelled Standing, Walking, Running,
  Badminton, in the ``.ts`` format; the record a user would cut: one Standing case then four
  Walking cases (a short still start, 20 %, then motion; samples held twice now and then);
- ``acsf1`` (sktime; ACS-F1): two appliances' power consumption, 1,460 samples each (held
  values, level jumps), in the ``.ts`` format;
- ``mitdb`` (sktime; MIT-BIH via PhysioNet): 7,500 samples of an ECG in mV on the
  digitiser's 0.005 mV grid, beside a 0/1 label column;
- ``solar`` (sktime; Sheffield Solar's PV_Live): UK solar generation, half-hourly, 6 days,
  date-times with ``+00:00``; the nights are zeros (held values, no sensor noise);
- ``uschange`` (sktime; Hyndman's fpp): US quarterly percentage changes (differenced data),
  an unnamed index column and ``1970 Q1`` dates;
- ``msft`` (pmdarima, MIT): Microsoft's daily prices 1986-2017 with dates (weekends: gaps),
  prices on a 1e-4 grid early on, the volume (heavy tails) and ``OpenInt`` (always 0);
- ``sunspots`` (pmdarima; R's ``sunspots``): monthly sunspot numbers 1749-1983, written 12 a
  line (a year a row), as R's ``dput`` of a ``ts`` prints them;
- ``seattle_temps`` (vega_datasets, BSD-3-Clause; NOAA): hourly temperature of 2010 in °F
  on a 0.1 grid, local date-times (a DST hour missing);
- ``seattle_weather`` (vega_datasets): daily precipitation (mostly 0: held), temperatures
  and wind, a text column;
- ``stocks`` (vega_datasets): five stocks' monthly prices stacked in one column with a text
  ``symbol`` column (the long format): as the user's file it is several series in one.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported; the IMU checks on the
   smartwatch): finite; R and the R to use inside the original's ci95 under reversal,
   dropping 1-3 leading samples, sign flip, scale x1e3, offset, linear trend; CLI
   ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported) on the file as a user
   has it (the smartwatch's record: cut into a CSV with a 10 Hz time column): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and
   the pages that show R (Signal, Estimator, Noise model, Two sensors, Fleet);
3. **references**: (a) the smartwatch's Standing case, a hand-cut still stretch: its
   var(d2)/6 against the R to use of the standing-then-walking record (within x1.5, or its
   ci95 covers it), the verdict not calling the whole record white; (b) a datasheet grid:
   the ECG's 0.005 mV (200 counts a mV), the temperatures' 0.1 °F, the sunspot numbers' 0.1:
   no R and no R to use under lsb²/12 / 4; (c) held zeros are no sensor noise: solar's
   nights and Seattle's dry days (precipitation 0) may not be quoted as the R to use (not
   under R / 100); (d) a unit conversion: ``--unit degF --unit-out degC`` gives (5/9)² R;
4. **the files as users have them**: each read (exit 0) or refused with one line (exit 2)
   that says what to do, never a traceback; with no ``--column``, a measured column is read
   (not a label, an index, a date); a date-time column gives the sample period, whatever it
   is (hourly, daily, monthly), with no note that it may count microseconds; a file that
   stacks several series (a text key column, time restarting) is not answered as one; a
   headerless table that is one series written 12 values a line says so.

Results: benchmarks/results/real_audit8.md.
"""

from __future__ import annotations

import gzip
import json
import sys
import tarfile
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
    held_refusal,
    ref_row,
    to_use,
)
from real_audit3 import _one_line, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from verdict_invariance import check as finding_moves  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit8.md"
_SK = "sktime/datasets/data/"
_PM = "pmdarima/datasets/data/"
_VG = "vega_datasets/_data/"
#: record -> (requirement, path inside the wheel, what it is)
RECORDS = {
    "basicmotions": (_refdata.SKTIME, _SK + "BasicMotions/BasicMotions_TRAIN.ts",
                     "smartwatch IMU, 10 Hz, Standing then Walking cases (.ts)"),
    "acsf1": (_refdata.SKTIME, _SK + "ACSF1/ACSF1_TRAIN.ts",
              "two appliances' power consumption (.ts)"),
    "mitdb": (_refdata.SKTIME, _SK + "mitdb/mitdb.csv", "MIT-BIH ECG (mV), a label column"),
    "solar": (_refdata.SKTIME, _SK + "solar/solar.csv",
              "UK solar generation, half-hourly, +00:00 date-times"),
    "uschange": (_refdata.SKTIME, _SK + "Uschange/Uschange.csv",
                 "US quarterly % changes, an index column, '1970 Q1'"),
    "msft": (_refdata.PMDARIMA, _PM + "msft.tar.gz", "Microsoft daily prices, volume, dates"),
    "sunspots": (_refdata.PMDARIMA, _PM + "sunspots.txt.gz",
                 "monthly sunspot numbers, 12 a line"),
    "seattle_temps": (_refdata.VEGA, _VG + "seattle-temps.csv",
                      "hourly temperature 2010 (°F), local date-times"),
    "seattle_weather": (_refdata.VEGA, _VG + "seattle-weather.csv",
                        "daily precipitation, temperatures, wind, a text column"),
    "stocks": (_refdata.VEGA, _VG + "stocks.csv", "five stocks' monthly prices, stacked"),
}  # fmt: skip
#: channels per record (the file's own names), read by the product from the file
CHANNELS = {
    "mitdb": ["data"], "solar": ["solar_gen"],
    "uschange": ["Consumption", "Income", "Production", "Savings", "Unemployment"],
    "msft": ["Open", "High", "Low", "Close", "Volume"],
    "seattle_temps": ["temp"],
    "seattle_weather": ["precipitation", "temp_max", "temp_min", "wind"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow)
PAGES = {"basicmotions": ["acc_x", "gyr_y"], "mitdb": ["data"], "seattle_temps": ["temp"],
         "uschange": ["Consumption", "Income"], "msft": ["Close"]}  # fmt: skip
#: datasheet grids (3b): MIT-BIH's 200 counts a mV, NOAA's 0.1 °F, the sunspots' 0.1
LSB = {("mitdb", "data"): 0.005, ("seattle_temps", "temp"): 0.1, ("sunspots", "sunspots"): 0.1}
#: channels whose held zeros are no sensor noise (3c)
HELD_ZEROS = {("solar", "solar_gen"), ("seattle_weather", "precipitation")}
_IMU6 = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")


def raw(name: str) -> Path:
    """The record's file as a user has it, extracted once to the cache (``msft``'s CSV out
    of its tarball, the sunspots' text out of its gzip)."""
    req, rel, _ = RECORDS[name]
    path = _refdata.wheel_path(req, rel)
    if rel.endswith(".tar.gz"):
        out = path.with_name(path.name.removesuffix(".tar.gz") + ".csv")
        if not out.exists():
            with tarfile.open(path) as tar:
                out.write_bytes(tar.extractfile(out.name).read())  # type: ignore[union-attr]
        return out
    if rel.endswith(".gz"):
        out = path.with_suffix("")
        if not out.exists():
            out.write_bytes(gzip.decompress(path.read_bytes()))
        return out
    return path


def ts_cases(name: str) -> list[tuple[str, list[np.ndarray]]]:
    """The cases of a ``.ts`` file (sktime's format): (label, one array per dimension)."""
    out, data = [], False
    for line in raw(name).read_text().splitlines():
        if data and line.strip():
            *dims, label = line.strip().split(":")
            out.append((label, [np.array(d.split(","), float) for d in dims]))
        data = data or line.strip().lower() == "@data"
    return out


def basicmotions() -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The record (one Standing case, then four Walking cases) and the Standing case."""
    cases = ts_cases("basicmotions")
    stand = next(d for lab, d in cases if lab == "Standing")
    walk = [d for lab, d in cases if lab == "Walking"][:4]
    rec = {c: np.concatenate([stand[i], *(w[i] for w in walk)]) for i, c in enumerate(_IMU6)}
    return rec, {c: stand[i] for i, c in enumerate(_IMU6)}


def basicmotions_csv() -> Path:
    """The standing-then-walking record as a user cuts it into a CSV (``time`` at 10 Hz, the
    six channels): the file the pages and the CLI read (check 2)."""
    out = raw("basicmotions").with_name("basicmotions_standing_walking.csv")
    if not out.exists():
        rec = basicmotions()[0]
        n = rec["acc_x"].size
        pd.DataFrame({"time": np.arange(n) / 10.0, **rec}).to_csv(out, index=False)
    return out


def stocks() -> dict[str, np.ndarray]:
    df = pd.read_csv(raw("stocks"))
    return {s: g["price"].to_numpy(float) for s, g in df.groupby("symbol", sort=False)}


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples, as the product reads them from the user's file (the
    ``.ts`` files, the sunspots' 12-a-line table and the stacked stocks: as their
    publishers document them)."""
    if name == "basicmotions":
        return basicmotions()[0]
    if name == "acsf1":
        cases = ts_cases(name)
        return {f"case{i}_{lab}": d[0] for i, (lab, d) in enumerate(cases[:20:10])}
    if name == "sunspots":
        return {"sunspots": np.loadtxt(raw(name)).ravel()}
    if name == "stocks":
        return stocks()
    table, out = load_table(raw(name)), {}
    for ch in CHANNELS[name]:
        z, _t = channel_record(table, ch, drop_nonfinite=True)
        out[ch] = np.asarray(z, float)[np.isfinite(z)]
    return out


def finding_kept(rows: list[dict], chans: dict[str, np.ndarray]) -> None:
    """Check 1's last part: the verdict's finding (its lead) kept under each transform
    (``verdict_invariance.check``); a transform that moves it is a failure of the row."""
    for row in rows:
        if "R" in row:
            base, moved, _other = finding_moves(chans[row["channel"]])
            row["fail"] += [f"finding moved under {m}"[:160] for m in moved]


def audited_rows(name: str, chans: dict[str, np.ndarray], rate: float, imu: bool = False
                 ) -> list[dict]:  # fmt: skip
    """Check 1 on every channel of one record (``real_audit.audit_channels``, channels of
    one length together: ``real_audit.by_length``), each finding kept (:func:`finding_kept`)."""
    rows = []
    for same in by_length(chans):
        new = audit_channels(name, same, rate, imu=imu)
        finding_kept(new, same)
        rows += new
    return rows


# ---------------------------------------------------------------- check 3: references
def _white(est) -> bool:
    return (est.verdict or "").startswith("white")


def still_reference(rec: dict, stand: dict) -> list[dict]:
    """3a: the Standing case's var(d2)/6 against the R to use of the whole record."""
    res = []
    for ch, z in rec.items():
        ref = float(np.var(np.diff(stand[ch], 2)) / 6.0)
        est, fail = nv.estimate(z), []
        use = to_use(est)
        if use is None:
            fail.append("no R to use (a still start of 20 %)")
        elif not (ref / 1.5 <= use.variance <= ref * 1.5 or use.ci95[0] <= ref <= use.ci95[1]):
            fail.append(f"R to use x{use.variance / ref:.3g} the Standing case's var(d2)/6")
        if _white(est):
            fail.append("a still start then walking called white")
        res.append(ref_row("basicmotions", ch, "Standing case var(d2)/6", ref, est, fail))
    return res


def grid_reference(name: str, ch: str, z: np.ndarray, lsb: float | None = None) -> dict:
    """3b: no R and no R to use under lsb²/12 / 4 (the datasheet's grid; ``lsb``: another
    audit's grid, by default :data:`LSB`'s)."""
    lsb = LSB[(name, ch)] if lsb is None else lsb
    floor = lsb**2 / 12.0
    est = nv.estimate(z)
    use = to_use(est)
    fail = [f"{w} {v:.3g} under lsb²/12 / 4" for w, v in
            (("R", est.variance), ("R to use", None if use is None else use.variance))
            if v is not None and v < floor / 4]  # fmt: skip
    return ref_row(name, ch, f"lsb²/12, lsb {lsb:g}", floor, est, fail)


def held_reference(name: str, ch: str, z: np.ndarray) -> dict:
    """3c: the held zeros are not quoted as the sensor's noise."""
    est = nv.estimate(z)
    use = to_use(est)
    fail = [] if use is None or use.variance >= est.variance / 100 else [
        f"R to use {use.variance:.3g}, x{use.variance / est.variance:.3g} R: the held zeros "
        "quoted as the sensor's noise"]  # fmt: skip
    return ref_row(name, ch, "R / 100 (held zeros)", est.variance / 100, est, fail)


def unit_reference() -> dict:
    """3d: ``--unit degF --unit-out degC`` gives (5/9)² R."""
    path = raw("seattle_temps")
    z, t = channel_record(load_table(path), "temp")
    est = nv.estimate(z, t=t)
    ref = est.variance * (5.0 / 9.0) ** 2
    rc, out, err = process("estimate", path, "--column", "temp", "--unit", "degF",
                           "--unit-out", "degC", "--format", "json")  # fmt: skip
    fail = []
    if rc:
        fail.append(f"exit {rc}: {err[:120]}")
    elif abs(json.loads(out)["variance"] / ref - 1) > 1e-6:
        fail.append(f"R in degC x{json.loads(out)['variance'] / ref:.6g} (5/9)² R in degF")
    return ref_row("seattle_temps", "temp degF -> degC", "(5/9)² R", ref, est, fail)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = []
    if name == "basicmotions":
        out += still_reference(*basicmotions())
    out += [grid_reference(name, ch, z) for ch, z in chans.items() if (name, ch) in LSB]
    out += [held_reference(name, ch, z) for ch, z in chans.items() if (name, ch) in HELD_ZEROS]
    if name == "seattle_temps":
        out.append(unit_reference())
    return out


# ---------------------------------------------------------------- check 4: the files
#: words of a refusal that says what to do
_TO_DO = ("give", "delete", "remove", "drop", "export", "clean", "convert", "try", "use ",
          "split", "filter", "save")  # fmt: skip
#: no default signal: a label, an index, a date's part
_NOT_SIGNALS = {"label", "col0", "OpenInt", "Date", "date", "Quarter"}


def _notes(out: str) -> list[str]:
    js = json.loads(out)
    rows = js.get("channels", [js])
    notes = rows[0].get("notes") or "[]"
    return json.loads(notes) if isinstance(notes, str) else list(notes)


def _file_checks(what: str, path: Path, rc: int, out: str, err: str) -> list[str]:
    fail = [] if rc == 0 or _one_line(rc, err) else [f"exit {rc}: {err[-160:]}"]
    if rc == 2 and not any(w in err for w in _TO_DO):
        fail.append("the refusal does not say what to do")
    if rc == 2 and "thousands separators" in err and ".ts" in what:
        fail.append("refused blaming thousands separators")
    if rc == 0 and "stacked" in what:
        fail.append("five series stacked in one column answered as one record")
    if rc != 0:
        if "refused" not in what and not held_refusal(err):
            fail.append("refused: a measured column must answer")
        return fail
    js = json.loads(out)
    names = [r.get("column") for r in js.get("channels", [js])]
    notes = " ".join([*_notes(out), *load_table(path).notes])
    if "no --column" in what and names[0] in _NOT_SIGNALS:
        fail.append(f"opened on {names[0]!r}, not a measured column")
    if "date" in what and "microseconds" in notes:
        fail.append("a date-time column said to perhaps count microseconds")
    if "date" in what and load_table(path).sample_period is None:
        fail.append("no sample period from its dates")
    if "12 a line" in what and "values a line" not in notes:
        fail.append(f"answered for {names[0]!r}: one calendar month of each year, unsaid")
    return fail


def msft_monthly() -> Path:
    """The MSFT rows of ``stocks.csv`` in their own file, as its refusal says to give them."""
    out = raw("stocks").with_name("stocks_MSFT.csv")
    if not out.exists():
        df = pd.read_csv(raw("stocks"))
        df[df["symbol"] == "MSFT"].to_csv(out, index=False)
    return out


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    cases = {
        "BasicMotions .ts (sktime/UEA), refused or read": (raw("basicmotions"), []),
        "ACSF1 .ts, refused or read": (raw("acsf1"), []),
        "MIT-BIH CSV, no --column (data, label)": (raw("mitdb"), []),
        "solar CSV, +00:00 date-times, no --column": (raw("solar"), []),
        "uschange CSV, unnamed index, '1970 Q1', no --column": (raw("uschange"), []),
        "msft CSV, daily dates, no --column": (raw("msft"), []),
        "msft CSV, --column OpenInt (always 0), refused": (raw("msft"), ["--column", "OpenInt"]),
        "sunspots, 12 a line, no header": (raw("sunspots"), []),
        "seattle-temps CSV, hourly date-times": (raw("seattle_temps"), []),
        "seattle-weather CSV, daily dates, a text column": (raw("seattle_weather"),
                                                            ["--columns", "all"]),
        "stocks CSV, five series stacked, refused": (raw("stocks"), []),
        "stocks CSV's MSFT rows, monthly dates": (msft_monthly(), []),
    }  # fmt: skip
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        res.append({"case": what, "exit": rc, "said": err if rc else cli_said(out),
                    "fail": _file_checks(what, path, rc, out, err)})  # fmt: skip
    return res


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "An eighth audit on real records nobody here wrote: a smartwatch IMU, appliance "
        "power, an ECG, solar generation, economic and market series, sunspots, weather "
        "(issue 26)",
        "real_audit8.py", f"the wheels of `{_refdata.SKTIME}`, `{_refdata.PMDARIMA}`, "
        f"`{_refdata.VEGA}`", RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    imu, rate = (True, 10.0) if name == "basicmotions" else (False, 1.0)
    rows = audited_rows(name, chans, rate, imu=imu)
    refs = references(name, chans)
    answers = []
    if pages and name in PAGES:
        path = basicmotions_csv() if name == "basicmotions" else raw(name)
        answers = one_answer(name, path, PAGES[name])
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

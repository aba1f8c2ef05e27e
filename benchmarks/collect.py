"""Assemble BENCHMARKS.md from the result files the benchmark commands write.

    python benchmarks/collect.py

Every number in BENCHMARKS.md comes from one of these commands (each writes
its section under ``benchmarks/results/``):

    python benchmarks/accuracy.py          -> results/accuracy.md   (issue 3)
    python benchmarks/peers.py             -> results/peers.md      (issue 3)
    python benchmarks/speed.py             -> results/speed.md      (issue 3)
    python benchmarks/kalman.py            -> results/kalman.md     (issue 4)
    python benchmarks/dashboard.py         -> results/dashboard.md  (issue 5)
    python benchmarks/seeds.py --runs 100 --kappa-selection
                                           -> results/seeds.md      (issue 6)
    python benchmarks/real_noise.py        -> results/real_noise.md (issue 13)
    python benchmarks/noise_model.py       -> results/noise_model.md (issue 14)
    python benchmarks/kalman_tuning.py     -> results/kalman_tuning.md (issue 14)
    python benchmarks/hostile.py --mb 500  -> results/hostile.md    (issue 15)
    python benchmarks/dashboard_browser.py -> results/dashboard_browser.md (issue 16)
    python benchmarks/batch.py --files 300 -> results/batch.md      (issue 17)

The summary at the top is ``benchmarks/summary.md`` (written by hand from
those files; it quotes them and must be updated when they change).
"""

from __future__ import annotations

from pathlib import Path

HERE = Path(__file__).resolve().parent
SECTIONS = [
    ("Core estimator: accuracy (issue 3)", "accuracy.md"),
    ("Core estimator: auto against the state-space MLE, paired (issue 3)", "peers.md"),
    ("Core estimator: speed and memory (issue 3)", "speed.md"),
    ("Adaptive Kalman filtering (issue 4)", "kalman.md"),
    ("Dashboard responsiveness (issue 5)", "dashboard.md"),
    ("The other seed systems (issue 6)", "seeds.md"),
    ("Real noise: heavy tails, coloured noise, quantisation, gaps (issue 13)", "real_noise.md"),
    ("Noise model: Allan deviation and inertial terms (issue 14)", "noise_model.md"),
    ("Noise model: Q and R together, coloured noise (issue 14)", "kalman_tuning.md"),
    ("Hostile input (issue 15)", "hostile.md"),
    ("The dashboard in a real browser (issue 16)", "dashboard_browser.md"),
    ("Channels and batch (issue 17)", "batch.md"),
    ("Records larger than memory (issue 17)", "stream.md"),
]


def _demote(body: str) -> str:
    """Nest a result file under its section: its title becomes bold, its headings level 3+."""
    lines = body.splitlines()
    out = []
    for i, line in enumerate(lines):
        if line.startswith("#"):
            text = line.lstrip("#").strip()
            hashes = len(line) - len(line.lstrip("#"))
            line = f"**{text}**" if i == 0 else "#" * max(hashes, 3) + " " + text
        out.append(line)
    return "\n".join(out)


def main() -> None:
    """Write BENCHMARKS.md next to the benchmarks folder."""
    parts = [(HERE / "summary.md").read_text().rstrip(), ""]
    for title, name in SECTIONS:
        body = _demote((HERE / "results" / name).read_text().strip())
        parts += [
            f"## {title}",
            "",
            f"*Produced by the command named in it; file `benchmarks/results/{name}`.*",
            "",
            body,
            "",
        ]
    (HERE.parent / "BENCHMARKS.md").write_text("\n".join(parts))


if __name__ == "__main__":
    main()

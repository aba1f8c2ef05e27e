"""``noisevar fit FILE --model rw|cv|ca --rate HZ``: Q and R of a kinematic Kalman filter."""

from __future__ import annotations

import argparse
import inspect
import json
from pathlib import Path
from typing import Any

from noisevar.cli._common import (
    add_regimes_flag,
    add_topic_flag,
    load_signal,
    print_json,
    regimes_of,
)
from noisevar.errors import NoisevarError


def _print_table(t: Any, args: argparse.Namespace) -> None:
    def iv(pair: tuple[float, float]) -> str:
        return f"(95 % {pair[0]:.4g} .. {pair[1]:.4g})"

    print(f"file      {args.file}" + (f"  column {args.column}" if args.column else ""))
    print(f"model     {t.model}   method {t.method}   samples {t.n}   regimes {t.regimes}")
    print(f"q         {t.q:.6g} {t.units['q']}  {iv(t.q_interval)}")
    print(f"r         {t.r:.6g} {t.units['r']}  {iv(t.r_interval)}")
    print(f"h         {t.h:.6g} (q T^k / r)  {iv(t.h_interval)}")
    print(f"gain      {', '.join(f'{g:.6g}' for g in t.gain)}")
    lo, hi = t.nis_band
    print(f"NIS mean  {t.nis_mean:.4g}   (95 % band {lo:.4g} .. {hi:.4g})")
    white = "white" if t.innovations_white else "NOT white"
    print(f"innov.    {white} (Ljung-Box p = {t.ljung_box_p:.3g})   loglik {t.loglik:.6g}")
    for note in t.notes:
        print(f"note      {note}")


def _cmd_fit(args: argparse.Namespace) -> int:
    from noisevar.config import load_config, validate_config
    from noisevar.estimators import DEFAULT_METHOD
    from noisevar.noise_model import evaluate_kalman, fit_kalman
    from noisevar.noise_model.export import from_config, to_config

    if args.rate is not None and not args.rate > 0:
        raise NoisevarError(
            f"--rate must be a positive number of samples per second, got {args.rate}"
        )
    z, dropped = load_signal(args.file, args.column, topic=args.topic)
    if args.config:
        if args.regimes is not None:
            raise NoisevarError(
                "--regimes chooses what a fit runs on: drop it with --config (no fit is made)"
            )
        kal = from_config(load_config(args.config))
        rate = args.rate if args.rate is not None else kal["rate"]
        model = args.model or kal["model"]
        if model != kal["model"] or rate != kal["rate"]:
            raise NoisevarError(
                f"the config's filter is model {kal['model']!r} at rate {kal['rate']}: "
                "drop --model/--rate or give the same values"
            )
        tuning = evaluate_kalman(z, model, kal["q"], kal["r"], rate=rate)
    else:
        if args.rate is None:
            raise NoisevarError("--rate is required: the sample rate in Hz (samples per second)")
        method = {} if args.method is None else {"method": args.method}  # else fit_kalman's
        model = args.model or "cv"
        tuning = fit_kalman(z, model=model, rate=args.rate, **method, **regimes_of(args))
    if args.save_config:
        config = to_config(tuning, {"method": DEFAULT_METHOD})
        text = json.dumps(validate_config(config), indent=2) + "\n"
        Path(args.save_config).write_text(text, encoding="utf-8")
    if args.format == "json":
        out = tuning.to_dict()
        out.update(file=args.file, column=args.column, dropped=dropped)
        print_json(out)
    else:
        _print_table(tuning, args)
    return 0


def add_parser(sub: Any) -> None:
    """Register ``fit`` on the sub-command set ``sub``."""
    from noisevar.noise_model.kalman_fit import METHODS, MODELS, fit_kalman

    p = sub.add_parser("fit", help="fit Q and R of a kinematic Kalman filter to a record")
    p.add_argument("file", help="CSV/TSV (with or without header), .npy, or NMEA file")
    p.add_argument("--column", help="column name or 0-based index (default: the only/first)")
    add_topic_flag(p)
    p.add_argument("--model", choices=list(MODELS), help="rw, cv or ca (default cv)")
    p.add_argument("--rate", type=float, help="sample rate in Hz (required unless in --config)")
    default = inspect.signature(fit_kalman).parameters["method"].default
    p.add_argument("--method", choices=list(METHODS), help=f"default {default}")
    add_regimes_flag(p)
    p.add_argument("--config", help="apply the Q and R of this config instead of fitting")
    p.add_argument("--save-config", metavar="OUT", help="write the tuned filter as a config")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_fit)

"""``noisevar scan-h FILE``: the h range of eq. 14 (smoothing strength)."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from noisevar.cli._common import add_drop_flag, add_topic_flag, load_signal, print_json


def _cmd_scan_h(args: argparse.Namespace) -> int:
    from noisevar.estimators import scale_exponent
    from noisevar.filters.envelope import scan_h

    z, _ = load_signal(args.file, args.column, args.drop_nonfinite, topic=args.topic)
    # the ratios do not depend on the units: an exact power-of-two rescale keeps squares finite
    scan = scan_h(np.ldexp(z, scale_exponent(z)), window=args.window)
    if args.format == "json":
        print_json(scan.to_dict())
    else:
        print(f"band      {scan.band[0]:.3g} .. {scan.band[1]:.3g} (|V1|/|V2|, eq. 14)")
        print(f"h range   {scan.h_min:.3g} .. {scan.h_max:.3g}")
        print(f"h chosen  {scan.h_chosen:.3g}")
        print("h          ratio")
        for h, r in zip(scan.h, scan.ratio, strict=True):
            mark = "  *" if scan.band[0] <= r <= scan.band[1] else ""
            print(f"{h:<10.3g} {r:.4f}{mark}")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``scan-h`` on the sub-command set ``sub``."""
    p = sub.add_parser("scan-h", help="h range of eq. 14 (smoothing strength)")
    p.add_argument("file")
    p.add_argument("--column")
    add_topic_flag(p)
    add_drop_flag(p)
    p.add_argument("--window", type=int, default=40)
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_scan_h)

"""``noisevar imu FILE --temperature COLUMN``: bias(T), warm-up and bias process noise (§E9)."""

from __future__ import annotations

import argparse

import numpy as np

from noisevar.errors import NoisevarError


def split_temperature(
    args: argparse.Namespace, data: dict[str, np.ndarray], rate: float
) -> np.ndarray | None:
    """The ``--temperature`` column (taken out of ``data`` if loaded with it), or None."""
    name = args.temperature
    if not name:
        return None
    if name in data:
        temp = data.pop(name)
    else:
        from noisevar.cli.allan import load_columns

        temp = load_columns(args.file, [name], rate, None, args.time_unit, args.series)[0][name]
    if not data:
        raise NoisevarError(f"--temperature {name}: give rate columns besides the temperature.")
    return temp


def temperature_models(
    data: dict[str, np.ndarray],
    temp: np.ndarray,
    rate: float,
    units: dict[str, tuple[float, str]] | None = None,
) -> dict:
    """One temperature model per column, in its unit (``units``: column -> (factor, unit))."""
    from noisevar.noise_model import temperature_model

    units = units or {c: (1.0, "u") for c in data}
    out = {}
    for scale, unit in dict.fromkeys(units.values()):
        names = [c for c in data if units[c] == (scale, unit)]
        stacked = np.stack([data[c] * scale for c in names])
        fitted = temperature_model(stacked, temp, rate, axis=-1, unit=unit)
        out.update(zip(names, fitted, strict=True))
    return {c: out[c] for c in data}


def print_models(models: dict, column: str) -> None:
    """bias(T), the warm-up, the process noise and the white level by T, with units."""
    for name, m in models.items():
        print(
            f"{name} against {column}: bias(T) of order {m.order} in "
            f"(T - {m.reference_temperature:g} °C), blocks of {m.block:.3g} s, "
            f"{m.ci:.1%} intervals"
        )
        for c in m.coefficients:
            lo, hi = c.interval
            print(f"  {c.name:<18} {c.value:11.4g} [{lo:.4g}, {hi:.4g}] {c.unit}")
        w = m.warmup
        if w is None:
            print("  warm-up: none found (BIC)")
        else:
            (alo, ahi), (tlo, thi) = w.amplitude_interval, w.time_constant_interval
            print(
                f"  warm-up: A {w.amplitude:.4g} [{alo:.4g}, {ahi:.4g}] {w.unit}, "
                f"tau {w.time_constant:.4g} [{tlo:.4g}, {thi:.4g}] s, "
                f"within 1 % after {w.settled_after:.4g} s"
            )
        p = m.process_noise
        print(
            f"  bias process noise: {p.density:.4g} {p.unit} (per sample variance "
            f"{p.per_step_variance:.4g}): {p.assumption}"
        )
        levels = ", ".join(
            f"{t:.3g} °C: {v:.4g}" for t, v in zip(m.noise.centres, m.noise.level, strict=True)
        )
        print(f"  white level by T ({m.noise.unit}): {levels}")
        for note in m.notes:
            print(f"  note: {note}")

"""Loading the signal: sample files, uploads, generated scenarios, and reopening a link's recipe."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import streamlit as st

import noisevar
from dashboard import cache
from dashboard.state import LoadedSignal, make_signal, parse_recipe, set_signal
from dashboard.url_params import RECIPE_PARAMS, check_recipe
from noisevar.errors import NoisevarError
from noisevar.io import content_digest, drop_nonfinite_rows, table_from_arrays
from noisevar.io.logs.record import combine_topics
from noisevar.signals import PAPER_SIGNAL, signal_spec

ROOT = Path(__file__).resolve().parents[1]
SAMPLE_DIR = ROOT / "sample_data"
SAMPLE_EXTENSIONS = (".csv", ".tsv", ".txt", ".dat", ".npy", ".nmea")


def sample_files() -> list[Path]:
    """The files of ``sample_data/`` the dashboard can load (listed at run time)."""
    if not SAMPLE_DIR.is_dir():
        return []
    return sorted(
        p for p in SAMPLE_DIR.iterdir() if p.is_file() and p.suffix.lower() in SAMPLE_EXTENSIONS
    )


def sample_descriptions() -> dict[str, str]:
    """One-line descriptions of the sample files, from ``sample_data/make_samples.py``."""
    return cache.sample_descriptions(str(SAMPLE_DIR))


def log_topics(raw: bytes, name: str) -> list | None:
    """The topics of an uploaded log (:func:`noisevar.io.log_topics`), None when not a log."""
    return cache.log_topics_cached(content_digest(raw), name, raw)


def max_upload_bytes() -> int:
    """The upload limit of the server config (``server.maxUploadSize``, MB), in bytes."""
    try:
        mb = float(st.get_option("server.maxUploadSize"))
    except Exception:  # noqa: BLE001
        mb = 200.0
    return int(mb * 1024 * 1024)


def load_bytes(
    raw: bytes,
    name: str,
    source: str = "upload",
    drop_nonfinite: bool = False,
    topic: str | None = None,
    also: Sequence[str] = (),
    time_unit: str | None = None,
    series: str | None = None,
) -> LoadedSignal:
    """Load file bytes as the new signal (raises NoisevarError; the old signal stays then).

    Parameters
    ----------
    raw : bytes
        File content (an upload's ``getvalue()`` is its own bytes, not a copy: CPython's
        BytesIO shares the bytes it was made from).
    name : str
        File name (its extension picks the format).
    source : str
        ``"upload"`` or ``"sample"``.
    drop_nonfinite : bool
        Drop the rows with an empty or NaN cell instead of refusing them.
    topic : str, optional
        For a log or workbook (``noisevar.io.logs.log_kinds``): the topic or sheet to read.
    also : sequence of str
        For a log: more topics read beside ``topic`` (:attr:`LoadedSignal.topics`: the
        Noise model page's gyroscope and accelerometer columns, each at its topic's rate).
    time_unit : str, optional
        The unit of the file's times where it states none (:func:`noisevar.io.load_table`).
    series : str, optional
        The series to read of a file that stacks several (:func:`noisevar.io.load_table`).

    Returns
    -------
    LoadedSignal
    """
    limit = max_upload_bytes()
    if len(raw) > limit:
        raise NoisevarError(
            f"{name} is {len(raw) / 1e6:.1f} MB, over the {limit / 1024 / 1024:.0f} MB upload "
            "limit: give a shorter record (or raise server.maxUploadSize)"
        )
    digest = content_digest(raw)
    table = cache.load_bytes_cached(digest, name, raw, topic, time_unit or None, series or None)
    if drop_nonfinite:
        table = drop_nonfinite_rows(table)
    recipe = f"sample:{name}" if source == "sample" else None
    sig = make_signal(table, None, table.sample_period, source, recipe)
    sig.log_params = cache.log_params_cached(digest, name, raw)  # the filter files' EKF step
    sig.time_unit, sig.series = time_unit or None, series or None  # the configs carry them
    chosen = list(dict.fromkeys([topic, *also])) if topic and also else []
    if len(chosen) > 1:
        tables = {t: cache.load_bytes_cached(digest, name, raw, t) for t in chosen}
        if drop_nonfinite:
            tables = {t: drop_nonfinite_rows(tab) for t, tab in tables.items()}
        sig.topics = combine_topics(name, tables)
        sig.topics_key = f"{digest}:{int(drop_nonfinite)}:" + "|".join(chosen)
    set_signal(sig)
    return sig


def load_sample(name: str, column: str | None = None, period: float | None = None) -> LoadedSignal:
    """Load a file of ``sample_data/`` as the new signal.

    Parameters
    ----------
    name : str
        File name inside ``sample_data/``.
    column : str, optional
        Column (default the first usable one).
    period : float, optional
        Override of the sample period.

    Returns
    -------
    LoadedSignal
    """
    path = SAMPLE_DIR / Path(name).name
    if not path.is_file() or path.suffix.lower() not in SAMPLE_EXTENSIONS:
        raise NoisevarError(f"no sample file {name!r} in sample_data/")
    raw = path.read_bytes()
    table = cache.load_bytes_cached(content_digest(raw), path.name, raw)
    sig = make_signal(
        table,
        column,
        period if period else table.period_of(column or table.first_signal),
        "sample",
        f"sample:{path.name}",
    )
    set_signal(sig)
    return sig


def generated_kwargs(
    name: str, n: int, seed: int, noise_std: float | None, **extra: float | int | str | None
) -> dict[str, float | int | str]:
    """Normalised keyword arguments of :func:`noisevar.generate` (for caching and the URL).

    The family's own parameters are checked and converted by their specs
    (:attr:`noisevar.signals.SignalSpec.extras`); others are left out.
    """
    kw: dict[str, float | int | str] = {"n": int(n), "seed": int(seed)}
    if noise_std is not None:
        kw["noise_std"] = float(noise_std)
    for spec in signal_spec(name).extras:
        if extra.get(spec.name) is not None:
            kw[spec.name] = spec.validate(extra[spec.name])
    return kw


def load_generated(name: str, **kwargs: float | int | str | None) -> LoadedSignal:
    """Generate a scenario of :func:`noisevar.generate` as the new signal.

    Parameters
    ----------
    name : str
        Family (:func:`noisevar.signal_names`).
    **kwargs
        ``n``, ``seed``, ``noise_std`` and the family's own parameters (its spec's ``extras``).

    Returns
    -------
    LoadedSignal
    """
    if name not in noisevar.signal_names():
        raise NoisevarError(f"unknown signal {name!r}; choose one of {noisevar.signal_names()}")
    kw = generated_kwargs(name, **kwargs)
    g = cache.generate_cached(name, json.dumps(kw, sort_keys=True))
    index_axis = np.array_equal(g.t, np.arange(g.t.size))
    period = None if index_axis else g.sample_period
    cols: dict[str, np.ndarray] = {} if index_axis else {"time": g.t}
    cols["measured"] = g.measured
    parts = [f"seed {kw['seed']}"] + [f"{k}={v}" for k, v in kw.items() if k not in ("n", "seed")]
    table = table_from_arrays(f"{name} ({', '.join(parts)})", cols, period, "generated")
    if not index_axis:
        table.time_column = "time"
    recipe = f"gen:{name};" + ";".join(f"{k}={v}" for k, v in kw.items())
    sig = make_signal(
        table, "measured", period, "generated", recipe, clean=g.clean, true_variance=g.true_variance
    )
    set_signal(sig)
    return sig


def paper_signal_defaults() -> dict[str, float | int]:
    """``n``, ``seed`` and ``noise_std`` of the paper's signal: its generator's defaults."""
    specs = signal_spec(PAPER_SIGNAL).param_specs
    return {key: specs[key].default for key in ("n", "seed", "noise_std")}


def load_paper_signal() -> LoadedSignal:
    """Generate the paper's signal (:data:`noisevar.signals.PAPER_SIGNAL`) as the new signal."""
    return load_generated(PAPER_SIGNAL, **paper_signal_defaults())


def load_simulated_sensors(noise_stds: Sequence[float] = (1.0, 2.0, 3.0), seed: int = 0) -> None:
    """Make simulated redundant sensors (``simulate_sensors``) the signal."""
    from noisevar.estimators.compare import simulate_sensors

    n = paper_signal_defaults()["n"]
    table = simulate_sensors(PAPER_SIGNAL, noise_stds, n=n, seed=seed, drift=3.0)
    set_signal(make_signal(table, None, table.sample_period, "generated", None))


def restore_from_recipe(recipe: str) -> LoadedSignal:
    """Rebuild a signal from its URL recipe (``gen:...`` or ``sample:...``)."""
    opts = check_recipe(recipe)  # bounds first, values converted: the link is untrusted input
    kind, name, _ = parse_recipe(recipe)
    col = opts.pop("col", None)
    period = opts.pop("T", None)
    if kind == "gen":
        for key in ("n", "seed", "noise_std"):
            opts.setdefault(key, RECIPE_PARAMS[key].default)
        return load_generated(name, **opts)
    if kind == "sample":
        return load_sample(name, None if col is None else str(col), period)
    raise NoisevarError(f"cannot rebuild the signal {recipe!r} from the link")

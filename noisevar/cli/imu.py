"""``noisevar imu FILE --rate HZ``: IEEE-952 terms per column, consumer exports (§E4, §E7, §E10).

``--export px4,kalibr,...|all --out DIR [--conservative]`` writes each consumer's file
(:mod:`noisevar.noise_model.exports`) into DIR from the ``--gyro`` and ``--accel`` columns;
``--model auto|SPEC``: composite models by GMWM with the comparison table (§E10);
``--temperature COLUMN``: bias(T), the warm-up and the bias process noise (§E9).
``--topic`` may be repeated: several topics of one log (PX4's ``sensor_gyro_fifo`` and
``sensor_accel_fifo``), each column at its own topic's rate
(:func:`noisevar.io.load_topics`), named by field or ``topic/field``.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import Any

import numpy as np

from noisevar.cli._common import (
    add_regimes_flag,
    add_series_flag,
    add_time_unit_flag,
    add_unit_flags,
    print_json,
    regimes_of,
    units_of,
)
from noisevar.cli._temperature import print_models, split_temperature, temperature_models
from noisevar.cli.allan import load_columns
from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs import log_kinds
from noisevar.io.logs.params import log_parameters
from noisevar.units import declared_unit, sensor_columns


def _columns(args: argparse.Namespace) -> list[str] | None:
    """Every column asked for, each once (None: all data columns)."""
    wanted = [*(args.columns or []), *(args.gyro or []), *(args.accel or [])]
    return list(dict.fromkeys(wanted)) or None


def _load(args: argparse.Namespace) -> tuple[dict, dict[str, float], dict, dict, list[str]]:
    """The columns asked for, each column's rate, declared unit and sample times (or None),
    and the loader's notes: from the file or one topic (one rate), or from several topics
    of a log (each column its topic's rate and times)."""
    topics = list(dict.fromkeys(args.topic or []))
    if len(topics) <= 1:
        topic = topics[0] if topics else None
        data, rate, declared, t, notes = load_columns(
            args.file, _columns(args), args.rate, topic, args.time_unit, args.series
        )
        return data, dict.fromkeys(data, rate), declared, dict.fromkeys(data, t), notes
    from noisevar.io import load_topics, record_times

    if args.rate is not None:
        raise NoisevarError(
            "--rate sets one rate for every column: with several --topic each column keeps "
            "its topic's rate from the log's timestamps (leave --rate out)"
        )
    if args.temperature:
        raise NoisevarError("--temperature reads one topic: give a single --topic")
    if args.time_unit or args.series:
        raise NoisevarError(
            "--time-unit and --series are for a table: a log's topics keep their times"
        )
    record = load_topics(args.file, topics, _name(args.file))
    cols = {c: record.column(c) for c in _columns(args) or record.columns}
    for col in cols.values():
        if col.rate is None:
            notes = "; ".join(record.tables[col.topic].notes[1:]) or "no time column"
            raise NoisevarError(
                f"topic {echo(col.topic)} has no sample rate from its times ({echo(notes, 300)})"
            )
    return (
        {c: col.values for c, col in cols.items()},
        {c: float(col.rate) for c, col in cols.items()},
        {c: col.unit for c, col in cols.items()},
        {c: record_times(record.tables[col.topic]) for c, col in cols.items()},
        [],
    )


def _name(path: str) -> str:
    import os

    return os.path.basename(os.path.normpath(path))


def _groups(data: dict, key: dict) -> list[list[str]]:
    """The columns in groups of one ``key`` value and one length (fitted together)."""
    groups: dict[tuple, list[str]] = {}
    for c, z in data.items():
        groups.setdefault((key[c], len(z)), []).append(c)
    return list(groups.values())


def _column_units(
    args: argparse.Namespace, declared: dict[str, str | None]
) -> dict[str, tuple[float, str]]:
    """Each column's factor (to ``--unit-out``) and the unit its terms are in.

    A unit given on the command line wins; else the one the file declares for the column
    (a log's message definition, a header's ``[unit]``); else none.
    """
    out = {}
    for c, said in declared.items():
        flag = args.gyro_unit if c in (args.gyro or []) else None
        flag = args.accel_unit if c in (args.accel or []) else flag
        if flag:
            out[c] = units_of(flag, None)
        else:
            out[c] = units_of(args.unit or declared_unit(said), args.unit_out)
    return out


def _kalibr(
    args: argparse.Namespace, fits: dict, data: dict, scales: dict, stretch: Any = None
) -> str:
    from noisevar.noise_model.kalibr import kalibr_imu, write_kalibr

    _need_sensors(args, "--kalibr")
    imu = kalibr_imu(
        [fits[c] for c in args.gyro],
        [fits[c] for c in args.accel],
        inflation=args.inflation,
        **_bias_fits(args, fits, data, scales, stretch),
    )
    write_kalibr(imu, args.kalibr)
    return args.kalibr


def _need_sensors(args: argparse.Namespace, flag: str) -> None:
    if not (args.gyro and args.accel):
        raise NoisevarError(
            f"{flag} needs --gyro COLUMNS and --accel COLUMNS (which columns are which sensor)"
        )


def _inertial_only(args: argparse.Namespace, data: dict, declared: dict, notes: list[str]) -> dict:
    """With no column asked for, the columns whose declared unit is an angular rate or an
    acceleration, when the file declares any (a ROS Imu message's orientation quaternion is
    not a sensor's noise), with a note of those left out; else every column."""
    if _columns(args) is not None:
        return data
    gyro, accel = sensor_columns({c: declared.get(c) for c in data}, data)
    inertial = {*gyro, *accel}
    if not inertial:
        return data
    keep = inertial | {args.temperature} if args.temperature else inertial
    out = {c: z for c, z in data.items() if c in keep}
    left = [c for c in data if c not in keep]
    if left:
        notes.append(
            f"fitting the {len(inertial)} sensor axes (columns in an angular-rate or acceleration "
            "unit, not their norm); "
            f"left out: {', '.join(left[:8])}{' ...' if len(left) > 8 else ''} (give "
            "--columns to fit others)"
        )
    return out


def _sensors_by_unit(
    args: argparse.Namespace, declared: dict, data: dict, notes: list[str]
) -> None:
    """``--gyro`` and ``--accel`` from the units the file declares, when neither is given and
    a consumer file is asked for: three columns in an angular-rate unit and three in an
    acceleration (EuRoC's ``[rad s^-1]`` and ``[m s^-2]``, a ROS Imu message), with a note;
    else left for :func:`_need_sensors` to ask for."""
    if args.gyro or args.accel or not (args.kalibr or args.export):
        return
    gyro, accel = sensor_columns({c: declared.get(c) for c in data}, data)
    if len(gyro) == 3 and len(accel) == 3:
        args.gyro, args.accel = gyro, accel
        notes.append(
            f"--gyro {' '.join(gyro)} and --accel {' '.join(accel)}: by the units the file "
            "declares (give --gyro and --accel to choose otherwise)"
        )


def _exports(
    args: argparse.Namespace, fits: dict, data: dict, scales: dict, ests: dict, stretch: Any
) -> tuple[list[str], dict, str]:
    """Each consumer's file of ``--export`` written into ``--out``, and the HTML report
    beside them; the files' paths, the model, the report's path. ``ests``: each sensor
    column's estimate for its answer (:func:`~noisevar.cli._imu_report.column_estimates`)."""
    from noisevar.cli._imu_report import column_answers, write_report
    from noisevar.noise_model import exports

    keys = exports.consumers(args.export)  # an unknown consumer: exit 2 before any work
    _need_sensors(args, "--export")
    if not args.out:
        raise NoisevarError("--export needs --out DIR: the directory the files go into")
    model = exports.imu_model(
        [fits[c] for c in args.gyro],
        [fits[c] for c in args.accel],
        variant="conservative" if args.conservative else "best",
        gnss=_gnss(args),
        **_bias_fits(args, fits, data, scales, stretch),
    )
    answers = column_answers(args, ests)  # each file's header says each verdict
    model = replace(model, verdicts={c: a.verdict for _, c, a in answers if a.verdict})
    files = exports.export(model, keys, params=log_parameters(args.file))  # the EKF's step
    paths = [str(p) for p in exports.write_exports(files, args.out)]
    report = None if args.no_report else write_report(args, model, files, fits, answers)
    return paths, model.to_dict(), report


def _column_estimates(
    args: argparse.Namespace, data: dict, scales: dict, times: dict
) -> tuple[dict, dict]:
    """With ``--export``, each sensor column's estimates for the fits' regimes and for the
    files' verdicts (:func:`~noisevar.cli._imu_report.column_estimates`); else none (each
    fit estimates its own axis, as it needs)."""
    if not args.export:
        return {}, {}
    from noisevar.cli._imu_report import column_estimates

    _need_sensors(args, "--export")
    return column_estimates(args, data, scales, times)


def _bias_fits(
    args: argparse.Namespace, fits: dict, data: dict, scales: dict, stretch: Any = None
) -> dict:
    """The composite fits K is taken from (``imu_model``'s ``gyro_bias``/``accel_bias``), of
    the same scaled columns, regimes and IMU still stretch as the IEEE-952 fits."""
    from noisevar.noise_model import exports

    out = {}
    for key, cols in (("gyro_bias", args.gyro), ("accel_bias", args.accel)):
        columns = [np.asarray(data[c], dtype=float) * scales[c] for c in cols]
        rates = [fits[c].rate for c in cols]
        out[key] = exports.composite_fits(columns, rates, **regimes_of(args), stretch=stretch)
    return out


def _imu_stretch(args: argparse.Namespace, data: dict, scales: dict, ests: dict) -> Any:
    """With ``--regimes still`` and a file to write (``--export``, ``--kalibr``): the IMU's
    stretch where every ``--gyro`` and ``--accel`` axis is still, which all its fits take
    (:func:`~noisevar.noise_model.inertial_axes.imu_still_stretch`); None otherwise, and
    for axes of different lengths (two topics: each axis its own stretch, as a single
    channel's)."""
    from noisevar.estimators.results import VarianceEstimate
    from noisevar.noise_model.inertial_axes import imu_still_stretch

    cols = list(dict.fromkeys([*(args.gyro or []), *(args.accel or [])]))
    wanted = args.regimes == "still" and args.gyro and args.accel and (args.export or args.kalibr)
    if not wanted or len({len(data[c]) for c in cols}) != 1:
        return None
    given = [ests.get(c) for c in cols]
    given = given if all(isinstance(e, VarianceEstimate) for e in given) else None
    return imu_still_stretch(np.stack([data[c] * scales[c] for c in cols]), given)


#: The unit each GNSS column's std goes into the EKFs' parameters in.
GNSS_UNITS = {"position": "m", "velocity": "m/s"}
#: ``--gnss-pos``/``--gnss-vel``'s help.
GNSS_HELP = {
    "position": "GNSS position column, for PX4/ArduPilot: m, or a length unit its header "
    "declares (not latitude or longitude in degrees)",
    "velocity": "GNSS velocity column: m/s, or a speed unit its header declares, e.g. (kn)",
}
#: Words of a column name that say geodetic coordinates (degrees), not metres.
_GEODETIC = {"lat", "lon", "lng", "latitude", "longitude"}


def _gnss(args: argparse.Namespace) -> dict[str, float]:
    """GNSS position (m) and velocity (m/s) stds: sqrt(R) of their columns (method auto),
    converted from the unit the file declares for the column (a header's ``(kn)``)."""
    from noisevar.cli._common import load_file
    from noisevar.estimators import estimate
    from noisevar.io import channel_record

    out = {}
    for key, column in (("position", args.gnss_pos), ("velocity", args.gnss_vel)):
        if column:
            series = None if args.gnss_file else args.series  # the series of FILE only
            table = load_file(args.gnss_file or args.file, None, args.time_unit, series)
            z, t = channel_record(table, column)
            k = _gnss_factor(key, column, table.units.get(column))
            out[key] = k * float(estimate(z, t=t).std)
    return out


def _gnss_factor(key: str, column: str, said: str | None) -> float:
    """The factor from the GNSS ``column``'s unit to :data:`GNSS_UNITS`'s; a latitude or a
    longitude (degrees) is refused in one line that says to give metres.

    Notes
    -----
    traffic's ADS-B records: ``--gnss-pos latitude`` wrote EKF2_GPS_P_NOISE = 2e-5 "m" for a
    fix noise of about 2 m (its std in degrees), and ``speed (kn)`` went in as m/s.
    """
    from noisevar.units import factor, parse_unit

    target = GNSS_UNITS[key]
    unit = declared_unit(said)
    flag = f"--gnss-{key[:3]}"
    words = {w for w in "".join(ch if ch.isalpha() else " " for ch in column).lower().split()}
    geodetic = (unit is None and bool(words & _GEODETIC)) or (
        unit is not None and parse_unit(unit).si == parse_unit("deg").si
    )
    if geodetic:
        raise NoisevarError(
            f"{flag} {echo(column)!r} holds degrees of latitude or longitude, not metres: give "
            f"the {key} in {target} (e.g. north and east of a fixed point, pymap3d's "
            "geodetic2ned), one column per axis"
        )
    try:
        return factor(unit, target)
    except NoisevarError:
        raise NoisevarError(
            f"{flag} {echo(column)!r} is in {unit}, not a {key}: give a column in {target} "
            "or in a unit that converts to it"
        ) from None


def _group_times(args: argparse.Namespace, times: dict, names: list[str]) -> Any:
    """The times of a group of columns, when they share them and ``--rate`` was not given
    (with it the samples are taken as uniform at that rate)."""
    t = times[names[0]]
    return None if args.rate is not None or any(times[c] is not t for c in names) else t


def _with_sampling_note(fit: Any, t: np.ndarray | None, placed: bool) -> Any:
    """``fit`` with a note when its column's times are not uniform and its samples were
    not ``placed`` on a grid of whole periods: taken as uniform at the fit's rate."""
    from noisevar.cli.allan import sampling_note

    return fit if placed else replace(fit, notes=(*fit.notes, *sampling_note(t, fit.rate)))


def _print_table(fits: dict) -> None:
    # a note every column carries (their shared times' jitter, say) is printed once, first
    shared = [n for n in next(iter(fits.values())).notes if len(fits) > 1] if fits else []
    shared = [n for n in shared if all(n in f.notes for f in fits.values())]
    for note in shared:
        print(f"note (every column): {note}")
    for name, fit in fits.items():
        print(f"{name}: {fit.allan.n_samples} samples at {fit.rate:g} Hz, {fit.ci:.1%} intervals")
        for t in fit.terms:
            lo, hi = t.interval
            print(
                f"  {t.symbol} {t.name:<17} {t.value:11.4g} [{lo:.3g}, {hi:.3g}] {t.unit:<12}"
                f" per sample {t.discrete:.4g} {t.discrete_unit}"
            )
        for note in fit.notes:  # what the figures assume and what the data could not tell
            if note not in shared:
                print(f"  note: {note}")


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
        lo, hi = fb.interval
        k_eq = f"K_eq {fb.random_walk:.4g} [{lo:.3g}, {hi:.3g}] {fit.unit}/s/√Hz"
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


def _cmd_models(args: argparse.Namespace, data: dict, rates: dict[str, float]) -> int:
    from noisevar.noise_model import fit_imu_model
    from noisevar.noise_model.gmwm import AUTO

    if args.kalibr:
        raise NoisevarError(f"--kalibr takes the IEEE-952 fit: use it with --model {IEEE952}")
    models = AUTO if args.model == AUTO else [m for m in args.model.split(",") if m]
    fits = {}
    for names in _groups(data, rates):  # one rate per fit: a topic's columns together
        stacked = np.column_stack([data[c] for c in names])
        fitted = fit_imu_model(
            stacked, rates[names[0]], models=models, robust=args.robust, **regimes_of(args)
        )
        fits.update(zip(names, fitted, strict=True))
    fits = {c: fits[c] for c in data}
    if args.format == "json":
        print_json({"columns": {c: f.to_dict() for c, f in fits.items()}})
    else:
        _print_models(fits)
    return 0


def _fit_columns(
    args: argparse.Namespace, loaded: tuple, col_units: dict, ests: dict, stretch: Any
) -> dict:
    """Each column's IEEE-952 fit (a group of one unit and rate together, its axes in
    threads); the IMU's axes on its still ``stretch`` when there is one."""
    from noisevar.estimators.results import VarianceEstimate
    from noisevar.noise_model import inertial_noise
    from noisevar.noise_model.allan_gaps import gap_grid

    data, rates, times = loaded
    imu_cols = {*(args.gyro or []), *(args.accel or [])} if stretch else set()
    fits, placed = {}, {}
    for names in _groups(data, {c: (col_units[c], rates[c]) for c in data}):
        scale, unit = col_units[names[0]]
        stacked = np.stack([data[c] * scale for c in names])  # axes in threads
        given = [ests.get(c) for c in names]
        given = given if all(isinstance(e, VarianceEstimate) for e in given) else None
        t = _group_times(args, times, names)
        fitted = inertial_noise(
            stacked, rates[names[0]], unit=unit, estimates=given, t=t, **regimes_of(args),
            stretch=stretch if set(names) <= imu_cols else None,
        )  # fmt: skip
        fits.update(zip(names, fitted, strict=True))
        placed.update(dict.fromkeys(names, gap_grid(t, "rate", "oadev", **regimes_of(args))))
    return {c: _with_sampling_note(fits[c], times[c], placed[c] is not None) for c in data}


def _cmd_imu(args: argparse.Namespace) -> int:
    if args.export:
        from noisevar.noise_model.exports import consumers

        consumers(args.export)  # refuse an unknown consumer before reading the file
    data, rates, declared, times, loaded = _load(args)
    data = _inertial_only(args, data, declared, loaded)
    _sensors_by_unit(args, declared, data, loaded)
    rate = next(iter(rates.values()), None)  # one topic or file: one rate
    temp = split_temperature(args, data, rate)
    if args.model != IEEE952:
        return _cmd_models(args, data, rates)
    col_units = _column_units(args, {c: declared[c] for c in data})
    scales = {c: col_units[c][0] for c in data}
    ests, answered = _column_estimates(args, data, scales, times)
    stretch = _imu_stretch(args, data, scales, ests)
    fits = _fit_columns(args, (data, rates, times), col_units, ests, stretch)
    written = _kalibr(args, fits, data, scales, stretch) if args.kalibr else None
    exported = (
        _exports(args, fits, data, scales, answered, stretch) if args.export else ([], None, None)
    )
    files, model, report = exported
    thermal = temperature_models(data, temp, rate, col_units) if temp is not None else {}
    if args.format == "json":
        out = {
            "columns": {c: f.to_dict() for c, f in fits.items()},
            "kalibr": written,
            "exports": files,
            "model": model,
            "report": report,
            "file_notes": loaded,
        }
        if thermal:
            out["temperature"] = {c: m.to_dict() for c, m in thermal.items()}
        print_json(out)
    else:
        for note in loaded:  # how the file was read: its clock, its unit, columns left out
            print(f"file note: {note}")
        _print_table(fits)
        print_models(thermal, args.temperature)
        if written:
            print(f"Kalibr imu.yaml written to {written} (inflation {args.inflation:g})")
        for f in files:
            variant = "conservative" if args.conservative else "best fit"
            print(f"{variant} export written to {f}")
        if report:
            print(f"report (verdict, units, conversions) written to {report}")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``imu`` on the sub-command set ``sub``."""
    p = sub.add_parser(
        "imu", help="IEEE-952 noise terms of rate columns; each consumer's file (§E4, §E7)"
    )
    p.add_argument("file")
    p.add_argument("--rate", type=float, help="sample rate in Hz (default: the time column's)")
    p.add_argument("--columns", nargs="+", help="columns to analyse (default: all)")
    p.add_argument("--gyro", nargs="+", help="gyroscope columns, for --kalibr and --export")
    p.add_argument("--accel", nargs="+", help="accelerometer columns, for --kalibr and --export")
    add_unit_flags(p)
    add_time_unit_flag(p)
    add_series_flag(p)
    p.add_argument("--gyro-unit", help="unit of the gyroscope columns (default --unit; rad/s)")
    p.add_argument("--accel-unit", help="unit of the accelerometer columns (default --unit)")
    p.add_argument("--kalibr", metavar="OUT.yaml", help="write Kalibr's imu.yaml here")
    p.add_argument("--inflation", type=float, default=1.0, help="factor on the Kalibr values")
    p.add_argument(
        "--export",
        metavar="LIST",
        help="consumers whose files to write: kalibr, openvins, vins, orbslam3, "
        "robot_localization, px4, ardupilot, matlab, filterpy (comma-separated) or all",
    )
    p.add_argument("--out", metavar="DIR", help="directory for the --export files")
    p.add_argument(
        "--no-report",
        action="store_true",
        help="with --export: skip DIR/report.html (each column's verdict, units, "
        "conversions, Allan fits)",
    )
    p.add_argument("--gnss-pos", metavar="COLUMN", help=GNSS_HELP["position"])
    p.add_argument("--gnss-vel", metavar="COLUMN", help=GNSS_HELP["velocity"])
    p.add_argument("--gnss-file", metavar="FILE", help="file of the GNSS columns (default FILE)")
    p.add_argument(
        "--conservative",
        action="store_true",
        help="export the conservative set (N, K raised to overbound the Allan curve's 95 %% "
        "upper bound) instead of the best fit (the default)",
    )
    p.add_argument(
        "--topic",
        action="append",
        help=f"for a log ({log_kinds()}): the topic, message or sheet to read "
        "('noisevar topics LOG' lists them); repeat it to read several "
        "topics of the log (e.g. sensor_gyro_fifo and sensor_accel_fifo), each column at its "
        "topic's rate, named by field or, when topics share a field, topic/field",
    )
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
    p.add_argument("--temperature", metavar="COLUMN", help="fit bias(T), warm-up (§E9)")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_imu)

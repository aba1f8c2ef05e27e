"""The parameters a flight log carries: the vehicle's own configuration when it flew.

A PX4 ULog holds its parameters at start (``initial_parameters``: ``EKF2_GYR_NOISE``,
``EKF2_PREDICT_US``, ``IMU_INTEG_RATE``); an ArduPilot DataFlash log, binary or text, its
``PARM`` messages (``SCHED_LOOP_RATE``, ``AHRS_EKF_TYPE``, ``EK3_GYRO_P_NSE``). The
consumer files of :mod:`noisevar.noise_model.exports` take the EKF's step from them
(:func:`noisevar.noise_model.exports.log_options`), and the audit compares the flight's
configured noise with the measured one (``benchmarks/logcfg_audit.py``).
"""

from __future__ import annotations

import os
from pathlib import Path

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo


def log_parameters(path: str | os.PathLike) -> dict[str, float]:
    """The parameters of the log at ``path``, name -> value (the first value a DataFlash
    log gives a name: the configuration the flight started with).

    Parameters
    ----------
    path : str or path
        A PX4 ULog or an ArduPilot DataFlash log (binary or text); any other file,
        a table or a bag, has none.

    Returns
    -------
    dict of str to float
        Empty when the file is not a log that carries parameters.

    Raises
    ------
    NoisevarError
        A ULog or DataFlash log its library cannot read.
    """
    from noisevar.io.logs import reader_for

    p = Path(path)
    if not p.is_file():
        return {}
    with p.open("rb") as fh:
        head = fh.read(64)
    reader = reader_for(p.name, head)
    kind = None if reader is None else reader.name
    try:
        if kind == "ulog":
            return _ulog(p)
        if kind == "dataflash":
            return _dataflash(p)
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - each library raises its own types on bad logs
        raise NoisevarError(
            f"the parameters of {echo(p.name)} could not be read ({type(exc).__name__})"
        ) from None
    return {}


def _ulog(path: Path) -> dict[str, float]:
    from pyulog import ULog

    log = ULog(str(path), message_name_filter_list=[])
    return {str(k): float(v) for k, v in log.initial_parameters.items()}


def _dataflash(path: Path) -> dict[str, float]:
    from noisevar.io.logs import dataflash

    return dataflash.parameters(path)

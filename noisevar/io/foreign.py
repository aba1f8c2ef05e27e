"""Files of formats noisevar does not read as tables, told apart from text: a FIT activity,
an XML track (GPX, TCX, KML), a TDMS, MDF, EDF, BLF, SQLite, CDF, GWF or MATLAB file, a
``.ts`` or ``.tsf`` archive file, a Vector ASC CAN log refused in one line that says what
to do; text whose fields a device pads with NUL bytes, read as the text it is."""

from __future__ import annotations

import re

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo

#: NUL bytes pad text when they are at most this share of the head, and every line that
#: holds them is otherwise text (a device's fixed-width fields)
NUL_SHARE = 0.05
NUL_NOTE = (
    "{n} NUL bytes (padding of fixed-width text fields, as GENEActiv's CSV export writes its "
    "notes) left out"
)


def nul_padding(head: bytes) -> int:
    """How many NUL bytes pad the text fields of ``head`` (0 when it has none, or when they
    are those of a binary file or of UTF-16 text without its byte-order mark).

    Notes
    -----
    GENEActiv's CSV export pads its ``Subject Notes`` and ``Config Notes`` with NULs (260
    in gaitpy's demo file, in 2 of 8,500 lines): refused as "a binary file", which it is not.
    """
    n = head.count(b"\x00")
    if n == 0 or n > NUL_SHARE * len(head):
        return 0
    lines = [ln for ln in head.split(b"\n") if b"\x00" in ln]
    text = b"".join(ln.replace(b"\x00", b"") for ln in lines)
    if any(b < 32 and b not in b"\r\t" for b in text):
        return 0
    return n


def refuse_fit(head: bytes, name: str) -> None:
    """Refuse a FIT file (Garmin's and other sports devices' binary activity format) in one
    line that says what to do.

    Notes
    -----
    sweat's rides (a Garmin Edge 1000's, a Forerunner 935's) were refused as "a binary file
    (it contains NUL bytes)", which did not say what the file is nor how to make it a table.
    """
    if len(head) < 12 or head[0] not in (12, 14) or head[8:12] != b".FIT":
        return
    raise NoisevarError(
        f"{echo(name)} is a FIT file (a sports device's binary activity log), which noisevar "
        "does not read: export its records to a CSV file (e.g. with fitdecode, fitparse or "
        "Garmin's FitCSVTool; a time column and one column per field) and give that file"
    )


_SQLITE = b"SQLite format 3\x00"
#: NASA's Common Data Format (version 3, 2.6 and 2.5 magic numbers)
_CDF = ("a CDF file (NASA's Common Data Format: a spacecraft's or an observatory's variables)",
        "with cdflib: cdflib.xarray.cdf_to_xarray(path).to_dataframe().to_csv(...)")
#: Binary files of measurements users have: leading bytes -> (what it is, how to convert)
_BINARY_KINDS = {
    b"TDSm": ("a TDMS file (National Instruments LabVIEW or DAQ)",
              "with npTDMS: TdmsFile.read(path).as_dataframe().to_csv(...)"),
    b"TDSh": ("a TDMS index file (National Instruments)",
              "give the .tdms file beside it, exported with npTDMS"),
    b"MDF     ": ("an MDF file (ASAM MDF, a vehicle or test-bench logger's)",
                  "with asammdf: MDF(path).to_dataframe().to_csv(...)"),
    b"UnFinMF ": ("an unfinalised MDF file (ASAM MDF)",
                  "with asammdf: MDF(path).to_dataframe().to_csv(...)"),
    b"\xffBIOSEMI": ("a BDF file (BioSemi, biosignals)",
                     "with pyedflib or mne: mne.io.read_raw_bdf(path).to_data_frame()"),
    b"LOGG": ("a BLF file (Vector's binary CAN log)",
              "decode its signals with python-can and cantools and the bus's DBC file"),
    _SQLITE: ("an SQLite database (an ActiGraph .agd file is one)",
                             "with sqlite3 or pandas.read_sql: the table of samples"),
    b"\xcd\xf3\x00\x01": _CDF, b"\xcd\xf2\x60\x02": _CDF, b"\xcd\xf2\x00\x02": _CDF,
    b"IGWD": ("a GWF frame file (the gravitational-wave detectors' IGWD frames)",
              "with gwpy: TimeSeries.read(path, channel).to_pandas().to_csv(...)"),
    b"MATLAB 5.0 MAT-file": ("a MATLAB .mat file",
                             "with MATLAB's writetable, or scipy.io.loadmat in Python"),
}  # fmt: skip
#: SQLite databases whose samples are no table's rows, known by a table their schema
#: creates -> (what it is, how to export it)
_SQLITE_KINDS = {
    "tr_data": ("a Vallen acoustic-emission transient database (.tradb, SQLite: each hit's "
                "waveform a compressed or raw blob, no table of samples)",
                "with vallenae: TraDatabase(path).read_wave(trai) gives a hit's volts and "
                "times"),
    "ae_data": ("a Vallen acoustic-emission primary database (.pridb, SQLite: hits, markers "
                "and parametric inputs)", "with vallenae: PriDatabase(path).read_parametric() "
                "or .read_hits()"),
    "trf_data": ("a Vallen acoustic-emission feature database (.trfdb, SQLite: features of "
                 "each hit)", "with vallenae: TrfDatabase(path).read()"),
}  # fmt: skip
#: a table an SQLite schema creates (its name)
_CREATE_TABLE = re.compile(rb"CREATE TABLE\s+(?:IF NOT EXISTS\s+)?[\"'`\[]?(\w{1,64})", re.I)
#: tables an SQLite refusal names at most
_TABLES_SAID = 8


def sqlite_kind(head: bytes) -> tuple[str, str]:
    """What an SQLite database is and how to export it, from the tables its schema (in
    ``head``) creates: a known kind (:data:`_SQLITE_KINDS`), else the generic SQLite
    entry with the tables named (a few; ``echo``-safe: word characters only).

    Notes
    -----
    vallenae's Vallen AE databases (``.tradb``, ``.pridb``, ``.trfdb``) were refused as "an
    SQLite database (an ActiGraph .agd file is one)" to be exported with ``pandas.read_sql``:
    a ``.tradb`` holds its waveforms as blobs, so no table read gives the samples.
    """
    names = list(dict.fromkeys(m[1].decode("ascii").lower() for m in _CREATE_TABLE.finditer(head)))
    found = next((v for k, v in _SQLITE_KINDS.items() if k in names), None)
    if found is not None:
        return found
    what, how = _BINARY_KINDS[_SQLITE]
    if names:
        said = ", ".join(names[:_TABLES_SAID]) + (", ..." if len(names) > _TABLES_SAID else "")
        how = f"{how}; its tables: {said}"
    return what, how


#: EDF's header: version "0" and 7 spaces, its start date (dd.mm.yy) at byte 168
_EDF = re.compile(rb"0 {7}.{160}\d\d\.\d\d\.\d\d", re.DOTALL)


def refuse_binary(head: bytes, name: str) -> None:
    """Refuse a binary file of measurements in a format noisevar does not read (TDMS, MDF,
    EDF, BDF, BLF, SQLite, CDF, GWF, MATLAB), known by its leading bytes, in one line that
    names it and a way to export it to CSV.

    Notes
    -----
    npTDMS's test files (a LabVIEW DAQ's TDMS) and pyActigraphy's ActiGraph .agd (SQLite)
    were refused as "a binary file (it contains NUL bytes)", which did not say what the file
    is nor how to make it a table; so were cdflib's spacecraft CDF files (a Parker Solar
    Probe magnetometer day) and gwpy's LIGO/Virgo GWF frame file.
    """
    found = next((v for k, v in _BINARY_KINDS.items() if head.startswith(k)), None)
    if found is _BINARY_KINDS[_SQLITE]:
        found = sqlite_kind(head)
    if found is None and _EDF.match(head[:176]):
        found = ("an EDF file (European Data Format, biosignals)",
                 "with pyedflib or mne: mne.io.read_raw_edf(path).to_data_frame()")  # fmt: skip
    if found is None:
        return
    raise NoisevarError(
        f"{echo(name)} is {found[0]}, which noisevar does not read: export its channels to "
        f"a CSV file ({found[1]}; a time column and one column per channel) and give that file"
    )


#: XML files users have: the root element's name -> what it is
_XML_KINDS = {
    "gpx": "a GPX track (GPS exchange format)",
    "trainingcenterdatabase": "a TCX activity (Garmin's Training Center XML)",
    "kml": "a KML file (Google Earth)",
}
_XML_ROOT = re.compile(r"<([A-Za-z_][\w.:-]*)")


def refuse_xml(text: str, name: str) -> None:
    """Refuse an XML file (a GPX track, a TCX activity, KML) in one line that says what to do.

    Notes
    -----
    sweat's TCX rides were refused as "'<TrainingCenterDatabase' is not a number", its GPX
    tracks blaming a row's field count: neither said what the file is. Only the root element
    is looked at (the file is not parsed).
    """
    body = text.lstrip("\ufeff \t\r\n")
    if not body.startswith("<"):
        return
    root = next((m.group(1) for m in _XML_ROOT.finditer(body[:4096])), "")  # not <?xml, <!--
    what = _XML_KINDS.get(root.split(":")[-1].lower(), "an XML file")
    raise NoisevarError(
        f"{echo(name)} is {what}, which noisevar does not read as a table: write its points "
        "to a CSV file (a time column and one column per value: elevation, speed, heart "
        "rate...; e.g. with gpxpy, or pandas.read_xml) and give that file; for a GPS "
        "track, an NMEA 0183 log is read too"
    )


#: A line of the header of sktime's / the UEA and UCR archives' ``.ts`` format, and of the
#: Monash forecasting archive's ``.tsf`` (its ``@attribute``, ``@frequency``, ``@horizon``)
_TS_HEADER = re.compile(
    r"^@(problemname|timestamps|missing|univariate|dimensions?|equallength|serieslength|"
    r"classlabel|targetlabel|data|attribute|frequency|horizon|relation)\b",
    re.IGNORECASE | re.MULTILINE,
)
#: The tags only a ``.tsf`` file has
_TSF_TAGS = {"attribute", "frequency", "horizon"}
#: Weka's ARFF's tags: ``@relation``, an ``@attribute`` per column, ``@data``
_ARFF_TAGS = {"relation", "attribute", "data"}


def refuse_ts(text: str, name: str) -> None:
    """Refuse a ``.ts`` file (sktime's, the UEA/UCR time-series classification archives') or
    a ``.tsf`` file (the Monash forecasting archive's) in one line that says what to do.

    Notes
    -----
    Its ``@`` header lines are followed, after ``@data``, by one case a line (its dimensions
    parted by ``:``, then its label): read as a table, it was refused blaming thousands
    separators (sktime's BasicMotions and ACSF1). aeon's ``.tsf`` test file (one series a
    line, its attributes then its values parted by ``:``) was called a ``.ts`` file, with
    the ``.ts`` loader as the way out; an ARFF file (``@relation``: tslearn's UCR copies)
    was called a ``.tsf`` file.
    """
    tags = {m.lower() for m in _TS_HEADER.findall(text)}
    if "data" not in tags or len(tags) < 2:
        return
    if "relation" in tags and tags <= _ARFF_TAGS:  # a .tsf has @frequency, @horizon...
        raise NoisevarError(
            f"{echo(name)} is an ARFF file (Weka's format: @relation, an @attribute line per "
            "column, rows after @data; the UCR archive's hold one series a row), which "
            "noisevar does not read: write one series as a column of a CSV file (e.g. with "
            "scipy.io.arff.loadarff) and give that file"
        )
    if tags & _TSF_TAGS:
        raise NoisevarError(
            f"{echo(name)} is a .tsf file (the Monash forecasting archive's format: one series "
            "a line after @data, its attributes then its values parted by ':'), which noisevar "
            "does not read: write one series as a column of a CSV file (e.g. with aeon's "
            "load_from_tsf_file or sktime's load_tsf_to_dataframe) and give that file"
        )
    raise NoisevarError(
        f"{echo(name)} is a .ts file (sktime's time-series classification format: one case a "
        "line after @data, dimensions parted by ':'), which noisevar does not read: write "
        "one case's series as a column of a CSV file (e.g. with sktime's load_from_tsfile) "
        "and give that file"
    )


#: Vector's ASC CAN log: its ``base hex|dec  timestamps absolute|relative`` line
_ASC = re.compile(r"^\s*base\s+(hex|dec)\s+timestamps\s+(absolute|relative)", re.MULTILINE)


def refuse_asc(text: str, name: str) -> None:
    """Refuse a Vector ASC file (a CAN bus log as text) in one line that says what to do.

    Notes
    -----
    python-can's ASC logs (a 2014 bus trace, error frames) were refused as rows of differing
    widths, one blaming thousands separators: neither said what the file is, though its BLF
    twin is named. Only the ``base ... timestamps ...`` line of its head is looked at.
    """
    if _ASC.search(text[:4096]) is None:
        return
    raise NoisevarError(
        f"{echo(name)} is a Vector ASC file (a CAN bus log as text: frames of bytes by "
        "message id), which noisevar does not read: export its channels to a CSV file "
        "(decode its signals with python-can and cantools and the bus's DBC file; a time "
        "column and one column per signal) and give that file"
    )


def refuse_text(text: str, name: str) -> None:
    """Refuse a text file of a format noisevar does not read as a table (:func:`refuse_xml`,
    :func:`refuse_ts`, :func:`refuse_asc`) in one line that says what to do."""
    refuse_xml(text, name)
    refuse_ts(text, name)
    refuse_asc(text, name)

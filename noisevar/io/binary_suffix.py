"""Binary files of instruments whose format has no signature to know it by, named by their
suffix: a BIOPAC AcqKnowledge ``.acq``, a seismometer's SAC or miniSEED file, a Slocum
glider's DBD files, refused in one line that says what it is and how to make it a table (a
binary file of any other suffix is refused as before)."""

from __future__ import annotations

from noisevar.errors import NoisevarError
from noisevar.io.foreign import nul_padding
from noisevar.io.limits import echo

_MSEED = "a miniSEED file (a seismometer's records, e.g. a Raspberry Shake's)"
#: a seismic trace's export, one trace a file
_OBSPY = "with obspy: tr = obspy.read(path)[0], then tr.times() and tr.data"
#: a Slocum glider's flight (d, s, m) and science (e, t, n) binary data, plain or compressed
_SLOCUM = ("a Slocum glider's binary data file (Teledyne Webb's DBD family)",
           "with dbdreader: t, v = dbdreader.DBD(path).get('sci_water_temp'); or Teledyne's "
           "dbd2asc")  # fmt: skip
#: suffix -> (what it is, how to export it to a text table)
_BY_SUFFIX = {
    ".acq": ("a BIOPAC AcqKnowledge file (a lab data acquisition system's biosignals)",
             "AcqKnowledge's File > Save As > Text, or bioread's acq2txt"),
    ".sac": ("a SAC file (Seismic Analysis Code: a seismometer's trace)", _OBSPY),
    ".mseed": (_MSEED, _OBSPY), ".miniseed": (_MSEED, _OBSPY), ".ms": (_MSEED, _OBSPY),
    **{f".{k}{b}d": _SLOCUM for k in "dsmetn" for b in "bc"},
}  # fmt: skip


def refuse_by_suffix(head: bytes, name: str) -> None:
    """Refuse a binary file (NUL bytes that are no text's padding) of a suffix of
    :data:`_BY_SUFFIX` in one line that names its format and a way to export it.

    Notes
    -----
    bioread's test recordings (``physio-5.0.1.acq``: a BIOPAC MP system's ECG and other
    channels) were refused as "a binary file (it contains NUL bytes)", which did not say
    what the file is nor how to make it a table. An ``.acq`` header has no fixed signature
    (its first bytes are a version number, in either byte order): the suffix names it. So
    do a SAC trace's (pysmo's ``testfile.sac``) and a miniSEED file's (rsudp's Raspberry
    Shake ``testdata.ms``), refused alike, and a Slocum ocean glider's ``.dbd`` / ``.ebd``
    / ``.sbd`` / ``.tbd`` / ``.mbd`` files and their compressed ``.?cd`` (dbdreader's test
    data: an ASCII header, then binary).
    """
    suffix = "." + name.rpartition(".")[2].lower() if "." in name else ""
    found = _BY_SUFFIX.get(suffix)
    if found is None or b"\x00" not in head or nul_padding(head):
        return
    raise NoisevarError(
        f"{echo(name)} is {found[0]}, which noisevar does not read: export its channels to "
        f"a CSV or text file ({found[1]}; a time column and one column per channel) and give "
        "that file"
    )

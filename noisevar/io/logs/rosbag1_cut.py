"""A ROS 1 bag without its index (a recording that never closed, ``.bag.active``, or a
copy cut short), read up to its cut: what ``rosbag reindex`` does.

A ROS 1 bag writes its index (connections and chunk infos) at the end, when it closes,
and sets the header's ``index_pos`` to it; ``rosbags`` reads a bag through that index.
Without it the chunks before the cut are whole: each is read in order with
``rosbags``' own record reader (:class:`rosbags.rosbag1.reader.Header`), inflated with
its declared size bounded (:func:`~noisevar.io.logs.repaired.inflate`), and its
connections and messages written again by ``rosbags``' writer as a complete bag, which
is then read as any bag (its message definitions checked as usual).
"""

from __future__ import annotations

import io
import struct
from pathlib import Path
from typing import BinaryIO

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.repaired import inflate, repaired

MAGIC = b"#ROSBAG V2.0\n"
_MSGDATA, _BAGHEADER, _CHUNK, _CONNECTION = 2, 3, 5, 7


def unindexed(path: Path) -> bool:
    """Whether ``path`` is a ROS 1 bag whose index is missing (``index_pos`` 0 or past its end)."""
    if not path.is_file():
        return False
    from rosbags.rosbag1.reader import Header, ReaderError

    with path.open("rb") as fh:
        if fh.read(len(MAGIC)) != MAGIC:
            return False
        try:
            header = Header.read(fh, None)
            if header.get_uint8("op") != _BAGHEADER:
                return False
            index_pos = header.get_uint64("index_pos")
        except ReaderError:
            return True  # not even its header is whole
        return index_pos == 0 or index_pos >= path.stat().st_size


def recovered(path: Path) -> tuple[Path, str]:
    """A complete (indexed) copy of the ROS 1 bag at ``path`` and a note saying what was kept.

    Raises
    ------
    NoisevarError
        No whole message before the cut.
    """
    return repaired(path, _rewrite, ".bag")


class _Copy:
    """The bag being written again: its connections by their id in the cut bag."""

    def __init__(self, dst: Path) -> None:
        from rosbags.rosbag1 import Writer

        self.writer = Writer(dst)
        self.writer.open()
        self.conns: dict[int, object] = {}
        self.kept = self.at = 0

    def records(self, src: BinaryIO) -> None:
        """Every record of ``src`` up to its end: chunks opened, connections and messages taken."""
        from rosbags.rosbag1.reader import Header, read_bytes, read_uint32

        while True:
            header = Header.read(src, None)
            op = header.get_uint8("op")
            data = read_bytes(src, read_uint32(src))
            if op == _CHUNK:
                raw = inflate(header.get_string("compression"), data, header.get_uint32("size"))
                inner = io.BytesIO(raw)
                while inner.tell() < len(raw):
                    self.record(Header.read(inner, None), inner, read_uint32, read_bytes)
            elif op in (_CONNECTION, _MSGDATA):
                self.record(header, io.BytesIO(struct.pack("<I", len(data)) + data),
                            read_uint32, read_bytes)  # fmt: skip
            self.at = src.tell()  # the end of the last whole record

    def record(self, header, src: BinaryIO, read_uint32, read_bytes) -> None:
        """One connection or message record whose header is read (its data next in ``src``)."""
        from rosbags.rosbag1.reader import Header
        from rosbags.typesys.msg import normalize_msgtype

        op = header.get_uint8("op")
        if op == _CONNECTION:
            conn = Header.read(src, None)  # the connection's own header: type, md5sum, ...
            cid = header.get_uint32("conn")
            if cid not in self.conns:
                latching = conn.get_string("latching") if "latching" in conn else ""
                self.conns[cid] = self.writer.add_connection(
                    header.get_string("topic"),
                    normalize_msgtype(conn.get_string("type")),
                    msgdef=conn.get_string("message_definition"),
                    md5sum=conn.get_string("md5sum"),
                    callerid=conn.get_string("callerid") if "callerid" in conn else None,
                    latching=int(latching) if latching.isdigit() else None,
                )
            return
        data = read_bytes(src, read_uint32(src))
        if op == _MSGDATA and header.get_uint32("conn") in self.conns:
            self.writer.write(self.conns[header.get_uint32("conn")], header.get_time("time"), data)
            self.kept += 1


def _rewrite(src: Path, dst: Path) -> str:
    """Copy ``src``'s whole chunks into an indexed bag at ``dst``; the note."""
    from rosbags.rosbag1.reader import Header

    copy = _Copy(dst)
    why = "the end of the file"
    with src.open("rb") as fh:
        try:
            fh.seek(len(MAGIC))
            Header.read(fh, None)  # the bag header, then its padding
            fh.seek(struct.unpack("<I", fh.read(4))[0], 1)
            copy.at = fh.tell()
            copy.records(fh)  # up to the end or the cut
        except Exception as exc:  # noqa: BLE001 - the cut ends the records any way it falls
            why = f"then a record cut short or damaged: {type(exc).__name__}"
    copy.writer.close()
    size = src.stat().st_size
    if copy.kept == 0:
        raise NoisevarError(
            f"{echo(src.name)} is a ROS 1 bag without its index and with no whole message "
            f"before its cut (whole records up to byte {copy.at:,} of {size:,}, {why}): "
            "copy the file again"
        )
    return (
        f"the ROS 1 bag has no index (a recording that never closed, or a copy cut short): "
        f"{copy.kept:,} messages (all topics) read from its whole chunks, up to byte "
        f"{copy.at:,} of {size:,} ({why}); what was recorded after them is lost (as "
        "rosbag reindex would)"
    )

"""An MCAP file cut short (a recording stopped by a crash or a pulled card), read up to its cut.

An MCAP file ends with a summary, a footer and the magic bytes; a recording that never
closed has none of them, and ``rosbags`` refuses it. Its records before the cut are
whole: the ``mcap`` library's stream reader reads them in order (each chunk's checksum
checked, its size bounded), and its writer lays them out again as a complete file
(:func:`~noisevar.io.logs.repaired.repaired`), which ``rosbags`` then reads as any bag,
its message definitions checked as usual (what ``mcap recover`` does). What was recorded
after the last whole record is lost; the note says how many messages were kept and
where the file was cut.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import BinaryIO

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.repaired import INFLATE_LIMIT, inflate, repaired

MAGIC = b"\x89MCAP0\r\n"


def cut_short(path: Path) -> bool:
    """Whether ``path`` is a single MCAP file whose closing magic bytes are missing."""
    if not path.is_file():
        return False
    with path.open("rb") as fh:
        if fh.read(len(MAGIC)) != MAGIC:
            return False
        size = fh.seek(0, 2)
        if size < 2 * len(MAGIC):
            return True
        fh.seek(size - len(MAGIC))
        return fh.read(len(MAGIC)) != MAGIC


def recovered(path: Path) -> tuple[Path, str]:
    """A complete copy of the cut MCAP file at ``path`` and a note saying what was kept.

    Raises
    ------
    NoisevarError
        No whole message before the cut.
    """
    return repaired(path, _rewrite, ".mcap")


class _Copy:
    """The MCAP file being written again: its schemas and channels by their id in the cut one."""

    def __init__(self, out: BinaryIO) -> None:
        from mcap.writer import CompressionType, Writer

        self.writer = Writer(out, compression=CompressionType.NONE)
        self.writer.start(profile="ros2", library="noisevar (recovered)")
        self.schemas: dict[int, int] = {}
        self.channels: dict[int, int] = {}
        self.kept = 0

    def take(self, rec: object) -> None:
        """One schema, channel or message record (others are not needed to read messages)."""
        from mcap.records import Channel, Message, Schema

        w = self.writer
        if isinstance(rec, Schema) and rec.id not in self.schemas:
            self.schemas[rec.id] = w.register_schema(rec.name, rec.encoding, rec.data)
        elif isinstance(rec, Channel) and rec.id not in self.channels:
            schema = self.schemas.get(rec.schema_id, 0)
            self.channels[rec.id] = w.register_channel(
                rec.topic, rec.message_encoding, schema, dict(rec.metadata)
            )
        elif isinstance(rec, Message) and rec.channel_id in self.channels:
            ch = self.channels[rec.channel_id]
            w.add_message(ch, rec.log_time, rec.data, rec.publish_time, rec.sequence)
            self.kept += 1


def _rewrite(src: Path, dst: Path) -> str:
    """Copy ``src``'s whole records into a complete MCAP at ``dst``; the note."""
    from mcap.records import Chunk
    from mcap.stream_reader import StreamReader, breakup_chunk

    with src.open("rb") as fh, dst.open("wb") as out:
        copy = _Copy(out)
        why, at = "the end of the file", len(MAGIC)
        reader = StreamReader(fh, emit_chunks=True, record_size_limit=INFLATE_LIMIT)
        try:
            for rec in reader.records:
                if isinstance(rec, Chunk):  # inflated here, bounded; then split by mcap
                    data = inflate(rec.compression, rec.data, rec.uncompressed_size)
                    for inner in breakup_chunk(replace(rec, compression="", data=data), True):
                        copy.take(inner)
                else:
                    copy.take(rec)
                at = fh.tell()  # the end of the last whole record
        except Exception as exc:  # noqa: BLE001 - the cut ends the records any way it falls
            why = f"then a record cut short or damaged: {type(exc).__name__}"
        copy.writer.finish()
    size = src.stat().st_size
    if copy.kept == 0:
        raise NoisevarError(
            f"{echo(src.name)} is an MCAP file cut short with no whole message before the "
            f"cut (whole records up to byte {at:,} of {size:,}, {why}): copy the file "
            "again, or record with smaller chunks"
        )
    return (
        f"the MCAP file is cut short (no summary or footer: a recording that never closed); "
        f"{copy.kept:,} messages (all topics) read from its whole records, up to byte {at:,} "
        f"of {size:,} ({why}); what was recorded after them is lost"
    )

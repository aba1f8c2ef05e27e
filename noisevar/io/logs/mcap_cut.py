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


def _rewrite(src: Path, dst: Path) -> str:
    """Copy ``src``'s whole records into a complete MCAP at ``dst``; the note."""
    from mcap.records import Channel, Chunk, Message, Schema
    from mcap.stream_reader import StreamReader, breakup_chunk
    from mcap.writer import CompressionType, Writer

    schemas: dict[int, int] = {}
    channels: dict[int, int] = {}
    kept = 0
    with src.open("rb") as fh, dst.open("wb") as out:
        writer = Writer(out, compression=CompressionType.NONE)
        writer.start(profile="ros2", library="noisevar (recovered)")

        def take(rec: object) -> None:
            nonlocal kept
            if isinstance(rec, Schema) and rec.id not in schemas:
                schemas[rec.id] = writer.register_schema(rec.name, rec.encoding, rec.data)
            elif isinstance(rec, Channel) and rec.id not in channels:
                schema = schemas.get(rec.schema_id, 0)
                channels[rec.id] = writer.register_channel(
                    rec.topic, rec.message_encoding, schema, dict(rec.metadata)
                )
            elif isinstance(rec, Message) and rec.channel_id in channels:
                writer.add_message(
                    channels[rec.channel_id], rec.log_time, rec.data, rec.publish_time,
                    rec.sequence,
                )  # fmt: skip
                kept += 1

        why, at = "the end of the file", len(MAGIC)
        reader = StreamReader(fh, emit_chunks=True, record_size_limit=INFLATE_LIMIT)
        try:
            for rec in reader.records:
                if isinstance(rec, Chunk):  # inflated here, bounded; then split by mcap
                    data = inflate(rec.compression, rec.data, rec.uncompressed_size)
                    rec = replace(rec, compression="", data=data)
                    for inner in breakup_chunk(rec, validate_crc=True):
                        take(inner)
                else:
                    take(rec)
                at = fh.tell()  # the end of the last whole record
        except Exception as exc:  # noqa: BLE001 - the cut ends the records any way it falls
            why = f"then a record cut short or damaged: {type(exc).__name__}"
        writer.finish()
    size = src.stat().st_size
    if kept == 0:
        raise NoisevarError(
            f"{echo(src.name)} is an MCAP file cut short with no whole message before the "
            f"cut (whole records up to byte {at:,} of {size:,}, {why}): copy the file "
            "again, or record with smaller chunks"
        )
    return (
        f"the MCAP file is cut short (no summary or footer: a recording that never closed); "
        f"{kept:,} messages (all topics) read from its whole records, up to byte {at:,} of "
        f"{size:,} ({why}); what was recorded after them is lost"
    )

"""An MCAP file cut short (a recording stopped by a crash or a pulled card), read up to its cut.

An MCAP file ends with a summary, a footer and the magic bytes; a recording that never
closed has none of them, and ``rosbags`` refuses it. Its records before the cut are
whole: the ``mcap`` library's stream reader reads them in order (each chunk's checksum
checked), and its writer lays them out again as a complete file, which ``rosbags`` then
reads as any bag, its message definitions checked as usual (what ``mcap recover`` does).
The records after the last whole chunk are lost; :func:`recovered` says how many
messages were kept and where the file was cut.

The copy lives in a temporary directory for the process; the last :data:`KEPT` copies
are kept (a dashboard reads one log many times), older ones deleted.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
from collections import OrderedDict
from itertools import count
from pathlib import Path

from noisevar.errors import NoisevarError
from noisevar.io.limits import MAX_BYTES, echo

MAGIC = b"\x89MCAP0\r\n"
#: Recovered copies kept per process.
KEPT = 4
#: Largest chunk (uncompressed) or record read: the table cap, so a forged size cannot
#: make the reader hold more than a log may.
RECORD_LIMIT = MAX_BYTES

_copies: OrderedDict[tuple, tuple[Path, str]] = OrderedDict()
_home: list[Path] = []
_serial = count()


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
    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    if key in _copies:
        _copies.move_to_end(key)
        return _copies[key]
    out = _workdir() / f"{next(_serial)}-{path.stem}.mcap"
    kept, at, why = _rewrite(path, out)
    if kept == 0:
        out.unlink(missing_ok=True)
        raise NoisevarError(
            f"{echo(path.name)} is an MCAP file cut short with no whole message before the "
            f"cut (whole records up to byte {at:,} of {stat.st_size:,}, {why}): copy the "
            "file again, or record with smaller chunks"
        )
    note = (
        f"the MCAP file is cut short (no summary or footer: a recording that never closed); "
        f"{kept:,} messages (all topics) read from its whole records, up to byte {at:,} of "
        f"{stat.st_size:,} ({why}); what was recorded after them is lost"
    )
    _copies[key] = (out, note)
    while len(_copies) > KEPT:
        old, _ = _copies.popitem(last=False)[1]
        old.unlink(missing_ok=True)
    return out, note


def _rewrite(src: Path, dst: Path) -> tuple[int, int, str]:
    """Copy ``src``'s whole records into a complete MCAP at ``dst``: (messages, where the
    reading stopped, why)."""
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
        reader = StreamReader(fh, emit_chunks=True, record_size_limit=RECORD_LIMIT)
        try:
            for rec in reader.records:
                if isinstance(rec, Chunk):
                    if rec.uncompressed_size > RECORD_LIMIT:
                        why = f"a chunk of {rec.uncompressed_size:,} bytes, over the limit"
                        break
                    for inner in breakup_chunk(rec, validate_crc=True):
                        take(inner)
                else:
                    take(rec)
                at = fh.tell()  # the end of the last whole record
        except Exception as exc:  # noqa: BLE001 - the cut ends the records any way it falls
            why = f"then a record cut short or damaged: {type(exc).__name__}"
        writer.finish()
    return kept, at, why


def _workdir() -> Path:
    """This process's directory of recovered copies (removed at exit)."""
    if not _home:
        home = Path(tempfile.mkdtemp(prefix="noisevar-mcap-"))
        atexit.register(shutil.rmtree, home, True)
        _home.append(home)
    return _home[0]

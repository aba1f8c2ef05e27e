"""A ROS bag topic's own first and last record times, from the bag's index (no message read).

``noisevar topics`` gives each topic's mean rate as its count over its own span: a topic
that starts late or stops early (evo's ORB-SLAM topic) is not diluted by the bag's span.

- ROS 1: ``rosbags`` reads every connection's index (record time, position) when the bag
  is opened: its first and last entries.
- ROS 2 sqlite3: the first and last ``timestamp`` of the topic's rows (two queries, each
  ordered by the ``timestamp`` index rosbag2 writes, limited to one row).
- ROS 2 MCAP: the message index records (log time, offset; 16 bytes a message) of the
  topic's channel in its earliest and latest chunks, read from the file's chunk index.

Anything else (an MCAP without chunk index, a ``rosbags`` whose readers lack these
attributes) gives None: the caller falls back on the bag's span.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable
from typing import Any

#: MCAP message index record: opcode 0x07, u64 length, u16 channel id, u32 bytes of
#: (u64 log time, u64 offset) pairs.
_MCAP_MESSAGE_INDEX = 0x07


def topic_span(connections: Iterable[Any]) -> tuple[int, int] | None:
    """First and last record time (ns) over a topic's connections, or None when the
    bag's index does not say (see the module's notes)."""
    spans = []
    for conn in connections:
        try:
            span = _connection_span(conn)
        except (AttributeError, KeyError, OSError, ValueError, struct.error, TypeError):
            return None
        if span is None:
            return None
        spans.append(span)
    if not spans:
        return None
    return min(s[0] for s in spans), max(s[1] for s in spans)


def _connection_span(conn: Any) -> tuple[int, int] | None:
    owner = conn.owner
    indexes = getattr(owner, "indexes", None)
    if isinstance(indexes, dict):  # ROS 1: read at opening, sorted by time
        rows = indexes.get(conn.id)
        return (int(rows[0].time), int(rows[-1].time)) if rows else None
    spans = []
    for storage in getattr(owner, "storages", None) or []:  # ROS 2: one per file
        ids = [
            c.id for c in storage.connections if c.topic == conn.topic and c.msgtype == conn.msgtype
        ]
        for cid in ids:
            if getattr(storage, "dbconn", None) is not None:
                span = _sqlite_span(storage.dbconn, cid)
            elif getattr(storage, "chunks", None):
                span = _mcap_span(storage, cid)
            else:
                return None
            if span is not None:
                spans.append(span)
    if not spans:
        return None
    return min(s[0] for s in spans), max(s[1] for s in spans)


def _sqlite_span(db: Any, cid: int) -> tuple[int, int] | None:
    ends = []
    for order in ("ASC", "DESC"):
        row = next(
            iter(
                db.execute(
                    f"SELECT timestamp FROM messages WHERE topic_id = ? "  # noqa: S608
                    f"ORDER BY timestamp {order} LIMIT 1",
                    (cid,),
                )
            ),
            None,
        )
        if row is None:
            return None
        ends.append(int(row[0]))
    return ends[0], ends[1]


def _mcap_times(bio: Any, offset: int) -> list[int]:
    """The log times of one message index record at ``offset``."""
    bio.seek(offset)
    op, _length, _channel, size = struct.unpack("<BQHI", bio.read(15))
    if op != _MCAP_MESSAGE_INDEX:
        raise ValueError("not an MCAP message index")
    data = bio.read(size)
    return [t for t, _ in struct.iter_unpack("<QQ", data)]


def _mcap_span(storage: Any, cid: int) -> tuple[int, int] | None:
    chunks = [c for c in storage.chunks if cid in c.message_index_offsets]
    if not chunks:
        return None
    bio = storage.bio
    here = bio.tell()
    try:
        first = last = None
        # chunks may overlap in time: go on while a chunk could hold an earlier message
        for c in sorted(chunks, key=lambda c: c.message_start_time):
            if first is not None and c.message_start_time > first:
                break
            times = _mcap_times(bio, c.message_index_offsets[cid])
            first = min([*times, *([] if first is None else [first])])
        for c in sorted(chunks, key=lambda c: -c.message_end_time):
            if last is not None and c.message_end_time < last:
                break
            times = _mcap_times(bio, c.message_index_offsets[cid])
            last = max([*times, *([] if last is None else [last])])
    finally:
        bio.seek(here)
    return (first, last) if first is not None and last is not None else None

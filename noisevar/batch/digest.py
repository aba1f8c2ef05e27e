"""A file's content hash, streamed: any size in bounded memory (issue 27).

The hash is :func:`noisevar.io.content_digest`'s (BLAKE2b, 16 bytes) of the file's bytes,
fed in :data:`CHUNK`-byte pieces, so a batch journal written before (which hashed the
bytes whole) still resumes. A ROS 2 bag directory hashes each of its files in name order,
each name and size before its bytes: one hash for the bag, changed by any of its files.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Any

#: Bytes read at a time.
CHUNK = 1 << 20


def _feed(h: Any, path: Path) -> None:
    with open(path, "rb") as f:
        while block := f.read(CHUNK):
            h.update(block)


def file_digest(path: str | os.PathLike) -> str:
    """The content hash of a file, or of a ROS 2 bag directory's files.

    Parameters
    ----------
    path : str or path
        A file, or a directory (every file under it, by relative name).

    Returns
    -------
    str
        32 hex characters; a file's equals ``content_digest(its bytes)``.

    Raises
    ------
    OSError
        A file that cannot be read.
    """
    root = Path(path)
    h = hashlib.blake2b(digest_size=16)
    if not root.is_dir():
        _feed(h, root)
        return h.hexdigest()
    for p in sorted(q for q in root.rglob("*") if q.is_file()):
        h.update(f"{p.relative_to(root).as_posix()}\0{p.stat().st_size}\0".encode())
        _feed(h, p)
    return h.hexdigest()

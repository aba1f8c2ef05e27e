"""A log uploaded as bytes, as a file: every log reader takes a path."""

from __future__ import annotations

import contextlib
import tempfile
from collections.abc import Iterator
from pathlib import Path


@contextlib.contextmanager
def log_file(raw: bytes, name: str) -> Iterator[Path]:
    """Log bytes as a file in a private temporary directory, named by ``name``'s suffix
    (the readers tell formats by it), removed on exit."""
    suffix = Path(name).suffix.lower()
    suffix = suffix if suffix.isascii() and len(suffix) <= 16 else ""
    with tempfile.TemporaryDirectory(prefix="noisevar-log-") as tmp:
        path = Path(tmp) / f"upload{suffix}"
        path.write_bytes(raw)
        yield path

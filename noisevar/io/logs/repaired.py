"""Complete copies of bags cut short, made once per process, and bounded decompression.

A recording that never closed (a crash, a pulled card, a copy cut short) has whole
records up to its cut and no index. The MCAP and ROS 1 repairs
(:mod:`~noisevar.io.logs.mcap_cut`, :mod:`~noisevar.io.logs.rosbag1_cut`) write those
records again as a complete file, which ``rosbags`` then reads as any bag. The copies
live in a temporary directory of the process; the last :data:`KEPT` are kept (a
dashboard reads one log many times), older ones deleted.
"""

from __future__ import annotations

import atexit
import bz2
import io
import shutil
import tempfile
from collections import OrderedDict
from collections.abc import Callable
from itertools import count
from pathlib import Path

from noisevar.errors import NoisevarError
from noisevar.io.limits import MAX_BYTES

#: Repaired copies kept per process.
KEPT = 4
#: Largest chunk (uncompressed) a repair reads: the table cap, so a forged size cannot make
#: the reader hold more than a log may.
INFLATE_LIMIT = MAX_BYTES

_copies: OrderedDict[tuple, tuple[Path, str]] = OrderedDict()
_home: list[Path] = []
_serial = count()


#: The files of a ROS 2 bag directory.
BAG_FILES = (".mcap", ".db3")


def bag_files(path: Path) -> list[Path]:
    """The ROS 2 bag files (``.mcap``, ``.db3``) directly inside the directory ``path``."""
    return sorted(p for p in path.iterdir() if p.suffix.lower() in BAG_FILES and p.is_file())


def unclosed_dir(path: Path) -> Path | None:
    """The one bag file of a ROS 2 bag directory without ``metadata.yaml`` (a recording that
    never closed: ``ros2 bag record`` writes it on closing), or None.

    The directory holds that file alone (with sqlite's ``-wal``/``-shm``/``-journal`` beside
    a ``.db3``): a folder of logs that happens to hold one ``.mcap`` is not a bag.
    """
    if not path.is_dir() or (path / "metadata.yaml").is_file():
        return None
    files = bag_files(path)
    if len(files) != 1:
        return None
    sidecars = {files[0].name + s for s in ("-wal", "-shm", "-journal")}
    rest = [p for p in path.iterdir() if p != files[0] and not p.name.startswith(".")]
    return files[0] if all(p.name in sidecars for p in rest) else None


def repaired(path: Path, rewrite: Callable[[Path, Path], str], suffix: str) -> tuple[Path, str]:
    """The repaired copy of ``path`` (named with ``suffix``) and its note: ``rewrite(src,
    dst)`` writes the copy and returns the note (or raises
    :class:`~noisevar.errors.NoisevarError`); made once per file version."""
    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    if key in _copies:
        _copies.move_to_end(key)
        return _copies[key]
    out = _workdir() / f"{next(_serial)}-{path.name.split('.')[0]}{suffix}"
    try:
        note = rewrite(path, out)
    except BaseException:
        out.unlink(missing_ok=True)
        raise
    _copies[key] = (out, note)
    while len(_copies) > KEPT:
        old, _ = _copies.popitem(last=False)[1]
        old.unlink(missing_ok=True)
    return out, note


def inflate(kind: str, data: bytes, size: int) -> bytes:
    """``data`` decompressed (``kind``: ``""``/``"none"``, ``"bz2"``, ``"lz4"``, ``"zstd"``), at
    most ``size`` bytes (the size its record declares, itself at most :data:`INFLATE_LIMIT`).

    Raises
    ------
    NoisevarError
        A declared size over the limit, a compression not known, or more bytes than
        declared.
    """
    if size > INFLATE_LIMIT:
        raise NoisevarError(f"a chunk declares {size:,} bytes, over the {INFLATE_LIMIT:,} limit")
    if kind in ("", "none"):
        out = data
    elif kind == "bz2":
        out = bz2.BZ2Decompressor().decompress(data, max_length=size + 1)
    elif kind == "lz4":
        import lz4.frame

        out = lz4.frame.LZ4FrameDecompressor().decompress(data, max_length=size + 1)
    elif kind == "zstd":
        import zstandard

        with zstandard.ZstdDecompressor().stream_reader(io.BytesIO(data)) as src:
            out = src.read(size + 1)  # a stream: no size taken from the frame on trust
    else:
        raise NoisevarError(f"a chunk compressed with {kind[:20]!r}, which is not known")
    if len(out) > size:
        raise NoisevarError(f"a chunk holds more than the {size:,} bytes it declares")
    return out


def _workdir() -> Path:
    """This process's directory of repaired copies (removed at exit)."""
    if not _home:
        home = Path(tempfile.mkdtemp(prefix="noisevar-repaired-"))
        atexit.register(shutil.rmtree, home, True)
        _home.append(home)
    return _home[0]

"""File limits checked before anything is read: the size cap, and safe echoes of names.

Standard library only, so that a command can refuse a file that is missing, unreadable
or over the cap before NumPy, pandas or the estimators are imported.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from noisevar.errors import NoisevarError

#: Largest file :func:`~noisevar.io.load.load_table` reads unless told otherwise (bytes);
#: checked before reading.
MAX_BYTES = 1 << 30
#: Characters of a file's field (a name, a cell) echoed in a message; the rest is elided.
ECHO_LIMIT = 60

_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")


def echo(value: object, limit: int = ECHO_LIMIT) -> str:
    """A field of a file, safe to echo in a message: control characters escaped, truncated.

    ANSI escape sequences and other control characters become ``\\x1b``-style escapes
    (a file cannot drive the terminal), and a long field is cut with its length noted.

    Parameters
    ----------
    value : object
        The field (converted with ``str``).
    limit : int
        Characters kept.

    Returns
    -------
    str
    """
    text = str(value)
    more = len(text) - limit
    if more > 0:
        text = text[:limit]
    text = _CONTROL.sub(lambda m: f"\\x{ord(m.group()):02x}", text)
    return f"{text}... ({more:,} more characters)" if more > 0 else text


def check_bytes(size: int, name: str, max_bytes: int | None = MAX_BYTES) -> int:
    """``size`` if it is within ``max_bytes``, else a :class:`NoisevarError` naming ``name``.

    Parameters
    ----------
    size : int
        Bytes of the file (or upload).
    name : str
        The name shown in the message.
    max_bytes : int or None
        The cap; None: no cap.

    Returns
    -------
    int
        ``size``.
    """
    if max_bytes is not None and size > max_bytes:
        raise NoisevarError(
            f"{echo(name)} is {size / 1e6:,.1f} MB, over the {max_bytes / 1e6:,.0f} MB limit: "
            "give a shorter record, or read it in chunks (CLI --stream; Python "
            "noisevar.stream.estimate_file): method auto, bounded memory"
        )
    return size


def check_size(
    source: str | os.PathLike, name: str | None = None, max_bytes: int | None = MAX_BYTES
) -> int:
    """The size in bytes of the file ``source``, once it is known to be readable and in the cap.

    Parameters
    ----------
    source : str or path
        The file.
    name : str, optional
        The name shown in messages (default: the path's name).
    max_bytes : int or None
        The cap (default :data:`MAX_BYTES`); None: no cap.

    Returns
    -------
    int
        The file's size in bytes.

    Raises
    ------
    NoisevarError
        No such file, not a regular file, not readable, or over ``max_bytes``.
    """
    path = Path(source)
    name = name or path.name
    try:
        if not path.is_file():
            raise NoisevarError(f"no such file: {echo(str(path))}")
        size = path.stat().st_size
    except OSError as exc:
        raise NoisevarError(f"cannot read {echo(name)}: {exc.strerror or exc}") from None
    if not os.access(path, os.R_OK):
        raise NoisevarError(f"cannot read {echo(name)}: Permission denied")
    return check_bytes(size, name, max_bytes)

"""The message definitions a ROS bag carries, checked before ``rosbags`` compiles them.

``rosbags`` turns a bag's own message definitions (text from the file) into Python code
that it executes to build its deserialisers. Before that happens, :func:`open_bag` parses
each connection's definition with ``rosbags``' own parsers (which only parse) and refuses
the bag, with one :class:`~noisevar.errors.NoisevarError` naming the type, unless every
type name, field name and constant name is a plain identifier, every constant value a
plain literal (a finite number, a bool, or a string without quotes, backslashes or line
breaks), and the text is bounded (:data:`MAX_TYPE_BYTES` per type, :data:`MAX_BAG_BYTES`
for the bag's distinct definitions).

Notes
-----
``rosbags`` 0.11 already writes constant values with ``repr`` and its grammar rejects most
odd names; this check does not rely on either, so a parser or generator change upstream
cannot let a log's text reach generated code.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from pathlib import Path

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo

#: Longest definition of one message type (one section of a connection's text), bytes.
MAX_TYPE_BYTES = 64 * 1024
#: Longest total of a bag's distinct message definitions, bytes.
MAX_BAG_BYTES = 1024 * 1024
#: Deepest nesting of array and sequence descriptors in one field.
MAX_NESTING = 4

IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,127}\Z")
TYPE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,127}(/[A-Za-z][A-Za-z0-9_]{0,127}){1,3}\Z")
#: Characters a string constant may not hold: quotes, backslash, line breaks, controls.
_UNSAFE_TEXT = re.compile(r"[\"'\\\x00-\x1f\x7f]")
#: A separator line between the types of a concatenated definition (ROS 1, ROS 2 msg, IDL).
_SEPARATOR = re.compile(r"^={3,}[ \t]*\r?$", re.MULTILINE)
_IDL_SEP = "=" * 80 + "\n"


class _Invalid(ValueError):
    """One part of a definition that is not plain (turned into the bag's error)."""


def _plain_literal(value: object) -> bool:
    if isinstance(value, bool | int):
        return True
    if isinstance(value, float):
        return math.isfinite(value)
    return isinstance(value, str) and len(value) <= 1024 and not _UNSAFE_TEXT.search(value)


def _check_desc(desc: object, depth: int = 0) -> None:
    """A field's type descriptor: a base type, a type name, or an array/sequence of one."""
    from rosbags.interfaces import Nodetype

    if depth > MAX_NESTING or not (isinstance(desc, tuple) and len(desc) == 2):
        raise _Invalid("field type")
    kind, detail = desc
    if kind == Nodetype.BASE:
        base, bound = detail
        if not (isinstance(base, str) and IDENTIFIER.match(base) and type(bound) is int):
            raise _Invalid(f"base type {base!r}")
    elif kind == Nodetype.NAME:
        if not (isinstance(detail, str) and TYPE_NAME.match(detail)):
            raise _Invalid(f"type name {detail!r}")
    elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        sub, count = detail
        if type(count) is not int or count < 0:
            raise _Invalid(f"array length {count!r}")
        _check_desc(sub, depth + 1)
    else:
        raise _Invalid(f"field kind {kind!r}")


def check_types(typs: dict) -> None:
    """Refuse parsed types (``rosbags`` Typesdict) holding any name or constant that is not
    plain; raises ``_Invalid`` naming the part, caught by :func:`check_definition`."""
    for name, (consts, fields) in typs.items():
        if not (isinstance(name, str) and TYPE_NAME.match(name)):
            raise _Invalid(f"type name {name!r}")
        for cname, ctype, value in consts:
            if not (isinstance(cname, str) and IDENTIFIER.match(cname)):
                raise _Invalid(f"constant name {cname!r}")
            if not (isinstance(ctype, str) and IDENTIFIER.match(ctype)):
                raise _Invalid(f"constant type {ctype!r}")
            if not _plain_literal(value):
                raise _Invalid(f"value of constant {cname}")
        for fname, desc in fields:
            if not (isinstance(fname, str) and IDENTIFIER.match(fname)):
                raise _Invalid(f"field name {fname!r}")
            _check_desc(desc)


def _parse(msgtype: str, fmt: str, text: str) -> dict:
    """``rosbags``' parse of one connection's definition (a parse only: nothing executed)."""
    from rosbags.typesys import get_types_from_idl, get_types_from_msg

    if fmt == "MSG":
        return get_types_from_msg(text, msgtype)
    typs: dict = {}
    if text.startswith(f"{_IDL_SEP}IDL: "):
        for part in text.split(_IDL_SEP)[1:]:
            _, _, idl = part.partition("\n")
            typs.update(get_types_from_idl(idl))
        return typs
    return get_types_from_idl(text)


def check_definition(msgtype: str, fmt: str, text: str) -> None:
    """Refuse one connection's definition (``fmt`` ``MSG`` or ``IDL``) unless it is plain.

    Raises
    ------
    NoisevarError
        The definition is too long, does not parse, or holds a name or constant value
        that is not plain; the message names the type.
    """
    try:
        if not TYPE_NAME.match(msgtype):
            raise _Invalid(f"type name {msgtype!r}")
        for section in _SEPARATOR.split(text):
            if len(section.encode("utf-8", "surrogatepass")) > MAX_TYPE_BYTES:
                raise _Invalid(f"a type's definition is over {MAX_TYPE_BYTES // 1024} KiB")
        try:
            typs = _parse(msgtype, fmt, text)
        except Exception as exc:  # noqa: BLE001 - rosbags' parsers raise several types
            raise _Invalid(f"it does not parse ({type(exc).__name__})") from None
        check_types(typs)
    except _Invalid as why:
        raise NoisevarError(
            f"the message definition of {echo(repr(msgtype), 120)} in this bag is not valid "
            f"({echo(why, 160)}): noisevar does not compile it; re-record the bag with its "
            "message packages' own definitions"
        ) from None


def check_connections(connections: Iterable) -> None:
    """Check every connection's embedded definition (``rosbags`` Connection objects)."""
    seen: set[tuple[str, str, str]] = set()
    total = 0
    for conn in connections:
        fmt = getattr(conn.msgdef.format, "name", str(conn.msgdef.format))
        if fmt == "NONE":  # no definition in the bag: the built-in typestore is used
            continue
        key = (conn.msgtype, fmt, conn.msgdef.data)
        if key in seen:
            continue
        seen.add(key)
        total += len(conn.msgdef.data.encode("utf-8", "surrogatepass"))
        if total > MAX_BAG_BYTES:
            raise NoisevarError(
                f"the message definitions in this bag are over {MAX_BAG_BYTES // 1024**2} "
                f"MiB in total (at type {echo(repr(conn.msgtype), 120)}), which is not valid "
                "for a sensor log: noisevar does not compile them"
            )
        check_definition(conn.msgtype, fmt, conn.msgdef.data)


class _Opened:
    """An opened sub-reader as ``AnyReader`` sees it while it registers: entering and
    leaving do nothing (it is already open), its connections are the reader's."""

    def __init__(self, reader):
        self.connections = reader.connections

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> bool:
        return False


def open_bag(path: Path, default_typestore):
    """``rosbags``' ``AnyReader`` of the bag at ``path`` whose opening checks the bag's
    definitions (:func:`check_connections`) after its index is read and before they are
    registered (compiled); use it as a context manager, like ``AnyReader``.

    Notes
    -----
    ``AnyReader._open`` enters the sub-readers, then parses and registers every definition
    in one step; the override enters them itself, checks, and hands ``_open`` the opened
    readers. A ``rosbags`` that renamed ``_open`` would skip the check: the tests of
    hostile bags then fail, as they expect this module's error.
    """
    from rosbags.highlevel import AnyReader

    class CheckedReader(AnyReader):
        def _open(self) -> None:
            assert self.stack is not None
            for reader in self.readers:
                self.stack.enter_context(reader)
            check_connections(c for r in self.readers for c in r.connections)
            readers, self.readers = self.readers, [_Opened(r) for r in self.readers]
            try:
                super()._open()
            finally:
                self.readers = readers

    return CheckedReader([path], default_typestore=default_typestore)

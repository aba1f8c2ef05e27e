"""A bag's own message definitions are checked before ``rosbags`` compiles them: bags
written by rosbags' writers with hand-made definitions (hostile constant, field name,
size) are one clear error; a plain hand-made definition still reads."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_table
from noisevar.io.logs.msgdefs import check_connections, check_definition, check_types

PAYLOAD = "x\"); __import__('pathlib').Path('PWNED').touch() #"


def write_evil(path: Path, msgdef: str, kind: str, n: int = 20, rihs: str = "0" * 64) -> Path:
    """``n`` messages of one float64 field on /evil, typed by ``msgdef`` as written (a
    made-up hash unless ``rihs`` is given)."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin, Writer

    if kind == "ros1":
        w = Writer1(path)
        w.open()
        conn = w.add_connection("/evil", "evil_msgs/msg/Evil", msgdef=msgdef, md5sum="0" * 32)
        head = b""
    else:
        w = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
        w.open()
        conn = w.add_connection(
            "/evil", "evil_msgs/msg/Evil", msgdef=msgdef, rihs01=f"RIHS01_{rihs}"
        )
        head = b"\x00\x01\x00\x00"  # little-endian CDR preamble
    for i in range(n):
        w.write(conn, 1_000_000_000 + i * 10_000_000, head + struct.pack("<d", 0.5 * i))
    w.close()
    return path


@pytest.mark.parametrize(
    "kind,msgdef,why",
    [
        ("ros1", f"string EVIL={PAYLOAD}\nfloat64 data\n", "value of constant EVIL"),
        ("mcap", f"string EVIL={PAYLOAD}\nfloat64 data\n", "value of constant EVIL"),
        ("ros1", "float64 data;__import__('os')\n", "does not parse"),
        ("mcap", "float64 __class__\n", "does not parse"),
        ("mcap", "# " + "x" * (65 * 1024) + "\nfloat64 data\n", "over 64 KiB"),
    ],
    ids=["ros1-constant", "mcap-constant", "ros1-field", "mcap-dunder", "mcap-size"],
)
def test_hostile_definition_is_one_error_and_nothing_runs(tmp_path, monkeypatch, kind, msgdef, why):
    monkeypatch.chdir(tmp_path)
    bag = write_evil(tmp_path / ("e.bag" if kind == "ros1" else "e"), msgdef, kind)
    with pytest.raises(NoisevarError) as err:
        load_table(bag, topic="/evil")
    msg = str(err.value)
    assert "message definition of 'evil_msgs/" in msg and "is not valid" in msg, msg
    assert why in msg and "\n" not in msg
    assert not (tmp_path / "PWNED").exists()
    assert main(["topics", str(bag)]) == 2  # listing a bag compiles its types too


def test_plain_hand_made_definition_reads(tmp_path):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    msgdef = "int32 K=3\nstring NAME=plain text, no quotes\nfloat64 data\n"
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(msgdef, "evil_msgs/msg/Evil"))
    rihs = store.hash_rihs01("evil_msgs/msg/Evil").removeprefix("RIHS01_")
    bag = write_evil(tmp_path / "ok", msgdef, "mcap", rihs=rihs)
    table = load_table(bag, topic="/evil")
    assert np.allclose(table.columns["data"], 0.5 * np.arange(20))


@pytest.mark.parametrize(
    "typs,why",
    [
        ({"a/msg/B": ([("K", "float64", float("nan"))], [])}, "value of constant K"),
        ({"a/msg/B": ([("K", "string", "a\\nb")], [])}, "value of constant K"),
        ({"a/msg/B": ([("K=1;", "int32", 1)], [])}, "constant name"),
        ({"a/msg/B(object)": ([], [])}, "type name"),
        ({"a/msg/B": ([], [("x", (2, "c/msg/D:pass"))])}, "type name"),
        ({"a/msg/B": ([], [("_x", (1, ("float64", 0)))])}, "field name"),
        ({"a/msg/B": ([], [("x", (3, ((1, ("float64 x", 0)), 3)))])}, "base type"),
    ],
)
def test_parsed_types_are_checked(typs, why):
    with pytest.raises(ValueError, match=why):
        check_types(typs)


def test_type_name_of_the_connection_is_checked():
    with pytest.raises(NoisevarError, match="is not valid.*type name"):
        check_definition("evil/Ev(object)", "MSG", "float64 data\n")


def test_idl_constants_and_the_bags_total_are_checked():
    from types import SimpleNamespace

    from rosbags.interfaces import MessageDefinitionFormat as Fmt

    ok = "module a { module msg { struct B { double x; }; }; };"
    check_definition("a/msg/B", "IDL", ok)
    bad = 'module a { module msg { module B_Constants { const string S = "x\'y"; }; }; };\n' + ok
    with pytest.raises(NoisevarError, match="'a/msg/B'.*not valid.*value of constant S"):
        check_definition("a/msg/B", "IDL", bad)
    big = "# " + "x" * (60 * 1024) + "\nfloat64 data\n"
    conns = [
        SimpleNamespace(msgtype=f"a/msg/T{i}", msgdef=SimpleNamespace(format=Fmt.MSG, data=big))
        for i in range(20)
    ]
    with pytest.raises(NoisevarError, match="over 1 MiB in total"):
        check_connections(conns)

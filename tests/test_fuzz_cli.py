"""Fuzz the CLI with hostile input (issue 15): every case is exit 2 with one line, or exit 0.

A generator builds the cases from each class of the issue: numeric range, degenerate
answers, bad configs, hostile files (size, width, encoding, control characters, huge
fields, thousands separators, big integers, complex fields, NMEA), bad flags. Each runs
``noisevar.cli.main`` in-process; on exit 0 the JSON output must be strict (no NaN or
Infinity tokens) and every reported variance finite and non-negative.
"""

from __future__ import annotations

import contextlib
import io
import json
import warnings
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from noisevar.cli import main

N = 600
#: Methods cheap enough to run on every case (the mle peers are covered by fewer cases).
FAST = ("rice", "diff2", "hkt3", "mad-diff", "wavelet-mad", "somd", "auto")
SLOW = ("mle-level", "mle-trend")
SCALES = (1e-300, 1e-200, 1e-155, 1e-150, 1e-30, 1.0, 1e30, 1e150, 1e154, 1e200, 1e300, 1e308)


def _nmea(body: str) -> str:
    c = 0
    for ch in body:
        c ^= ord(ch)
    return f"${body}*{c:02X}"


def _gga(hms: str, lat: str) -> str:
    return _nmea(f"GPGGA,{hms},{lat},N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")


def _files(tmp: Path) -> Iterator[tuple[str, str, bytes]]:
    """(class, file name, content) of hostile files."""
    rng = np.random.default_rng(0)
    z = np.cumsum(rng.normal(0, 0.1, N)) + rng.normal(0, 1, N)
    col = "\n".join(repr(float(v)) for v in z)
    yield "ordinary", "ok.csv", ("x\n" + col).encode()
    for s in SCALES:
        with np.errstate(over="ignore"):  # 1e308 x a few: inf cells, a hostile case too
            text = "x\n" + "\n".join(repr(float(v * s)) for v in z)
        yield "numeric-range", f"scale{s:g}.csv", text.encode()
    yield "numeric-range", "pm308.csv", ("x\n" + "\n".join(["1e308", "-1e308"] * 300)).encode()
    yield "numeric-range", "tiny.csv", ("x\n" + "\n".join(["5e-324", "0"] * 300)).encode()
    yield "degenerate", "quantised.csv", ("x\n" + "0\n" * 599 + "1\n").encode()
    yield "degenerate", "constant.csv", ("x\n" + "3\n" * 600).encode()
    yield "degenerate", "short.csv", b"x\n1\n2\n"
    yield "files", "empty.csv", b""
    yield "files", "blank.csv", b"\n\n  \n"
    yield "files", "binary.csv", bytes(range(256)) * 10
    yield "files", "nul.csv", b"x\n1\x002\n"
    yield "files", "wide.csv", (",".join(f"c{i}" for i in range(5000)) + "\n").encode() * 2
    yield (
        "files",
        "dupnames.csv",
        (",".join(["a"] * 500) + "\n" + ",".join(["1"] * 500) + "\n").encode(),
    )
    yield "files", "hugefield.csv", b"x\n1\n" + b"9" * 2_000_000 + b"x\n"
    yield "files", "ragged.csv", b"a,b\n1,2\n3,4,5\n"
    yield "files", "notnumber.csv", b"x\n1\nabc\n"
    yield "files", "latin1.csv", ("x\u00e9\n" + col).encode("latin-1")
    yield "files", "npz.npz", b"PK\x03\x04"
    yield "files", "badnpy.npy", b"\x93NUMPY garbage"
    yield (
        "silent-wrong",
        "thousands.csv",
        (
            "price\n"
            + "\n".join(f"{4 + i % 3},{(i * 37) % 1000:03d}.{i % 100:02d}" for i in range(N))
        ).encode(),
    )
    yield "silent-wrong", "thousands_multi.csv", ("a,b\n" + "4,867.69,1\n" * 50).encode()
    yield (
        "silent-wrong",
        "euro.csv",
        ("t;x\n" + "\n".join(f"{i};{v:.6f}".replace(".", ",") for i, v in enumerate(z))).encode(),
    )
    yield (
        "silent-wrong",
        "int63.csv",
        ("x\n" + "\n".join(str(2**63 - 1 - 3 * i) for i in range(N))).encode(),
    )
    yield (
        "silent-wrong",
        "int64.csv",
        ("x\n" + "\n".join(str(2**64 + 3 * i) for i in range(N))).encode(),
    )
    yield "silent-wrong", "ansi\x1b[31m.csv", ("a\x1b[2J\n" + col).encode()
    yield "silent-wrong", "ansi_cell.csv", b"x\n1\n\x1b[31mred\n"
    yield "silent-wrong", "nan_inf.csv", ("x\n" + col + "\nnan\ninf\n-inf\n").encode()
    structured = np.zeros(N, dtype=[("t", "f8"), ("x", "c16")])
    buf = io.BytesIO()
    np.save(buf, structured)
    yield "silent-wrong", "complex.npy", buf.getvalue()
    buf = io.BytesIO()
    np.save(buf, np.arange(N, dtype=np.int64) + 2**62)
    yield "silent-wrong", "bigint.npy", buf.getvalue()
    buf = io.BytesIO()
    np.save(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    yield "files", "pickle.npy", buf.getvalue()
    fixes = [_gga(f"1200{s:02d}.00", f"4807.{s:03d}") for s in range(20)]
    yield (
        "files",
        "badtime.nmea",
        "\n".join([*fixes[:5], _gga("999999.00", "4807.038"), *fixes[5:]]).encode(),
    )
    yield (
        "files",
        "lat95.nmea",
        "\n".join([*fixes[:5], _gga("120030.00", "9500.000"), *fixes[5:]]).encode(),
    )
    yield "files", "checksum.nmea", ("\n".join(fixes) + "\n$GPGGA,1,2*00\n").encode()
    yield (
        "files",
        "time_ms_hourly.csv",
        (
            "time,x\n"
            + "\n".join(f"{1_700_000_000_000 + 3_600_000 * i},{v!r}" for i, v in enumerate(z))
        ).encode(),
    )
    yield (
        "files",
        "time_ns.csv",
        (
            "time,x\n"
            + "\n".join(f"{1_700_000_000_000_000_000 + i},{v!r}" for i, v in enumerate(z))
        ).encode(),
    )


CONFIGS = {
    "inf": '{"method": "rice", "drop_nonfinite": Infinity}',
    "window_inf": '{"method": "somd", "window": Infinity}',
    "window_1e400": '{"method": "somd", "window": 1e400}',
    "window_digits": '{"method": "somd", "window": ' + "9" * 5000 + "}",
    "nan": '{"method": "somd", "gamma_amp": NaN}',
    "deep": "[" * 50_000 + "]" * 50_000,
    "refvar_inf": '{"method": "somd-redundant", "reference_variance": 1e999}',
    "refvar_neg": '{"method": "somd-redundant", "reference_variance": -1}',
    "list": "[1, 2, 3]",
    "string": '"somd"',
    "unknown": '{"method": "x\\u001b[31m"}',
    "badjson": "{method: somd",
    "ok": '{"method": "somd", "window": 40}',
}


def _cases(tmp: Path) -> Iterator[tuple[str, list[str]]]:
    """(class, argv) of every hostile case."""
    paths = {}
    for cls, name, data in _files(tmp):
        p = tmp / name
        p.write_bytes(data)
        paths[name] = (cls, str(p))
    for cls, path in paths.values():
        methods = FAST if cls in ("numeric-range", "degenerate", "ordinary") else ("rice",)
        for m in methods:
            yield cls, ["estimate", path, "--method", m, "--format", "json"]
        if cls in ("numeric-range", "degenerate"):
            for m in SLOW:
                yield cls, ["estimate", path, "--method", m, "--format", "json"]
    ok = paths["ok.csv"][1]
    for name, text in CONFIGS.items():
        p = tmp / f"{name}.json"
        p.write_text(text)
        yield "config", ["estimate", ok, "--config", str(p), "--format", "json"]
    big = tmp / "big.json"
    with big.open("wb") as fh:
        fh.truncate(5 << 20)
    yield "config", ["estimate", ok, "--config", str(big)]
    yield (
        "flags",
        [
            "estimate",
            ok,
            "--method",
            "somd-redundant",
            "--reference-column",
            "x",
            "--reference-variance",
            "-1",
        ],
    )
    yield (
        "flags",
        [
            "estimate",
            ok,
            "--method",
            "somd-redundant",
            "--reference-column",
            "x",
            "--reference-variance",
            "1e999",
        ],
    )
    yield "flags", ["estimate", ok, "--window", "1e999"]
    yield "flags", ["estimate", ok, "--window", "9" * 400]
    yield "flags", ["estimate", ok, "--h-smooth", "nan"]
    yield "flags", ["estimate", ok, "--column", "9" * 5000]
    yield "flags", ["estimate", ok, "--column", "\x1b[31mred"]
    yield "flags", ["estimate", str(tmp / ("x" * 300 + ".csv"))]
    yield "flags", ["estimate", str(tmp / "missing.csv")]
    yield "flags", ["estimate", str(tmp)]
    yield "flags", ["experiment", "outliers", "--seed", "-1"]
    yield "flags", ["experiment", "outliers", "--runs", "0"]
    yield "flags", ["experiment", "outliers", "--runs", "1e999"]
    yield "flags", ["methods", "--format", "json"]
    ansi = paths["ansi\x1b[31m.csv"][1]
    yield "silent-wrong", ["estimate", ansi, "--method", "rice", "--column", "a\x1b[2J"]
    yield "silent-wrong", ["estimate", ansi, "--method", "rice"]
    yield "nan-json", ["experiment", "outliers", "--runs", "2", "--format", "json"]
    yield "files", ["scan-h", paths["pm308.csv"][1], "--format", "json"]
    yield "files", ["scan-h", paths["quantised.csv"][1], "--format", "json"]


def _strict(text: str) -> object:
    def refuse(token: str) -> None:
        raise AssertionError(f"non-strict JSON token {token}")

    return json.loads(text, parse_constant=refuse)


def _variances(obj: object) -> Iterator[float]:
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k in ("variance", "std") and isinstance(v, float | int):
                yield float(v)
            else:
                yield from _variances(v)
    elif isinstance(obj, list):
        for v in obj:
            yield from _variances(v)


def run_case(argv: list[str]) -> tuple[int, str, str]:
    """Exit status, stdout and stderr; a warning is written to stderr as a user would see it."""
    out, err = io.StringIO(), io.StringIO()
    with (
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
        warnings.catch_warnings(record=True) as caught,
    ):
        warnings.simplefilter("always")
        code = main(argv)
    for w in caught:
        err.write(f"{w.filename}:{w.lineno}: {w.category.__name__}: {w.message}\n")
    return code, out.getvalue(), err.getvalue()


def check_case(argv: list[str]) -> str | None:
    """None when the case behaves (exit 2 + one safe line, or exit 0 + strict JSON)."""
    code, out, err = run_case(argv)
    if "\x1b" in out or "\x1b" in err:
        return "a raw escape sequence reached the terminal"
    if code == 0 and err:
        return f"exit 0 with output on stderr {err[:300]!r}"
    if code == 2:
        lines = err.splitlines()
        if len(lines) != 1 or not lines[0].startswith("noisevar: error: "):
            return f"exit 2 but stderr is {err[:300]!r}"
        if "\x1b" in err or len(err) > 2100:
            return f"unsafe error line {err[:200]!r}"
        return None
    if code != 0:
        return f"exit {code}: {err[:300]!r}"
    if "--format" in argv and argv[argv.index("--format") + 1] == "json":
        try:
            data = _strict(out)
        except (AssertionError, ValueError) as exc:
            return f"invalid JSON: {exc}"
        bad = [v for v in _variances(data) if not (np.isfinite(v) and v >= 0)]
        if bad:
            return f"bad variances {bad[:3]}"
    return None


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    return list(_cases(tmp_path_factory.mktemp("fuzz")))


def test_the_generator_covers_every_class_with_over_100_cases(cases):
    classes = {c for c, _ in cases}
    assert len(cases) >= 100
    assert classes >= {
        "numeric-range",
        "degenerate",
        "config",
        "files",
        "silent-wrong",
        "flags",
        "nan-json",
    }


def test_every_hostile_case_exits_2_with_one_line_or_0_with_strict_json(cases):
    failures = [(argv, why) for _, argv in cases if (why := check_case(argv))]
    assert not failures, failures[:5]


def test_specific_answers(cases, tmp_path):
    """Not only 'no crash': the answers the issue asked for."""
    paths = {Path(a[1]).name: a[1] for c, a in cases if a[0] == "estimate" and len(a) > 1}
    code, out, _ = run_case(
        ["estimate", paths["thousands.csv"], "--method", "rice", "--format", "json"]
    )
    assert code == 0 and _strict(out)["n_total"] == N
    code, out, err = run_case(["estimate", paths["int63.csv"], "--method", "rice"])
    assert code == 2 and "precision lost" in err
    code, out, err = run_case(["estimate", paths["int64.csv"], "--method", "rice"])
    assert code == 2 and "precision lost" in err
    code, out, err = run_case(["estimate", paths["quantised.csv"], "--method", "mad-diff"])
    assert code == 2 and "quantised" in err
    code, out, err = run_case(["estimate", paths["complex.npy"], "--method", "rice"])
    assert code == 2 and "complex" in err
    code, out, _ = run_case(["estimate", paths["euro.csv"], "--method", "rice", "--format", "json"])
    assert code == 0 and _strict(out)["variance"] > 0
    code, out, err = run_case(["estimate", paths["ansi\x1b[31m.csv"], "--column", "nope"])
    assert code == 2 and "\x1b" not in err and "\\x1b" in err
    code, out, err = run_case(["estimate", paths["scale1e+300.csv"], "--method", "rice"])
    assert code == 2 and "larger than the largest" in err


def test_scaled_files_give_scaled_variances(cases):
    paths = {Path(a[1]).name: a[1] for c, a in cases if a[0] == "estimate" and len(a) > 1}
    ref = _strict(
        run_case(["estimate", paths["ok.csv"], "--method", "hkt3", "--format", "json"])[1]
    )["variance"]
    for s in (1e-150, 1e-30, 1e30, 1e150):
        name = f"scale{s:g}.csv"
        if name not in paths:
            continue
        out = _strict(
            run_case(["estimate", paths[name], "--method", "hkt3", "--format", "json"])[1]
        )
        assert out["variance"] / s**2 == pytest.approx(ref, rel=1e-9)

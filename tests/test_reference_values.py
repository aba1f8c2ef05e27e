"""Reference values (``tests/results/reference.json``) that a refactoring must leave unchanged.

The file was written by ``tests/results/make_reference.py`` before the redesign; this test
recomputes every number the same way and compares to rounding.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "results"))

import make_reference  # noqa: E402


def _compare(expected: object, actual: object, path: str, bad: list[str]) -> None:
    if isinstance(expected, dict):
        if not isinstance(actual, dict) or set(expected) != set(actual):
            bad.append(f"{path}: keys differ")
            return
        for key in expected:
            _compare(expected[key], actual[key], f"{path}/{key}", bad)
    elif isinstance(expected, list):
        if not isinstance(actual, list) or len(expected) != len(actual):
            bad.append(f"{path}: lengths differ")
            return
        for i, (e, a) in enumerate(zip(expected, actual, strict=True)):
            _compare(e, a, f"{path}[{i}]", bad)
    elif isinstance(expected, float) and isinstance(actual, int | float):
        if not math.isclose(expected, actual, rel_tol=1e-9, abs_tol=1e-12):
            bad.append(f"{path}: {actual!r} != {expected!r}")
    elif isinstance(expected, str) and " " in expected and len(expected) > 30:
        return  # prose (a note or a reason) may be reworded; names and numbers may not
    elif expected != actual:
        bad.append(f"{path}: {actual!r} != {expected!r}")


def test_every_reference_value_is_reproduced() -> None:
    expected = json.loads((HERE / "results" / "reference.json").read_text())
    bad: list[str] = []
    _compare(expected, make_reference.compute(), "", bad)
    assert not bad, "\n".join(bad[:40])

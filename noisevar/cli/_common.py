"""Helpers shared by the CLI's sub-commands: one-line errors, JSON output, loading a column."""

from __future__ import annotations

import argparse
import json
import os
from typing import Any, NoReturn

import numpy as np

from noisevar.errors import NoisevarError

EXIT_ERROR = 2


class Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line, like every other error."""

    def error(self, message: str) -> NoReturn:
        raise NoisevarError(f"{message} (see '{self.prog} --help')")


def json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def print_json(data: dict) -> None:
    print(json.dumps(data, indent=2, default=json_default, allow_nan=True))


def load_signal(
    path: str, column: str | None, drop_nonfinite: bool = False
) -> tuple[np.ndarray, int]:
    """One column of a data file as floats, and how many non-finite cells were dropped.

    Empty/NaN/Inf cells are refused (naming the first row) unless
    ``drop_nonfinite``.
    """
    from noisevar.io import load_table, pick_column

    table = load_table(path, os.path.basename(path))
    z = np.asarray(pick_column(table, column, drop_nonfinite=drop_nonfinite), dtype=float)
    return z, table.n_rows - z.size

"""The run/result protocol shared by the system families.

Every family (scenarios, carrier, fusion, robust, latency) simulates a batch of
seeded Monte Carlo runs and returns a result that says how many runs it holds
(``runs``), names itself (``label``) and refuses a bad run index
(``check_run``). Figures rely on this protocol only.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, TypeVar, runtime_checkable

from noisevar.errors import NoisevarError

__all__ = ["BatchResult", "RunResult", "as_list", "check_run_index"]

T = TypeVar("T")


def check_run_index(run: int, runs: int) -> None:
    """Refuse a Monte Carlo run index outside ``0 .. runs - 1``.

    Parameters
    ----------
    run : int
        Requested run.
    runs : int
        Runs the result holds.

    Raises
    ------
    NoisevarError
        When ``run`` is out of range.
    """
    if not 0 <= run < runs:
        raise NoisevarError(f"run {run} out of range: the result has {runs} runs")


@runtime_checkable
class RunResult(Protocol):
    """A batch of seeded runs: what every system result and data set offers."""

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        ...

    @property
    def label(self) -> str:
        """Short name for legends."""
        ...

    def check_run(self, run: int) -> None:
        """Raise :class:`NoisevarError` when ``run`` is not one of the runs."""
        ...


class BatchResult:
    """Mixin implementing :meth:`RunResult.check_run` from ``runs``.

    Subclasses (frozen dataclasses) define ``runs`` and ``label``.
    """

    __slots__ = ()

    def check_run(self, run: int) -> None:
        """Raise :class:`NoisevarError` when ``run`` is not one of the runs.

        Parameters
        ----------
        run : int
            Requested run.
        """
        check_run_index(run, self.runs)  # type: ignore[attr-defined]


def as_list(items: T | Sequence[T], cls: type[T], name: str | None = None) -> list[T]:
    """One result or a sequence of results as a non-empty list, each checked against ``cls``.

    Parameters
    ----------
    items : cls or sequence of cls
        One result or several.
    cls : type
        The class every item must be an instance of.
    name : str, optional
        Argument name for the error message.

    Returns
    -------
    list of cls

    Raises
    ------
    NoisevarError
        When ``items`` is empty or holds anything but ``cls`` instances.
    """
    out = [items] if isinstance(items, cls) else list(items)  # type: ignore[arg-type]
    if not out or not all(isinstance(r, cls) for r in out):
        what = f"{name}: " if name else ""
        raise NoisevarError(
            f"{what}give a {cls.__name__} or a non-empty list of {cls.__name__} objects"
        )
    return out

"""The run/result protocol shared by the system families.

Every family (scenarios, carrier, fusion, robust, latency) simulates a batch of
seeded Monte Carlo runs and returns a result that says how many runs it holds
(``n_runs``), names itself (``label``) and refuses a bad run index
(``check_run``). Figures rely on this protocol only.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from noisevar.errors import NoisevarError

__all__ = ["BatchResult", "RunResult", "check_run_index"]


def check_run_index(run: int, n_runs: int) -> None:
    """Refuse a Monte Carlo run index outside ``0 .. n_runs - 1``.

    Parameters
    ----------
    run : int
        Requested run.
    n_runs : int
        Runs the result holds.

    Raises
    ------
    NoisevarError
        When ``run`` is out of range.
    """
    if not 0 <= run < n_runs:
        raise NoisevarError(f"run {run} out of range: the result has {n_runs} runs")


@runtime_checkable
class RunResult(Protocol):
    """A batch of seeded runs: what every system result and data set offers."""

    @property
    def n_runs(self) -> int:
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
    """Mixin implementing :meth:`RunResult.check_run` from ``n_runs``.

    Subclasses (frozen dataclasses) define ``n_runs`` and ``label``.
    """

    __slots__ = ()

    def check_run(self, run: int) -> None:
        """Raise :class:`NoisevarError` when ``run`` is not one of the runs.

        Parameters
        ----------
        run : int
            Requested run.
        """
        check_run_index(run, self.n_runs)  # type: ignore[attr-defined]

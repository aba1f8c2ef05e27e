"""The one exception type noisevar raises for bad input or bad parameters."""

from __future__ import annotations


class NoisevarError(ValueError):
    """Bad input or parameters, with a message that says what is wrong and what to do.

    Every user-facing check in :mod:`noisevar` raises this type, so a caller
    (the CLI, the dashboard, a notebook) can catch one exception and show its
    message as it is: one line, no traceback.
    """


class NoWindowKept(NoisevarError):
    """SOMD's window selection kept no window (a :class:`NoisevarError`, as every other).

    The message says how many windows each test rejected and what to relax.
    The attributes let a caller show why without running the filters again.

    Attributes
    ----------
    summary : dict
        ``windows``, ``kept`` (0), ``failed_amplitude``, ``failed_angle``
        (:meth:`noisevar.filters.selection.WindowSelection.rejection_summary`).
    diagnosis : VarianceEstimate or None
        The estimate that was refused, with a NaN variance and interval: its
        ``details`` carry the filter outputs and every window's tests
        (:class:`noisevar.estimators.results.SomdDetails`), for drawing.
    """

    def __init__(self, message: str, summary: dict, diagnosis: object | None = None) -> None:
        super().__init__(message)
        self.summary = summary
        self.diagnosis = diagnosis


class EmptyCells(NoisevarError):
    """Empty, NaN or Inf values refused where dropping them is right (a :class:`NoisevarError`).

    The message says how many and where. Passing ``drop_nonfinite=True`` (CLI:
    ``--drop-nonfinite``) reads the other samples; a caller with its own control for that
    (the dashboard's checkbox) can name it by catching this type.
    """


class StackedSeries(NoisevarError):
    """A file that stacks several series (the long format) read as one record: refused.

    The message names the column whose values label the series and how to give one
    (``--series LABEL``, the Signal page's series picker). A caller with its own control
    for that (the dashboard's picker) offers :attr:`labels` without parsing the message.

    Attributes
    ----------
    column : str
        The column whose value names each row's series.
    labels : tuple of str
        Its values in file order, at most :data:`noisevar.io.series_option.MAX_LABELS`.
    n_labels : int
        How many values it holds in all.
    """

    def __init__(self, message: str, column: str, labels: tuple[str, ...], n_labels: int) -> None:
        super().__init__(message)
        self.column = column
        self.labels = labels
        self.n_labels = n_labels

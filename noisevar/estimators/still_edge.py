"""Still stretches at the minimum length, read where no grid phase moves them (issue 26 item 2).

The stretches still on both block grids are whole blocks of the record's grid, whose phase
moves when leading samples are dropped; a piece under :data:`STILL_MIN` plus one block is
64 samples or more on some phases and under 64 on others, where the still path read another
stretch instead (the union of the grids', the grid aligned with the record's end, the rest
to the sample), so the R to use came and went or moved with the phase (real_audit20's
cgm5: a 64-sample stretch, 32 samples with 1-3 dropped; docs/algorithms.md §E1 *A still
stretch at the minimum length*). Such a piece is read on that other stretch on every phase.
"""

from __future__ import annotations

from collections.abc import Callable

from numpy.typing import NDArray

from noisevar.diagnostics.profile import LevelProfile
from noisevar.estimators.still_extent import to_the_sample
from noisevar.estimators.still_grids import at_the_ends, grown_to_either
from noisevar.estimators.still_set import STILL_MIN


def phase_stable(
    pieces: list[tuple[int, int]],
    prof: LevelProfile,
    back: LevelProfile,
    read: Callable[[int, int], NDArray] | None,
    n: int,
) -> list[tuple[int, int]]:
    """The stretches still on both block grids, each that a grid phase can cut under
    :data:`STILL_MIN` read on a stretch the phase does not move.

    Parameters
    ----------
    pieces : list of (int, int)
        The stretches still on both grids (:func:`~noisevar.diagnostics.profile.on_both_grids`).
    prof, back : LevelProfile
        The record's profile and the reversed record's (its own sample indices).
    read : callable or None
        ``read(a, b)``: samples ``a .. b`` of the record (None: nothing is read to the sample).
    n : int
        Samples in the record.

    Returns
    -------
    list of (int, int)
        In order: each piece of at least :data:`STILL_MIN` samples plus one profile block as
        it is; each shorter one replaced by the stretch that holds it on the grid aligned
        with the record's end it touches (:func:`~.still_grids.at_the_ends`), else by the
        run of either grid's still stretches that holds it (:func:`~.still_grids.grown_to_either`),
        else, when that is under :data:`STILL_MIN`, by its run read to the sample
        (:func:`~.still_extent.to_the_sample`); a piece none of these makes long enough is
        left out.

    Notes
    -----
    docs/algorithms.md §E1 (*A still stretch at the minimum length*). The record's grid
    finds one block more or less of a rest as its phase moves, so a piece with a block to
    spare over :data:`STILL_MIN` stays long enough on every phase; a shorter one is read
    on what does not move with the phase (the end's own grid, the reversed grid laid from
    the record's end together with the record's, the samples), as it already was on the
    phases where it fell under :data:`STILL_MIN`.
    """
    if not pieces or not prof.start.size or not back.start.size:
        return pieces
    spare = STILL_MIN + int(prof.stop[0] - prof.start[0])
    out: list[tuple[int, int]] = []
    for piece in pieces:
        out += [piece] if piece[1] - piece[0] >= spare else _stable(piece, prof, back, read, n)
    return sorted(set(out))


def _stable(
    piece: tuple[int, int],
    prof: LevelProfile,
    back: LevelProfile,
    read: Callable[[int, int], NDArray] | None,
    n: int,
) -> list[tuple[int, int]]:
    """One short piece's stretch that no grid phase moves (:func:`phase_stable`)."""
    ends = at_the_ends([piece], prof, back, n)
    if ends != [piece]:
        return _long(ends)
    grown = _long(grown_to_either([piece], prof, back, n))
    return grown or to_the_sample([piece], prof, back, read, n)


def _long(ranges: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The ranges of at least :data:`STILL_MIN` samples."""
    return [(a, b) for a, b in ranges if b - a >= STILL_MIN]

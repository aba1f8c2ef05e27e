"""The diagnostics that come with every estimate."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics.glitches import Glitch
from noisevar.diagnostics.ma_fit import ma_fits
from noisevar.diagnostics.profile import LevelProfile
from noisevar.diagnostics.regimes import STILL, QuietLevel, StillLevel
from noisevar.diagnostics.segments import Gap
from noisevar.diagnostics.whiteness import (
    AR1_EVIDENCE,
    MA1_EXPLAINS,
    MA1_SHORT,
    MA1_SHORT_EXPLAINS,
    WhitenessTest,
)

#: A fitted noise correlation below this at some lag (differenced white noise: -1/2 at lag
#: 1; a central difference, -1/2 at lag 2) reads as differenced data; white noise gives 0,
#: and smooth coloured noise positive ones.
DIFFERENCED_LAG1 = -0.3


def _finite(x: float | None) -> float | None:
    return None if x is None or not np.isfinite(x) else float(x)


@dataclass(frozen=True)
class NoiseDiagnostics:
    """What a record's noise looks like, and whether a white-noise R describes it.

    Attributes
    ----------
    n : int
        Samples examined.
    whiteness : WhitenessTest
        The residual's autocorrelation against the white-noise null (docs/algorithms.md §E2).
    increments : WhitenessTest
        The same test on the first difference (white: the record is a random walk).
    kurtosis : float
        Kurtosis of the noise (3 for Gaussian).
    tail_index : float or None
        Hill's tail index of the residual (about ν for Student-t with ν dof).
    lsb : float or None
        Quantisation step when the samples sit on a grid, or on one that moves linearly
        (a trend added to a quantised record: its second differences keep the grid,
        docs/algorithms.md §E3 *Held values*); None off a grid.
    gaps : tuple of Gap
        Spliced or non-uniform places.
    jitter : float
        Largest relative deviation of the sampling period inside the uniform segments.
    level_profile : LevelProfile
        Noise level per block, with the quiet set.
    power_law : tuple of (int, int)
        ``(averaging factor, α)`` of the dominant power-law noise (allantools'
        identification; α = 2 white, 1 flicker, 0 random walk), only for coloured noise.
    still_whiteness : WhitenessTest or None
        The whiteness test on the still regimes' quiet blocks alone, when the level
        varies (None otherwise): white there and not over the whole record means motion
        leaking through, not coloured noise.
    still_increments : WhitenessTest or None
        The increments' whiteness test on the still stretches alone, when the level varies
        (None otherwise): a track that stops is a walk with its noise measurable where it
        stood; a walk of smaller steps there (a temperature at night) is not
        (:attr:`on_still`).
    other_still : tuple of StillLevel
        The near-still regimes' levels over the R to use, those whose interval lies above
        it (another posture, slow sway: docs/algorithms.md §E1 *Several still levels*);
        set by the estimate, which measures them with its own method.
    glitches : tuple of Glitch
        The lone outlying samples (``noisevar.diagnostics.glitches``): noise in R, read
        bridged by the level profile, named by the verdict.
    core_kurtosis : float or None
        The noise kurtosis with the lone glitches bridged (the profile blocks'): heavy
        tails beyond them are the noise's own, and the verdict says so, not the glitches.
    quiet : QuietLevel or None
        The quiet level on the same residual as R, or why there is none
        (docs/algorithms.md §E1 *The quiet level*); set by the estimate (None: diagnostics
        made without one, :func:`noisevar.diagnostics.diagnose`).
    verdict : str
        One plain sentence.
    notes : tuple of str
        Further plain remarks.
    """

    n: int
    whiteness: WhitenessTest
    increments: WhitenessTest
    kurtosis: float
    tail_index: float | None
    lsb: float | None
    gaps: tuple[Gap, ...]
    jitter: float
    level_profile: LevelProfile
    power_law: tuple[tuple[int, int], ...] = ()
    still_whiteness: WhitenessTest | None = None
    still_increments: WhitenessTest | None = None
    other_still: tuple[StillLevel, ...] = ()
    glitches: tuple[Glitch, ...] = ()
    core_kurtosis: float | None = None
    quiet: QuietLevel | None = None
    verdict: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def white(self) -> bool:
        """The noise passes the whiteness test (white noise passes 95 % of the time)."""
        return self.whiteness.white

    @property
    def acf(self) -> NDArray:
        """Autocorrelation of the residual at lags ``1..K``."""
        return self.whiteness.acf

    @property
    def heavy_tailed(self) -> bool:
        from noisevar.diagnostics.tails import heavy_tails

        return heavy_tails(self.kurtosis)

    @property
    def tails_beyond_glitches(self) -> bool:
        """Heavy-tailed even with the lone glitches bridged: the tails are the noise's."""
        from noisevar.diagnostics.tails import heavy_tails

        return heavy_tails(self.kurtosis if self.core_kurtosis is None else self.core_kurtosis)

    @property
    def fourth_moment_unreliable(self) -> bool:
        """The tails are so heavy that a variance interval cannot be trusted."""
        from noisevar.diagnostics.tails import unreliable_tail

        return self.heavy_tailed and unreliable_tail(self.tail_index)

    @property
    def quiet_variance(self) -> float | None:
        """Noise level of the still regimes, on the same residual as R; None when there is none.

        The estimate's :attr:`quiet` (``quiet.reason`` says why there is none). Diagnostics
        made without an estimate give the level profile's quiet level, on the diagnostics'
        own residual, which their verdict's level is measured on too.
        """
        if self.quiet is None:
            return self.level_profile.quiet_variance
        return self.quiet.variance

    @property
    def level_varies(self) -> bool:
        """The level changes along the record far more than its intervals allow.

        True when the record has a regime that is not still: a level above the lowest
        regime's beyond what its interval allows (:mod:`noisevar.diagnostics.regimes`).
        """
        return any(not r.still for r in self.level_profile.regimes)

    @property
    def level_changes(self) -> bool:
        """The level changes along the record, as the verdict says it: :attr:`level_varies`,
        or the estimate holds a still R apart from one regime (its quiet level is its
        ``.still``: ``estimators.still_set.has_still_apart``; a drive the jump detector
        leaves out, then parked). The flags' ``level_varies`` and the answer's."""
        return self.level_varies or (self.quiet is not None and self.quiet.source == STILL)

    @property
    def motion_explains_colour(self) -> bool:
        """The record is not white, but its still stretches are: motion leaks through."""
        w = self.still_whiteness
        return bool(not self.white and w is not None and w.white)

    @property
    def regimes(self) -> tuple:
        """Stretches of one noise level, in order (:mod:`noisevar.diagnostics.regimes`)."""
        return self.level_profile.regimes

    @property
    def differenced(self) -> bool:
        """The noise looks differenced: not white, with a correlation near -1/2 at a short lag.

        A record that is the difference of a noisy one (frequency from phase, velocity
        from positions) carries MA(1) noise of lag-1 correlation -1/2; a central
        difference (``np.gradient``) or a derivative filter, MA(q) noise negative at a
        lag up to 4 (docs/algorithms.md §E2): :attr:`noise_correlation` is not None, and
        the noise is not evidently AR(1) (:attr:`ar1_phi`). Below the evidence either way
        it may be both (:attr:`differenced_or_ar1`).
        """
        return bool(self.short_correlated and self.ar1_phi is None)

    @property
    def short_correlated(self) -> bool:
        """Not white, with a short-memory correlation R is corrected for to the variance
        per sample (:attr:`noise_correlation`): differenced data or AR(1) noise of negative φ."""
        return bool(not self.white and self.noise_correlation is not None)

    @property
    def noise_correlation(self) -> NDArray | None:
        """The noise's correlations ``r_1..r_q`` R is corrected for (None: none).

        The lag-1 fit (``whiteness.noise_lag1``) when it is below
        :data:`DIFFERENCED_LAG1`, unless the departure is an oscillation's
        (:meth:`_vibration_not_ma1`: a vibration near the Nyquist rate alternates in sign
        at every lag, and its lag-1 fit reads -0.56: docs/algorithms.md §E2 *Vibration*);
        AR(1) ones (``φ^k`` at every lag tested: ``whiteness.ar1_correlation``) when AR(1)
        noise is evident (:attr:`ar1_phi`; an MA(4) fit read φ = -0.7 26 % high);
        else the short-memory fit (``whiteness.short_memory``) when one of its
        correlations is.
        """
        w = self.whiteness
        lag1 = np.array([w.noise_lag1])
        if lag1[0] < DIFFERENCED_LAG1:
            if self._vibration_not_ma1(lag1):
                return None  # nor MA(q): a near-Nyquist vibration's MA(4) fit alternates too
            return w.ar1_correlation(w.acf.size) if self._ar1_evident() else lag1
        r = w.short_memory  # MA(q) noise that fits its own lags (not an oscillation's)
        return r if r is not None and float(r.min()) < DIFFERENCED_LAG1 and ma_fits(w, r) else None

    def refit_correlation(self, w: WhitenessTest) -> NDArray:
        """:attr:`noise_correlation`'s model (AR(1), else MA(q) of its size) fitted on
        another test ``w`` of the same lags: the jackknife's, with a block left out."""
        q = self.noise_correlation.size
        return w.ar1_correlation(q) if self.ar1_phi is not None else w.ma_fit(q)

    def _lag1_correlated(self) -> bool:
        """The lag-1 fit reads a short correlation (below :data:`DIFFERENCED_LAG1`) that no
        oscillation explains better."""
        lag1 = np.array([self.whiteness.noise_lag1])
        return bool(lag1[0] < DIFFERENCED_LAG1 and not self._vibration_not_ma1(lag1))

    def _vibration_not_ma1(self, lag1: NDArray) -> bool:
        """The departure is an oscillation's, not MA(1) noise's: an oscillation is the
        finding (:attr:`~.whiteness.Oscillation.found`), the MA(1) fit explains under
        :data:`~noisevar.diagnostics.whiteness.MA1_EXPLAINS` of it over every lag, and at
        the short lags
        (:data:`~noisevar.diagnostics.whiteness.MA1_SHORT`), where differenced noise departs
        at lag 1 alone, the MA(1) fit explains under
        :data:`~noisevar.diagnostics.whiteness.MA1_SHORT_EXPLAINS` of it. The fit's share
        over every lag is no evidence: a taxiing airliner's velocity from positions (motion
        at lags 7-9 and 15-17: the fit 13 %, an oscillation 75 %) is differenced, and its
        short lags are MA(1)'s (96 %)."""
        w = self.whiteness
        o = w.oscillation
        if o is None or not o.found or w.ma_left(lag1) <= 1.0 - MA1_EXPLAINS:
            return False
        return bool(w.ma_left(lag1, MA1_SHORT) > 1.0 - MA1_SHORT_EXPLAINS)

    def _ar1_evident(self) -> bool:
        """AR(1) noise of negative φ fits the departure better than MA(1) noise by
        :data:`~noisevar.diagnostics.whiteness.AR1_EVIDENCE`."""
        w = self.whiteness
        return bool(w.ar1[0] < 0 and w.ar1_evidence >= AR1_EVIDENCE)

    @property
    def ar1_phi(self) -> float | None:
        """φ of AR(1) noise the record's short correlation evidently is (None: not).

        Its lag-1 correlation reads as differenced data's, and from lag 2 on AR(1) noise
        (``φ^k``) fits better than MA(1) noise (0) by
        :data:`~noisevar.diagnostics.whiteness.AR1_EVIDENCE` (docs/algorithms.md §E2
        *Differenced or AR(1)*).
        """
        if self.white or not self._lag1_correlated() or not self._ar1_evident():
            return None
        return self.whiteness.ar1[0]

    @property
    def differenced_or_ar1(self) -> bool:
        """Differenced by its lag-1 correlation, but neither MA(1) nor AR(1) noise of
        negative φ fits evidently better: the record is too short to tell them apart."""
        w = self.whiteness
        lag1 = self.differenced and self._lag1_correlated()
        return bool(lag1 and w.ar1[0] < 0 and w.ar1_evidence > -AR1_EVIDENCE)

    @property
    def identifiable(self) -> bool:
        """False when the record behaves like a random walk (white first difference);
        True when its increments are too few to test."""
        return _measurable(self.increments)

    @property
    def still_a_walk(self) -> bool:
        """The still stretches' increments are white: there too the record is a walk (of
        smaller steps), no noise level; its still level only bounds the noise."""
        inc = self.still_increments
        return inc is not None and not _measurable(inc)

    @property
    def smoothed(self) -> WhitenessTest | None:
        """The test that reads the noise smoother than AR(1) noise can be
        (:attr:`~.whiteness.WhitenessTest.smoother_than_ar1`: a filter's smoothed output,
        or slow motion), else None: the still stretches' where the level varies (None when
        they are too short to test: the whole record's smoothness is then its motion's, a
        walking IMU's lag-1 +0.79 beside 2 % still), else the whole record's
        (docs/algorithms.md §E2 *Smoothed outputs*)."""
        w = self.still_whiteness if self.level_varies else self.whiteness
        return w if w is not None and w.smoother_than_ar1 else None

    @property
    def still_smoothed(self) -> WhitenessTest | None:
        """:attr:`smoothed` where the level varies (the still stretches' own test), else
        None: what makes a still R no R to use (``estimators.still_set.still_refusal``).

        Notes
        -----
        A record of one level is its own still R: its whole-record test reads its signal
        and rounding too (an ECG on a 0.001 grid, NN intervals), which the verdict does not
        call a smoothed output; its R keeps the assumption ``unsmoothed`` False instead.
        """
        return self.smoothed if self.level_varies else None

    @property
    def on_still(self) -> NoiseDiagnostics:
        """These diagnostics with the still stretches' increments for the record's: what
        the still R's interval rests on (:attr:`identifiable` there, not over the walk)."""
        inc = self.still_increments
        return self if inc is None else replace(self, increments=inc)

    @property
    def flags(self) -> dict[str, bool | None]:
        """The yes/no findings, for tables; None for what the record is too short to check
        (:func:`~noisevar.diagnostics.assumptions.unchecked`)."""
        from noisevar.diagnostics.assumptions import SHORT_RECORD

        white = self.whiteness.tested
        long = self.n >= SHORT_RECORD
        return {
            "white": self.white if white else None,
            "heavy_tailed": self.heavy_tailed if long else None,
            "quantised": self.lsb is not None,
            "gaps": bool(self.gaps),
            "level_varies": self.level_changes if long else None,
            "identifiable": self.identifiable if self.increments.tested else None,
            "differenced": self.differenced if white else None,
        }

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (no NaN or infinity)."""
        w = self.whiteness
        return {
            "verdict": self.verdict,
            "flags": self.flags,
            "white": self.white,
            "whiteness_p": _finite(w.p_value),
            "acf": w.acf.tolist(),
            "acf_white": w.expected.tolist(),
            "acf_band": w.band.tolist(),
            "lag1_excess": _finite(w.lag1),
            "noise_lag1": _finite(w.noise_lag1),
            "noise_correlation": None
            if (r := self.noise_correlation) is None
            else [_finite(x) for x in r],
            "kurtosis": _finite(self.kurtosis),
            "tail_index": _finite(self.tail_index),
            "lsb": _finite(self.lsb),
            "gaps": [g.to_dict() for g in self.gaps],
            "jitter": _finite(self.jitter),
            "quiet_variance": _finite(self.quiet_variance),
            "quiet_share": _finite(self.level_profile.quiet_share),
            "quiet_level": None if self.quiet is None else self.quiet.to_dict(),
            "level_profile": self.level_profile.to_dict(),
            "power_law": [list(p) for p in self.power_law],
            "other_still_levels": [x.to_dict() for x in self.other_still],
            "glitches": [g.to_dict() for g in self.glitches],
            "notes": list(self.notes),
        }


def _measurable(inc: WhitenessTest) -> bool:
    """Noise measurable apart from a walk: increments too few to test, not white, or of a
    lag-1 correlation towards white noise's own (-0.5)."""
    return bool(not inc.tested or not inc.white or inc.lag1 < -0.1)

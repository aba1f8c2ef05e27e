"""Parts of the verdict that stand alone: the other still levels' clause and fields, the
sentence on a record whose R is a few glitches, the sentence on differenced data and the
one on a random walk (:mod:`noisevar.diagnostics.verdict` joins them)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from noisevar.diagnostics.power_law import WHITE
from noisevar.diagnostics.regimes import STILL_RATIO
from noisevar.format import eng

#: R over the core variance above which the outlying samples hold nearly all of R (over
#: 90 %): on a record whose level varies they, not the level, are then the finding when the
#: bulk without them rests at the still level (:func:`glitches_lead`). traffic's ADS-B
#: altitude: 13,153x, from 2.2 % of the samples (benchmarks/real_audit9.py).
GLITCHES_DOMINATE = 10.0
#: At most this share of outlying samples is "some" glitches (garbled or spoofed values).
OUTLIERS_SOME = 0.05
#: A regime louder than the still level over more blocks than this is motion, not glitches:
#: a lone glitch raises the blocks its smoother reaches, a held or garbled stretch a few
#: (measured: the ADS-B altitude's longest 1 block, the seeded reproducer's 150 held samples
#: 4; a 1,500-sample motion burst 25, SURFRAD's irradiance by day 14).
MOTION_BLOCKS = 8
#: A core variance more than this many times below the quiet level is no still level: on a
#: grid the core reads below it (the seeded reproducer 0.48x, the ADS-B altitude 0.58x: noise
#: under the step), far below it the quiet level is something else (MIDC's CHP1 temperature
#: 1e-8x, its samples mostly the held missing code; MIDC's accumulated PSP 0.07-0.08x).
CORE_BELOW = 4.0
#: The first clause of every sentence on a level that changes: which kind (no quiet
#: stretch, none quieter than R, mostly motion, a quiet level to use) is said after it.
#: The kind rests on the quiet set's share and level, which the block grid's phase moves:
#: SURFRAD's wind less 0-3 samples had 51, 38, 47, 43 % quiet (13, 4, 11, 10 quiet blocks on
#: its own grid, 10 on the reversed one), and its first clause flipped at half (issue 26).
CHANGES = "the noise level changes along the record"
#: The quiet stretches cover less than this share: the record is mostly motion.
MOSTLY_MOTION = 0.5
#: A whiteness test failed at a p-value above this, with no colour named, is a weak finding.
WEAK_P = 0.01
#: The lead of a level that changes where the still stretches are coloured about as much as
#: the whole record (:func:`colour_in_still`): both findings, the level's first (its
#: finding is :data:`CHANGES`), so the lead does not hang on the still level's ratio to R.
BOTH = f"{CHANGES}, and the noise is coloured even in its still stretches"
#: The finding of a record whose R is nearly all a few outlying samples.
GLITCHES_HOLD = "a few outlying samples hold nearly all of R"

if TYPE_CHECKING:
    from noisevar.diagnostics.regimes import StillLevel
    from noisevar.diagnostics.results import NoiseDiagnostics
    from noisevar.diagnostics.whiteness import Oscillation, WhitenessTest

#: What a still level adds where the still stretches are a walk too (white increments).
STILL_WALK = (
    "; but there the record behaves like a random walk of small steps (its first "
    "difference is white): no noise can be told apart from it, so this level only bounds "
    "the noise from above (record the sensor at rest to measure it)"
)

#: What to do with an oscillation the verdict names (:func:`oscillation_words`).
OSC_TO_DO = (
    "notch or low-pass it out before the filter (a filter that sees it takes it for "
    "noise), or model it as a state"
)


def still_level_fields(level: StillLevel, n: int) -> dict[str, str]:
    """A near-still regime's stretch, share, level and interval, as every page says them.

    Parameters
    ----------
    level : StillLevel
        One of ``NoiseDiagnostics.other_still``.
    n : int
        Samples in the record.

    Returns
    -------
    dict
        ``stretch`` ("samples 300-5400"), ``share`` of the record ("76%"), ``level`` and
        its ``ci95`` as multiples of the R to use ("2.20x", "1.95-2.48x").
    """
    return {
        "stretch": f"samples {level.start}-{level.stop}",
        "share": f"{(level.stop - level.start) / max(n, 1):.0%}",
        "level": f"{level.ratio:.2f}x",
        "ci95": f"{level.lo:.2f}-{level.hi:.2f}x",
    }


def other_still_clause(diag: NoiseDiagnostics) -> str:
    """What the other still levels add to the verdict ('' when there is none).

    Each near-still regime whose level, measured as the R to use is, lies above it
    (docs/algorithms.md §E1 *Several still levels*): the R to use stays the floor.
    """
    if not diag.other_still:
        return ""
    said = "; ".join(
        f"{f['stretch']} ({f['share']} of the record) at {f['level']} (ci95 {f['ci95']})"
        for f in (still_level_fields(x, diag.n) for x in diag.other_still)
    )
    own = ", the sensor's own noise," if not_at_rest(diag) is None else ""
    return (
        f". Other still stretches rest at a higher level on the same residual: {said}: "
        f"another posture, or slow sway; the still level above is the floor{own} and a "
        "filter that runs through those stretches without modelling that motion needs "
        "their level"
    )


def differenced_verdict(diag: NoiseDiagnostics, r: str) -> str:
    """The verdict on short-correlated noise (``diag.short_correlated``): MA(1) (a
    difference), AR(1) of negative φ (:attr:`~.results.NoiseDiagnostics.ar1_phi`), either
    when the record cannot tell them apart, or MA(q) (a derivative filter)."""
    corr = diag.noise_correlation
    if diag.ar1_phi is not None:
        phi = diag.ar1_phi
        return (
            f"the noise is AR(1) noise of φ = {phi:+.2f}: its correlation alternates and decays "
            f"(lag 1 {phi:+.2f}, lag 2 {phi**2:+.2f}, where differenced data give -0.5 and 0), "
            "so the data are not differenced; its power rises towards the Nyquist rate, as a "
            "vibration spread near it does (rotors); "
            f"{r} is the variance per sample, but successive errors are correlated: model "
            "AR(1) measurement noise (a state), or whiten the measurements (z_k - φ z_{k-1}), "
            "or low-pass a vibration out before the filter"
        )
    if diag.differenced_or_ar1:
        return (
            "the data look differenced (a frequency from phase, a velocity from positions), "
            f"or the noise is AR(1) noise of negative φ: the noise's lag-1 correlation is "
            f"{corr[0]:+.2f}, which both give (the difference of white noise -0.5); they differ "
            "from lag 2 on, and this record is too short to tell them apart (a longer one "
            f"would); {r} is the variance per sample, but successive errors are correlated: "
            "if the data are a difference, filter the undifferenced quantity (its R is about "
            "half this) or model MA(1) measurement noise; if not, model AR(1) measurement noise"
        )
    if corr.size == 1:
        return (
            "the data look differenced (a frequency from phase, a velocity from positions): "
            f"the noise's lag-1 correlation is {corr[0]:+.2f}, as the difference of white "
            f"noise gives (-0.5); {r} is the variance per sample, but successive errors are "
            "correlated: filter the undifferenced quantity (its R is about half this) or "
            "model MA(1) measurement noise"
        )
    lag = int(np.argmin(corr)) + 1
    return (
        "the data look differenced (a velocity from positions by a central difference or a "
        f"derivative filter): the noise's correlation at lag {lag} is {corr[lag - 1]:+.2f} "
        f"(np.gradient's central difference gives -0.5 at lag 2); {r} is the variance per "
        "sample, but errors up to "
        f"{corr.size} samples apart are correlated: filter the undifferenced quantity or "
        f"model MA({corr.size}) measurement noise"
    )


def glitches_lead(
    diag: NoiseDiagnostics, variance: float, core: float | None, outliers: float
) -> bool:
    """Whether some outlying samples hold nearly all of R of a record whose level varies
    only by them: the verdict's finding (:func:`glitches_verdict`).

    Decided on evidence: at most :data:`OUTLIERS_SOME` of the samples, R over
    :data:`GLITCHES_DOMINATE` times the core variance, and the core (the record without
    them) at the still level, as a still regime is (at most
    :data:`~noisevar.diagnostics.regimes.STILL_RATIO` times it, at least a
    :data:`CORE_BELOW`-th of it): without them the level
    does not change; and no regime louder than that longer than :data:`MOTION_BLOCKS`
    blocks (a burst of motion, which R's method may follow). A bulk louder than that
    (ADS-B positions spoofed for a while, 4.2x;
    SURFRAD's solar irradiance by day against its nights, 4-6x) keeps the level change the
    finding, and the verdict names the outlying samples after it. The still level's upper
    95 % bound is no measure here: SURFRAD's quiet set read 0.004 then 0.04 with 2 samples
    dropped, and the finding flipped.
    """
    if core is None or not 0 < outliers <= OUTLIERS_SOME or not variance > GLITCHES_DOMINATE * core:
        return False
    if not diag.level_varies:
        return False
    prof, quiet = diag.level_profile, diag.quiet_variance
    quiet = prof.quiet_variance if quiet is None else quiet
    block = float(np.median(prof.stop - prof.start)) if prof.start.size else 1.0
    loud = [
        r.stop - r.start for r in diag.regimes if not r.still and r.variance > STILL_RATIO * quiet
    ]
    at_still = quiet / CORE_BELOW <= core <= STILL_RATIO * quiet
    return bool(at_still and max(loud, default=0) <= MOTION_BLOCKS * block)


def glitches_verdict(r: str, core: str, held: tuple[str, str], level: str) -> str:
    """The verdict of a record whose R is nearly all a few outlying samples
    (:func:`glitches_lead`): said first, with the level without them and the R to use.

    ``r``: R as the verdict says it; ``core``: the core variance; ``held``: the outlying
    samples' share of the record and of R; ``level``: the quiet level's clause, or ''.
    """
    return (
        f"{GLITCHES_HOLD}: {held[0]} of the samples are outlying (garbled, spoofed or held "
        f"values, or short bursts) and hold {held[1]} of {r}; without them the record is of "
        f"one level, the core variance {core}{level}. R counts them as noise, as a plain "
        "Kalman filter needs; if they are not the sensor's noise, reject them (a gate on the "
        "innovations) and use the core variance, or a robust filter"
    )


#: An oscillation at this share of the sample rate or above is at the Nyquist rate itself
#: (period 2.0 samples, as said; the fit's frequency step is 0.002): what a record whose
#: every other sample repeats the one before gives, its signal a staircase of two-sample
#: steps (a Polar M400's altitude, read at 0.5 Hz and written at 1 Hz:
#: benchmarks/real_audit11.py). A rotor's lines lie below it (EuRoC's hexacopter: 0.47-0.49).
HELD_PAIRS = 0.495


def oscillation_words(o: Oscillation) -> str:
    """An oscillation the whiteness test found (:attr:`~.whiteness.WhitenessTest.oscillation`),
    as the verdict says it: its frequency as a share of the sample rate and its period.

    A vibration (rotors, motors, a gait) or a periodic signal: its correlation alternates in
    sign lag after lag, which no low-pass or difference of white noise does
    (docs/algorithms.md §E2 *Vibration*). The record's rate is not known here: the share
    times the rate in Hz is its frequency. At the Nyquist rate itself (:data:`HELD_PAIRS`)
    it may be values held for two samples, said first.
    """
    held = (
        "values held for two samples (every other sample repeating the one before: a sensor "
        "read at half the record's rate; keep one sample in two), "
        if o.frequency >= HELD_PAIRS
        else ""
    )
    return (
        f"an oscillation at {o.frequency:.2f} of the sample rate (period "
        f"{1.0 / o.frequency:.1f} samples): {held}a vibration (rotors, motors, a gait) or a "
        "periodic signal, not white sensor noise"
    )


def found_oscillation(w: WhitenessTest | None) -> Oscillation | None:
    """The oscillation of a failed whiteness test that is its finding, or None."""
    if w is None or w.white:
        return None
    o = w.oscillation
    return o if o is not None and o.found else None


def departure_cause(w: WhitenessTest, k: int) -> str:
    """What a still stretch's departure from white noise at lag ``k + 1`` may be.

    A positive correlation is what a sensor's low-pass gives; a negative one no low-pass
    gives (EuRoC's hexacopter's still stretches: lag-3 -0.34, said "low-passed by the
    sensor"): an oscillation, or motion left in the stretches.
    """
    if w.acf[k] - w.expected[k] < 0:
        return "a vibration, or motion left in the stretches"
    return "low-passed by the sensor, or slow motion left in the stretches"


#: The still stretches share the record's oscillation (:func:`still_oscillation`) when theirs
#: is at a frequency this close to it (relative) and explains at least
#: :data:`SHARED_EXPLAINS` of their departure from white noise, more than a low-pass does:
#: the record's oscillation is then the evidence, which their shorter test alone may not
#: reach (the legged robot's acc_z: 0.13 against 0.124 of the rate, 56 % of its still
#: stretches' departure, a low-pass 5 %; AR(1) still noise beside oscillating bursts: a
#: low-pass explains more, and it is not called an oscillation).
SHARED_FREQUENCY = 0.15
SHARED_EXPLAINS = 0.5


def still_oscillation(diag: NoiseDiagnostics) -> Oscillation | None:
    """The oscillation the still stretches' own noise carries (None: none found).

    Their own (:func:`found_oscillation`), or the whole record's when theirs is at the same
    frequency (:data:`SHARED_FREQUENCY`) and explains at least :data:`SHARED_EXPLAINS` of
    their departure, more than a low-pass (``low_pass``). A still stretch of a walking robot
    (a slower phase of the gait) or of a sensor at rest on a running machine carries the
    gait's or the machine's oscillation: its level is then an upper bound on the sensor's
    noise, not its level at rest
    (docs/algorithms.md §E2 *Vibration*).
    """
    w = diag.still_whiteness
    own = found_oscillation(w)
    whole = found_oscillation(diag.whiteness)
    if own is not None or whole is None or w is None or w.white:
        return own
    o = w.oscillation
    if o is None or abs(o.frequency - whole.frequency) > SHARED_FREQUENCY * whole.frequency:
        return None
    return o if o.explains >= SHARED_EXPLAINS and o.explains > o.low_pass else None


def upper_bound_words(o: Oscillation, named: bool = False) -> str:
    """What a still level that carries an oscillation is (:func:`still_oscillation`);
    ``named``: the sentence has named the record's oscillation already."""
    which = "that oscillation too" if named else oscillation_words(o)
    to_do = "" if named else f": {OSC_TO_DO}"
    return (
        "an upper bound on the sensor's noise, not its level at rest: the still stretches "
        f"carry {which} (a slower phase of a gait, or a machine running){to_do}"
    )


def to_use_words(diag: NoiseDiagnostics, named: bool = False) -> str:
    """How the verdict names a still level it quotes: "the R to use", an upper bound, or
    what a smoothed output's or a moving signal's quietest stretches read
    (:func:`not_at_rest`)."""
    o = still_oscillation(diag)
    if o is not None:
        return upper_bound_words(o, named)
    rest = not_at_rest(diag)
    return "the R to use" if rest is None else f"not the R to use{rest}"


def not_at_rest(diag: NoiseDiagnostics) -> str | None:
    """Why the still stretches do not measure the sensor at rest, as a clause (None: they
    may), beyond a walk (:data:`STILL_WALK`) and an oscillation (:func:`still_oscillation`).

    Smoothed (:attr:`~.results.NoiseDiagnostics.smoothed`): the noise is smoother than a
    sensor's own low-pass leaves it, so the level is neither the sensor's noise nor the
    output's variance per sample. Moving: a record mostly in motion (quiet stretches under
    :data:`MOSTLY_MOTION` of it) whose still stretches depart from white noise as the whole
    record does (its autocorrelation explains :data:`SHARED_EXPLAINS` of theirs, the whole
    record failing too): the same process, quieter, the quietest part of a signal that
    never stops moving (calm wind), so their level only bounds the noise, as a walk of
    smaller steps does. A record mostly still is the sensor at rest, its louder stretches
    the same noise louder (AR(1) noise 2.5x over 35 %: tests/diagnostics/
    test_level_before_colour.py); docs/algorithms.md §E2 *Smoothed outputs*, *Calm stretches*.
    """
    if (w := diag.smoothed) is not None:
        return (
            "; but there the noise is smoother than a sensor's own low-pass leaves it "
            f"(lag-1 autocorrelation {w.acf[0]:+.2f}, where noise through a first-order "
            f"low-pass gives at most {w.ar1_limit:+.2f}"
            "): a filter's smoothed output (an RTK or INS solution, a running average), "
            "whose sensor noise the record does not hold, or slow motion, which bounds it "
            "from above; this level is not the output's variance per sample either (the "
            f"residual sees under {w.seen_share():.0%} of it): not an R to use; take R "
            "from the raw measurements or the solver's own variance"
        )
    if diag.level_profile.quiet_share >= MOSTLY_MOTION:  # mostly still: the sensor's rest
        return None
    shared = shared_colour(diag)  # the whole record's share of their departure
    if shared is None or shared < SHARED_EXPLAINS:
        return None
    return (
        "; but there the noise is correlated as over the whole record (its autocorrelation "
        f"explains {shared:.0%} of theirs): the quietest stretches of a "
        "signal that never stops moving, not the sensor at rest, so this level only bounds "
        "the noise from above (record the sensor at rest to measure it)"
    )


def walk_verdict(r: str, stood: tuple[float, str, str] | None, measured: bool) -> str:
    """The verdict of a record that behaves like a random walk (white first difference).

    ``stood``: its still stretches' share, level and what that level adds (a track that
    stops: where it stood still its noise is measured apart, the R to use), or None.
    ``measured``: their increments are not white. Where they are, the still stretches are
    a walk too, of smaller steps (a temperature at night): their level only bounds the
    noise (:data:`STILL_WALK`), never "the R to use".
    """
    lead = (
        "the record behaves like a random walk (its first difference is white): no "
        f"measurement noise can be told apart from it, so {r} is not a noise level; "
        "model the walk as a state (see the noise model)"
    )
    if stood is None:
        return lead
    share, level, said = stood
    if not measured:
        return f"{lead}; its still stretches ({share:.0%} of it) give {level}{said}"
    return (
        f"{lead}; its still stretches ({share:.0%} of it) give {level}: the noise where "
        f"it stood still, the R to use{said}"
    )


def none_quieter(r: str, quiet: float, diag: NoiseDiagnostics | None = None) -> str:
    """The verdict of a varying level whose quietest stretches, as the level profile reads
    them (indicative: no still R), are not below R: nothing quieter to quote as the sensor's.
    With ``diag``, its quiet level's reason is said when its still stretches are held values
    (:attr:`~noisevar.diagnostics.regimes.QuietLevel.held`)."""
    why = " (spikes or held values, not a sensor at rest)"
    level = None if diag is None else diag.quiet
    if level is not None and level.held:
        why = f", and {level.reason}"
    return (
        f"{CHANGES}: {r} is an average, and no stretch of it "
        "is measurably quieter: the level profile's quietest stretches read "
        f"{eng(quiet)}, not below R{why}, so R over the whole record is the only level measured"
    )


def level_changes(
    share: float, r: str, quiet: float, said: str, moved: str = "", lead: str = CHANGES
) -> str:
    """The verdict of a record whose level varies: R an average (``moved``: where it moved
    too fast to measure, :func:`moved_clause`), the quiet level to use; ``lead``: its first
    clause (:data:`BOTH` where the still stretches are as coloured: :func:`colour_in_still`)."""
    return (
        f"{lead}: {r} is an average{moved}; its quiet stretches ({share:.0%}) give "
        f"{eng(quiet)}{said}"
    )


def moved_clause(diag: NoiseDiagnostics) -> str:
    """Where the record moved too fast to measure (``LevelProfile.unmeasured``: every
    residual left out around level jumps), as a clause; '' where nowhere."""
    runs = diag.level_profile.unmeasured
    if not runs:
        return ""
    where = ", ".join(f"{a}-{b}" for a, b in runs[:3]) + (", ..." if len(runs) > 3 else "")
    return f" (samples {where} move too fast to measure, left out around level jumps)"


def rounding_clause(r: str, lsb: float, variance: float) -> str:
    """What R (``r``, its text) holds of the rounding error lsb²/12 of a grid of step ``lsb``.

    Notes
    -----
    docs/algorithms.md §E3: where the signal crosses the steps too slowly, the rounding
    error is a bias that follows it, which auto does not correct; R is then under lsb²/12
    (a USGS pH record on a 0.1 grid, changing in 1.9 % of its samples: R 56.4×10⁻⁶, 15x
    under it, said to "include" it, benchmarks/real_audit19.py). The error a filter reading
    the values sees is R + lsb²/12 (the loader's note), said with R's number.
    """
    q = lsb * lsb / 12.0
    if variance >= q:
        return f"{r} includes the rounding error lsb²/12 = {eng(q)}"
    return (
        f"{r} is under the rounding error lsb²/12 = {eng(q)} and leaves it out (the signal "
        "crosses the steps too slowly to tell it from a bias that follows the signal): a "
        f"filter reading these values sees R + lsb²/12 = {eng(variance + q)}"
    )


def colour_in_still(diag: NoiseDiagnostics) -> bool:
    """Whether the still stretches are coloured about as much as the whole record: both
    fail the whiteness test (the whole record's not weakly: :func:`weak_colour`; nor by an
    oscillation, its own finding), and the whole record's autocorrelation explains at least
    :data:`SHARED_EXPLAINS` of the still stretches' departure from white noise
    (:func:`shared_colour`, the measure :func:`not_at_rest` reads "correlated as over the
    whole record" on).

    The regimes then do not explain the colour: a still R apart from R makes the level
    change a finding and the colour another, said together (:data:`BOTH`), whatever the
    still level's ratio to R, which dropping a sample moves across a cut (real_audit18's
    Totem GR: 1.89-3.07x; watch_ride's v_north: its interval's top under R or not); docs/
    algorithms.md §E2. Not a test of equal lag-1 autocorrelations: on Bartlett's spread
    Totem's still stretches are measurably less coloured (lag-1 0.966 against 0.979, z 3-7
    over 28,000 samples), which says the two differ, not that the regimes explain the colour.
    """
    w = diag.whiteness
    if w.white or found_oscillation(w) is not None or weak_colour(diag):
        return False
    shared = shared_colour(diag)
    return shared is not None and shared >= SHARED_EXPLAINS


def shared_colour(diag: NoiseDiagnostics) -> float | None:
    """The share of the still stretches' departure from white noise that the whole record's
    autocorrelation explains (None: either tests white, or theirs is not tested)."""
    s, whole = diag.still_whiteness, diag.whiteness
    if s is None or not s.tested or s.white or whole.white:
        return None
    return 1.0 - s.left(whole.acf)


def weak_colour(diag: NoiseDiagnostics) -> bool:
    """Whether the whole record's departure from white noise is a weak finding: no colour
    named by the power law (:attr:`~.results.NoiseDiagnostics.power_law`) and a whiteness
    test failed at a p-value of :data:`WEAK_P` or more (white noise gives such a p-value 1
    time in ``1/p``, 1 in 20 at most)."""
    named = any(alpha != WHITE for _, alpha in diag.power_law)
    return not named and diag.whiteness.p_value >= WEAK_P

"""Whiteness of the noise seen through a residual filter (docs/algorithms.md §E2).

The residual ``e = d * z`` of a local-polynomial fit is not white even when the noise
is: on white noise its autocorrelation is that of ``d``, known exactly. The test
compares the measured autocorrelation at lags ``1..K`` with that null, weighted by
Bartlett's covariance of sample autocorrelations, so that it is calibrated at any
kurtosis of an iid noise.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property, lru_cache

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_sf
from noisevar.numeric.fir import lagged_products

#: Most lags tested (a record of :data:`WHITE_FULL` residuals or more).
WHITE_LAGS = 20
#: Fewest lags tested; residuals per lag tested (:func:`white_lags`).
WHITE_LAGS_MIN = 3
WHITE_PER_LAG = 15
#: Residuals (kept) at which all :data:`WHITE_LAGS` lags are tested.
WHITE_FULL = WHITE_LAGS * WHITE_PER_LAG
#: Fewest kept residuals for the test: fewer, and it is not made (``tested`` False).
WHITE_MIN = 24
#: Eigenvalues of Bartlett's covariance below this fraction of the largest are left out.
WHITE_EIG_FLOOR = 0.02
#: Significance level of the whiteness test.
WHITE_ALPHA = 0.05
#: Lags of the residual's autocorrelation that the noise's lag-1 correlation is fitted on.
MA1_LAGS = 3
#: Lags of correlation of short-memory noise (a difference over k samples, a derivative
#: filter: ``np.gradient``'s central difference is -1/2 at lag 2) fitted when lag 1 alone
#: does not say it (:attr:`WhitenessTest.short_memory`).
MA_ORDER = 4
#: Share of the residual's departure from white noise (over every lag tested) that such a
#: fit must explain; a vibration leaking through the smoother (its correlation lasts at
#: every lag) explains 15-25 %, derivative filters 86-99 % (docs/algorithms.md §E2).
MA_EXPLAINS = 0.75
#: Lags the MA(1) fit must explain most of the departure on (:meth:`WhitenessTest.ma_left`
#: with ``lags``): differenced noise departs at lag 1 alone, so over lags 1-5 its fit
#: leaves little (measured: np.diff of white noise 0.3-16 %, with a slow signal and a burst
#: up to 32 %; a taxiing airliner's velocity from positions 4 %), while a vibration near the
#: Nyquist rate alternates at every lag (EuRoC's hexacopter ADIS16448: 60-82 % left, a
#: sinusoid of period 2.1 samples 72-78 %).
MA1_SHORT = MA1_LAGS + 2
#: Share of the departure over the first :data:`MA1_SHORT` lags the MA(1) fit must
#: explain for the record to be differenced rather than vibrating (both above).
MA1_SHORT_EXPLAINS = 0.5
#: ... and over every lag tested (:meth:`WhitenessTest.ma_left`): np.diff of white noise
#: 48-99 % (300 samples with a burst of motion and a slow signal: 48 %; 20,000 samples:
#: 98-99 %), a sinusoid of period 2.1 samples in white noise 8-9 %, EuRoC's hexacopter
#: 14-38 %; AR(1) noise, whose power rises to the Nyquist rate, 40-64 % at φ = -0.7 (an
#: oscillation 1 time in 20) and 26-47 % at φ = -0.8 (an oscillation 37 times in 40: seeds
#: 20000-20019 at 1,000 and 5,000 samples; docs/algorithms.md §E2 *Differenced or AR(1)*).
MA1_EXPLAINS = 0.45
#: Evidence (a difference of χ²-like misfits, :attr:`WhitenessTest.ar1_evidence`) for
#: AR(1) noise of negative φ against MA(1) noise at which one is told from the other: the
#: two share a lag-1 correlation of -1/2 at φ = -1/2 and differ from lag 2 on (+1/4 against
#: 0). Measured over seeded records (docs/algorithms.md §E2 *Differenced or AR(1)*).
AR1_EVIDENCE = 25.0
#: Decays per lag of the oscillation fitted to the residual's departure
#: (:attr:`WhitenessTest.oscillation`): a vibration's correlation lasts many cycles (the
#: fit's share on them: 0.86-0.99); a faster decay fits the residual filter's response to
#: low-passed noise as well (a 2nd-order Butterworth at 0.3: 0.86-0.99 at a decay of 0.8).
OSC_DECAYS = (1.0, 0.95)
#: Fewest periods of an oscillation inside the lags tested: a slower one cannot be told
#: from low-frequency noise shaped by the residual filter (positive, then negative lags).
OSC_PERIODS = 2.0
#: Share of the residual's departure from white noise an oscillation must explain to be
#: the finding: measured, vibrations 0.86-0.99 (EuRoC's hexacopter at 0.48 of the sample
#: rate, a legged robot at 0.12, sinusoids in white noise); low-passed, AR(1) and
#: differenced noise 0.14-0.74 (docs/algorithms.md §E2 *Vibration*).
OSC_EXPLAINS = 0.8
#: Evidence (:attr:`Oscillation.apart`) that an oscillation near the Nyquist rate lies
#: below it: the misfit of a damped resonance plus white noise fitted through the residual
#: filter at the Nyquist rate itself (AR(1) noise of negative φ plus white noise, whose
#: power rises to it) less that at the best frequency near the oscillation's, in units of
#: that AR(1) noise's spread of sample autocorrelations. Measured (seeds 20000-20099,
#: 300-5,000 samples, the records whose oscillation passes the other counts): AR(1) noise
#: of φ = -0.6 up to 23, -0.7 28, -0.8 64, -0.9 57; sinusoids of amplitude 0.7 in unit
#: white noise at 0.47 of the rate 38-103 at 300 samples, 141-359 at 1,000; values held
#: for two samples 94-130; EuRoC's hexacopter acc_z 82 (docs/algorithms.md §E2 *Vibration*).
OSC_APART = 70.0
#: Resonance fits (:meth:`WhitenessTest.resonance`): frequencies either side of the
#: oscillation's (cycles per sample), and the grids of radius and of the resonant share.
RES_REACH = 0.05
RES_FREQUENCIES = 51
RES_RADII = np.linspace(0.0, 1.0, 41)
RES_SHARES = np.linspace(0.02, 1.0, 50)
#: The AR(1) fit's grid of φ, refined to :data:`AR1_STEP` about its best point.
AR1_GRID = np.round(np.linspace(-0.95, 0.95, 39), 2)
AR1_STEP = 0.001


@dataclass(frozen=True)
class Oscillation:
    """An oscillation in the noise's autocorrelation (:attr:`WhitenessTest.oscillation`).

    Attributes
    ----------
    frequency : float
        Cycles per sample (x the sample rate: Hz), up to 0.5.
    explains : float
        The share of the residual's departure from white noise it explains.
    low_pass : float
        The share AR(1) noise of the best φ in [0, 0.95] explains, seen through the
        residual filter (:meth:`WhitenessTest.low_pass`).
    returns : bool
        The departure two periods on (the lag nearest ``2 / frequency``) is positive beyond
        its 95 % band: the correlation comes back, as a vibration's does and the residual
        filter's response to low-passed noise (a negative lobe, then none) does not.
    apart : float
        Evidence (χ² units) that its frequency is told from the Nyquist rate, where AR(1)
        noise of negative φ peaks (:meth:`WhitenessTest.resonance`); infinite when not
        measured (an oscillation that is no finding on the other counts).
    """

    frequency: float
    explains: float
    low_pass: float = 0.0
    returns: bool = True
    apart: float = float("inf")

    @property
    def found(self) -> bool:
        """The finding: it explains at least :data:`OSC_EXPLAINS` of the departure, more
        than noise low-passed by the sensor does (``low_pass``), it ``returns``, and it is
        ``apart`` from the Nyquist rate by :data:`OSC_APART` (not AR(1) noise of negative φ)."""
        near = self.explains >= OSC_EXPLAINS and self.explains > self.low_pass
        return near and self.returns and self.apart >= OSC_APART


@dataclass(frozen=True)
class WhitenessTest:
    """The residual's autocorrelation against the white-noise null.

    Attributes
    ----------
    acf : ndarray, shape (K,)
        Measured autocorrelation at lags ``1..K``.
    expected : ndarray, shape (K,)
        Its value for white noise (the residual filter's own autocorrelation).
    band : ndarray, shape (K,)
        95 % half-width around ``expected`` for each lag under the null.
    statistic : float
        ``n (r - ρ)' W⁻¹ (r - ρ)``, about χ²(K) for white noise.
    p_value : float
    n : int
        Residuals the test was made on.
    tested : bool
        False when they are fewer than :data:`WHITE_MIN`: no test was made (the
        measured autocorrelation is then the null's, ``p_value`` 1: no evidence either way).
    white : bool
        ``p_value >= WHITE_ALPHA``.
    """

    acf: NDArray
    expected: NDArray
    band: NDArray
    statistic: float
    p_value: float
    n: int = 0
    tested: bool = True

    @property
    def white(self) -> bool:
        return bool(self.p_value >= WHITE_ALPHA)

    @property
    def lag1(self) -> float:
        """The lag-1 autocorrelation of the noise, read off the residual's excess."""
        return float(self.acf[0] - self.expected[0])

    @property
    def noise_lag1(self) -> float:
        """The noise's lag-1 correlation ``r``, fitted as MA(1) noise through the residual filter.

        Notes
        -----
        docs/algorithms.md §E2: noise of autocorrelation ``(1, r, 0, ...)`` seen through a
        filter of autocorrelation ``α`` gives a residual of autocorrelation
        ``ρ_k = (α_k + r (α_{k-1} + α_{k+1})) / (1 + 2 r α_1)``, linear in ``r`` once
        multiplied out; ``r`` is its least-squares solution over lags ``1..MA1_LAGS``
        (0 for white noise, -1/2 for differenced white noise).
        """
        k = min(MA1_LAGS, self.acf.size - 1)
        alpha = np.r_[1.0, self.expected[: k + 1]]  # α_0..α_{k+1}
        rho = self.acf[:k]
        c = alpha[:k] + alpha[2 : k + 2] - 2.0 * alpha[1] * rho
        y = rho - alpha[1 : k + 1]
        den = float(c @ c)
        return float(c @ y / den) if den > 0 else 0.0

    @property
    def short_memory(self) -> NDArray | None:
        """The noise's correlations ``r_1..r_q`` (``q`` up to :data:`MA_ORDER`), fitted as
        MA(q) noise through the residual filter, when that explains at least
        :data:`MA_EXPLAINS` of the residual's departure from white noise; else None.

        Notes
        -----
        docs/algorithms.md §E2: noise of autocorrelation ``(1, r_1, .., r_q, 0, ...)``
        seen through a filter of autocorrelation ``α`` gives a residual of autocorrelation
        ``ρ_k = (α_k + Σ_j r_j (α_{|k-j|} + α_{k+j})) / (1 + 2 Σ_j r_j α_j)``, linear in
        ``r`` once multiplied out: least squares over lags ``1..q+2``. The departure is
        ``Σ_k ((acf_k - model_k) / band_k)²`` over every lag tested, against the same sum
        for white noise.
        """
        q = min(MA_ORDER, self.acf.size - 2)
        if q < 1 or not self.tested:
            return None
        c, y, _, _ = self._ma_design(q)
        r = np.linalg.lstsq(c, y, rcond=None)[0]
        return r if self.ma_left(r) <= 1.0 - MA_EXPLAINS else None

    def ma_left(self, r: NDArray, lags: int | None = None) -> float:
        """The share of the residual's departure from white noise that MA(q) noise of
        correlations ``r`` (``q = r.size``) leaves unexplained (1 when there is none).

        Parameters
        ----------
        r : ndarray, shape (q,)
        lags : int, optional
            Measure over lags ``1..lags`` only (default: every lag tested).

        Notes
        -----
        ``Σ_k ((acf_k - model_k) / band_k)²`` over the lags, over the same sum for
        white noise (:attr:`short_memory`'s measure).
        """
        r = np.atleast_1d(np.asarray(r, dtype=float))
        _, _, pair, alpha = self._ma_design(r.size)
        j = np.arange(1, r.size + 1)
        model = (alpha[1 : self.acf.size + 1] + pair @ r) / (1.0 + 2.0 * float(r @ alpha[j]))
        return self.left(model, lags)

    def left(self, model: NDArray, lags: int | None = None) -> float:
        """The share of the residual's departure from white noise that the autocorrelation
        ``model`` (at the lags tested) leaves unexplained (1 when there is none):
        :meth:`ma_left`'s measure, for any model (another test's measured ``acf``)."""
        white = float(self._misfit(self.expected, lags))
        return float(self._misfit(model, lags)) / white if white > 0 else 1.0

    @property
    def smoother_than_ar1(self) -> bool:
        """The residual is smoother than AR(1) noise of any φ can make it: its lag-1
        autocorrelation, less its band, above what AR(1) noise of the fit's largest φ
        (:data:`AR1_GRID`) gives through the residual filter.

        Notes
        -----
        docs/algorithms.md §E2 *Smoothed outputs*. A sensor's own low-pass (first order,
        AR(1) noise) raises the residual's lag-1 autocorrelation towards a limit as φ nears
        1 (+0.46 for ``auto``'s filter, +0.462 at φ = 0.95): the filter's zeros at DC leave
        the band just above them. Noise past that limit has less power at high frequencies
        than any first-order low-pass leaves (a filter's smoothed output, whose state
        model rolls its noise off faster, or slow motion): the residual then sees a share
        of its variance per sample that no white or AR(1) reading recovers.
        """
        if not self.tested or self.white:
            return False
        return bool(self.acf[0] - self.band[0] > self.ar1_limit)

    @property
    def ar1_limit(self) -> float:
        """The residual's lag-1 autocorrelation for AR(1) noise of the fit's largest φ."""
        return float(self._ar1_models(AR1_GRID[-1:])[0, 0])

    def seen_share(self) -> float:
        """The share of AR(1) noise's variance per sample the residual sees at the fit's
        largest φ (:data:`AR1_GRID`): more than noise smoother than that leaves it
        (:attr:`smoother_than_ar1`)."""
        m = np.abs(np.arange(-self.acf.size, self.acf.size + 1))
        return float(AR1_GRID[-1] ** m @ np.r_[1.0, self.expected][m])

    def _misfit(self, model: NDArray, lags: int | None = None) -> NDArray | float:
        """``Σ_k ((acf_k - model_k) / band_k)²`` over the lags tested, or lags
        ``1..lags`` (each row of a 2-D ``model``); lags with no band count for nothing."""
        scale = np.where(self.band > 0, self.band, np.inf)
        x = ((self.acf - model) / scale)[..., :lags]
        return np.sum(x**2, axis=-1)

    @cached_property
    def ar1(self) -> tuple[float, float]:
        """The AR(1) noise (φ from -0.95 to 0.95) that best explains the residual's
        departure from white noise, seen through the residual filter: ``(φ, misfit)``.

        Notes
        -----
        Noise of autocorrelation ``φ^|m|`` through a filter of autocorrelation ``α`` gives a
        residual of autocorrelation ``Σ_m α_m φ^|k-m|`` over its lag-0 value; ``α`` beyond
        the lags tested is taken as 0 (exact when they reach the filter's span). The misfit
        is :meth:`ma_left`'s sum.
        """
        misfit = self._misfit(self._ar1_models(AR1_GRID))
        i = int(np.argmin(misfit))
        step = float(AR1_GRID[1] - AR1_GRID[0])
        lo, hi = max(AR1_GRID[i] - step, AR1_GRID[0]), min(AR1_GRID[i] + step, AR1_GRID[-1])
        phi = np.linspace(lo, hi, int(round((hi - lo) / AR1_STEP)) + 1)
        misfit = self._misfit(self._ar1_models(phi))
        i = int(np.argmin(misfit))
        return float(phi[i]), float(misfit[i])

    def ar1_correlation(self, lags: int) -> NDArray:
        """The correlations ``φ^1..φ^lags`` of the AR(1) noise :attr:`ar1` fits."""
        return self.ar1[0] ** np.arange(1, lags + 1)

    def _ar1_models(self, phi: NDArray) -> NDArray:
        """The residual's autocorrelation at lags ``1..K`` for AR(1) noise of each ``φ``."""
        k, m = np.arange(self.acf.size + 1), np.arange(-self.acf.size, self.acf.size + 1)
        am = np.r_[1.0, self.expected][np.abs(m)]
        rho = (phi[:, None, None] ** np.abs(k[:, None] - m[None, :])) @ am
        return rho[:, 1:] / rho[:, :1]

    @cached_property
    def ar1_evidence(self) -> float:
        """Evidence for AR(1) noise over MA(1) noise: the best MA(1) fit's misfit less the
        best AR(1) fit's, in χ² units (positive: AR(1) fits better).

        Notes
        -----
        docs/algorithms.md §E2 *Differenced or AR(1)*: both one-parameter shapes, fitted by
        weighted least squares over a grid (MA(1): ``r`` from -1 to 1, a shape, not only an
        invertible process: a differenced record's sample lag-1 correlation goes below
        -1/2), each misfit ``Σ_k ((acf_k - model_k) / (band_k / 1.96))²`` over every lag
        tested. MA(1) noise departs at lag 1 alone, AR(1) noise at every lag by ``φ^k``.
        """
        r = np.linspace(-1.0, 1.0, 201)
        _, _, pair, alpha = self._ma_design(1)
        ma = alpha[1 : self.acf.size + 1] + r[:, None] * pair[:, 0]
        ma /= 1.0 + 2.0 * r[:, None] * alpha[1]
        ma_misfit = float(np.min(self._misfit(ma)))
        return (ma_misfit - self.ar1[1]) * 1.96**2

    @cached_property
    def oscillation(self) -> Oscillation | None:
        """The slowly decaying oscillation ``a λ^k cos(2π f k)`` that best explains the
        residual's departure from white noise (a vibration, a periodic signal), or None
        when the lags tested hold fewer than :data:`OSC_PERIODS` periods of any.

        Notes
        -----
        docs/algorithms.md §E2 *Vibration*: a weighted least-squares fit (weights the
        null's band) of the departure ``acf - expected`` over a grid of frequencies
        ``f`` from ``OSC_PERIODS / K`` to 0.5 cycles per sample and decays ``λ`` in
        :data:`OSC_DECAYS`; ``explains`` is the share of the departure it explains.
        """
        k = np.arange(1, self.acf.size + 1)
        low = OSC_PERIODS / k.size
        if not self.tested or low >= 0.5:
            return None
        scale = np.where(self.band > 0, self.band, np.inf)
        x = (self.acf - self.expected) / scale
        total = float(x @ x)
        if total <= 0:
            return None
        f = np.linspace(low, 0.5, 200)
        lam = np.asarray(OSC_DECAYS)
        basis = lam[:, None, None] ** k * np.cos(2 * np.pi * f[None, :, None] * k) / scale
        num = (basis @ x) ** 2
        share = num / np.maximum(np.sum(basis**2, axis=-1), 1e-300) / total
        i = np.unravel_index(int(np.argmax(share)), share.shape)
        lag = min(int(round(2.0 / f[i[1]])), k.size) - 1  # two periods on (f >= 2 / K)
        back = bool(self.acf[lag] - self.expected[lag] >= self.band[lag])
        o = Oscillation(float(f[i[1]]), float(share[i]), self.low_pass(), back)
        if o.explains < OSC_EXPLAINS or o.explains <= o.low_pass or not back:
            return o  # no finding: the resonance fits are not needed
        near = np.linspace(max(o.frequency - RES_REACH, low), 0.5, RES_FREQUENCIES)
        ar1, radius, share = self.resonance(np.array([0.5]), AR1_GRID[AR1_GRID >= 0])
        # in the spread of the sample autocorrelation of that AR(1) noise (Bartlett's
        # 1 + 2 Σ g(m)², over white noise's): its lags err together, and far more
        spread = 1.0 + 2.0 * share**2 * radius**2 / (1.0 - radius**2)
        return replace(o, apart=(ar1 - self.resonance(near, RES_RADII)[0]) / spread)

    def resonance(self, f: NDArray, radii: NDArray) -> tuple[float, float, float]:
        """The damped resonance plus white noise at the frequencies ``f`` and radii
        ``radii`` that best fits the residual's autocorrelation through the residual
        filter: ``(misfit, ϱ, c)``, the misfit in χ² units.

        Notes
        -----
        docs/algorithms.md §E2 *Vibration*: noise of autocorrelation
        ``c ϱ^|m| cos(2π f m)`` (``m ≠ 0``; 1 at lag 0) through a filter of autocorrelation
        ``α`` gives a residual of autocorrelation ``Σ_m α_m g(k - m)`` over its lag-0
        value; ``c`` over :data:`RES_SHARES`. At ``f = 1/2`` it is AR(1) noise of
        ``φ = -ϱ`` plus white noise; a sinusoid plus white noise is ``ϱ = 1``. The misfit
        is :attr:`ar1_evidence`'s.
        """
        size = self.acf.size
        k, m = np.arange(size + 1), np.arange(-size, size + 1)
        am = np.r_[1.0, self.expected][np.abs(m)]
        lag = np.abs(k[:, None] - m[None, :])
        g = radii[None, :, None, None] ** lag * np.cos(2 * np.pi * f[:, None, None, None] * lag)
        rho = (g @ am)[:, :, None, :]  # (f, ϱ, 1, lags 0..K) for c = 1
        c = RES_SHARES[None, None, :, None]
        model = c * rho + (1.0 - c) * am[size:]
        misfit = self._misfit(model[..., 1:] / model[..., :1])
        i = np.unravel_index(int(np.argmin(misfit)), misfit.shape)
        return float(misfit[i]) * 1.96**2, float(radii[i[1]]), float(RES_SHARES[i[2]])

    def low_pass(self) -> float:
        """The share of the residual's departure from white noise that AR(1) noise (a
        sensor's low-pass, φ from 0 to 0.95) explains at best, seen through the residual
        filter.

        Notes
        -----
        :attr:`ar1`'s models, over φ >= 0 only.
        """
        model = self._ar1_models(np.linspace(0.0, 0.95, 20))
        white = float(self._misfit(self.expected))
        return float(1.0 - np.min(self._misfit(model)) / white) if white > 0 else 0.0

    def ma_fit(self, q: int) -> NDArray:
        """The noise's correlations ``r_1..r_q`` fitted as MA(q) noise, whether or not
        the fit explains the residual (``q = 1``: :attr:`noise_lag1`, over its lags).

        Parameters
        ----------
        q : int
            The order: the size of :attr:`~noisevar.diagnostics.NoiseDiagnostics.noise_correlation`.

        Returns
        -------
        ndarray, shape (q,)

        Notes
        -----
        The fit :attr:`noise_lag1` and :attr:`short_memory` make, refitted on another
        ``acf`` (the differenced interval's block jackknife, docs/algorithms.md §E2).
        """
        if q == 1:
            return np.array([self.noise_lag1])
        c, y, _, _ = self._ma_design(q)
        return np.linalg.lstsq(c, y, rcond=None)[0]

    def _ma_design(self, q: int) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """The linear system ``c r = y`` of the MA(q) fit over lags ``1..q+2`` (at most
        those tested), the pair sums ``α_{|k-j|} + α_{k+j}`` at every lag, and ``α``."""
        alpha = np.r_[1.0, self.expected, np.zeros(q + 1)]  # α_0..α_K, 0 beyond the filter
        k = np.arange(1, self.acf.size + 1)
        j = np.arange(1, q + 1)
        pair = alpha[np.abs(k[:, None] - j[None, :])] + alpha[k[:, None] + j[None, :]]
        fit = slice(0, min(q + 2, self.acf.size))
        c = pair[fit] - 2.0 * self.acf[fit, None] * alpha[j][None, :]
        return c, self.acf[fit] - alpha[k[fit]], pair, alpha


def _null_acf(d: NDArray, reach: int) -> NDArray:
    """Autocorrelation ``ρ(m)`` of the sequence ``d`` for ``m = -reach..reach``."""
    full = np.correlate(d, d, mode="full") / np.dot(d, d)  # lags -(L-1)..L-1
    out = np.zeros(2 * reach + 1)
    half = d.size - 1
    out[reach - half : reach + half + 1] = full
    return out


@lru_cache(maxsize=16)
def _bartlett(d_key: tuple[float, ...], lags: int) -> tuple[NDArray, NDArray]:
    """Null ACF at lags ``1..K`` and Bartlett's covariance ``W`` of ``sqrt(n) r_k``."""
    d = np.asarray(d_key)
    reach = d.size + 2 * lags
    rho = _null_acf(d, reach)
    m = np.arange(-reach + lags, reach - lags + 1)  # inner sum index, shifts stay in range

    def r(idx: NDArray) -> NDArray:
        return rho[idx + reach]

    k = np.arange(1, lags + 1)
    plus = r(m[None, :] + k[:, None])  # ρ(m + k)
    minus = r(m[None, :] - k[:, None])  # ρ(m - k)
    r0 = r(m)
    rk = r(k)
    # W_kl = Σ_m ρ(m+k)ρ(m+l) + ρ(m-k)ρ(m+l) + 2ρ(k)ρ(l)ρ(m)² - 2ρ(k)ρ(m)ρ(m+l) - 2ρ(l)ρ(m)ρ(m+k)
    w = plus @ plus.T + minus @ plus.T
    w += 2.0 * np.outer(rk, rk) * np.sum(r0**2)
    cross = plus @ r0
    w -= 2.0 * (np.outer(rk, cross) + np.outer(cross, rk))
    return rk, 0.5 * (w + w.T)


def _pair_counts(keep: NDArray, lags: int) -> NDArray:
    """Pairs ``(i, i + k)`` with both kept, for ``k = 0..lags``, from the runs of ``keep``.

    Exact when the runs of left-out samples are at least ``lags`` long (the separators
    between segments), and a close count otherwise.
    """
    edges = np.flatnonzero(np.diff(np.r_[0, keep.view(np.int8), 0]))
    runs = edges[1::2] - edges[::2]  # lengths of the kept runs
    k = np.arange(lags + 1)
    return np.maximum(runs[None, :] - k[:, None], 0).sum(axis=1).astype(float)


def sample_acf(e: NDArray, lags: int, keep: NDArray | None = None) -> NDArray:
    """Autocorrelation of ``e`` at lags ``1..lags``; samples where ``keep`` is False are left out.

    Parameters
    ----------
    e : ndarray, shape (n,)
    lags : int
    keep : ndarray of bool, optional
        Samples to use (pairs with a left-out member do not count).

    Returns
    -------
    ndarray, shape (lags,)
    """
    x = e - np.mean(e if keep is None else e[keep])
    n = x.size
    if keep is not None:
        x = np.where(keep, x, 0.0)
        count = _pair_counts(keep, lags)
    else:
        count = n - np.arange(lags + 1.0)
    # γ_k = Σ x_i x_{i+k} / (pairs at lag k)
    gamma = lagged_products(x, lags) / np.maximum(count, 1.0)
    with np.errstate(invalid="ignore", divide="ignore"):  # no variation: NaN, refused after
        return gamma[1:] / gamma[0]


def white_lags(n: int) -> int:
    """Lags tested on ``n`` residuals: one per :data:`WHITE_PER_LAG`, from
    :data:`WHITE_LAGS_MIN` to :data:`WHITE_LAGS`.

    Notes
    -----
    Bartlett's covariance is asymptotic: with 20 lags the test rejected white noise 51 %
    of the time on 28 residuals, 17 % on 60 and 10 % on 130 (5 % asked); with a lag per
    15 residuals, 3-7 % (``tests/diagnostics/test_short_records.py``).
    """
    return int(np.clip(n // WHITE_PER_LAG, WHITE_LAGS_MIN, WHITE_LAGS))


def whiteness_test(
    e: NDArray,
    d: NDArray,
    lags: int | None = None,
    keep: NDArray | None = None,
    inflation: float = 1.0,
) -> WhitenessTest:
    """Test whether the noise behind the residual ``e = d * z`` is white.

    Parameters
    ----------
    e : ndarray, shape (n,)
        Residual of the filter ``d``.
    d : ndarray
        The residual filter.
    lags : int, optional
        Lags ``1..lags`` tested; default :func:`white_lags` of the kept residuals.
    keep : ndarray of bool, optional
        Samples to use.
    inflation : float
        Factor on the null covariance (a noise level that changes along the record:
        ``n Σσ⁴ / (Σσ²)²``).

    Returns
    -------
    WhitenessTest
        Not ``tested`` on fewer than :data:`WHITE_MIN` kept residuals.

    Notes
    -----
    docs/algorithms.md §E2: ``Q = n (r - ρ)' W⁻¹ (r - ρ)`` with ``W`` from Bartlett's
    formula for the linear process ``d * v``; ``Q`` is about χ²(K) when ``v`` is iid.
    """
    from noisevar.errors import NoisevarError

    n = int(e.size if keep is None else np.count_nonzero(keep))
    lags = white_lags(n) if lags is None else lags
    rho, w = _bartlett(tuple(np.asarray(d, dtype=float)), lags)
    band = 1.96 * np.sqrt(np.diag(w) / max(n, 1))
    if n < WHITE_MIN:  # too few to test (none: every residual touches an edge)
        return WhitenessTest(rho.copy(), rho, band, 0.0, 1.0, n, tested=False)
    w = w * inflation
    r = sample_acf(e, lags, keep)
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(w))):
        raise NoisevarError("the residual is degenerate (no variation to correlate)")
    lam, u = np.linalg.eigh(w)
    # directions where W is near singular (the residual filter's spectral zeros pin them)
    # carry finite-sample bias, not information: leave them out
    use = lam > WHITE_EIG_FLOOR * lam[-1]
    proj = u[:, use].T @ (r - rho)
    # Q = n (r - ρ)' W⁺ (r - ρ), over the well-conditioned directions
    q = float(n * np.sum(proj**2 / lam[use]))
    p = chi2_sf(q, int(np.count_nonzero(use)))
    return WhitenessTest(r, rho, band, q, p, n)

"""GMWM numerics for speed (issue 30): analytic Jacobians, the wavelet variance pyramid."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm import wavelet
from noisevar.noise_model.gmwm.processes import PROCESSES

TAU = 2.0 ** np.arange(1, 23)
CASES = [
    ("WN", [3.0]),
    ("QN", [2.0]),
    ("RW", [1e-3]),
    ("DR", [1e-6]),
    ("FL", [0.5]),
    ("GM", [2.0, 0.7]),
    ("GM", [2.0, 5.0]),
    ("GM", [2.0, 300.0]),
    ("GM", [1.0, 3e6]),
]


def _central(key: str, p: np.ndarray, i: int, step: float = 1e-4) -> np.ndarray:
    up, down = np.log(p), np.log(p)
    up[i] += step
    down[i] -= step
    wv = PROCESSES[key].wv
    return (wv(np.exp(up), TAU) - wv(np.exp(down), TAU)) / (2.0 * step)


@pytest.mark.parametrize(("key", "p"), CASES)
def test_process_jacobian_matches_central_differences(key: str, p: list[float]) -> None:
    p = np.array(p)
    jac = PROCESSES[key].jac(p, TAU)
    assert jac.shape == (p.size, TAU.size)
    for i in range(p.size):
        num = _central(key, p, i)
        # central differences are good to about 1e-8 of the largest derivative here
        assert np.max(np.abs(jac[i] - num)) <= 1e-7 * np.max(np.abs(num))


def test_model_jacobian_stacks_the_processes() -> None:
    keys = ("QN", "WN", "GM", "GM", "RW")
    p = np.array([0.1, 2.0, 1.0, 4.0, 0.5, 900.0, 1e-5])
    jac = est.model_jac(keys, p, TAU)
    assert jac.shape == (TAU.size, p.size)
    assert jac[:, 2] == pytest.approx(PROCESSES["GM"].jac(p[2:4], TAU)[0], rel=1e-14)
    assert jac[:, 5] == pytest.approx(PROCESSES["GM"].jac(p[4:6], TAU)[1], rel=1e-14)


def _direct_wv(row: np.ndarray, t: int) -> float:
    """The Haar wavelet variance by its definition: each coefficient's two half-sums."""
    x = row - row.mean()
    h = t // 2
    w = [(x[k + h : k + t].sum() - x[k : k + h].sum()) / t for k in range(x.size - t + 1)]
    return float(np.mean(np.square(w)))


@pytest.mark.parametrize("block", [7, 64, 2**16])
def test_blocked_wavelet_variance_matches_its_definition(
    block: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(wavelet, "BLOCK", block)
    rng = np.random.default_rng(3)
    x = np.cumsum(rng.standard_normal((301, 3)), axis=0) + 5.0  # (n, axes): rows strided
    tau = wavelet.dyadic_scales(x.shape[0])
    nu, m = wavelet.haar_wv(np.moveaxis(x, 0, -1), tau)
    assert m == pytest.approx(x.shape[0] - tau + 1)
    for i in range(x.shape[1]):
        want = [_direct_wv(x[:, i], int(t)) for t in tau]
        assert nu[i] == pytest.approx(want, rel=1e-10)


def test_haar_wv_asks_for_dyadic_scales() -> None:
    with pytest.raises(NoisevarError, match="powers of two"):
        wavelet.haar_wv(np.ones((1, 64)), np.array([2.0, 6.0]))


@pytest.mark.parametrize("block", [16, 64, 2**10])
@pytest.mark.parametrize("n", [33, 301, 5000])
def test_fused_levels_give_the_same_numbers(
    block: int, n: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The first levels fused tile by tile give the level-by-level sums to the last bit."""
    monkeypatch.setattr(wavelet, "BLOCK", block)
    rng = np.random.default_rng(n)
    rows = np.moveaxis(np.cumsum(rng.standard_normal((n, 2)), axis=0) + 3.0, 0, -1)
    tau = wavelet.dyadic_scales(n)
    fused = wavelet.haar_wv(rows, tau)[0]
    monkeypatch.setattr(wavelet, "FUSED_SHARE", 2 * block)  # nothing fused
    assert np.array_equal(fused, wavelet.haar_wv(rows, tau)[0])

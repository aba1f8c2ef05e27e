"""Records read in chunks give the one-pass estimate and diagnostics (issue 17, item 2)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import noisevar
from noisevar.errors import NoisevarError
from noisevar.estimators.auto import AUTO_BLOCK
from noisevar.estimators.auto.chunked import chunks
from noisevar.stream import estimate_chunked, estimate_file


def _ar(rng: np.random.Generator, n: int, phi: float) -> np.ndarray:
    from scipy.signal import lfilter

    return lfilter([1.0], [1.0, -phi], rng.standard_normal(n))


def _families() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(17)
    n = 40_000
    t = np.arange(n)
    smooth = 20 * np.sin(t / 400)
    jumps = rng.standard_normal(n)
    # level jumps and spikes on and next to chunk boundaries (chunks of 4096 below)
    for k in (4096, 8192 - 1, 12288 + 1, 20480):
        jumps[k:] += 25.0
    spikes = smooth + rng.standard_normal(n)
    spikes[[4095, 4096, 8191, 16384, 16385]] += 60.0
    return {
        "white": smooth + rng.standard_normal(n),
        "jumps": jumps,
        "spikes": spikes,
        "t3": smooth + rng.standard_t(3, n),
        "quantised": np.round(smooth + 2 * rng.standard_normal(n)),
        "coloured": _ar(rng, n, 0.7),
        "level_steps": smooth + rng.standard_normal(n) * np.where(t < n // 2, 1.0, 3.0),
        "huge": (smooth + rng.standard_normal(n)) * 1e120,
        "tiny": (smooth + rng.standard_normal(n)) * 1e-140,
        "odd_length": (smooth + rng.standard_normal(n))[: n - 77],
        # differenced noise: R's interval is a block jackknife read block by block
        "differenced": smooth + np.diff(rng.standard_normal(n + 1)),
        "derivative": smooth + np.convolve(rng.standard_normal(n + 4), [1, 1, 0, -1, -1], "valid"),
    }


def _streamed(z: np.ndarray, chunk: int = 4096, workers: int = 2) -> noisevar.VarianceEstimate:
    return estimate_chunked(
        lambda a, b: z[max(a, 0) : b].copy(), z.size, probe=z.__getitem__, chunk=chunk,
        workers=workers,
    )  # fmt: skip


@pytest.mark.parametrize("family", sorted(_families()))
def test_chunked_equals_one_pass(family: str) -> None:
    z = _families()[family]
    one = noisevar.estimate(z)
    many = _streamed(z)
    np.testing.assert_allclose(many.variance, one.variance, rtol=1e-9)
    np.testing.assert_allclose(many.core_variance, one.core_variance, rtol=1e-9)
    np.testing.assert_allclose(many.ci95, one.ci95, rtol=1e-9)
    np.testing.assert_allclose(many.dof, one.dof, rtol=1e-9)
    assert many.n_used == one.n_used and many.n_total == one.n_total
    assert many.outlier_fraction == one.outlier_fraction
    a, b = one.diagnostics, many.diagnostics
    np.testing.assert_allclose(b.kurtosis, a.kurtosis, rtol=1e-9)
    np.testing.assert_allclose(b.whiteness.p_value, a.whiteness.p_value, rtol=1e-6, atol=1e-300)
    np.testing.assert_allclose(b.quiet_variance, a.quiet_variance, rtol=1e-9)
    assert b.lsb == a.lsb and b.flags == a.flags and b.verdict == a.verdict
    assert many.notes[1:] == one.notes  # the first says it was streamed


def test_threads_and_chunk_sizes_agree() -> None:
    z = _families()["spikes"]
    ref = _streamed(z, chunk=4096, workers=1)
    for chunk, workers in ((512, 2), (8192 * 3, 2), (1 << 18, 3)):
        r = _streamed(z, chunk=chunk, workers=workers)
        np.testing.assert_allclose(r.variance, ref.variance, rtol=1e-12)
        np.testing.assert_allclose(r.diagnostics.kurtosis, ref.diagnostics.kurtosis, rtol=1e-12)


@settings(max_examples=60)
@given(st.integers(600, 200_000), st.integers(2, 64))
def test_chunks_tile_the_record_on_the_block_grid(n: int, blocks: int) -> None:
    cs = chunks(n, blocks * AUTO_BLOCK)
    assert cs[0].lo == 0 and cs[-1].hi == n
    for c, d in zip(cs, cs[1:], strict=False):
        assert c.hi == d.lo and c.lo % AUTO_BLOCK == 0 and c.hi % AUTO_BLOCK == 0
    for c in cs:
        assert c.wa <= c.lo < c.hi <= c.wb and c.wa % AUTO_BLOCK == 0
        # the record's last block takes the rest: no chunk ends inside it
        assert c.hi == n or c.hi <= (n // AUTO_BLOCK - 1) * AUTO_BLOCK


def test_files_npy_raw_csv(tmp_path) -> None:
    rng = np.random.default_rng(3)
    z = 5 * np.sin(np.arange(30_000) / 300) + rng.standard_normal(30_000)
    one = noisevar.estimate(z)
    np.save(tmp_path / "a.npy", z)
    table = np.column_stack([np.zeros_like(z), z])
    np.save(tmp_path / "c.npy", table)
    np.save(tmp_path / "f.npy", np.asfortranarray(table))
    table.astype("<f8").tofile(tmp_path / "r.bin")
    np.savetxt(tmp_path / "t.csv", table, delimiter=";", header="zero;v", comments="")
    for path, kw in (
        ("a.npy", {}),
        ("c.npy", {"column": 1}),
        ("f.npy", {"column": 1}),
        ("r.bin", {"dtype": "<f8", "column": "1/2"}),
        ("t.csv", {"column": "v"}),
    ):
        r = estimate_file(tmp_path / path, chunk=4096, **kw)
        np.testing.assert_allclose(r.variance, one.variance, rtol=1e-9, err_msg=path)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: np.save(p / "x.npy", np.r_[np.ones(5000), np.nan]), "non-finite"),
        (lambda p: np.save(p / "x.npy", np.zeros((10, 3, 2))), "shape"),
        (lambda p: np.save(p / "x.npy", np.zeros(5000, dtype="c16")), "integers or floats"),
        (lambda p: np.save(p / "x.npy", np.full(5000, 2.0)), "constant"),
    ],
)
def test_bad_files_give_one_clear_error(tmp_path, make, message) -> None:
    make(tmp_path)
    with pytest.raises(NoisevarError, match=message):
        estimate_file(tmp_path / "x.npy", chunk=1024)


def test_raw_file_of_the_wrong_size(tmp_path) -> None:
    (tmp_path / "x.bin").write_bytes(b"\0" * 4099)
    with pytest.raises(NoisevarError, match="whole number"):
        estimate_file(tmp_path / "x.bin", dtype="<f4")


def test_cli_streams(tmp_path) -> None:
    rng = np.random.default_rng(4)
    z = np.sin(np.arange(20_000) / 300) + 0.1 * rng.standard_normal(20_000)
    np.save(tmp_path / "a.npy", z)
    run = [sys.executable, "-m", "noisevar", "estimate", str(tmp_path / "a.npy")]
    out = subprocess.run([*run, "--stream", "--format", "json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    import json

    got = json.loads(out.stdout)
    assert got["variance"] == pytest.approx(noisevar.estimate(z).variance, rel=1e-9)
    bad = subprocess.run([*run, "--stream", "--method", "rice"], capture_output=True, text=True)
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1


def test_a_long_record_in_memory_is_estimated_in_chunks_with_the_same_numbers() -> None:
    from noisevar.estimators.auto import auto_estimate
    from noisevar.estimators.pipeline import CHUNKED_MIN

    rng = np.random.default_rng(8)
    n = CHUNKED_MIN + 1234
    z = np.sin(np.arange(n) / 5000) + 0.1 * rng.standard_normal(n)
    z[n // 3 :] += 2.0  # a jump
    got = noisevar.estimate(z)
    one = auto_estimate(z)  # one pass, no diagnostics
    assert got.notes[0].startswith("estimated in chunks")
    np.testing.assert_allclose(got.variance, one.variance, rtol=1e-9)
    np.testing.assert_allclose(got.core_variance, one.core_variance, rtol=1e-9)
    assert got.n_used == one.n_used and got.diagnostics is not None


def test_strided_block_medians_keep_a_white_record_steady(monkeypatch) -> None:
    """Blocks longer than MEDIAN_MAX take the median of strided squares, with their dof."""
    from noisevar.diagnostics import plan

    monkeypatch.setattr(plan, "MEDIAN_MAX", 64)  # blocks of 1,000 squares: stride 16
    rng = np.random.default_rng(21)
    z = np.sin(np.arange(200_000) / 20_000) + 0.1 * rng.standard_normal(200_000)
    diag = noisevar.estimate(z).diagnostics
    assert not diag.level_varies and diag.level_profile.quiet_share > 0.95
    assert "white Gaussian noise" in diag.verdict


def test_profile_bounds_stay_finite_on_blocks_of_few_dof() -> None:
    """Very heavy tails or a block emptied by jumps: the lower χ² quantile underflows."""
    from noisevar.diagnostics.profile import profile_from_blocks

    one = np.ones(2)
    prof = profile_from_blocks(
        np.array([0, 50]), np.array([50, 100]), np.array([1.0, 50.0]), one, one, 1e-3, 1.0
    )
    assert np.all(np.isfinite(prof.hi)) and np.all(prof.hi >= prof.variance)


def test_a_2d_npy_without_a_column_streams_its_first_as_in_memory(tmp_path) -> None:
    x = np.random.default_rng(8).normal(size=(5000, 3)) * [1.0, 2.0, 3.0]
    np.save(tmp_path / "x.npy", x)
    got = estimate_file(tmp_path / "x.npy", chunk=1024)
    assert got.variance == pytest.approx(noisevar.estimate(x[:, 0]).variance, rel=1e-9)

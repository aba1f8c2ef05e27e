"""Lean imports (issue 15's sub-second refusal, issue 17's memory): ``import noisevar`` and
the estimate path leave the heavy libraries unloaded; the lazy public names still work;
the CLI refuses an oversized file before it imports them; the scipy.special forms give
scipy.stats' numbers."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy import signal, stats

from noisevar import _distributions as dist
from noisevar.estimators.auto import residual_sequence
from noisevar.io.limits import MAX_BYTES, check_size

ROOT = Path(__file__).resolve().parents[1]
#: Never imported by ``import noisevar``, by ``noisevar.estimate`` (auto, diagnostics on),
#: nor by ``noisevar estimate FILE.npy``.
FORBIDDEN = (
    "pandas",
    "pyarrow",
    "allantools",
    "statsmodels",
    "dask",
    "plotly",
    "scipy.stats",
    "scipy.signal",
)


def _run_python(code: str, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code), *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=env,
        timeout=300,
        check=False,
    )


def _loaded_after(code: str, *args: str) -> dict:
    """Run ``code`` in a fresh interpreter; the forbidden modules it left loaded, and more."""
    probe = (
        textwrap.dedent(code)
        + f"\nimport json, sys\nFORBIDDEN = {FORBIDDEN!r}\n"
        + "print(json.dumps({'loaded': [m for m in FORBIDDEN if m in sys.modules], "
        + "'numpy': 'numpy' in sys.modules, 'out': globals().get('OUT')}))\n"
    )
    done = _run_python(probe, *args)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_import_noisevar_loads_no_third_party_library():
    seen = _loaded_after("import noisevar")
    assert seen["loaded"] == []
    assert not seen["numpy"]


def test_estimate_with_diagnostics_loads_none_of_the_heavy_libraries():
    seen = _loaded_after(
        """
        import numpy as np
        import noisevar
        rng = np.random.default_rng(5)
        z = np.ones(4000) + rng.normal(0, 0.5, 4000)
        est = noisevar.estimate(z)
        both = noisevar.estimate(np.stack([z, 2 * z]), axis=-1)
        OUT = [est.variance, est.ci95[0], est.diagnostics.white, list(both.variance)]
        """
    )
    assert seen["loaded"] == []
    variance, low, white, both = seen["out"]
    assert 0.2 < variance < 0.3 and 0 < low < variance
    assert white
    assert both[1] == pytest.approx(4 * both[0], rel=1e-12)


def test_coloured_noise_loads_none_of_the_heavy_libraries():
    # the power-law identification (diagnostics/power_law.py) is allantools' equations
    # vectorised: naming a coloured noise needs neither allantools nor scipy.stats
    seen = _loaded_after(
        """
        import numpy as np
        import noisevar
        rng = np.random.default_rng(5)
        z = np.ones(4000) + np.cumsum(rng.normal(0, 0.01, 4000)) + rng.normal(0, 0.5, 4000)
        OUT = bool(noisevar.estimate(z).diagnostics.white)
        """
    )
    assert seen["out"] is False
    assert set(seen["loaded"]) <= {"scipy.signal"}


def test_cli_estimate_of_a_npy_file_loads_none_of_the_heavy_libraries(tmp_path):
    rng = np.random.default_rng(6)
    np.save(tmp_path / "z.npy", np.sin(np.arange(3000) / 200.0) + rng.normal(0, 0.1, 3000))
    for fmt in ("table", "json"):
        seen = _loaded_after(
            """
            import sys
            from noisevar.cli import main
            OUT = main(sys.argv[1:])
            """,
            "estimate",
            str(tmp_path / "z.npy"),
            "--format",
            fmt,
        )
        assert seen["out"] == 0
        assert seen["loaded"] == []


def test_lazy_public_names_still_work():
    seen = _loaded_after(
        """
        import numpy as np
        from noisevar.batch import read_table  # the subpackage first: noisevar.batch stays
        import noisevar
        from noisevar import generate

        names = set(dir(noisevar))
        sig = noisevar.generate("fast-slow", n=2000, seed=1)
        res = noisevar.allan(np.random.default_rng(2).normal(size=4000), rate=10.0)
        OUT = {
            "all_listed": sorted(set(noisevar.__all__) - names),
            "batch_is_function": callable(noisevar.batch)
            and noisevar.batch.__module__ == "noisevar.batch",
            "same_generate": generate is noisevar.generate,
            "n": int(sig.measured.size),
            "taus": int(np.size(res.taus)),
            "every_name": all(getattr(noisevar, n) is not None for n in noisevar.__all__),
        }
        """
    )
    out = seen["out"]
    assert out["all_listed"] == []
    assert out["batch_is_function"]
    assert out["same_generate"]
    assert out["n"] == 2000
    assert out["taus"] > 3
    assert out["every_name"]


def test_batch_runs_through_the_lazy_name(tmp_path):
    rng = np.random.default_rng(7)
    np.savetxt(tmp_path / "a.csv", rng.normal(0, 0.2, 2000), header="x", comments="")
    seen = _loaded_after(
        f"""
        import noisevar
        frame = noisevar.batch([{str(tmp_path / "a.csv")!r}], jobs=1, progress=False)
        OUT = [int(len(frame)), float(frame["variance"].iloc[0])]
        """
    )
    rows, variance = seen["out"]
    assert rows == 1
    assert variance == pytest.approx(0.04, rel=0.15)


def test_unknown_name_is_an_attribute_error():
    import noisevar
    import noisevar.io

    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = noisevar.nope
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = noisevar.io.nope


def _sparse(path: Path, size: int) -> Path:
    path.write_bytes(b"\x93NUMPY" if path.suffix == ".npy" else b"x\n1\n")
    os.truncate(path, size)
    return path


@pytest.mark.parametrize(
    ("name", "flags"), [("big.csv", []), ("big.npy", ["--method", "rice"]), ("big.csv", ["-q"])]
)
def test_oversized_sparse_file_is_refused_with_exit_2_and_one_line(tmp_path, name, flags):
    # a .npy over the cap is streamed by method auto; by another method it is refused
    path = _sparse(tmp_path / name, MAX_BYTES + 1)
    done = subprocess.run(
        [sys.executable, "-m", "noisevar", "estimate", str(path), *flags],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        timeout=300,
        check=False,
    )
    assert done.returncode == 2
    assert done.stdout == ""
    lines = done.stderr.splitlines()
    assert len(lines) == 1
    assert lines[0].startswith(f"noisevar: error: {name} is 1,073.7 MB, over the 1,074 MB limit")


def test_precheck_leaves_streamed_files_to_the_stream(tmp_path):
    from noisevar.cli.estimate import precheck
    from noisevar.errors import NoisevarError

    csv = _sparse(tmp_path / "big.csv", MAX_BYTES + 1)
    npy = _sparse(tmp_path / "big.npy", MAX_BYTES + 1)
    for refused in ([str(csv)], [str(csv), "--method", "auto"], [str(npy), "--method=rice"]):
        with pytest.raises(NoisevarError, match="over the 1,074 MB limit"):
            precheck(refused)
    for streamed in ([str(csv), "--stream"], [str(csv), "--dtype=<f4"], [str(npy)]):
        precheck(streamed)
    precheck(["--column", "x", str(csv)])  # FILE not first: the parser's path checks it
    with pytest.raises(NoisevarError, match="no such file"):
        precheck([str(tmp_path / "missing.npy"), "--stream"])


def test_check_size_refuses_missing_directories_and_oversized(tmp_path):
    from noisevar.errors import NoisevarError

    small = tmp_path / "s.csv"
    small.write_text("x\n1\n2\n")
    assert check_size(small) == small.stat().st_size
    with pytest.raises(NoisevarError, match="over the 0 MB limit"):
        check_size(small, max_bytes=3)
    assert check_size(small, max_bytes=None) == small.stat().st_size
    with pytest.raises(NoisevarError, match="no such file"):
        check_size(tmp_path / "missing.csv")
    with pytest.raises(NoisevarError, match="no such file"):
        check_size(tmp_path)


def test_cli_missing_file_is_one_line_before_the_parser(tmp_path):
    from noisevar.cli import main

    assert main(["estimate", str(tmp_path / "missing.csv"), "--method", "auto"]) == 2


@pytest.mark.parametrize("span", [5, 7, 11, 21, 41, 81, 101])
@pytest.mark.parametrize("order", [0, 1, 2, 3])
def test_residual_sequence_is_savitzky_golay(span, order):
    w = signal.savgol_coeffs(span, order)
    expected = -0.5 * (w + w[::-1])
    expected[span // 2] += 1.0
    got = residual_sequence(span, order)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)
    np.testing.assert_array_equal(got, got[::-1])  # exactly symmetric


def test_chi2_and_normal_functions_give_scipy_stats_floats():
    rng = np.random.default_rng(8)
    q = np.r_[rng.uniform(size=300), 0.0, 1.0, 0.025, 0.975, 1 - 0.05 / 200, 1.5, -0.1]
    nu = np.r_[rng.uniform(0.1, 1e5, size=300), 1.0, 2.0, 3.0, 400.0, 7000.0, 3.0, 3.0]
    np.testing.assert_array_equal(dist.chi2_ppf(q, nu), stats.chi2.ppf(q, nu))
    assert dist.chi2_ppf(0.975, 37.5) == stats.chi2.ppf(0.975, 37.5)
    assert np.isnan(dist.chi2_ppf(0.5, 0.0)) and np.isnan(stats.chi2.ppf(0.5, 0.0))
    for x, k in [(3.3, 4), (0.0, 3), (-1.0, 2), (np.inf, 3), (12.5, 17), (250.0, 200)]:
        assert dist.chi2_sf(x, k) == stats.chi2.sf(x, k)
    assert np.isnan(dist.chi2_sf(1.0, 0)) and np.isnan(stats.chi2.sf(1.0, 0))
    median = stats.chi2.ppf(0.5, 1)
    assert dist.chi2_pdf(median, 1) == stats.chi2.pdf(median, 1)
    for x in rng.normal(0, 3, size=200):
        assert dist.norm_cdf(x) == stats.norm.cdf(x)
        assert dist.norm_pdf(x) == stats.norm.pdf(x)

"""Short records (< 100 samples) get an R, an honest interval and a verdict that says what
could and could not be checked (issue 26, polish).

Before: 22-47 samples came without a verdict; 47-99 got the full verdict from tests that
cannot work on so few samples: the whiteness test (20 lags) rejected white noise in 52 %
of 48-sample records and 33 % of 64-sample ones ("the noise is coloured ... model the
coloured part"), and no level change can be seen in one block of the level profile.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar.cli import main
from noisevar.estimators.answer import record_answer


def _record(kind: str, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    noise = rng.normal(0.0, 1.0, n)
    if kind == "ramp":
        return 0.5 * np.arange(n) + noise
    if kind == "gps":  # a slow random walk under the fixes' noise
        return np.cumsum(rng.normal(0.0, 0.3, n)) + noise
    return noise


@pytest.mark.parametrize("n", [22, 32, 47, 64, 99])
@pytest.mark.parametrize("kind", ["white", "ramp", "gps"])
def test_a_short_record_has_an_r_a_wide_interval_and_says_what_was_not_checked(kind, n):
    est = nv.estimate(_record(kind, n, n), method="auto")
    lo, hi = est.ci95
    assert np.isfinite(est.variance) and lo < est.variance < hi
    assert hi / lo > 1.8  # never a tight interval on so few samples
    v = est.verdict
    assert v.startswith(f"only {n} samples: R = ")
    assert "too few samples to check" in v and "whether its level changes" in v
    assert "tails and glitches" in v and "coloured" not in v and "good Kalman R" not in v
    assert est.to_row()["verdict"] == v == record_answer(est).verdict
    assert record_answer(est).severity in ("caution", "warning")


def test_the_cli_prints_a_short_records_verdict(tmp_path, capsys):
    path = tmp_path / "fixes.csv"
    np.savetxt(path, _record("gps", 32, 1), header="alt", comments="")
    assert main(["estimate", str(path)]) == 0
    out = capsys.readouterr().out
    (line,) = [x for x in out.splitlines() if x.startswith("verdict")]
    assert "only 32 samples" in line and "whether the noise is white" in line


@pytest.mark.parametrize(("n", "most"), [(48, 0.10), (64, 0.10), (100, 0.10)])
def test_the_whiteness_test_holds_its_level_on_short_white_records(n, most):
    rng = np.random.default_rng(n)
    rejected = [not nv.estimate(rng.normal(size=n)).diagnostics.white for _ in range(150)]
    assert np.mean(rejected) <= most  # was 0.52, 0.33 and 0.13 (5 % asked)


def test_what_a_short_record_cannot_check_is_a_blank_flag_not_false():
    row = nv.estimate(_record("white", 64, 3)).to_row()
    assert row["flag_level_varies"] is None and row["flag_heavy_tailed"] is None
    assert row["flag_white"] is True  # tested, over its few lags
    long = nv.estimate(_record("white", 100, 3)).to_row()
    assert long["flag_level_varies"] is False and not long["verdict"].startswith("only")

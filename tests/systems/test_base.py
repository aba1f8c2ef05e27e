"""The run/result protocol every system family follows, and the subpackage layout."""

from __future__ import annotations

import pytest

from noisevar.errors import NoisevarError
from noisevar.systems import carrier, fusion, latency, robust, scenarios
from noisevar.systems.base import BatchResult, RunResult, as_list


def _families() -> dict[str, tuple[RunResult, int]]:
    sc = carrier.CarrierScenario(duration_s=0.5)
    data = robust.simulate_robust(robust.RobustScenario(duration_s=60.0), seed=0, runs=2)
    fdata = fusion.simulate_fusion(fusion.FusionScenario(n_steps=10), seed=0, runs=3)
    return {
        "carrier truth": (carrier.simulate_channel(sc, seed=0, runs=2), 2),
        "carrier result": (carrier.run_carrier(sc, method="ekf", runs=2), 2),
        "fusion data": (fdata, 3),
        "fusion result": (fusion.run_fusion(fdata, local="fixed"), 3),
        "robust data": (data, 2),
        "robust result": (robust.run_robust(data, filters=("ekf",), skip=2), 2),
        "latency": (
            latency.run_latency(
                latency.simulate_latency(latency.LatencyScenario(duration_s=60.0), seed=0)
            ),
            1,
        ),
        "scenario": (scenarios.noise_step(runs=2, seed=0, n_steps=300), 2),
    }


@pytest.fixture(scope="module")
def families() -> dict[str, tuple[RunResult, int]]:
    return _families()


def test_every_family_follows_the_protocol(families) -> None:
    for name, (obj, n) in families.items():
        assert isinstance(obj, RunResult), name
        assert isinstance(obj, BatchResult), name
        assert obj.runs == n, name
        assert isinstance(obj.label, str) and obj.label, name
        obj.check_run(n - 1)
        with pytest.raises(NoisevarError, match="out of range"):
            obj.check_run(n)
        with pytest.raises(NoisevarError, match="out of range"):
            obj.check_run(-1)


def test_as_list(families) -> None:
    data = families["fusion data"][0]
    assert as_list(data, type(data)) == [data]
    with pytest.raises(NoisevarError, match="^clean: give a FusionData"):
        as_list([data, 1], type(data), "clean")


def test_old_module_paths_re_export_the_subpackages() -> None:
    from noisevar.systems.carrier.run import run_carrier
    from noisevar.systems.fusion_scenario import simulate_fusion
    from noisevar.systems.latency.delay import estimate_delay
    from noisevar.systems.robust.kappa import kappa_tradeoff
    from noisevar.systems.scenarios.gps import gps_circle

    assert carrier.run_carrier is run_carrier
    assert fusion.simulate_fusion is simulate_fusion
    assert latency.estimate_delay is estimate_delay
    assert robust.kappa_tradeoff is kappa_tradeoff
    assert scenarios.gps_circle is gps_circle
    for mod in (carrier, fusion, latency, robust, scenarios):
        for name in mod.__all__:
            assert hasattr(mod, name), (mod.__name__, name)

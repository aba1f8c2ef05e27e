"""``inertial_noise``'s unit: None is no unit, anything else not a name is one clear error
(before: an AttributeError traceback from the unit's formatting)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.errors import NoisevarError


def test_no_unit_is_u() -> None:
    z = np.random.default_rng(0).normal(size=4000)
    none = noisevar.inertial_noise(z, 100.0, unit=None)
    u = noisevar.inertial_noise(z, 100.0)
    assert none.to_dict() == u.to_dict()


def test_a_unit_that_is_not_a_name_is_refused() -> None:
    z = np.random.default_rng(0).normal(size=4000)
    with pytest.raises(NoisevarError, match="unit must be"):
        noisevar.inertial_noise(z, 100.0, unit=5)  # type: ignore[arg-type]

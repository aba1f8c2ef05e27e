"""Units (noisevar.units, pint): parsing, conversions of values and variances, term units."""

from __future__ import annotations

import math

import numpy as np
import pytest

from noisevar import units
from noisevar.errors import NoisevarError

TOL = 1e-9


@pytest.mark.parametrize(
    ("source", "target", "closed_form"),
    [
        ("deg/s", "rad/s", math.pi / 180),
        ("rad/s", "deg/s", 180 / math.pi),
        ("deg/h", "rad/s", math.pi / 180 / 3600),
        ("g", "m/s^2", 9.80665),  # standard gravity, not the gram
        ("mg", "m/s^2", 9.80665e-3),
        ("ug", "m/s^2", 9.80665e-6),
        ("ns", "s", 1e-9),
        ("km", "m", 1e3),
        ("0.00875 deg/s", "rad/s", 0.00875 * math.pi / 180),  # raw counts x scale
        ("0.061 mg", "m/s^2", 0.061 * 9.80665e-3),
    ],
)
def test_factor_closed_form(source: str, target: str, closed_form: float) -> None:
    assert units.factor(source, target) == pytest.approx(closed_form, rel=TOL)
    z = np.array([1.0, -2.5])
    np.testing.assert_allclose(units.convert(z, source, target), z * closed_form, rtol=TOL)
    np.testing.assert_allclose(
        units.convert_variance(z**2, source, target), z**2 * closed_form**2, rtol=TOL
    )


def test_no_unit_converts_nothing() -> None:
    assert units.parse_unit(None) is None and units.parse_unit("u") is None
    assert units.factor(None, "rad/s") == 1.0 and units.factor("deg/s", "") == 1.0


@pytest.mark.parametrize("bad", ["furlongs/fortnight^^", "deg/", "0 deg/s", "-1 g"])
def test_bad_unit_names_it_and_lists_examples(bad: str) -> None:
    with pytest.raises(NoisevarError) as info:
        units.parse_unit(bad)
    assert repr(bad) in str(info.value) and "deg/s" in str(info.value)


def test_different_dimensions_refused() -> None:
    with pytest.raises(NoisevarError, match="different dimensions"):
        units.factor("deg/s", "m/s^2")


@pytest.mark.parametrize(
    ("unit", "symbol", "label"),
    [
        ("rad/s", "N", "rad/s/√Hz"),
        ("rad/s", "K", "rad/s²/√Hz"),
        ("m/s^2", "K", "m/s³/√Hz"),
        ("deg/s", "R", "deg/s²"),
        ("m", "K", "m/s/√Hz"),
        (None, "B", "u"),
    ],
)
def test_term_units(unit, symbol, label) -> None:
    assert units.term_unit(unit, symbol) == label


def test_discrete_forms() -> None:
    n, k, f = 1.888e-4, 2.557e-6, 400.0
    assert units.sigma_at(n, f) == pytest.approx(n * 20.0, rel=TOL)
    assert units.density_from_sigma(units.sigma_at(n, f), f) == pytest.approx(n, rel=TOL)
    assert units.walk_step(k, f) == pytest.approx(k / 20.0, rel=TOL)
    assert units.walk_rate_sigma(k, f) == pytest.approx(units.walk_step(k, f) * f, rel=TOL)
    with pytest.raises(NoisevarError):
        units.sigma_at(n, 0.0)
    assert units.variance_label("deg/s") == "(deg/s)²" and units.variance_label("m") == "m²"


@pytest.mark.parametrize(("source", "target", "k"), [("degC", "degF", 1.8), ("°C", "K", 1.0)])
def test_a_temperature_is_a_difference(source: str, target: str, k: float) -> None:
    """Logs declare temperatures in degC (PX4, ROS, DataFlash): noise has no offset, so the
    unit is read as its degree and converts by the factor alone (on main: refused)."""
    assert units.factor(source, target) == pytest.approx(k, rel=TOL)
    assert units.declared_unit("degC") == "degC"


@pytest.mark.parametrize(
    ("source", "target", "k"), [("gauss", "T", 1e-4), ("mG", "uT", 0.1), ("mgauss", "gauss", 1e-3)]
)
def test_gauss_converts_to_tesla(source: str, target: str, k: float) -> None:
    """PX4 and DataFlash log the magnetometer in gauss, ROS's MagneticField in tesla (main:
    'different dimensions': pint's gauss is the Gaussian system's)."""
    assert units.factor(source, target) == pytest.approx(k, rel=TOL)
    assert units.factor("g", "m/s^2") == pytest.approx(9.80665, rel=TOL)  # g stays gravity


@pytest.mark.parametrize(
    ("source", "target", "closed_form"),
    [
        ("W/m2", "W/m^2", 1.0),  # GOES XRS netCDF4 (sunpy's test files): real_audit6
        ("W m-2", "W/m^2", 1.0),  # CF conventions
        ("m s-2", "m/s^2", 1.0),
        ("km2", "m^2", 1e6),
        ("1e-6 m/s2", "m/s^2", 1e-6),  # the number's exponent stays a number's
    ],
)
def test_udunits_exponents(source: str, target: str, closed_form: float) -> None:
    """A netCDF/HDF5 file's unit in UDUNITS' syntax is read, not dropped to ``u``."""
    assert units.factor(source, target) == pytest.approx(closed_form, rel=TOL)
    assert units.declared_unit(source) == source

"""Unit helpers convert exactly and keep scalars scalar."""

import math

import numpy as np
import pytest

import mechsynth as ms


def test_degrees_round_trip():
    assert ms.deg(180.0) == pytest.approx(math.pi, rel=1e-15)
    assert isinstance(ms.deg(30), float)
    np.testing.assert_allclose(ms.to_deg(ms.deg(np.array([1.0, 2.0]))), [1.0, 2.0], rtol=1e-15)


def test_rpm_and_spm():
    # 600 rpm = 10 rev/s = 20 pi rad/s
    assert ms.rpm(600) == pytest.approx(20 * math.pi, rel=1e-15)
    assert ms.spm(6.7) == pytest.approx(6.7 * 2 * math.pi / 60, rel=1e-15)
    assert ms.to_rpm(ms.rpm(1440.0)) == pytest.approx(1440.0, rel=1e-15)


def test_inch():
    assert ms.inch(100) == pytest.approx(2.54, rel=1e-15)
    assert ms.to_inch(2.54) == pytest.approx(100.0, rel=1e-15)


def test_dms():
    assert ms.dms(65, 59, 47) == pytest.approx(math.radians(65 + 59 / 60 + 47 / 3600), rel=1e-15)


def test_cycle_excludes_endpoint_and_validates():
    phi = ms.cycle(4)
    np.testing.assert_allclose(phi, [0, math.pi / 2, math.pi, 3 * math.pi / 2])
    with pytest.raises(ValueError, match=r"n \(the number of angles\) must be between 2"):
        ms.cycle(1)
    with pytest.raises(ms.MechanismError, match="whole number, got 2.5"):
        ms.cycle(2.5)  # was silently 2 angles
    with pytest.raises(ms.MechanismError, match="whole number"):
        ms.cycle("360")
    with pytest.raises(ms.MechanismError, match="start must be finite"):
        ms.cycle(8, start=float("nan"))
    np.testing.assert_allclose(ms.cycle(4.0), phi)  # a float with no fraction is a count


@pytest.mark.parametrize("convert", [ms.deg, ms.to_deg, ms.rpm, ms.to_rpm, ms.inch, ms.to_inch])
@pytest.mark.parametrize("bad", ["30", b"30", True, None, 1 + 2j, ["30"], np.array([1j])])
def test_unit_helpers_refuse_what_is_not_a_number(convert, bad):
    with pytest.raises(ms.MechanismError, match="must be"):
        convert(bad)


def test_unit_helpers_convert_numbers_and_arrays_with_nan():
    assert ms.deg(np.float32(180)) == pytest.approx(math.pi)
    assert ms.deg(180) == pytest.approx(math.pi)
    np.testing.assert_allclose(ms.to_deg(np.array([np.pi, np.nan])), [180.0, np.nan])

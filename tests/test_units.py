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
    with pytest.raises(ValueError, match="n must be at least 2"):
        ms.cycle(1)

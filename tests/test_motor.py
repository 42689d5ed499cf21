import numpy as np
import pytest

from mechsynth.dynamics import InductionMotor, LinearDrive

RPM = np.pi / 30


def catalogue(**kw):
    args = dict(
        rated_power=4000.0, rated_speed=1440 * RPM, sync_speed=1500 * RPM, overload_ratio=2.2
    )
    args.update(kw)
    return InductionMotor.from_catalogue(**args)


def test_catalogue_motor_gives_rated_torque_at_rated_speed():
    m = catalogue()
    mn = 4000.0 / (1440 * RPM)
    assert m.shaft_torque(1440 * RPM) == pytest.approx(mn, rel=1e-12)
    assert m.breakdown_torque == pytest.approx(2.2 * mn, rel=1e-12)


def test_kloss_maximum_at_critical_slip():
    m = catalogue()
    s = np.linspace(1e-4, 0.9, 20001)
    t = m.shaft_torque((1 - s) * m.sync_speed)
    assert s[np.argmax(t)] == pytest.approx(m.critical_slip, abs=1e-4)
    assert t.max() == pytest.approx(m.breakdown_torque, rel=1e-8)
    assert m.shaft_torque(m.sync_speed) == 0.0


def test_gear_referral():
    m = catalogue(gear_ratio=2.4, efficiency=0.9)
    w = np.array([55.0, 60.0, 62.0])
    assert np.allclose(m.torque(w), 0.9 * 2.4 * m.shaft_torque(2.4 * w))
    assert m.crank_sync_speed == pytest.approx(1500 * RPM / 2.4)


@pytest.mark.parametrize(
    "kw, field",
    [
        (dict(rated_power=-1.0), "rated_power"),
        (dict(rated_speed=float("nan")), "rated_speed"),
        (dict(overload_ratio=0.9), "overload_ratio"),
        (dict(rated_speed=1600 * RPM), "rated_speed"),
        (dict(rated_speed=100 * RPM), "critical slip"),
        (dict(gear_ratio=0.0), "gear_ratio"),
        (dict(efficiency=1.2), "efficiency"),
    ],
)
def test_bad_catalogue_data(kw, field):
    with pytest.raises(ValueError, match=field):
        catalogue(**kw)


@pytest.mark.parametrize("sk", [0.0, 1.0, -0.1, float("nan")])
def test_bad_critical_slip(sk):
    with pytest.raises(ValueError, match="critical_slip"):
        InductionMotor(50.0, sk, 157.0)


def test_linear_drive_validation():
    with pytest.raises(ValueError, match="b"):
        LinearDrive(10.0, -1.0)

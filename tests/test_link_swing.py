"""A link's swing over the cycle, from its angle made continuous (LinkTrack.swing): the raw
angle wraps at +-180 deg, so np.ptp of a rocker's angle that passes through -x reads ~360 deg."""

import casadi as ca
import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError


def _rocker_through_minus_x(dy=0.06):
    """Crank O-A 30 mm, rod AB 100 mm, rocker D-B 80 mm pivoted at D (120 mm, dy): B lies left
    of D, so the rocker points along -x and its angle crosses +-180 deg."""
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, dy)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.10), ("D", 0.08))
    )


def test_swing_of_a_rocker_whose_angle_crosses_180_deg():
    m = _rocker_through_minus_x().motion(ms.cycle(720))
    rocker = m.links["DB"]
    assert np.ptp(rocker.angle) > np.radians(359.0)  # the wrapped angle: no swing
    # the same swing measured from -x, where this rocker never goes near the cut
    from_minus_x = np.angle(np.exp(1j * (rocker.angle - np.pi)))
    assert np.ptp(from_minus_x) < np.radians(90.0)
    assert rocker.swing == pytest.approx(np.ptp(from_minus_x), abs=1e-12)
    assert np.degrees(rocker.swing) == pytest.approx(44.84, abs=0.01)
    assert np.max(np.abs(np.diff(rocker.unwrapped_angle))) < np.radians(2.0)
    assert np.allclose(np.exp(1j * rocker.unwrapped_angle), np.exp(1j * rocker.angle))
    # the crank revolves: its swing is the whole sampled turn
    assert np.degrees(m.links["OA"].swing) == pytest.approx(359.5, abs=1e-9)


def test_swing_per_design_of_a_batch_and_at_speed():
    lk = _rocker_through_minus_x()
    phi = ms.cycle(360)
    one = [lk(D_y=dy).motion(phi).links["DB"].swing for dy in (0.02, 0.06)]
    batch = lk(D_y=np.array([[0.02], [0.06]])).motion(phi, speed=ms.rpm(60)).links["DB"]
    assert batch.swing.shape == (2,)
    assert np.allclose(batch.swing, one, atol=1e-12)
    assert np.degrees(one[0]) < 180.0 and np.degrees(one[1]) < 180.0


def test_swing_of_symbolic_angles_is_refused_clearly():
    lk = _rocker_through_minus_x()
    track = ms.kinematics.tracks.LinkTrack(ca.SX.sym("a"), 0.0, 0.0)
    with pytest.raises(MechanismError, match="numeric angles"):
        track.swing  # noqa: B018
    assert lk.motion(0.3).links["DB"].swing == 0.0

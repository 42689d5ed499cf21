"""Torque factor x polished-rod load = crank torque, by the general kinetostatics of the forces
layer (virtual work checked against the joint-reaction solution of the linkage)."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics.inertia import LinkInertia
from mechsynth.dynamics.kinetostatics import FRAME, ForceModel, Revolute, kinetostatics
from mechsynth.dynamics.loads import PointForce


def _model(load):
    bodies = {
        "crank": LinkInertia("crank", "O1", 0.0),
        "pitman": LinkInertia("pitman", "A", 0.0),
        "beam": LinkInertia("beam", "O2", 0.0),
    }
    joints = (
        Revolute("R10", "crank", FRAME, "O1"),
        Revolute("R21", "pitman", "crank", "A"),
        Revolute("R32", "beam", "pitman", "B"),
        Revolute("R30", "beam", FRAME, "O2"),
    )
    # the rod hangs vertically from the horsehead: a downward force at the polished-rod point
    rod = PointForce(
        "beam", "PR", lambda m: (0.0 * m.points["PR"].x, -load + 0.0 * m.points["PR"].x)
    )
    return ForceModel(bodies, joints, (rod,), "crank")


@pytest.mark.parametrize("unit_class", ["conventional", "mark-ii"])
@pytest.mark.parametrize("rotation", ["cw", "ccw"])
def test_torque_factor_times_load_is_the_kinetostatic_crank_torque(unit_class, rotation):
    if unit_class == "conventional":  # C-320D-256-120 geometry (inches), as in the pump tests
        u = ms.BeamPumpingUnit.from_api(
            A=155.0,
            C=111.06,
            I=111.02,
            P=132.01,
            R=42.01,
            H=231.97,
            G=95.98,
            units="in",
            rotation=rotation,
        )
    else:  # Lufkin Mark II M-912D-365-168, long-stroke hole (inches), as in the pump tests
        u = ms.BeamPumpingUnit.from_api(
            A=334.0,
            C=270.0,
            I=202.56,
            P=193.5,
            R=63.56,
            H=295.13,
            G=112.13,
            units="in",
            unit_class="mark-ii",
            rotation=rotation,
        )
    load = 80e3  # N
    speed = ms.spm(7.0)
    theta = np.linspace(0.0, 2 * np.pi, 97)[:-1] + 0.013
    m = u.motion(theta, speed=speed)
    res = kinetostatics(_model(load), m)
    crank_omega = m.links["crank"].omega
    # power of the drive = power against the rod load (massless links)
    np.testing.assert_allclose(
        res.torque * crank_omega,
        load * m.torque_factor * speed,
        rtol=1e-9,
        atol=1e-9 * load * np.max(np.abs(m.torque_factor)) * speed,
    )
    # the torque factor vanishes at the dead centres, so does the kinetostatic torque
    dc = np.asarray(u.dead_centres, dtype=float)
    res_dc = kinetostatics(_model(load), u.motion(dc, speed=speed))
    assert np.max(np.abs(res_dc.torque)) < 1e-6 * load

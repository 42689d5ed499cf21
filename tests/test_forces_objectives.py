"""Force measures and the affine reaction map."""

import numpy as np
import pytest

from mechsynth.machines.nail_header.model import NailHeader
from mechsynth.objectives.forces import (
    peak_reaction,
    peak_torque,
    reaction_affine_map,
    rms_torque,
)
from mechsynth.units import cycle

PHI = -cycle(360)


def test_measures_match_kinetostatics():
    nh = NailHeader()
    res = nh.forces(PHI)
    assert peak_reaction("R32").evaluate(nh, PHI, speed=nh.omega) == pytest.approx(
        res.magnitude("R32").max()
    )
    both = peak_reaction(["R10", "R32"]).evaluate(nh, PHI, speed=nh.omega)
    assert both == pytest.approx(max(res.magnitude("R10").max(), res.magnitude("R32").max()))
    assert peak_torque().evaluate(nh, PHI, speed=nh.omega) == pytest.approx(
        np.abs(res.torque).max()
    )
    assert rms_torque().evaluate(nh, PHI, speed=nh.omega) == pytest.approx(
        np.sqrt(np.mean(res.torque**2))
    )
    with pytest.raises(ValueError, match="joints"):
        peak_reaction([])


def test_affine_map_exact():
    def design(x):
        return NailHeader(m3=x[0], counterweight=x[1])

    A, b, rows = reaction_affine_map(design, ["R10", "R32"], [15.0, 0.5], PHI)
    assert A.shape == (720, 2, 2) and rows.shape == (720,)
    x = np.array([37.0, 1.3])
    res = design(x).forces(PHI)
    want = np.concatenate([np.stack(res.reactions[j], -1) for j in ("R10", "R32")])
    np.testing.assert_allclose(A @ x + b, want, rtol=1e-9, atol=1e-6)


def test_casadi_reactions_match_numpy_and_finite_differences():
    ca = pytest.importorskip("casadi")
    phi = -cycle(24)
    x = ca.SX.sym("x", 2)
    nh = NailHeader(m3=x[0], counterweight=x[1])
    m = nh.motion(phi, speed=nh.omega)
    per = peak_reaction(["R10", "R32"]).samples(nh, m)
    torque = rms_torque().samples(nh, m)
    f = ca.Function("f", [x], [per, torque])
    jac = ca.Function("j", [x], [ca.jacobian(per, x)])
    x0 = np.array([30.0, 0.8])
    got, tq = (np.asarray(v).ravel() for v in f(x0))
    num = NailHeader(m3=30.0, counterweight=0.8).forces(phi)
    want = np.maximum(num.magnitude("R10"), num.magnitude("R32"))
    np.testing.assert_allclose(got, want, rtol=1e-10)
    np.testing.assert_allclose(tq, num.torque, rtol=1e-9, atol=1e-6)
    J = np.asarray(jac(x0))
    for k in range(2):
        h = 1e-4
        e = np.eye(2)[k] * h
        fd = (np.asarray(f(x0 + e)[0]).ravel() - np.asarray(f(x0 - e)[0]).ravel()) / (2 * h)
        np.testing.assert_allclose(J[:, k], fd, rtol=1e-6, atol=1e-6 * np.max(np.abs(want)))

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics import (
    LinkInertia,
    ReducedModel,
    gravity_moment,
    point_force_moment,
    reduced_inertia,
    reduced_model,
)
from mechsynth.dynamics.inertia import com_track

SC = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01)
BODIES = [
    LinkInertia("crank", "O", 2.0, (0.035, 0.0), 0.001),
    LinkInertia("rod", "A", 3.0, (0.08, 0.01), 0.02),
    LinkInertia(None, "B", 15.0),
]
PHI = np.linspace(0.05, 6.2, 40)


def test_spline_inertia_and_derivative_match_exact_and_finite_differences():
    r = reduced_model(SC, BODIES, n=360)
    j, dj = reduced_inertia(SC, BODIES, PHI)
    assert np.allclose(r.inertia(PHI), j, rtol=1e-6)
    assert np.allclose(r.inertia_derivative(PHI), dj, rtol=1e-4, atol=1e-6 * np.abs(dj).max())
    h = 1e-6
    jp, _ = reduced_inertia(SC, BODIES, PHI + h)
    jm, _ = reduced_inertia(SC, BODIES, PHI - h)
    assert np.allclose(dj, (jp - jm) / (2 * h), rtol=1e-6, atol=1e-9)
    assert np.allclose(r.inertia(PHI + 2 * np.pi), r.inertia(PHI))  # periodic


def test_gravity_moment_is_minus_derivative_of_potential():
    tilt = 0.3
    g = 9.80665

    def potential(phi):
        m = SC.motion(phi)
        gx, gy = g * np.sin(tilt), -g * np.cos(tilt)
        return -sum(b.mass * (gx * com_track(m, b).x + gy * com_track(m, b).y) for b in BODIES)

    mg, dmg = gravity_moment(SC, BODIES, PHI, tilt=tilt)
    h = 1e-6
    assert np.allclose(mg, -(potential(PHI + h) - potential(PHI - h)) / (2 * h), atol=1e-7)
    mp, _ = gravity_moment(SC, BODIES, PHI + h, tilt=tilt)
    mm, _ = gravity_moment(SC, BODIES, PHI - h, tilt=tilt)
    assert np.allclose(dmg, (mp - mm) / (2 * h), atol=1e-6)


def test_point_force_moment_by_virtual_work():
    force = lambda phi, omega: (-1000.0 + 0 * phi, 200.0 + 0 * phi)  # noqa: E731
    m = point_force_moment(SC, "B", force, PHI)
    h = 1e-6
    bp, bm = SC.motion(PHI + h).points["B"], SC.motion(PHI - h).points["B"]
    work = -1000.0 * (bp.x - bm.x) + 200.0 * (bp.y - bm.y)
    assert np.allclose(m, work / (2 * h), atol=1e-5)
    r = reduced_model(SC, BODIES, n=720, gravity=False, loads=[("B", force)])
    assert np.allclose(r.moment(PHI, 60.0), m, atol=1e-3 * np.abs(m).max())


def test_extra_speed_dependent_load():
    r = reduced_model(SC, BODIES, n=90, gravity=False, extra=[lambda p, w: -0.5 * w])
    assert r.moment(1.0, 40.0) == pytest.approx(-20.0)


def test_bad_model_inputs():
    phi = np.linspace(0, 2 * np.pi, 9)
    z = np.zeros_like(phi)
    with pytest.raises(ValueError, match="reduced inertia"):
        ReducedModel(phi, z - 1.0, z, z)
    with pytest.raises(ValueError, match="j_grid"):
        ReducedModel(phi, z + np.nan, z, z)
    with pytest.raises(ValueError, match="flywheel"):
        ReducedModel(phi, z + 1.0, z, z, flywheel=-2.0)
    with pytest.raises(ValueError, match="mass"):
        LinkInertia("rod", "A", -3.0)


@pytest.mark.parametrize("with_dm", [False, True])
def test_scalar_terms_equal_the_splines_at_any_angle(with_dm):
    """The integrators' one-angle evaluation (J, dJ, M) is the splines' own, wrapped to a turn."""
    phi = np.linspace(0.0, 2 * np.pi, 37)
    model = ReducedModel(
        phi, 2 + np.cos(phi), -np.sin(phi), np.sin(2 * phi),
        2 * np.cos(2 * phi) if with_dm else None,
        extra=(lambda p, w: 0.1 * w,), flywheel=0.3,
    )  # fmt: skip
    rng = np.random.default_rng(3)
    for p in [*rng.uniform(-20, 20, 100), 0.0, np.pi, 2 * np.pi, -1e-17, phi[5]]:
        got = model.terms(p, 3.0)
        want = (model.inertia(p), model.inertia_derivative(p), model.moment(p, 3.0))
        assert got == pytest.approx([float(w) for w in want], rel=1e-14, abs=1e-14), p

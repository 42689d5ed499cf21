"""Mass properties: kinetic energy and the reduced moment of inertia."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics import LinkInertia, com_track, kinetic_energy, reduced_inertia

BODIES = (
    LinkInertia("crank", "O", 2.0, (0.01, 0.0), 0.01),
    LinkInertia("rod", "A", 12.0, (0.05, 0.01), 0.5),
    LinkInertia(None, "B", 15.0),
)


def test_reduced_inertia_derivative_matches_finite_differences():
    sc = ms.SliderCrank(0.07, 0.24, 0.01)
    phi = ms.cycle(720)
    h = 1e-6
    j, dj = reduced_inertia(sc, BODIES, phi)
    jp, _ = reduced_inertia(sc, BODIES, phi + h)
    jm, _ = reduced_inertia(sc, BODIES, phi - h)
    np.testing.assert_allclose(dj, (jp - jm) / (2 * h), atol=1e-7 * np.max(np.abs(j)))


def test_kinetic_energy_scales_with_speed_squared():
    sc = ms.SliderCrank(0.07, 0.24)
    phi = ms.cycle(90)
    j, _ = reduced_inertia(sc, BODIES, phi)
    omega = ms.rpm(600)
    t = kinetic_energy(sc.motion(phi, speed=omega), BODIES)
    np.testing.assert_allclose(t, 0.5 * j * omega**2, rtol=1e-12)


def test_slider_only_reduced_inertia_is_mass_times_velocity_analog_squared():
    sc = ms.SliderCrank(0.07, 0.24)
    phi = ms.cycle(90)
    j, _ = reduced_inertia(sc, [LinkInertia(None, "B", 15.0)], phi)
    v = sc.motion(phi).slider.velocity
    np.testing.assert_allclose(j, 15.0 * v**2, rtol=1e-12)


def test_com_track_of_crank_about_its_pivot():
    sc = ms.SliderCrank(0.07, 0.24)
    phi = np.array([0.0, np.pi / 2])
    g = com_track(sc.motion(phi), LinkInertia("crank", "O", 1.0, (0.02, 0.0)))
    np.testing.assert_allclose(g.x, [0.02, 0.0], atol=1e-15)
    np.testing.assert_allclose(g.y, [0.0, 0.02], atol=1e-15)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(mass=-1.0), "mass of rod must not be negative"),
        (dict(mass=float("nan")), "mass of rod must be finite"),
        (dict(mass=1.0, inertia=-0.1), "inertia of rod must not be negative"),
    ],
)
def test_bad_mass_properties_name_the_field(kwargs, match):
    with pytest.raises(ValueError, match=match):
        LinkInertia("rod", "A", **kwargs)

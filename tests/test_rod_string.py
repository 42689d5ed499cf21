"""The wave-equation dynamometer card and the bundled card of the spatial-pump study."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.machines.pumping_unit import RodString, wave_equation_card
from mechsynth.machines.pumping_unit.torque import GRAVITY

UNIT = ms.BeamPumpingUnit.from_api(
    A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in"
)


def test_constants():
    r = RodString(depth=1000.0, diameter=0.02, pump_diameter=0.05, lift=800.0)
    assert r.wave_speed == pytest.approx(np.sqrt(2.06e11 / 7850.0))
    assert r.buoyant_weight == pytest.approx(np.pi * 0.01**2 * 1000 * GRAVITY * (7850 - 900))
    assert r.fluid_load == pytest.approx(900 * GRAVITY * 800 * np.pi * 0.025**2)


def test_slow_pumping_tends_to_the_static_card():
    """Slowly, the rods follow quasi-statically: the plunger loses the static stretch
    F_o L / (E A) of its stroke, and the loads tend to W_rf + F_o up and W_rf down, the stress
    waves (and the damping) adding a load of the order of the impedance rho A a times the rod
    speed, which halves with the speed."""
    rods = RodString(depth=1000.0, diameter=0.022, pump_diameter=0.056, lift=1000.0, damping=0.05)
    stretch = rods.fluid_load * rods.depth / (rods.E * rods.area)
    impedance = rods.density * rods.area * rods.wave_speed
    dev = []
    for spm in (0.5, 0.25):
        card, info = wave_equation_card(UNIT, rods, ms.spm(spm), cycles=2, nodes=10)
        v_max = float(
            np.max(np.abs(UNIT.motion(ms.cycle(360), speed=ms.spm(spm)).polished_rod.velocity))
        )
        assert info["plunger_stroke"] == pytest.approx(UNIT.stroke - stretch, rel=1e-3)
        up = info["peak_load"] - (rods.buoyant_weight + rods.fluid_load)
        down = rods.buoyant_weight - info["min_load"]
        assert 0 < up < 1.5 * impedance * v_max and 0 < down < 1.5 * impedance * v_max
        dev.append(max(up, down))
        assert card.stroke == pytest.approx(UNIT.stroke, rel=1e-3)
    assert 0.4 < dev[1] / dev[0] < 0.6


def test_the_bundled_study_card_is_this_model_s_output():
    from mechsynth.studies.spatial_pump import example_card, make_example_card

    card, info = make_example_card()
    bundled = example_card()
    np.testing.assert_allclose(bundled.position, card.position, rtol=0, atol=2e-9)
    np.testing.assert_allclose(bundled.load, card.load, rtol=0, atol=2e-6)
    assert info["last_cycle_change"] < 1e-6  # periodic
    # within the 7SK12's 12 t rating
    assert 0.6 < info["peak_load"] / (12e3 * GRAVITY) < 0.9


def test_bad_rods_are_named():
    with pytest.raises(ValueError, match="cannot exceed the pump depth"):
        RodString(depth=100.0, diameter=0.02, pump_diameter=0.05, lift=200.0)
    with pytest.raises(ValueError, match="denser than the well fluid"):
        RodString(depth=100.0, diameter=0.02, pump_diameter=0.05, lift=50.0, fluid_density=9e3)
    with pytest.raises(ValueError, match="damping must not be negative"):
        RodString(depth=100.0, diameter=0.02, pump_diameter=0.05, lift=50.0, damping=-1)
    with pytest.raises(ValueError, match="diameter must be positive"):
        RodString(depth=100.0, diameter=0.0, pump_diameter=0.05, lift=50.0)
    r = RodString(depth=100.0, diameter=0.02, pump_diameter=0.05, lift=50.0)
    with pytest.raises(ValueError, match="nodes must be at least 10"):
        wave_equation_card(UNIT, r, 1.0, nodes=3)

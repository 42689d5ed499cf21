"""Paper 000: the pitman force of the axial and desaxial units under the same load (massless
links): kinetostatics against the beam's moment balance, the power balance, the finding."""

import numpy as np
import pytest

from mechsynth.dynamics.kinetostatics import applied_power, kinetostatics
from mechsynth.machines.pumping_unit import DynamometerCard
from mechsynth.studies.beam_pump import (
    CARD_DOWN,
    CARD_UP,
    base_design,
    pitman_force,
    pitman_force_model,
    pitman_table,
    variants,
)
from mechsynth.units import cycle, spm

THETA = cycle(360)


@pytest.fixture(scope="module")
def setup():
    units, _ = variants(base_design())
    card = DynamometerCard(
        np.concatenate([np.linspace(0, 1, 50), np.linspace(1, 0, 50)]),
        np.concatenate([np.full(50, CARD_UP), np.full(50, CARD_DOWN)]),
        "idealized rectangular card",
    )
    return units, card


def test_pitman_force_equals_the_beam_moment_balance(setup):
    # Two computations: |R21| from the kinetostatic solve, and W k1 / (k cos(pressure angle))
    # from the moment balance of the beam about its centre bearing (the pitman a two-force link).
    units, card = setup
    for u in units.values():
        pf = pitman_force(u, THETA, spm(6), card)
        np.testing.assert_allclose(pf["force"], pf["closed_form"], rtol=1e-12)
        # the force lies along the pitman (a two-force member)
        res, m = pf["result"], pf["motion"]
        fx, fy = res.reactions["R21"]
        ang = m.links["pitman"].angle
        cross = fx * np.sin(ang) - fy * np.cos(ang)
        assert np.max(np.abs(cross)) <= 1e-9 * np.max(pf["force"])


def test_pitman_model_power_balance(setup):
    # massless links: the crank torque's power balances the load's, T omega + P = 0
    units, card = setup
    for u in units.values():
        m = u.motion(THETA, speed=spm(6))
        model = pitman_force_model(u, card)
        res = kinetostatics(model, m)
        lhs = res.torque * m.links["crank"].omega
        rhs = -applied_power(model, m)
        assert np.max(np.abs(lhs - rhs)) <= 1e-9 * np.max(np.abs(rhs))
        # and the crank torque is the API torque factor times the load
        w = card.load_on(m, u.stroke)
        np.testing.assert_allclose(
            np.abs(res.torque), np.abs(w * np.asarray(m.torque_factor)), atol=1e-6 * CARD_UP
        )


def test_desaxial_pressure_angle_loads_the_pitman_more(setup):
    # Paper 000: "the pressure angle grows, which loads the pitman more" -- holds under the same
    # load: peak pitman force axial < 2a < 2b, each at its upstroke's largest pressure angle.
    units, card = setup
    t = pitman_table(units, cycle(720), spm(6), card)
    peaks = [t[k]["peak_pitman_force"] for k in ("axial", "2a", "2b")]
    assert peaks[0] < peaks[1] < peaks[2]
    assert peaks[2] / peaks[0] == pytest.approx(1.233, abs=0.005)
    for row in t.values():
        assert row["load_there"] == CARD_UP
        assert row["pressure_angle_there_deg"] == pytest.approx(
            row["upstroke_max_pressure_angle_deg"], abs=0.3
        )
        assert row["closed_form_deviation"] < 1e-6


def test_position_functions_in_the_base_frame_15_and_polished_rod_16(setup):
    # Paper 000, (6)-(7) in the frame along O1O2, turned into the base frame by (15) with alpha1
    # the direction of O1O2, give the unit's pitman and beam angles; (16): V_K = omega3 l_O2K.
    from mechsynth.kinematics.four_bar_formulas import position_functions

    units, _ = setup
    for u in units.values():
        m = u.motion(THETA, speed=spm(6))
        alpha1 = np.arctan2(u.pivot_y, u.pivot_x)
        d = np.hypot(u.pivot_x, u.pivot_y)
        phi1 = np.asarray(m.links["crank"].angle) - alpha1
        best = []
        for branch in ("open", "crossed"):
            p2, p3 = position_functions(phi1, u.crank, u.pitman, u.rear_arm, d, branch)
            dev2 = np.angle(np.exp(1j * (p2 + alpha1 - m.links["pitman"].angle)))
            dev3 = np.angle(np.exp(1j * (p3 + alpha1 - m.links["rear_arm"].angle)))
            best.append(max(np.max(np.abs(dev2)), np.max(np.abs(dev3))))
        assert min(best) < 1e-10
        np.testing.assert_allclose(
            np.abs(m.polished_rod.velocity),
            u.front_arm * np.abs(m.links["rear_arm"].omega),
            atol=1e-12,
        )

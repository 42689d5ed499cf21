"""Newton's impact law and the blow reduced to the crank: energy and momentum bookkeeping."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics.inertia import com_track
from mechsynth.machines.impact import five_link, six_link, special_angles
from mechsynth.machines.impact.impact import Tool, blow, blow_angle, newton_impact, striker_track

INERTIAS = {
    "OA": (0.3, (0.002, 0.0), 2e-4),
    "AB": (0.2, (0.031, 0.0), 7e-5),
    "DB": (0.4, (0.01, -0.01), 3e-4),
    "KN": (0.15, (0.035, 0.0), 6e-5),
    "N": (3.0, (0.0, 0.0), 0.0),
}
W = ms.rpm(2000)


@pytest.mark.parametrize("mt", [0.5, 1.5, 40.0])
@pytest.mark.parametrize("e", [0.0, 0.3, 1.0])
def test_newton_law_bookkeeping(mt, e):
    m_eff, v = 7.0, 4.0
    r = newton_impact(m_eff, v, Tool(mt, e))
    # momentum, Newton's law, energy
    assert m_eff * v == pytest.approx(m_eff * r["v_after"] + mt * r["tool_velocity"], rel=1e-14)
    assert r["tool_velocity"] - r["v_after"] == pytest.approx(e * v, rel=1e-13, abs=1e-13)
    total = 0.5 * m_eff * r["v_after"] ** 2 + r["energy_delivered"] + r["energy_lost"]
    assert total == pytest.approx(r["energy_before"], rel=1e-14)
    if e == 1.0:
        assert abs(r["energy_lost"]) < 1e-12 * r["energy_before"]
    if e == 0.0:
        assert r["v_after"] == pytest.approx(r["tool_velocity"], rel=1e-14)
        mu = m_eff * mt / (m_eff + mt)
        assert r["energy_lost"] == pytest.approx(0.5 * mu * v * v, rel=1e-13)


@pytest.mark.parametrize("e", [-0.1, 1.01, float("nan")])
def test_bad_restitution_raises(e):
    with pytest.raises(ms.MechanismError, match="restitution e must (lie in|be finite)"):
        Tool(1.0, e)


def test_bad_tool_mass_raises():
    for mass in (-1.0, 0.0, None, float("inf")):
        with pytest.raises(ms.MechanismError, match="tool mass"):
            Tool(mass, 0.5)


def _case(linkage):
    phi = special_angles(linkage)[0]
    s, u, _, _ = striker_track(linkage, "N", phi)
    return phi, float(s), int(np.sign(u))


@pytest.mark.parametrize("make", [six_link, five_link])
@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_blow_reduced_to_the_crank(make, e):
    lk = make()
    inertias = dict(INERTIAS)
    if "KN" not in lk.topology().bodies:
        inertias.pop("KN")
    phi, s, sense = _case(lk)
    assert blow_angle(lk, "N", s, sense) == pytest.approx(phi, abs=1e-10)
    tool = Tool(1.5, e)
    b = blow(lk, inertias, phi, W, tool, sense=sense, drive_inertia=0.01)
    _, u, _, _ = striker_track(lk, "N", phi)
    # generalized impulse: J (w+ - w-) = -u P (the crank's speed jumps)
    assert b.inertia * (b.omega_after - b.omega_before) == pytest.approx(
        -abs(float(u)) * b.impulse, rel=1e-12
    )
    # the machine's energy loss is what the tool takes plus what the collision dissipates
    lost = b.machine_energy_before - b.machine_energy_after
    assert lost == pytest.approx(b.energy_delivered + b.energy_lost, rel=1e-12)
    if e == 1.0:
        assert abs(b.energy_lost) < 1e-10 * lost
    # the motor gives no impulse: the drive's inertia is in the crank body
    assert abs(b.crank_impulse) < 1e-9 * b.impulse * abs(float(u))
    # momentum of the whole linkage: frame impulses + tool impulse = sum m dv
    m = lk.motion(np.array([phi]), speed=0.0, epsilon=b.omega_after - b.omega_before)
    model = lk.force_model(inertias)
    dp = np.zeros(2)
    for body in model.bodies.values():
        t = com_track(m, body)
        dp += body.mass * np.array([float(t.ax[0]), float(t.ay[0])])
    frame = np.zeros(2)
    for j in model.joints:
        if j.by == "frame":
            frame += np.array(b.joint_impulses[j.name])
    tool_on_striker = -b.impulse * np.array(b.direction)
    assert np.allclose(frame + tool_on_striker, dp, atol=1e-10 * b.impulse)


def test_blow_bad_input():
    lk = six_link()
    phi, s, sense = _case(lk)
    with pytest.raises(ms.MechanismError, match="moves away from the tool"):
        blow(lk, INERTIAS, phi, W, Tool(1.0, 0.5), sense=-sense)
    with pytest.raises(ms.MechanismError, match="outside the striker's stroke"):
        blow_angle(lk, "N", s + 1.0, sense)
    with pytest.raises(ms.MechanismError, match="rebound turns the crank backwards"):
        blow(lk, INERTIAS, phi, W, Tool(200.0, 1.0), sense=sense)


def test_blow_names_a_speed_that_is_not_a_number():
    from mechsynth.machines.impact.design import representative_machine

    with pytest.raises(ms.MechanismError, match=r"omega\) must be a number \(rad/s\), got 'fast'"):
        representative_machine("six").blow(omega="fast")

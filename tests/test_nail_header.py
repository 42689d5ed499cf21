"""AB4115 nail header (paper 003, first part): Table 1, power balance, the study."""

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mechsynth.dynamics.kinetostatics import applied_power, kinetic_energy_rate, kinetostatics
from mechsynth.jsonutil import dumps
from mechsynth.machines.nail_header.model import NailHeader
from mechsynth.studies import run_study
from mechsynth.studies.nail_header import PUBLISHED
from mechsynth.units import cycle

PHI = -cycle(720)  # clockwise from the outer dead centre


@pytest.mark.parametrize("m3", [15.0, 50.0])
def test_table_1(m3):
    # Paper 003, Table 1 (columns of the 15 kg row as read in the seeds notes): maxima at phi = 0
    # to 0.05 % (the claim of the README and docs/forces.md; largest: -0.047 % for R21 at 50 kg)
    res = NailHeader(m3=m3).forces(PHI)
    for joint, published in PUBLISHED[m3].items():
        peak, at = res.peak(joint)
        assert peak == pytest.approx(published, rel=5e-4)
        assert np.cos(at) == pytest.approx(1.0)  # at the outer dead centre


def test_power_balance_nail_header():
    nh = NailHeader()
    phi = PHI[(np.abs(np.sin(PHI)) > 1e-3)]  # the upsetting force jumps at the dead centre
    m = nh.motion(phi, speed=nh.omega)
    model = nh.force_model()
    res = kinetostatics(model, m)
    lhs = res.torque * m.omega
    rhs = kinetic_energy_rate(model, m) - applied_power(model, m)
    assert np.max(np.abs(lhs - rhs)) <= 1e-9 * np.max(np.abs(rhs))


@pytest.mark.slow
def test_study_json_and_optimum(tmp_path):
    r = run_study("nail-header", out=tmp_path, angles=720, scan_step=1.0)
    data = json.loads(dumps(r.data))
    assert [row["slider_mass"] for row in data["table"]] == [15.0, 50.0]
    for row in data["table"]:
        for j in ("R10", "R21", "R32", "R43", "R50"):
            assert set(row[j]) == {"max", "angle_deg"}
    opt = data["optimal_slider_mass"]
    assert opt["objective"] == "R32" and opt["status"] == "optimal"
    # the scan on a 1 kg grid never beats the minimax optimum and lies within one step of it
    assert opt["scan_peak"] >= opt["peak"] * (1 - 1e-6)
    assert abs(opt["scan_mass"] - opt["mass"]) <= 1.0
    assert opt["peak"] < data["table"][1]["R32"]["max"] < data["table"][0]["R32"]["max"]
    cw = data["optimal_with_counterweight"]
    assert cw["peak"] <= data["optimal_slider_mass_train"]["peak"] * (1 + 1e-6)
    assert cw["peak_recomputed"] == pytest.approx(cw["peak"], rel=1e-4)
    assert all(p.exists() for p in r.files) and len(r.errata) >= 4
    # Table 1 to half a newton with the printed spring law; the ~15 N residual of the outer
    # dead-centre reading explained in the summary
    res = data["table_residual"]
    assert res["max_abs_deviation_N"] < 0.5
    assert -15.5 < res["outer_min_deviation_N"] <= res["outer_max_deviation_N"] < -14.0
    assert "spring's zero angle" in r.summary
    assert data["ejector"]["slot_normal_min"] > 1.0
    # balancing: shaking force checked against the ground reactions, the counterweight SOCP
    bal = data["balancing"]
    for check in bal["shaking_vs_ground_reactions_max_difference"].values():
        assert check["force_N"] < 1e-7 and check["moment_Nm"] < 1e-8
    sp = bal["shaking_force_peak_N"]
    assert sp["15 kg"] < sp["50 kg"] < sp["R32-optimal"]
    cw = bal["counterweight"]
    assert cw["status"] == "optimal" and cw["shaking_peak_N"] < 0.5 * sp["15 kg"]
    assert cw["reactions_after_N"]["R10"] > cw["reactions_before_N"]["R10"]
    front = bal["front_slider_and_counterweight"]
    assert all(f["status"] == "optimal" for f in front)
    nails = bal["nail_sizes"]
    assert nails["robust"]["certified"] and nails["compromise"]["certified"]
    assert nails["cases"][0]["own_mass"] < nails["compromise"]["mass"] < nails["robust"]["mass"]
    assert (tmp_path / "nail_header_balance.png").stat().st_size > 10_000
    # speed fluctuation at 600 rpm of the same NailHeader with the assumed motor
    sf = data["speed_fluctuation"]
    assert "no motor" in sf["motor"]["note"] and sf["motor"]["rated_power_W"] == 4000.0
    light, heavy = sf["rows"]
    assert (light["slider_mass"], heavy["slider_mass"]) == (15.0, 50.0)
    for row in sf["rows"]:
        assert row["mean_rpm"] == pytest.approx(600.0, rel=2e-4)
        assert row["delta_stepping"] == pytest.approx(row["delta"], rel=2e-3)
        assert 0 < row["delta_without_upsetting"] < row["delta"]
    assert 0.005 < light["delta"] < 0.012 and 3 * light["delta"] < heavy["delta"] < 0.04
    assert any(p.name == "nail_header_speed.png" for p in r.files)
    # the flywheel that holds the 15 kg fluctuation with the R32-optimal slider
    fw = sf["flywheel"]
    assert fw["slider_mass"] == data["optimal_slider_mass"]["mass"]
    assert fw["delta"] > heavy["delta"] > light["delta"]
    assert fw["delta_with_flywheel"] == pytest.approx(light["delta"], rel=1e-4)
    assert fw["flywheel_kgm2"] > 0
    # the classic energy estimate (constant-speed work swing) is the same order, conservative
    assert fw["flywheel_kgm2"] < fw["energy_method_kgm2"] < 2 * fw["flywheel_kgm2"]


@settings(max_examples=25, deadline=None)
@given(
    st.floats(1.0, 100.0),
    st.floats(0.0, 50.0),
    st.floats(0.0, 2.0),
    st.floats(0.0, 0.05),
    st.floats(0.0, 3.0),
    st.sampled_from([1, -1]),
)
def test_power_balance_random_nail_headers(m3, m2, m5, j5, cw, sense):
    nh = NailHeader(m3=m3, m2=m2, m5=m5, j_s5=j5, counterweight=cw, spring_sense=sense)
    phi = PHI[(np.abs(np.sin(PHI)) > 1e-3)][::7]
    m = nh.motion(phi, speed=nh.omega)
    model = nh.force_model()
    res = kinetostatics(model, m)
    rhs = kinetic_energy_rate(model, m) - applied_power(model, m)
    assert np.max(np.abs(res.torque * m.omega - rhs)) <= 1e-9 * np.max(np.abs(rhs))


def test_upsetting_acts_on_the_advancing_stroke_for_analog_and_real_motion():
    """The crank turns clockwise: the punch advances into the blank for phi just above 0
    (clockwise angle just below 360 deg). An analog motion must put the force there too."""
    nh = NailHeader()
    phi = np.deg2rad(np.array([-20.0, -5.0, -1.0, 1.0, 5.0, 20.0]))
    real = np.asarray(nh.upsetting(nh.motion(phi, speed=nh.omega)))
    analog = np.asarray(nh.upsetting(nh.motion(phi)))
    np.testing.assert_array_equal(analog, real)
    # approaching the outer dead centre clockwise = phi decreasing towards 0 from above; the
    # contact begins within h = 3 mm of it (phi about 14.8 deg)
    assert np.all(real[3:5] > 0) and np.all(real[[0, 1, 2, 5]] == 0)

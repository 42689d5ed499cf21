"""A problem's refinement slots allocated once (``Problem(slots=...)``): one program for the
starts and every refinement round, multipliers carried into a larger program, and the same
certified optimum as the growing ladder of programs."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.errors import MechanismError
from mechsynth.synthesis import transcription as T

W = ms.rpm(300)
PEAK_V = ob.peak_velocity("slider")
PEAK_A = ob.peak_acceleration("slider")
PRESSURE = ob.max_pressure_angle()


def _coarse(slots=None):
    """A maximized peak on a grid of 8 angles: its certification adds angles round after
    round (tests/test_synthesis_engine.py's refinement case)."""
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"offset": (-0.05, 0.05)},
        fixed={"crank": 0.05, "rod": 0.2},
        speed=W,
        angles=8,
        slots=slots,
    )
    return prob.maximize(PEAK_V + PEAK_A)


def _minimized(slots=None):
    """A minimized peak (an epigraph) with a pressure-angle bound on a coarse grid."""
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.02, 0.08), "rod": (0.15, 0.4), "offset": (-0.05, 0.05)},
        speed=W,
        angles=12,
        slots=slots,
    )
    return prob.minimize(PEAK_A).subject_to(ob.stroke() == 0.1, PRESSURE <= 0.45)


def _rocker(slots=None):
    """A four-bar's peak rocker acceleration on 8 angles: its certification adds an angle in
    each of seven rounds."""
    prob = ms.Problem(
        ms.FourBar,
        variables={"crank": (0.02, 0.06), "coupler": (0.1, 0.3), "rocker": (0.08, 0.2)},
        fixed={"ground": 0.2},
        speed=W,
        angles=8,
        slots=slots,
    )
    prob.minimize(ob.peak_angular_acceleration("rocker"))
    return prob.subject_to(ob.min_transmission_angle() >= ms.deg(40))


def test_slots_are_checked_and_copied():
    with pytest.raises(MechanismError, match="slots"):
        _coarse(slots=0)
    with pytest.raises(MechanismError, match="slots"):
        _coarse(slots="8")
    with pytest.raises(MechanismError, match="slots"):
        _coarse(slots=2.5)
    prob = _coarse(slots=8)
    assert prob.slots == 8 and prob.copy().slots == 8 and _coarse().slots is None
    assert prob._transcription().n_extra == 8 and _coarse()._transcription().n_extra == 16


@pytest.mark.parametrize("make", [_coarse, _minimized, _rocker])
def test_fixed_slots_build_one_program_for_the_same_certified_optimum(make):
    T.clear_cache()
    ladder = make().solve(starts=2)
    T.clear_cache()
    fixed = make(slots=16).solve(starts=2)
    info = T.cache_info()
    assert ladder.success and fixed.success, fixed.report()
    assert fixed.certification.certified and fixed.certification.refinement_rounds >= 1
    assert info["structures"] == 1 and info["solvers"] == 1
    assert fixed.value == pytest.approx(ladder.value, rel=1e-8)
    for k, v in ladder.variables.items():
        assert fixed.variables[k] == pytest.approx(v, rel=1e-6, abs=1e-9)
    # the certificate is the same: the dense maximum of the objective is the reported value
    m = fixed.design.motion(ms.cycle(100_000), speed=W)
    if make is _coarse:
        dense = np.abs(m.slider.velocity).max() + np.abs(m.slider.acceleration).max()
        assert fixed.value == pytest.approx(dense, rel=1e-8)
    elif make is _rocker:
        assert fixed.value == pytest.approx(np.abs(m.links["rocker"].epsilon).max(), rel=1e-8)
    else:
        assert fixed.value == pytest.approx(np.abs(m.slider.acceleration).max(), rel=1e-8)


def test_a_full_program_moves_its_angles_then_grows():
    """Four slots, the seven angles the ladder adds: an angle found near an earlier one of
    the same peak takes its slot for half the rounds (the peak slides along it here), then
    angles are added and the program grows once (to twice its slots). The same optimum,
    certified."""
    T.clear_cache()
    reference = _rocker().solve(starts=1)
    T.clear_cache()
    res = _rocker(slots=4).solve(starts=1)
    assert reference.success and res.success and res.certification.certified
    assert res.value == pytest.approx(reference.value, rel=1e-8)
    assert len(res.certification.refined_angles) > 4
    assert T.cache_info()["structures"] == 2
    m = res.design.motion(ms.cycle(100_000), speed=W)
    dense = np.abs(m.links["rocker"].epsilon).max()
    assert res.value == pytest.approx(dense, rel=1e-8)


def test_carry_maps_each_row_to_the_same_constraint():
    prob = _minimized()
    small, large = prob._transcription(4), prob._transcription(8)
    n_base = len(prob.base_angles)
    rng = np.random.default_rng(1)
    lam_x = rng.random(small.x.numel())
    lam_g = rng.random(small.lbg.size) + 1.0  # nonzero everywhere
    cx, cg = large.carry((lam_x, lam_g), small)
    assert np.array_equal(cx, lam_x) and cg.size == large.lbg.size
    # every row of the small program lands once, with its multiplier, on its key's row
    keys_small, keys_large = small.row_keys(), large.row_keys()
    assert len(set(keys_large)) == len(keys_large)
    where = {k: i for i, k in enumerate(keys_large)}
    for j, k in enumerate(keys_small):
        assert cg[where[k]] == lam_g[j]
    # the per-angle rows: branch b, slot s of an epigraph at b * (n_base + slots) + s
    epi = [i for i, (kind, s) in enumerate(zip(small.g_kinds, small.g_slots)) if s >= 0]
    first = epi[0]
    for b in range(2):
        for s in (0, n_base - 1, n_base + 3):
            j = first + b * (n_base + 4) + s
            i = where[keys_small[j]]
            assert i == epi[0] + b * (n_base + 8) + s
            assert large.g_slots[i] == s
    # the new slots' rows start at zero
    new = large.g_slots >= n_base + 4
    assert new.any() and np.all(cg[new] == 0.0)
    assert np.count_nonzero(cg) == lam_g.size

"""A warm re-solve of a refinement round (fixed slots) starts with each epigraph variable
raised to its largest row over the new grid (``Transcription.lift_epigraphs``): the design
unchanged, the added angles' rows feasible, the unused slots ignored."""

import numpy as np
import pytest
from test_refinement_slots import W, _minimized, _rocker  # the same coarse-grid problem

import mechsynth as ms
from mechsynth.synthesis import solvers as SV
from mechsynth.synthesis import transcription as T


def test_lift_raises_each_epigraph_to_its_largest_row_on_the_grid():
    prob = _minimized(slots=4)
    tr = prob._transcription()
    assert tr.n_epi == 2
    base = np.asarray(prob.base_angles)
    # two refinement angles used, the other two slots repeat the first angle
    grid = np.concatenate([base, [0.3, 4.0]])
    z = np.array([0.5, 0.4, 0.6])
    mech = SV._design(prob, tr, z)
    motion = mech.motion(grid, speed=W)
    peaks = [float(np.max(a.q(mech, motion))) for a in tr.epigraphs]
    t_scales = np.array([0.5 * peaks[0], peaks[1]])
    scales = (1.0, t_scales, np.ones(len(prob.constraints)))
    P = tr.parameter_vector(grid, *scales)
    x = np.concatenate([z, [0.1, 1.5]])  # the first below its rows, the second above them
    lifted = tr.lift_epigraphs(x, P, grid.size)
    assert np.array_equal(lifted[:3], z)
    # the rows q / T - tau <= 0: the first raised to max q / T (= 2), the second kept
    assert lifted[3] == pytest.approx(2.0, rel=1e-12) and lifted[4] == 1.5
    assert np.array_equal(x, np.concatenate([z, [0.1, 1.5]]))  # the input is not changed
    # the first peak's true angle in the last slot: counted only when the grid reaches it
    dense = ms.cycle(3600)
    q = tr.epigraphs[0].q(mech, mech.motion(dense, speed=W))
    top = float(dense[np.argmax(np.max(q, axis=0))])
    far = np.concatenate([base, [0.3, top]])
    P2 = tr.parameter_vector(far, *scales)
    short = far[: base.size + 1]
    want = float(np.max(tr.epigraphs[0].q(mech, mech.motion(short, speed=W)))) / t_scales[0]
    assert tr.lift_epigraphs(x, P2, short.size)[3] == pytest.approx(want, rel=1e-12)
    assert tr.lift_epigraphs(x, P2, far.size)[3] == pytest.approx(
        float(np.max(q)) / t_scales[0], rel=1e-12
    )
    assert want < float(np.max(q)) / t_scales[0] * (1 - 1e-6)


def test_warm_rounds_of_fixed_slots_reach_the_same_certified_optimum(monkeypatch):
    """The lift only moves the warm starts: the same certified optimum as without it (and as
    the ladder of programs), in fewer re-solve iterations (measured: 67 against 79)."""
    T.clear_cache()
    lifted = _rocker(slots=4).solve(starts=1)
    monkeypatch.setattr(T.Transcription, "lift_epigraphs", lambda self, x, P, n: x)
    plain = _rocker(slots=4).solve(starts=1)
    ladder = _rocker().solve(starts=1)
    for r in (lifted, plain, ladder):
        assert r.success and r.certification.certified, r.report()
        assert r.value == pytest.approx(ladder.value, rel=1e-8)
    assert lifted.certification.refinement_iterations < plain.certification.refinement_iterations
    m = lifted.design.motion(ms.cycle(100_000), speed=W)
    assert lifted.value == pytest.approx(np.abs(m.links["rocker"].epsilon).max(), rel=1e-8)

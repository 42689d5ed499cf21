"""The synthesis engine's parts: problem validation, atoms of every kind inside IPOPT, grid
refinement, the vectorized population evaluation, results as JSON and figures."""

import json

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.jsonutil import dumps
from mechsynth.synthesis import STATUSES
from mechsynth.synthesis.solvers import _BatchEvaluator

W = ms.rpm(300)


def _sc_problem(**kw):
    return ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.02, 0.08), "rod": (0.15, 0.4), "offset": (-0.05, 0.05)},
        speed=W,
        **kw,
    )


def test_problem_validation():
    with pytest.raises(ValueError, match="no parameter 'length'"):
        ms.Problem(ms.SliderCrank, variables={"length": (0, 1)})
    with pytest.raises(ValueError, match="lower < upper"):
        ms.Problem(ms.SliderCrank, variables={"crank": (0.2, 0.1)}, fixed={"rod": 1.0})
    with pytest.raises(ValueError, match="give rod"):
        ms.Problem(ms.SliderCrank, variables={"crank": (0.1, 0.2)})
    with pytest.raises(ValueError, match="both a variable and fixed"):
        ms.Problem(ms.SliderCrank, variables={"crank": (0.1, 0.2)}, fixed={"crank": 0.1, "rod": 1})
    with pytest.raises(ValueError, match="speed"):
        ms.Problem(ms.SliderCrank, variables={"crank": (0.1, 0.2)}, fixed={"rod": 1}, speed=0.0)
    prob = _sc_problem()
    with pytest.raises(TypeError, match="constraints such as"):
        prob.subject_to(ob.stroke())
    with pytest.raises(ValueError, match="no objective"):
        prob.solve()
    with pytest.raises(ValueError, match="method"):
        prob.minimize(ob.stroke()).solve(method="newton")


def test_builder_chains_and_copies():
    prob = _sc_problem().minimize(ob.peak_velocity("slider")).subject_to(ob.stroke() >= 0.1)
    twin = prob.copy().subject_to(ob.max_pressure_angle() <= 0.5)
    assert len(prob.constraints) == 1 and len(twin.constraints) == 2
    vals = prob.evaluate({"crank": 0.05, "rod": 0.2, "offset": 0.0})
    assert vals["stroke(slider)"] == pytest.approx(0.1)
    assert "peak_velocity(slider)" in repr(prob)


def test_point_magnitude_rms_and_generic_stroke_in_ipopt():
    """Square-branch epigraph (|a| of a point), an rms atom and a max-min range together."""
    prob = _sc_problem()
    prob.minimize(
        ob.peak_acceleration("B")
        + 0.0 * ob.CycleMeasure("rms_a", lambda m, mo: mo.slider.acceleration, "rms")
    )
    prob.subject_to(ob.stroke("B") == 0.09, ob.max_pressure_angle() <= ms.deg(20))
    res = prob.solve(starts=3)
    assert res.success, res.report()
    sc = res.design
    m = sc.motion(ms.cycle(200_000), speed=W)
    assert res.value == pytest.approx(np.abs(m.slider.acceleration).max(), rel=1e-8)
    assert res.constraints[0].value == pytest.approx(np.ptp(m.slider.position), rel=1e-8)
    assert sc.stroke == pytest.approx(0.09, rel=1e-7)


def test_rms_objective_matches_quadrature():
    prob = _sc_problem(angles=96)
    rms = ob.CycleMeasure("rms_a", lambda m, mo: mo.slider.acceleration, "rms", "m/s^2")
    prob.minimize(rms).subject_to(ob.stroke() == 0.1)
    res = prob.solve(starts=2)
    assert res.success, res.report()
    # rms of a smooth periodic function: the uniform-grid rule is exact to round-off
    m = res.design.motion(ms.cycle(4096), speed=W)
    assert res.value == pytest.approx(np.sqrt(np.mean(m.slider.acceleration**2)), rel=1e-10)


def test_maximized_peak_and_coarse_grid_refinement():
    """A peak on the non-epigraph side (maximized) and a coarse grid that needs many refinement
    angles (more than the 16 pre-allocated slots)."""
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"offset": (-0.05, 0.05)},
        fixed={"crank": 0.05, "rod": 0.2},
        speed=W,
        angles=8,
    )
    prob.maximize(ob.peak_velocity("slider") + ob.peak_acceleration("slider"))
    res = prob.solve(starts=2)
    assert res.success, res.report()
    m = res.design.motion(ms.cycle(100_000), speed=W)
    dense = np.abs(m.slider.velocity).max() + np.abs(m.slider.acceleration).max()
    assert res.value == pytest.approx(dense, rel=1e-8)
    assert res.certification.refinement_rounds >= 1


def test_unused_refinement_slots_add_no_constraints():
    """The refinement slots not yet holding an angle repeat a grid angle; their epigraph rows are
    left free, so an active peak is never one constraint repeated up to 17 times (a degenerate
    program)."""
    prob = _sc_problem(angles=32)
    prob.minimize(ob.peak_acceleration("slider")).subject_to(ob.max_pressure_angle() <= 0.5)
    tr = prob._transcription(16)
    n_slots = 32 + 16
    epi = np.array([k[0] == "epigraph" for k in tr.g_kinds])
    assert epi.sum() % n_slots == 0
    branches = epi.sum() // n_slots
    for used in (32, 40, 48):
        lbg, ubg = tr.g_bounds(used)
        free = ~np.isfinite(lbg) & ~np.isfinite(ubg)
        assert free.sum() == branches * (n_slots - used)
        assert np.all(epi[free])
        assert np.array_equal(ubg[~free], tr.ubg[~free])


def test_time_ratio_inequality():
    prob = _sc_problem()
    prob.maximize(ob.stroke()).subject_to(ob.time_ratio() <= 1.1, ob.max_pressure_angle() <= 0.6)
    res = prob.solve(starts=3)
    assert res.success, res.report()
    assert res.design.time_ratio <= 1.1 * (1 + 1e-7)


def test_batch_evaluator_equals_single_designs():
    prob = _sc_problem()
    prob.minimize(ob.peak_acceleration("slider")).subject_to(
        ob.stroke() == 0.1, ob.max_pressure_angle() <= 0.5
    )
    ev = _BatchEvaluator(prob, 128, 1e-4)
    Z = np.random.default_rng(2).random((40, 3))
    f, rows = ev(Z)
    vals = ev.tr.params_of(Z)
    n_valid = 0
    for j, (a, b, e) in enumerate(vals):
        if b - a - abs(e) < 1e-3 * b:
            assert f[j] == np.inf
            continue
        n_valid += 1
        sc = ms.SliderCrank(crank=a, rod=b, offset=e)
        mo = sc.motion(ms.cycle(128), speed=W)
        assert f[j] == pytest.approx(np.abs(mo.slider.acceleration).max(), rel=1e-12)
        assert rows[0, j] == pytest.approx(sc.stroke, rel=1e-12)
        assert rows[1, j] == pytest.approx(mo.pressure_angle.max(), rel=1e-12)
    assert n_valid > 10


def test_result_json_report_plot():
    prob = _sc_problem().minimize(ob.peak_velocity("slider")).subject_to(ob.stroke() == 0.1)
    res = prob.solve(starts=2, method="slsqp")
    assert res.success and res.status in STATUSES
    data = json.loads(dumps(res.to_dict()))
    assert data["mechanism"] == "SliderCrank" and data["certification"]["method"] == "slsqp"
    assert set(data["variables"]) == {"crank", "rod", "offset"}
    text = res.report()
    assert "certified: True" in text and "stroke(slider) == 0.1" in text
    fig = res.plot()
    assert len(fig.axes) == 4


def _bounded_problem(bound, variables=None):
    prob = ms.Problem(
        ms.SliderCrank,
        variables=variables or {"crank": (0.02, 0.08), "rod": (0.15, 0.4), "offset": (-0.05, 0.05)},
        speed=W,
        angles=32,
    )
    return prob.minimize(PEAK_ACC).subject_to(STROKE == 0.1, PRESSURE <= bound)


PEAK_ACC, STROKE, PRESSURE = (
    ob.peak_acceleration("slider"),
    ob.stroke("slider"),
    ob.max_pressure_angle(),
)


def test_one_build_serves_every_bound_of_a_structure():
    """Build once, solve many: problems that differ only in their constraints' bounds (a Pareto
    front's epsilon levels) and their variables' bounds share one expression graph and one
    IPOPT solver (the bounds are parameters of the program), and give the optima of solves
    each with a build of its own."""
    from mechsynth.synthesis import transcription as T

    cases = [
        (0.2, None),
        (0.15, None),
        (0.18, {"crank": (0.03, 0.07), "rod": (0.2, 0.3), "offset": (-0.04, 0.04)}),
    ]
    T.clear_cache()
    shared = [_bounded_problem(b, v).solve(starts=1) for b, v in cases]
    info = T.cache_info()
    assert info["structures"] == 1 and info["solvers"] == 1
    assert info["variants"] <= 1  # the warm start's options, on the same derivatives
    for (b, v), res in list(zip(cases, shared))[1:]:
        T.clear_cache()
        own = _bounded_problem(b, v).solve(starts=1)
        assert res.success and own.success
        assert res.value == pytest.approx(own.value, rel=1e-9)
        for k in res.variables:
            assert res.variables[k] == pytest.approx(own.variables[k], rel=1e-6, abs=1e-9)
    # each optimum respects its own bounds (the bounds really are the solver's parameters)
    for (b, _), res in zip(cases, shared):
        assert res.constraints[1].value == pytest.approx(b, rel=1e-6)  # active
    assert shared[2].variables["rod"] == pytest.approx(0.3)  # its own box
    assert shared[0].value < shared[1].value * (1 - 1e-5)  # the tighter bound costs


def test_structures_are_few_and_not_held_by_problems():
    """The cache holds at most CACHE_SIZE structures (least recently used dropped), and a
    Problem holds none (many problems: flat memory)."""
    from mechsynth.synthesis import transcription as T

    T.clear_cache()
    problems = []
    for k in range(T.CACHE_SIZE + 2):
        prob = _sc_problem(angles=16 + k)  # a new grid size: a new structure
        prob.minimize(PEAK_ACC)
        problems.append(prob)
        prob._transcription(16)
    assert T.cache_info()["structures"] == T.CACHE_SIZE + 2
    assert T.cache_info()["cached"] == T.CACHE_SIZE
    assert all(
        not any("Transcription" in type(v).__name__ for v in p._cache.values()) for p in problems
    )
    # the same structure again: served from the cache
    again = _sc_problem(angles=16 + T.CACHE_SIZE + 1).minimize(PEAK_ACC)
    again._transcription(16)
    assert T.cache_info()["structures"] == T.CACHE_SIZE + 2
    # another measure object is another structure (measures are keyed by identity)
    _sc_problem(angles=16).minimize(ob.peak_acceleration("slider"))._transcription(16)
    assert T.cache_info()["structures"] == T.CACHE_SIZE + 3


def test_the_cache_keeps_built_solvers_within_its_instruction_budget(monkeypatch):
    """Memory follows the built Hessians: beyond CACHE_INSTRUCTIONS the least recently used
    structures are dropped (never the newest)."""
    from mechsynth.synthesis import transcription as T

    T.clear_cache()
    a = _sc_problem(angles=16).minimize(PEAK_ACC)._transcription(16)
    a.solver("ipopt")
    first = a.structure
    assert first.weight > 0
    monkeypatch.setattr(T, "CACHE_INSTRUCTIONS", first.weight + 1)
    b = _sc_problem(angles=17).minimize(PEAK_ACC)._transcription(16)
    assert T.cache_info()["cached"] == 2  # b's solver not built yet: no weight
    b.solver("ipopt")
    # a transcription still uses the first (a solve in progress): kept, dropping frees nothing
    assert T.cache_info()["cached"] == 2
    del a
    c = _sc_problem(angles=18).minimize(PEAK_ACC)._transcription(16)
    c.solver("ipopt")
    cached = list(T._STRUCTURES.values())
    assert first not in cached and c.structure in cached

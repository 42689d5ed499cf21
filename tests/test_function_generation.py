"""Function generation (Freudenstein): exact, least squares and certified min-max designs."""

from __future__ import annotations

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.synthesis.freudenstein import (
    chebyshev_spacing,
    four_bar_lengths,
    freudenstein_k,
    slider_crank_coefficients,
    slider_crank_lengths,
)
from mechsynth.synthesis.function_expr import parse_function

# a non-Grashof design (triple-rocker) and a crank-rocker, on both branches
FOUR_BARS = [
    dict(crank=1.0, coupler=3.5, rocker=3.0, ground=4.0),
    dict(crank=2.2, coupler=1.7, rocker=2.5, ground=3.0),
]


def _rocker(design, phi):
    return design.motion(np.asarray(phi, float)).links["rocker"].angle


def _wrap(a):
    return np.arctan2(np.sin(a), np.cos(a))


# ------------------------------------------------------------------ the equations
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_freudenstein_equation_holds_on_the_four_bar_motion(branch):
    """The equation's signs and constants checked against FourBar.motion, not copied."""
    a, b, c, d = 1.0, 3.5, 3.0, 4.0
    fb = ms.FourBar(a, b, c, d, branch, False)
    phi = np.linspace(0.2, 2.5, 50)
    psi = _rocker(fb, phi)
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    residual = k1 * np.cos(psi) - k2 * np.cos(phi) + k3 - np.cos(phi - psi)
    assert np.max(np.abs(residual)) < 1e-12


def test_chebyshev_spacing_is_the_zeros_of_the_chebyshev_polynomial():
    for n in (3, 4, 7):
        x = chebyshev_spacing(2.0, 5.0, n)
        roots = np.sort(np.polynomial.chebyshev.Chebyshev.basis(n).roots())
        assert np.allclose(x, 3.5 + 1.5 * roots, atol=1e-12)
    # three points on [1, 2]: 1.5 -+ cos(30 deg) / 2
    assert np.allclose(chebyshev_spacing(1.0, 2.0, 3), [1.0669873, 1.5, 1.9330127], atol=1e-7)


@pytest.mark.parametrize("dims", FOUR_BARS)
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_three_pairs_sampled_from_a_four_bar_recover_it(dims, branch):
    fb = ms.FourBar(**dims, branch=branch, full_turn=False)
    phi = np.array([0.3, 0.9, 1.4])
    pairs = np.column_stack([phi, _rocker(fb, phi)])
    fg = ms.function_generation(pairs=pairs, ground=dims["ground"])
    assert fg.method == "exact" and fg.design.branch == branch
    for name, value in dims.items():
        assert abs(getattr(fg.design, name) - value) < 1e-9 * value
    assert fg.max_error < 1e-9
    assert np.allclose(_rocker(fg.design, pairs[:, 0]), pairs[:, 1], atol=1e-9)


def test_negative_lengths_are_the_links_turned_half_a_turn():
    """Pairs measured with the crank and the rocker half a turn away: K1, K2 < 0; the design
    is the same four-bar, its angles shifted by pi."""
    fb = ms.FourBar(1.0, 3.5, 3.0, 4.0, "open", False)
    phi = np.array([0.3, 0.9, 1.4])
    psi = _rocker(fb, phi)
    k = freudenstein_k(phi + np.pi, psi + np.pi)
    assert k[0] < 0 and k[1] < 0
    a, b2, c, sa, sc = four_bar_lengths(k, 4.0)
    assert np.allclose([a, np.sqrt(b2), c, sa, sc], [1.0, 3.5, 3.0, np.pi, np.pi], atol=1e-9)
    fg = ms.function_generation(pairs=np.column_stack([phi + np.pi, psi + np.pi]), ground=4.0)
    assert abs(fg.design.crank - 1.0) < 1e-9 and abs(fg.design.rocker - 3.0) < 1e-9
    assert fg.max_error < 1e-9


def test_least_squares_on_exact_pairs_is_exact():
    fb = ms.FourBar(**FOUR_BARS[1], branch="crossed", full_turn=False)
    phi = np.linspace(0.1, 1.5, 9)
    fg = ms.function_generation(pairs=np.column_stack([phi, _rocker(fb, phi)]), ground=3.0)
    assert fg.method == "least squares"
    assert abs(fg.design.coupler - 1.7) < 1e-9 and fg.max_error < 1e-9


@pytest.mark.parametrize("offset", [0.0, 0.03, -0.05])
def test_slider_crank_recovered_from_pairs(offset):
    sc = ms.SliderCrank(crank=0.1, rod=0.35, offset=offset)
    phi = np.array([0.4, 1.3, 2.1, 2.9, 3.3])
    s = sc.motion(phi).slider.position
    u = s - s[0]
    coef = slider_crank_coefficients(phi[:3], u[:3], 0.1)
    s0, e, rod2 = slider_crank_lengths(coef, 0.1)
    assert abs(s0 - s[0]) < 1e-12 and abs(e - offset) < 1e-12 and abs(rod2 - 0.35**2) < 1e-12
    for pairs in (np.column_stack([phi[:3], s[:3]]), np.column_stack([phi, s])):
        fg = ms.function_generation(pairs=pairs, mechanism="slider-crank", crank=0.1)
        assert abs(fg.design.rod - 0.35) < 1e-9 and abs(fg.design.offset - offset) < 1e-9
        assert fg.max_error < 1e-10


# ------------------------------------------------------------------ function form
def _log_design(**kw):
    opts = dict(x=(1.0, 10.0), input_range=ms.deg(60), output_range=ms.deg(90))
    opts.update(kw)
    return ms.function_generation("log10(x)", **opts)


def test_exact_design_passes_its_precision_points_and_its_error_is_the_true_one():
    fg = _log_design(phases=(ms.deg(120), ms.deg(20)))
    assert fg.method == "exact"
    xp = chebyshev_spacing(1.0, 10.0, 3)
    assert np.allclose(fg.precision_x, xp)
    # the design goes through the precision points (its own motion)
    pp = fg.precision_points
    assert np.max(np.abs(_wrap(_rocker(fg.design, pp[:, 0]) - pp[:, 1]))) < 1e-9
    # the error curve is the motion minus the ideal, evaluated here independently
    phi0, psi0 = fg.phases
    x = np.linspace(1.0, 10.0, 5001)
    phi = phi0 + (x - 1.0) / 9.0 * ms.deg(60)
    ideal = psi0 + np.log10(x) * ms.deg(90)
    dense = _wrap(_rocker(fg.design, phi) - ideal)
    assert np.allclose(np.interp(fg.x, x, dense), fg.error, atol=1e-6)
    assert abs(fg.max_error - np.max(np.abs(dense))) < 1e-4 * np.max(np.abs(dense))
    # three precision points: the error changes sign three times, at them
    signs = np.flatnonzero(np.diff(np.sign(dense)) != 0)
    assert len(signs) == 3
    assert np.allclose(np.sort(x[signs]), xp, atol=2 * (x[1] - x[0]))
    assert np.allclose(fg.error_y, fg.error / ms.deg(90))
    assert fg.min_transmission_angle == pytest.approx(ms.deg(32.24), abs=ms.deg(0.01))


def test_error_curve_matches_a_dense_evaluation_on_the_same_points():
    fg = _log_design(phases=(ms.deg(120), ms.deg(20)), n_eval=801)
    phi = fg.phases[0] + (fg.x - 1.0) / 9.0 * ms.deg(60)
    ideal = fg.phases[1] + np.log10(fg.x) * ms.deg(90)
    assert np.allclose(fg.error, _wrap(_rocker(fg.design, phi) - ideal), atol=1e-12)


def test_phase_scan_picks_an_admissible_design():
    fg = _log_design()
    assert fg.min_transmission_angle >= ms.deg(30)
    lengths = [fg.design.crank, fg.design.coupler, fg.design.rocker, fg.design.ground]
    assert max(lengths) / min(lengths) <= 20
    # the listed alternatives: distinct, most accurate first, the chosen one at their head
    sol = fg.solutions
    assert len(sol) == 20 and sol[0]["max_error"] == pytest.approx(fg.max_error, rel=1e-9)
    assert all(a["max_error"] <= b["max_error"] for a, b in zip(sol, sol[1:]))
    assert len({(round(r["crank"], 9), round(r["rocker"], 9)) for r in sol}) == 20
    assert all(r["min_transmission_angle"] >= ms.deg(30) - 1e-9 for r in sol)
    crank = _log_design(require_crank=True)
    assert crank.design.full_turn and crank.design.grashof.crank_rotates


def test_slider_crank_function_generator():
    fs = ms.function_generation(
        "x**2", x=(0, 1), input_range=ms.deg(120), output_range=0.5, mechanism="slider-crank",
        phases=(ms.deg(120),),
    )  # fmt: skip
    pp = fs.precision_points
    assert np.allclose(fs.design.motion(pp[:, 0]).slider.position, pp[:, 1], atol=1e-12)
    x = fs.x
    s = fs.design.motion(fs.phases[0] + x * ms.deg(120)).slider.position
    assert np.allclose(fs.error, s - fs.phases[1] - 0.5 * x**2, atol=1e-12)
    assert np.allclose(fs.error_y, fs.error / 0.5)


def test_linkage_form_moves_as_the_design():
    fg = _log_design(phases=(ms.deg(120), ms.deg(20)))
    phi = fg.phases[0] + np.linspace(0, ms.deg(60), 50)
    lm = fg.linkage.motion(phi)
    assert np.allclose(_wrap(lm.links["O2B"].angle - _rocker(fg.design, phi)), 0, atol=1e-12)
    fs = ms.function_generation(
        "x**2", x=(0, 1), input_range=ms.deg(120), output_range=0.5, mechanism="slider-crank",
        phases=(ms.deg(120),),
    )  # fmt: skip
    phi = np.linspace(0, 6, 40)
    s_link = fs.linkage.motion(phi).sliders["B"].position
    assert np.allclose(s_link, fs.design.motion(phi).slider.position, atol=1e-12)


def test_design_file_reads_back(tmp_path):
    from mechsynth.synthesis.design_file import load_design

    fg = _log_design(phases=(ms.deg(120), ms.deg(20)))
    files = fg.write(tmp_path)
    assert {f.name for f in files} == {
        "design.toml", "error.csv", "precision_points.csv", "solutions.csv", "result.json",
        "error.png", "problem.toml",
    }  # fmt: skip
    back = load_design(tmp_path / "design.toml").design
    assert back == fg.design


def test_error_figure_has_no_layout_problems():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechsynth.plotting import layout_problems

    pairs = [(0.3, 1.9), (0.9, 2.2), (1.4, 2.5), (1.6, 2.6)]
    for fg in (_log_design(phases=(ms.deg(120), ms.deg(20))), ms.function_generation(pairs=pairs)):
        fig = fg.plot()
        assert layout_problems(fig) == []
        plt.close(fig)


# ------------------------------------------------------------------ min-max
def test_min_max_lowers_the_certified_worst_error_and_equioscillates():
    fo = _log_design(phases=(ms.deg(120), ms.deg(20)), points=5, optimize=True,
                     min_transmission=None, n_eval=2001)  # fmt: skip
    assert fo.method == "min-max" and fo.solve.success and fo.solve.certification.certified
    assert fo.max_error < 0.2 * fo.start_max_error
    # the certifier searched the input range only (the triple rocker cannot even be assembled
    # over a whole turn): every angle it added, and the worst one, lie in [0, input range]
    cert = fo.solve.certification
    span = ms.deg(60)
    assert all(0.0 <= a <= span for a in cert.refined_angles)
    assert all(0.0 <= p.angle <= span for p in cert.peaks)
    with pytest.raises(ms.MechanismError):
        fo.design.motion(ms.cycle(360))
    # the certified peak is the error curve's maximum (the dense curve is evaluated apart)
    assert abs(fo.solve.value - fo.max_error) < 1e-6 * fo.max_error
    # alternating extrema of one magnitude (to 0.1 % on the 2001-point grid): five, ends included
    e = fo.error
    inner = [i for i in range(1, e.size - 1) if (e[i] - e[i - 1]) * (e[i + 1] - e[i]) <= 0]
    ext = [0, *inner, e.size - 1]
    top = [i for i in ext if abs(e[i]) > (1 - 1e-3) * fo.max_error]
    assert len(top) >= 5
    assert np.all(np.diff(np.sign(e[top])) != 0)  # alternating
    # the design really is a four-bar of the usual kind, with the reported phases
    x = np.linspace(1, 10, 3001)
    ideal = fo.phases[1] + np.log10(x) * ms.deg(90)
    true = _rocker(fo.design, fo.phases[0] + (x - 1) / 9 * ms.deg(60))
    assert abs(np.max(np.abs(_wrap(true - ideal))) - fo.max_error) < 1e-6


def test_min_max_keeps_the_transmission_limit_and_a_slider_crank_too():
    fo = _log_design(phases=(ms.deg(120), ms.deg(20)), points=4, optimize=True)
    assert fo.solve.success
    assert fo.min_transmission_angle >= ms.deg(30) * (1 - 1e-6) - 1e-9
    assert fo.max_error < fo.start_max_error
    fs = ms.function_generation(
        "x**2", x=(0, 1), input_range=ms.deg(120), output_range=0.5, mechanism="slider-crank",
        phases=(ms.deg(120),), points=4, optimize=True,
    )  # fmt: skip
    assert fs.solve.success and fs.max_error < fs.start_max_error


@pytest.mark.slow
def test_min_max_is_local_more_starts_in_a_wider_box_do_better():
    wide = {"crank": (0.05, 5.0), "coupler": (0.2, 10.0), "rocker": (0.02, 5.0),
            "phi0": (0.0, 2 * np.pi), "psi0": (-np.pi, np.pi)}  # fmt: skip
    kw = dict(phases=(ms.deg(120), ms.deg(20)), points=5, optimize=True, min_transmission=None)
    near = _log_design(**kw)
    far = _log_design(**kw, starts=24, bounds=wide)
    assert far.solve.success and far.solve.certification.certified
    assert ms.to_deg(near.max_error) == pytest.approx(0.92369, abs=1e-4)
    assert ms.to_deg(far.max_error) < 0.79  # 0.7809 deg, the rocker at its bound of 5 m
    assert far.solve.on_bounds() == {"rocker": "upper"}


def test_bad_bounds_are_named():
    with pytest.raises(ms.MechanismError, match="bounds must be a dict"):
        _log_design(phases=(ms.deg(120), ms.deg(20)), optimize=True, bounds=[1, 2])
    with pytest.raises(ms.MechanismError, match="outside its bounds"):
        _log_design(phases=(ms.deg(120), ms.deg(20)), optimize=True, bounds={"crank": (1, 2)})


def test_min_max_keeps_a_crank_that_turns():
    fo = _log_design(require_crank=True, optimize=True)
    assert fo.solve.success and fo.max_error < fo.start_max_error
    assert fo.design.full_turn and fo.design.grashof.crank_rotates
    fo.design.motion(ms.cycle(360))  # assembles over the whole turn


def test_a_solution_starts_a_problem_of_ones_own():
    """Any design can start an ms.Problem: here with a tighter transmission limit."""
    from mechsynth import objectives as ob
    from mechsynth.synthesis.function_minmax import minmax

    fg = _log_design(phases=(ms.deg(120), ms.deg(20)))
    g = fg.generator()
    t = (fg.x - 1.0) / 9.0 * ms.deg(60)  # the generator's input: rotation from phi0
    assert np.allclose(
        g.output(g.motion(t)) - fg.error,
        np.log10(fg.x) * ms.deg(90),  # output travel - error = the ideal travel
        atol=1e-12,
    )
    res = minmax(g, lambda t: np.log10(1 + 9 * t / ms.deg(60)) * ms.deg(90),
                 min_transmission=ms.deg(32))  # fmt: skip
    assert res.success and res.value < fg.max_error
    assert ob.min_transmission_angle().evaluate(res.design, np.linspace(0, ms.deg(60), 400)) \
        >= ms.deg(32) - 1e-6  # fmt: skip


# ------------------------------------------------------------------ failures
@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(spacing=[2.0, 2.0, 5.0]), "two equal precision points"),
        (dict(spacing=[2.0, 5.0, 11.0]), "outside the range"),
        (dict(input_range=ms.deg(400)), "below 360 deg"),
        (dict(output_range=0.0), "non-zero"),
        (dict(x=(0.0, 10.0)), "not finite"),
        (dict(x=(3.0, 3.0)), "must differ"),
        (dict(phases=(ms.deg(45), ms.deg(120))), "no valid design for these phases"),
        (dict(points=2), "points"),
        (dict(spacing="random"), "spacing"),
        (dict(min_transmission=ms.deg(89)), "no phases in a 5 deg scan"),
    ],
)
def test_bad_input_is_named(kwargs, message):
    with pytest.raises(ms.MechanismError, match=message):
        _log_design(**kwargs)


def test_more_bad_input():
    with pytest.raises(ms.MechanismError, match="f\\(x0\\) = f\\(x1\\)"):
        ms.function_generation("cos(x)", x=(-1, 1), input_range=1.0, output_range=1.0)
    with pytest.raises(ms.MechanismError, match="either a function or precision pairs"):
        ms.function_generation("x", x=(0, 1), pairs=[(0, 0), (1, 1), (2, 2)])
    with pytest.raises(ms.MechanismError, match="optimize needs a function"):
        ms.function_generation(pairs=[(0.3, 1.9), (0.9, 2.2), (1.4, 2.5)], optimize=True)
    with pytest.raises(ms.MechanismError, match="two equal precision points"):
        ms.function_generation(pairs=[(0.3, 1.9), (0.3, 2.2), (1.4, 2.5)])
    with pytest.raises(ms.MechanismError, match="at least 3 rows"):
        ms.function_generation(pairs=[(0.3, 1.9), (0.9, 2.2)])
    with pytest.raises(ms.MechanismError, match="mechanism"):
        _log_design(mechanism="cam")


def test_expressions_are_read_safely():
    assert parse_function("2*x^2 + sin(pi*x) - e")(1.5) == pytest.approx(
        2 * 1.5**2 + np.sin(np.pi * 1.5) - np.e
    )
    assert parse_function("-log10(x)")(100.0) == -2.0
    for bad, why in [
        ("log10(x", "cannot be parsed"),
        ("__import__('os')", "unknown function"),
        ("x.real", "Attribute"),
        ("(lambda: 1)()", "unknown function"),
        ("y + 1", "unknown name 'y'"),
        ("x if x else 1", "IfExp"),
        ("x[0]", "Subscript"),
        ("'a'", "only real numbers"),
        ("log(x, 2)", "exactly one argument"),
        ("x < 1", "Compare"),
        ("sin", "parentheses"),
        ("", "empty"),
    ]:
        with pytest.raises(ms.MechanismError, match=why):
            parse_function(bad)


def test_a_callable_function_works_as_its_expression():
    a = _log_design(phases=(ms.deg(120), ms.deg(20)))
    phases = (ms.deg(120), ms.deg(20))
    b = ms.function_generation(
        np.log10, x=(1.0, 10.0), input_range=ms.deg(60), output_range=ms.deg(90), phases=phases
    )
    assert b.function == "log10" and np.array_equal(a.error, b.error)

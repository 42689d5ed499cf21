"""The nomogram engine: forms, reading through the geometry, layout, ticks, accuracy report,
fitted charts, rendering, and ``ms.nomogram`` for a user's relation."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.nomograms import (
    Product,
    Sum,
    Var,
    determinant,
    parallel,
    proportional,
    z_chart,
)
from mechsynth.nomograms.fitting import Alignment, fitted
from mechsynth.nomograms.layout import apply, homography
from mechsynth.nomograms.ticks import number_text, tick_text, ticks
from mechsynth.plotting import layout_problems


def _collinear(nm, **values):
    """Largest distance (mm) of a block's third point from the line of the other two."""
    iso = nm.isopleth(**values)
    worst = 0.0
    for b in nm.blocks:
        p = [nm.scales[k].position(float(iso[k])) for k in b]
        d = p[1] - p[0]
        worst = max(worst, abs(d[0] * (p[2] - p[0])[1] - d[1] * (p[2] - p[0])[0]) / np.hypot(*d))
    return worst


# ------------------------------------------------------------------------------ forms
def test_parallel_scales_read_a_sum_both_ways():
    nm = parallel([Var("a", (0, 10)), Var("b", (0, 5))], Var("c", (0, 15)))
    assert nm.read(a=3, b=4) == pytest.approx(7, abs=1e-12)
    assert nm.read(a=3, c=7) == pytest.approx(4, abs=1e-12)  # any two give the third
    assert nm.read(a=np.array([0, 10]), b=np.array([0, 5])) == pytest.approx([0, 15], abs=1e-12)
    a = nm.accuracy
    assert a.max_error < 1e-11 and a.max_mm < 1e-9 and a.misses == 0 and a.points == 404


def test_chained_parallel_scales_go_through_turning_axes():
    nm = parallel([Var("a", (0, 1)), Var("b", (0, 2)), Var("c", (0, 3)), Var("d", (-1, 1))],
                  Var("s", (-1, 7)))
    turning = [k for k, s in nm.scales.items() if s.scale.turning]
    assert len(turning) == 2 and len(nm.blocks) == 3
    assert nm.read(a=0.5, b=0.5, c=0.5, d=0.5) == pytest.approx(2.0, abs=1e-12)
    assert nm.read(a=0.5, b=0.5, c=0.5, s=2.0) == pytest.approx(0.5, abs=1e-12)
    assert _collinear(nm, a=0.2, b=1.1, c=2.9, d=-0.3) < 1e-9
    assert nm.accuracy.max_error < 1e-12
    # supports are apart: no two vertical scales closer than 10 mm
    xs = sorted(float(s.position(s.domain[0])[0]) for s in nm.scales.values())
    assert min(np.diff(xs)) > 10.0


def test_log_parallel_chain_reads_a_product():
    nm = parallel(
        [Var("D", (1, 4), lambda d: 2 * np.log(d)), Var("S", (20, 200), np.log),
         Var("N", (4, 20), np.log)],
        Var("Q", (0.1 * 1 * 20 * 4, 0.1 * 16 * 200 * 20), np.log), constant=np.log(0.1))
    assert nm.read(D=2, S=100, N=10) == pytest.approx(0.1 * 4 * 100 * 10, rel=1e-12)
    assert nm.read(Q=400, S=100, N=10) == pytest.approx(2.0, rel=1e-12)


def test_z_chart_reads_a_product_and_keeps_its_corners():
    nm = z_chart(Var("T", (1e3, 1e5)), Var("F", (10, 100)), Var("W", (100, 1000)))
    assert nm.read(F=20, W=300) == pytest.approx(6000, rel=1e-12)
    assert nm.read(T=6000, W=300) == pytest.approx(20, rel=1e-12)
    x0, y0, x1, y1 = nm.paper.box
    T, F = nm.scales["T"], nm.scales["F"]
    assert T.position(1e3) == pytest.approx([x0, y0]) and T.position(1e5) == pytest.approx(
        [x0, y1])
    assert F.position(10) == pytest.approx([x1, y1]) and F.position(100) == pytest.approx(
        [x1, y0])
    # the diagonal runs from corner to corner: W's ends are T's low / F's high and back
    assert nm.read(F=100, W=100) == pytest.approx(1e4, rel=1e-12)


def test_proportional_chart_crosses_on_the_ratio():
    nm = proportional(Var("u", (1, 10)), Var("v", (1, 10)), Var("w", (1, 10)),
                      Var("t", (0.1, 100)))
    assert nm.read(u=2, v=4, w=3) == pytest.approx(6, rel=1e-12)
    assert nm.accuracy.max_relative < 1e-10 and nm.accuracy.misses == 0


def test_general_determinant_with_a_curved_scale_solves_a_quadratic():
    # z^2 + p z + q = 0: q on x = 0, p on x = 1, z on the conic (z/(1+z), -z^2/(1+z))
    nm = determinant(
        {"q": lambda q: (0 * q, q, 1 + 0 * q), "p": lambda p: (1 + 0 * p, p, 1 + 0 * p),
         "z": lambda z: (z, -z * z, 1 + z)},
        {"q": (-10, -0.5), "p": (-3, 3), "z": (0.1, 5.1)}, "z",
        model=lambda p, q: (-p + np.sqrt(p * p - 4 * q)) / 2)
    assert nm.read(p=1, q=-6) == pytest.approx(2.0, abs=1e-12)  # z^2 + z - 6 = (z + 3)(z - 2)
    assert nm.read(z=2, p=1) == pytest.approx(-6.0, abs=1e-11)
    assert nm.accuracy.max_error < 1e-11 and nm.accuracy.misses == 0


# ------------------------------------------------------------------------------ geometry
def test_homography_maps_the_four_corners_and_keeps_lines():
    src = np.array([[0, 0], [0, 1], [1, 2], [1, -1.0]])
    dst = np.array([[20, 30], [20, 250], [190, 250], [190, 30.0]])
    H = homography(src, dst)
    assert apply(H, np.c_[src, np.ones(4)]) == pytest.approx(dst)
    pts = apply(H, np.c_[np.array([[0.2, 0.1], [0.4, 0.5], [0.6, 0.9]]), np.ones(3)])
    d1, d2 = pts[1] - pts[0], pts[2] - pts[0]
    assert abs(d1[0] * d2[1] - d1[1] * d2[0]) < 1e-9 * np.hypot(*d1) * np.hypot(*d2)
    with pytest.raises(ms.MechanismError, match="degenerate"):
        homography(np.array([[0, 0], [1, 1], [2, 2], [3, 3.0]]), dst)


def test_position_and_value_are_inverse_and_scales_stay_on_the_page():
    nm = z_chart(Var("T", (1e3, 1e5)), Var("F", (10, 100)), Var("W", (100, 1000)))
    W = nm.scales["W"]
    vals = np.array([100.0, 233.3, 999.0])
    assert W.value(W.position(vals)) == pytest.approx(vals, rel=1e-9)
    off = W.position(500.0) + np.array([0.3, -0.2])  # a point beside the scale: its foot
    assert 480 < W.value(off) < 520
    x0, y0, x1, y1 = nm.paper.box
    for s in nm.scales.values():
        p = s.position(s.scale.sample(50))
        assert np.all(p[:, 0] >= x0 - 1e-9) and np.all(p[:, 0] <= x1 + 1e-9)
        assert np.all(p[:, 1] >= y0 - 1e-9) and np.all(p[:, 1] <= y1 + 1e-9)


def test_a_scale_through_infinity_is_refused():
    with pytest.raises(ms.MechanismError, match="infinity"):
        determinant({"a": lambda a: (0 * a, a, 1 + 0 * a), "b": lambda b: (1 + 0 * b, b, b),
                     "c": lambda c: (c, c, 1 + 0 * c)}, {"a": (0, 1), "b": (-1, 1), "c": (0, 1)},
                    "c")


# ------------------------------------------------------------------------------ reading
def test_read_refuses_values_off_the_scales_and_wrong_names():
    nm = parallel([Var("a", (0, 10)), Var("b", (0, 5))], Var("c", (0, 15)))
    with pytest.raises(ms.MechanismError, match="off its scale"):
        nm.read(a=11, b=1)
    with pytest.raises(ms.MechanismError, match="give all but one"):
        nm.read(a=1)
    with pytest.raises(ms.MechanismError, match="unknown names: x"):
        nm.read(a=1, x=2)
    with pytest.raises(ms.MechanismError, match="off its scale"):
        nm.read(a=float("nan"), b=1)
    narrow = parallel([Var("a", (0, 10)), Var("b", (0, 5))], Var("c", (0, 8)))
    with pytest.raises(ms.MechanismError, match="misses the scale of c"):
        narrow.read(a=9, b=4)
    assert np.isnan(narrow.isopleth(a=9, b=4)["c"])


def test_accuracy_report_finds_a_wrong_model_and_counts_in_mm():
    nm = parallel([Var("a", (0, 10)), Var("b", (0, 5))], Var("c", (0, 15)),
                  model=lambda a, b: a + b + 0.1)
    acc = nm.check(n=50)
    assert acc.max_error == pytest.approx(0.1, rel=1e-9)
    mm_per_unit = nm.scales["c"].length() / 15.0
    assert acc.max_mm == pytest.approx(0.1 * mm_per_unit, rel=1e-6)
    assert acc.points == 54 and "0.1" in acc.text()
    assert set(acc.to_dict()) >= {"max_error", "rms_error", "max_mm", "rms_mm", "worst"}
    assert determinant({"q": lambda q: (0 * q, q, 1 + 0 * q),
                        "p": lambda p: (1 + 0 * p, p, 1 + 0 * p),
                        "z": lambda z: (z, -z * z, 1 + z)},
                       {"q": (-10, -0.5), "p": (-3, 3), "z": (0.1, 5.1)}, "z").models == {}


# ------------------------------------------------------------------------------ ticks
def test_ticks_follow_the_value_density_without_collisions():
    def position(v):  # a log scale 200 mm long from 1 to 1000
        v = np.asarray(v, dtype=float)
        return np.stack([np.zeros_like(v), 200 * np.log10(v) / 3], axis=-1)

    tk = ticks(position, 1.0, 1000.0, 1.0)
    lab = tk.labelled
    assert {1, 2, 3, 5, 10, 20, 100, 1000} <= set(lab.tolist())
    pos = position(lab)[:, 1]
    assert np.min(np.diff(pos)) >= 0.75 * 7 * 25.4 / 72 + 1.0 - 1e-9  # label height + gap
    # label steps of 0.5 where the values spread (1 to 5), of 1 where they crowd (5 to 10)
    assert {1.5, 4.5} <= set(lab.tolist()) and not {5.5, 9.5, 950} & set(lab.tolist())
    assert len(tk.minor) > len(lab)
    assert tick_text(0.5, 0.5) == "0.5" and tick_text(20000, 5000) == "20\u2009000"
    assert tick_text(-0.0, 0.1) == "0.0" and number_text(600000.0) == "600\u2009000"


# ------------------------------------------------------------------------------ fitted
def test_alignment_jacobian_matches_finite_differences():
    rng = np.random.default_rng(3)
    n, m, g = 5, 40, 9
    Vu = np.polynomial.chebyshev.chebvander(rng.uniform(-1, 1, m), n - 1)
    Vv = np.polynomial.chebyshev.chebvander(rng.uniform(-1, 1, m), n - 1)
    V = np.polynomial.chebyshev.chebvander(np.linspace(-1, 1, g), n - 1)
    p = np.concatenate([[-1.0, 0.1, 0, 0, 0], rng.normal(0, 0.3, n), [1.0, -0.1, 0, 0, 0],
                        rng.normal(0, 0.3, n)])
    prob = Alignment(Vu, Vv, V, rng.uniform(0, 1, m), p + 0.01, even=0.05)
    J = prob.jacobian(p)
    h = 1e-6
    fd = np.stack([(prob.residuals(p + h * e) - prob.residuals(p - h * e)) / (2 * h)
                   for e in np.eye(len(p))], axis=1)
    assert np.max(np.abs(J - fd)) < 1e-6 * max(1.0, np.abs(J).max())


def test_fitted_chart_of_an_exact_sum_is_near_exact_and_of_a_product_reports_its_error():
    nm = fitted(lambda u, v: u + v, Var("u", (0, 1)), Var("v", (0, 2)), [Var("w", None)])
    assert nm.accuracy.max_error < 2e-3 and nm.accuracy.max_mm < 0.5
    assert nm.fit["degree"] == 6 and nm.fit["samples"] == 625
    nm = fitted(lambda u, v: u * v**2, Var("u", (1, 10)), Var("v", (1, 5)), [Var("w", None)])
    acc = nm.accuracy
    assert 0 < acc.max_mm < 1.0 and acc.misses == 0
    # the report is what reading gives: the worst point read again
    worst = acc.worst
    read = nm.read(u=worst["u"], v=worst["v"])
    assert abs(read - worst["u"] * worst["v"] ** 2) == pytest.approx(acc.max_error, rel=1e-6)


def test_fitted_refuses_bad_functions():
    with pytest.raises(ms.MechanismError, match="not finite"):
        fitted(lambda u, v: np.log(u - v), Var("u", (0, 1)), Var("v", (0, 1)), [Var("w", None)])
    with pytest.raises(ms.MechanismError, match="does not vary"):
        fitted(lambda u, v: 0 * u + 1.0, Var("u", (0, 1)), Var("v", (0, 1)), [Var("w", None)])
    with pytest.raises(ms.MechanismError, match="degree"):
        fitted(lambda u, v: u + v, Var("u", (0, 1)), Var("v", (0, 1)), [Var("w", None)],
               degree=20)


# ------------------------------------------------------------------------------ user's own
def test_user_nomogram_exact_forms_and_fitted_default():
    f = lambda u, v: u * v**2  # noqa: E731
    log = ms.nomogram(f, u=(1, 10), v=(1, 5), form=Product(v=lambda v: v**2))
    z = ms.nomogram(f, u=(1, 10), v=(1, 5), form=Product(v=lambda v: v**2, chart="z"))
    for nm in (log, z):
        assert nm.read(u=2, v=3) == pytest.approx(18, rel=1e-12)
        assert nm.accuracy.max_relative < 1e-10
    s = ms.nomogram(lambda a, b: a + 2 * b, u=(-1, 10), v=(1, 5), form=Sum(v=lambda b: 2 * b),
                    names=("a", "b", "c"), titles={"c": "sum"}, units={"a": "m"})
    assert s.read(a=2, b=3) == pytest.approx(8, abs=1e-12)
    assert s.scales["c"].scale.title == "sum" and s.scales["a"].scale.unit == "m"
    fit = ms.nomogram(f, u=(1, 10), v=(1, 5))
    assert fit.fit and fit.scales["w"].position(12.0).shape == (2,)
    assert abs(fit.read(u=2, v=3) - 18) < 0.2


def test_user_nomogram_checks_the_stated_form_and_its_arguments():
    with pytest.raises(ms.MechanismError, match="stated form differs"):
        ms.nomogram(lambda u, v: u + 2 * v, u=(-1, 10), v=(1, 5), form=Sum())
    with pytest.raises(ms.MechanismError, match="positive"):
        ms.nomogram(lambda u, v: u * v, u=(-1, 10), v=(1, 5), form=Product())
    with pytest.raises(ms.MechanismError, match="low < high"):
        ms.nomogram(lambda u, v: u + v, u=(1, 1), v=(1, 5))
    for bad in ((True, 2), ("1", 2), (1j, 2), (float("nan"), 2), 3, "ab", (1, 2, 3)):
        with pytest.raises(ms.MechanismError, match="nomogram: u"):
            ms.nomogram(lambda u, v: u + v, u=bad, v=(1, 5))
    with pytest.raises(ms.MechanismError, match="not finite"):
        ms.nomogram(lambda u, v: 1 / (u - v), u=(1, 5), v=(1, 5))
    with pytest.raises(ms.MechanismError, match="unknown variables"):
        ms.nomogram(lambda u, v: u + v, u=(1, 5), v=(1, 5), titles={"x": "?"})


# ------------------------------------------------------------------------------ rendering
@pytest.mark.parametrize("paper", ["a4", "letter"])
def test_sheet_is_the_paper_at_one_to_one_and_clean(paper):
    nm = parallel([Var("D", (1, 4), lambda d: 2 * np.log(d), title="plunger"),
                   Var("S", (20, 200), np.log, title="stroke"),
                   Var("N", (4, 20), np.log, title="speed")],
                  Var("Q", (8, 12800), np.log, title="displacement"), constant=np.log(0.1),
                  paper=paper, title="A chain")
    fig = nm.draw()
    w, h = fig.get_size_inches() * 25.4
    assert (w, h) == pytest.approx((nm.paper.width, nm.paper.height))
    assert layout_problems(fig) == []
    texts = " ".join(t.get_text() for t in fig.texts + fig.axes[0].texts)
    assert "Reading error" in texts and "scale 1:1" in texts and "Example" in texts


def test_save_writes_pdf_svg_png_and_refuses_other_suffixes(tmp_path):
    nm = z_chart(Var("T", (1e3, 1e5), title="torque"), Var("F", (10, 100), title="factor"),
                 Var("W", (100, 1000), title="load"), title="Z")
    for suffix in ("pdf", "svg", "png"):
        path = nm.save(tmp_path / f"z.{suffix}", dpi=60)
        assert path.stat().st_size > 1000
    assert (tmp_path / "z.pdf").read_bytes()[:4] == b"%PDF"
    with pytest.raises(ms.MechanismError, match="must end in"):
        nm.save(tmp_path / "z.jpg")


# ------------------------------------------------------------------------------ grids
def _lever_rule():
    from mechsynth.nomograms import Grid, Nomogram, Scale
    from mechsynth.nomograms.scales import homogeneous

    # the lever rule of mixing, Tm = (T1 + r T2) / (1 + r): T1 on x = 0, T2 on x = 1 and the
    # grid of (r, Tm) at (r / (1 + r), Tm) -- lines of constant r vertical, of constant Tm
    # horizontal; the line T1-T2 meets x = r/(1+r) at height Tm
    T1 = Scale("T1", lambda t: homogeneous(0 * t, t), (0, 100))
    T2 = Scale("T2", lambda t: homogeneous(1 + 0 * t, t), (0, 100))
    r = Scale("r", None, (0.1, 10), title="m2 / m1", spacing="log")
    Tm = Scale("Tm", None, (0, 100), title="mixed")
    grid = Grid("mix", (r, Tm), lambda r, t: homogeneous(r / (1 + r), t))
    return Nomogram([T1, T2, grid], [("T1", "T2", "mix")], "Tm",
                    lambda T1, T2, r: (T1 + r * T2) / (1 + r), title="Mixing", search=False,
                    example={"T1": 20.0, "T2": 80.0, "r": 2.0})


def test_grid_scale_reads_either_of_its_variables():
    nm = _lever_rule()
    assert nm.inputs == ("T1", "T2", "r")
    assert nm.read(T1=20, T2=80, r=2.0) == pytest.approx(60.0, abs=1e-12)
    assert nm.read(T1=20, T2=80, Tm=60.0) == pytest.approx(2.0, rel=1e-12)  # along Tm = 60
    assert nm.read(T2=80, r=2.0, Tm=60.0) == pytest.approx(20.0, abs=1e-10)
    acc = nm.accuracy
    assert acc.max_error < 1e-11 and acc.max_mm < 1e-9 and acc.misses == 0
    p = nm.grids["mix"].position(np.array([0.1, 10.0]), np.array([0.0, 100.0]))
    x0, y0, x1, y1 = nm.paper.box
    assert p[0, 1] == pytest.approx(y0) and p[1, 1] == pytest.approx(y1)
    assert nm.variable("r").title == "m2 / m1" and nm.to_dict()["grids"]["mix"]["variables"] == [
        "r", "Tm"]


def test_grid_sheet_is_clean_and_its_variables_unique():
    from mechsynth.nomograms import Grid, Nomogram, Scale
    from mechsynth.nomograms.scales import homogeneous

    fig = _lever_rule().draw()
    assert layout_problems(fig) == []
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert "m2 / m1" in texts and "mixed" in texts and "10" in texts
    a = Scale("a", None, (0, 1))
    with pytest.raises(ms.MechanismError, match="two differently named"):
        Grid("g", (a, a), lambda x, y: homogeneous(x, y))
    T = Scale("a", lambda t: homogeneous(0 * t, t), (0, 1))
    g = Grid("g", (Scale("a", None, (0, 1)), Scale("b", None, (0, 1))),
             lambda x, y: homogeneous(x, y))
    with pytest.raises(ms.MechanismError, match="appears twice"):
        Nomogram([T, g, Scale("c", lambda t: homogeneous(1 + 0 * t, t), (0, 1))],
                 [("a", "g", "c")], "c")

"""The proved lower bound of prescribed-timing path generation (synthesis/path_bound.py)."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.synthesis import path_bound as pb
from mechsynth.synthesis.path_cases import exact_case
from mechsynth.synthesis.path_generation import evaluate


def _known(n=9, noise=0.0, seed=1):
    t, d, ang = exact_case(9)
    t = t[:n] + np.random.default_rng(seed).normal(scale=noise, size=(n, 2))
    return t, d, ang[:n], pb.box_point(d, ang[0])


def _q(xs, sigma, turns, targets):
    """The targets in the coupler's frame, straight from the geometry (the test's own)."""
    a = xs[:, None, 0:2] + pb._rot(turns, xs[:, 2:4])
    dv = xs[:, None, 4:6] - a
    dn = np.hypot(dv[..., 0], dv[..., 1])
    k = (xs[:, None, 6] ** 2 + dn**2 - xs[:, None, 7] ** 2) / (2 * xs[:, None, 6] * dn)
    good = np.all(np.abs(k) <= 1, axis=1)
    psi = np.arctan2(dv[..., 1], dv[..., 0]) + sigma * np.arccos(np.clip(k, -1, 1))
    v = targets[None] - a
    c, s = np.cos(psi), np.sin(psi)
    return np.stack([c * v[..., 0] + s * v[..., 1], -s * v[..., 0] + c * v[..., 1]], -1), good


def test_relaxed_error_is_the_four_bars_error_with_the_best_coupler_point():
    t, d, ang, x = _known(noise=0.05)
    for branch, sg in (("open", 1.0), ("crossed", -1.0)):
        err, m = pb.relaxed_error(x[None], np.array([sg]), ang - ang[0], t)
        des = dict(d, u=m[0, 0], v=m[0, 1])
        assert err[0] == pytest.approx(evaluate(des, ang, t, branch).sum(), rel=1e-12)
    # the best coupler point: the error at (u, v) of the known design is not smaller
    err, m = pb.relaxed_error(x[None], np.array([1.0]), ang - ang[0], t)
    assert err[0] <= evaluate(d, ang, t, "open").sum()


@pytest.mark.parametrize("size", [0.3, 0.05, 0.005])
@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_enclosures_hold_every_design_of_the_box(size, sigma):
    t, d, ang, x = _known(noise=0.05)
    turns = ang - ang[0]
    rng = np.random.default_rng(3)
    for _ in range(3):
        c = x + rng.normal(scale=size, size=8)
        lo, hi = c - size * rng.uniform(0.2, 1, 8), c + size * rng.uniform(0.2, 1, 8)
        qlo, qhi, ok = pb.enclosures(lo[None], hi[None], np.array([sigma]), turns, t)
        xs = lo + (hi - lo) * rng.uniform(size=(20000, 8))
        q, good = _q(xs, sigma, turns, t)
        if good.any():
            assert ok[0]
            assert np.all(q[good] >= qlo) and np.all(q[good] <= qhi)
            err, _ = pb.relaxed_error(xs[good], np.full(good.sum(), sigma), turns, t)
            lb = pb._box_bounds(lo[None], hi[None], np.array([sigma]), turns, t)[0]
            assert lb <= err.min() * (1 + 1e-12)


def test_a_box_where_no_design_assembles_is_dropped():
    t, d, ang, x = _known()
    lo, hi = x.copy(), x.copy() + 1e-3
    lo[7], hi[7] = 20.0, 21.0  # a rocker far longer than coupler plus |A O2|
    _, _, ok = pb.enclosures(lo[None], hi[None], np.array([1.0]), ang - ang[0], t)
    assert not ok[0]
    assert pb._box_bounds(lo[None], hi[None], np.array([1.0]), ang - ang[0], t)[0] == np.inf


def test_kappa_range_is_exact():
    from scipy.optimize import minimize

    def kappa(z):
        return (z[0] ** 2 + z[2] ** 2 - z[1] ** 2) / (2 * z[0] * z[2])

    rng = np.random.default_rng(5)
    for _ in range(20):
        box = [tuple(np.sort(rng.uniform(a, b, 2))) for a, b in ((0.5, 3), (0.5, 3), (0.5, 4))]
        lo, hi = pb._kappa_range(*(np.array([v]) for b in box for v in b))
        g = [np.linspace(a, b, 41) for a, b in box]
        Z = np.stack(np.meshgrid(*g, indexing="ij")).reshape(3, -1)
        k = kappa(Z)
        assert lo[0] <= k.min() and hi[0] >= k.max()  # it holds every point
        for sign, end in ((1, lo[0]), (-1, hi[0])):  # and its ends are reached
            z0 = Z[:, np.argmin(sign * k)]
            r = minimize(lambda z, s=sign: s * kappa(z), z0, bounds=box, method="L-BFGS-B",
                         options={"ftol": 1e-15, "gtol": 1e-12})  # fmt: skip
            assert abs(kappa(r.x) - end) < 1e-9


def test_least_spread_is_the_exact_minimum():
    rng = np.random.default_rng(7)
    lo = rng.normal(size=(50, 6))
    hi = lo + rng.uniform(0, 1.5, size=(50, 6))
    got = pb._least_spread(lo, hi)
    m = np.linspace(-5, 5, 20001)
    d = np.maximum(lo[:, None, :] - m[None, :, None], 0) + np.maximum(
        m[None, :, None] - hi[:, None, :], 0
    )
    brute = np.min(np.sum(d * d, axis=2), axis=1)
    assert np.all(got <= brute + 1e-15)
    assert np.allclose(got, brute, atol=1e-6)


def test_exact_points_the_bound_closes_at_zero():
    t, d, ang = exact_case(9)
    pg = ms.path_generation(t, timing="prescribed", angles=ang, starts=1, bound=True)
    b = pg.bound
    assert pg.error < 1e-20
    assert b.lower == 0.0 and b.lower <= pg.error
    assert b.closed and b.useful
    assert "lower bound" in pg.summary() and pg.as_dict()["bound"]["closed"] is True


def _fixed_pivots(x, size):
    """A region with the pivots fixed (to 1e-9 m) and the crank vector, coupler and rocker
    free within ``size``: four effective dimensions."""
    w = np.array([1e-9, 1e-9, size, size, 1e-9, 1e-9, size, size])
    return {k: (v - a, v + a) for k, v, a in zip(pb.COORDS, x, w)}


@pytest.mark.parametrize("seed, n", [(4, 6), (9, 7)])
def test_bound_is_below_the_optimum_found_by_dense_search(seed, n):
    # six or seven points of the known four-bar moved by 0.03 m; the pivots fixed, the crank vector,
    # coupler and rocker within 0.2 m: dense sampling (5e4 designs) then least squares from
    # the best 5 samples of each branch give the minimum the bound must not exceed
    from scipy.optimize import least_squares

    t, d, ang, x = _known(n=n, noise=0.03, seed=seed)
    reg = _fixed_pivots(x, 0.2)
    lo = np.array([reg[k][0] for k in pb.COORDS])
    hi = np.array([reg[k][1] for k in pb.COORDS])
    turns = ang - ang[0]
    rng = np.random.default_rng(0)
    xs = lo + (hi - lo) * rng.uniform(size=(50_000, 8))
    best = np.inf
    for sg in (1.0, -1.0):
        err, _ = pb.relaxed_error(xs, np.full(len(xs), sg), turns, t)
        for i in np.argsort(err)[:5]:
            if not np.isfinite(err[i]):
                continue

            def res(z, sg=sg):
                q, good = _q(z[None], sg, turns, t)
                r = (q[0] - q[0].mean(axis=0)).ravel()
                return r if good[0] else np.full(r.size, 1e3)

            sol = least_squares(res, xs[i], bounds=(lo, hi))
            best = min(best, err[i], float(np.sum(sol.fun**2)))
    b = pb.path_bound(t, ang, region=reg, max_boxes=40_000, time_limit=60, rtol=1e-2)
    assert b.lower <= best * (1 + 1e-9)
    assert b.best >= best * (1 - 1e-6)  # the tree's best centre is a design of the region
    assert b.closed and b.lower >= best * (1 - 1.1e-2)  # and it closes on that minimum


def test_the_gap_shrinks_as_the_boxes_are_refined_and_closes():
    # seven points of the known four-bar moved by 0.03 m; the pivots fixed, the crank vector,
    # coupler and rocker within 0.1 m, both branches
    t, d, ang, x = _known(n=7, noise=0.03)
    reg = _fixed_pivots(x, 0.1)
    runs = [pb.path_bound(t, ang, region=reg, max_boxes=m) for m in (1_000, 3_000, 40_000)]
    for r in runs:
        lows = [h[1] for h in r.history]
        assert np.all(np.diff(lows) >= 0)  # the lower bound only rises
        assert 0 <= r.lower <= r.best
    assert runs[0].lower < runs[1].lower < runs[2].lower
    assert runs[0].gap > runs[1].gap > runs[2].gap
    last = runs[2]
    assert last.closed and last.useful and last.open == 0 and last.boxes < 40_000
    assert last.gap <= 1e-3 * last.best  # the default rtol
    import matplotlib

    matplotlib.use("Agg")
    from mechsynth.plotting import layout_problems

    fig = last.figure()
    assert layout_problems(fig) == [] and "closed" in fig.axes[0].get_title()
    # the best centre is a four-bar: its error by the library's model
    des = last.best_design
    phi = des["phi1"] + ang - ang[0]
    err = evaluate(des, phi, t, des["branch"]).sum()
    assert err == pytest.approx(last.best, rel=1e-9)


@pytest.mark.parametrize("size", [0.1, 0.02, 0.004])
@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_jacobian_enclosure_holds_the_derivatives(size, sigma):
    from mechsynth.synthesis import path_bound_linear as pl

    t, d, ang, x = _known(noise=0.05)
    turns = ang - ang[0]
    rng = np.random.default_rng(11)
    c = x + rng.normal(scale=size, size=8)
    h = size * rng.uniform(0.2, 1, 8)
    lo, hi = c - h, c + h
    Jlo, Jhi, ok = pl.jacobian_enclosure(lo[None], hi[None], np.array([sigma]), turns, t)
    assert ok[0]
    xs = lo + (hi - lo) * rng.uniform(size=(2000, 8))
    sg = np.full(len(xs), sigma)
    eps = 1e-6
    J = np.stack([(pl._q_at(xs + eps * e, sg, turns, t) - pl._q_at(xs - eps * e, sg, turns, t))
                  / (2 * eps) for e in np.eye(8)], axis=-1)  # fmt: skip
    assert np.all(J >= Jlo - 1e-7) and np.all(J <= Jhi + 1e-7)
    # and the linear bound lies below every design of the box, near the least on small boxes
    lin = pl.linear_bound(lo[None], hi[None], np.array([sigma]), turns, t)[0]
    err, _ = pb.relaxed_error(xs, sg, turns, t)
    assert lin <= err.min()
    if size < 0.01:
        assert lin >= 0.9 * err.min()


def test_bad_input_is_named():
    t, d, ang = exact_case(9)
    with pytest.raises(MechanismError, match="angles: need one per target"):
        pb.path_bound(t, ang[:5])
    with pytest.raises(MechanismError, match="region must give"):
        pb.path_bound(t, ang, region={"x0": (0, 1)})
    with pytest.raises(MechanismError, match="bound is for a four-bar with timing='prescribed'"):
        ms.path_generation(t, bound=True, starts=1)
    with pytest.raises(MechanismError, match="bound: no option"):
        ms.path_generation(t, timing="prescribed", angles=ang, bound={"boxes": 3})
    with pytest.raises(MechanismError, match="branch"):
        pb.path_bound(t, ang, branch="left")


def test_cli_bound(tmp_path, capsys):
    import json

    from mechsynth.cli import main

    pts, _, angles = exact_case()
    f = tmp_path / "t.csv"
    rows = np.column_stack([pts + 0.02 * np.sin(np.arange(9))[:, None], np.rad2deg(angles)])
    f.write_text("x,y,deg\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows))
    code = main(["synthesize", "path", str(f), "--timing", "prescribed", "--starts", "2",
                 "--bound", "--bound-around", "1 cm", "--bound-time", "2", "--json"])  # fmt: skip
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    b = data["bound"]
    assert 0 <= b["lower"] <= data["best"]["error"] == b["best"]
    assert b["region"]["coupler"][1] - b["region"]["coupler"][0] == pytest.approx(0.02)
    assert b["seconds"] < 10 and b["boxes"] > 0 and isinstance(b["useful"], bool)
    code = main(["synthesize", "path", str(f), "--bound", "--starts", "1"])
    assert code == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("mechsynth: error: --bound needs --timing prescribed")


def test_bound_region_holds_every_four_bar_of_the_bounds():
    t, d, ang = exact_case(9)
    fixed = {k: (d[k] - 1e-6, d[k] + 1e-6) for k in ("x0", "y0", "ground", "angle")}
    bounds = {**fixed, "crank": (0.5, 1.5), "coupler": (2, 4), "rocker": (2, 3)}
    reg = pb.bound_region(t, bounds)
    assert reg["x2"][1] - reg["x2"][0] < 1e-5 and reg["crank_x"] == (-1.5, 1.5)
    rng = np.random.default_rng(2)
    lo = np.array([v[0] for v in bounds.values()])
    hi = np.array([v[1] for v in bounds.values()])
    for row in lo + (hi - lo) * rng.uniform(size=(200, len(bounds))):
        des = dict(zip(bounds, row), u=0.0, v=0.0)
        x = pb.box_point(des, rng.uniform(0, 2 * np.pi))
        for k, v in zip(pb.COORDS, x):
            assert reg[k][0] <= v <= reg[k][1], k

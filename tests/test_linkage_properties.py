"""Property tests of general linkages over random assemblable designs (hypothesis).

A Stephenson III six-bar (a four-bar whose coupler point drives an RRR dyad to the ground), a
Watt II six-bar (two four-bars in series), the four-bar with an extra rod and slider (paper 001's
six-link), an RRP on a guide carried by the rocker and an RPR whose pivot moves: every loop
closes to 1e-12, every velocity and acceleration analog equals central differences of the
positions, and CasADi derivatives with respect to the dimensions equal differences of the numpy
model.
"""

import casadi as ca
import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechsynth as ms

PHI = np.linspace(0.0, 2.0 * np.pi, 49)[:-1]
H = 3e-5
SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _wrap(x):
    return np.angle(np.exp(1j * np.asarray(x)))


def _fd(f, phi, angle=False):
    """Central difference with one Richardson step (error O(H^4))."""
    w = _wrap if angle else (lambda x: x)
    d1 = w(f(phi + H) - f(phi - H)) / (2.0 * H)
    d2 = w(f(phi + 2 * H) - f(phi - 2 * H)) / (4.0 * H)
    return (4.0 * d1 - d2) / 3.0


def _close(fd, exact, scale):
    np.testing.assert_allclose(fd, exact, atol=1e-6 * max(scale, 1.0), rtol=0)


def _check_analogs(lk):
    """Every point, link angle and slider: analogs equal differences, nothing NaN."""
    pts, links, sliders = lk.jets(PHI)

    def at(phi, kind, name, field):
        p, lnk, sl = lk.jets(phi)
        return getattr({"p": p, "l": lnk, "s": sl}[kind][name], field)

    for name, j in pts.items():
        for f, d1, d2 in (("x", "dx", "ddx"), ("y", "dy", "ddy")):
            v1, v2 = np.broadcast_to(getattr(j, d1), PHI.shape), getattr(j, d2)
            scale = float(np.max(np.abs(v1)))
            assert np.all(np.isfinite(v1)) and np.all(np.isfinite(v2))
            _close(_fd(lambda q, n=name, f=f: at(q, "p", n, f), PHI), v1, scale)
            _close(
                _fd(lambda q, n=name, d=d1: at(q, "p", n, d), PHI), v2, float(np.max(np.abs(v2)))
            )
    for name in links:
        j = links[name]
        _close(_fd(lambda q, n=name: at(q, "l", n, "value"), PHI, angle=True), j.d1, 1.0)
        d2 = np.broadcast_to(j.d2, PHI.shape)
        _close(_fd(lambda q, n=name: at(q, "l", n, "d1"), PHI), d2, float(np.max(np.abs(d2))))
    for name in sliders:
        j = sliders[name]
        _close(
            _fd(lambda q, n=name: at(q, "s", n, "value"), PHI), j.d1, float(np.max(np.abs(j.d1)))
        )
        _close(_fd(lambda q, n=name: at(q, "s", n, "d1"), PHI), j.d2, float(np.max(np.abs(j.d2))))


def _dist(m, p, q):
    a, b = m.points[p], m.points[q]
    return np.hypot(a.x - b.x, a.y - b.y)


def _closure(residuals):
    for r in residuals:
        assert np.max(np.abs(r)) <= 1e-12, np.max(np.abs(r))


def _reach(lk, p, q):
    """Range of |pq| over the cycle (numpy, assembly of the earlier groups)."""
    m = lk.motion(ms.cycle(720))
    d = _dist(m, p, q)
    return float(d.min()), float(d.max())


def _dyad_lengths(dmin, dmax, ratio):
    """Lengths l1 >= l2 of an RRR dyad whose pivot distance stays in (|l1 - l2|, l1 + l2) with
    room on both sides: l1 + l2 = 1.25 dmax, |l1 - l2| = ratio * dmin (ratio < 1)."""
    total, diff = 1.25 * dmax, ratio * dmin
    return (total + diff) / 2.0, (total - diff) / 2.0


@st.composite
def four_bars(draw):
    """A crank-rocker O-A-B-D with the crank the shortest link (Grashof), D anywhere."""
    d = draw(st.floats(0.08, 0.2))
    gamma = draw(st.floats(-1.0, 1.0))
    r = draw(st.floats(0.1, 0.3)) * d
    b = draw(st.floats(0.9, 1.6)) * d
    c = draw(st.floats(0.6, 1.2)) * d
    # Grashof crank-rocker with margin: r + longest < sum of the other two
    longest = max(b, c, d)
    if r + longest >= 0.95 * (b + c + d - longest):
        c = (r + longest) / 0.9 - b - d + longest + 0.01 * d
    branch = draw(st.sampled_from([1, -1]))
    lk = (
        ms.Linkage(ground={"O": (0.0, 0.0), "D": (d * np.cos(gamma), d * np.sin(gamma))})
        .crank("A", about="O", length=r, phase=draw(st.floats(-np.pi, np.pi)))
        .rrr("B", ("A", b), ("D", c), branch=branch)
    )
    return lk


@st.composite
def stephenson_iii(draw):
    lk = draw(four_bars())
    d = lk.parameters["AB"]
    lk = lk.attach(
        "C",
        on=("A", "B"),
        along=draw(st.floats(-0.5, 1.5)) * d,
        left=draw(st.floats(-0.8, 0.8)) * d,
    )
    fx, fy = draw(st.floats(-2.0, 2.0)) * d, draw(st.floats(-2.0, 2.0)) * d
    lk = lk.ground_point("F", fx, fy)
    lo, hi = _reach(lk, "C", "F")
    l1, l2 = _dyad_lengths(lo, hi, draw(st.floats(0.0, 0.8)))
    if draw(st.booleans()):
        l1, l2 = l2, l1
    return lk.rrr("E", ("C", l1), ("F", l2), branch=draw(st.sampled_from([1, -1])))


@st.composite
def watt_ii(draw):
    lk = draw(four_bars())
    d = lk.parameters["DB"]
    lk = lk.attach(
        "K", on="DB", along=draw(st.floats(-1.5, 1.5)) * d, left=draw(st.floats(-0.5, 0.5)) * d
    )
    lk = lk.ground_point("F", draw(st.floats(-2.0, 2.0)) * d, draw(st.floats(-2.0, 2.0)) * d)
    lo, hi = _reach(lk, "K", "F")
    l1, l2 = _dyad_lengths(lo, hi, draw(st.floats(0.0, 0.8)))
    return lk.rrr("E", ("K", l1), ("F", l2), branch=draw(st.sampled_from([1, -1])))


@st.composite
def six_links(draw):
    """Paper 001's six-link: the rocker's arm K drives a rod KN and a slider N on a straight
    guide at the angle rho; the rod is long enough to reach the guide all cycle."""
    lk = draw(four_bars())
    d = lk.parameters["DB"]
    lk = lk.attach("K", on=("D", "B"), along=draw(st.floats(-1.5, -0.2)) * d)
    rho = draw(st.floats(0.2, np.pi - 0.2))
    gx, gy = draw(st.floats(-1.0, 1.0)) * d, draw(st.floats(-1.0, 1.0)) * d
    m = lk.motion(ms.cycle(720))
    k = m.points["K"]
    height = np.abs(-(k.x - gx) * np.sin(rho) + (k.y - gy) * np.cos(rho))
    rod = float(height.max()) * draw(st.floats(1.2, 3.0)) + 1e-3 * d
    return lk.rrp("N", ("K", rod), guide=((gx, gy), rho), branch=draw(st.sampled_from([1, -1])))


@SETTINGS
@given(stephenson_iii())
def test_stephenson_iii_closure_and_analogs(lk):
    m = lk.motion(PHI)
    p = lk.parameters
    _closure(
        [
            _dist(m, "O", "A") - p["OA"],
            _dist(m, "A", "B") - p["AB"],
            _dist(m, "D", "B") - p["DB"],
            _dist(m, "A", "C") - np.hypot(p["C_along"], p["C_left"]),
            _dist(m, "B", "C") - np.hypot(p["C_along"] - p["AB"], p["C_left"]),
            _dist(m, "C", "E") - p["CE"],
            _dist(m, "F", "E") - p["FE"],
        ]
    )
    _check_analogs(lk)


@SETTINGS
@given(watt_ii())
def test_watt_ii_closure_and_analogs(lk):
    m = lk.motion(PHI)
    p = lk.parameters
    _closure(
        [
            _dist(m, "A", "B") - p["AB"],
            _dist(m, "D", "B") - p["DB"],
            _dist(m, "D", "K") - np.hypot(p["K_along"], p["K_left"]),
            _dist(m, "K", "E") - p["KE"],
            _dist(m, "F", "E") - p["FE"],
        ]
    )
    _check_analogs(lk)


@SETTINGS
@given(six_links())
def test_four_bar_with_rrp_closure_and_analogs(lk):
    m = lk.motion(PHI)
    p = lk.parameters
    rho = p["N_guide_angle"]
    n = m.points["N"]
    on_guide = -(n.x - p["N_guide_x"]) * np.sin(rho) + (n.y - p["N_guide_y"]) * np.cos(rho)
    along = (n.x - p["N_guide_x"]) * np.cos(rho) + (n.y - p["N_guide_y"]) * np.sin(rho)
    _closure(
        [
            _dist(m, "A", "B") - p["AB"],
            _dist(m, "D", "B") - p["DB"],
            _dist(m, "K", "N") - p["KN"],
            on_guide,
            along - m.sliders["N"].position,
        ]
    )
    _check_analogs(lk)


@SETTINGS
@given(four_bars(), st.floats(-0.6, 0.6), st.floats(1.5, 3.0), st.sampled_from([1, -1]))
def test_guide_carried_by_the_rocker_and_moving_rpr_pivot(lk, alpha, reach, branch):
    """An RRP whose guide turns with the rocker, and an RPR whose pivot is a moving joint."""
    d = lk.parameters["DB"]
    m = lk.motion(ms.cycle(720))
    th = m.links["DB"].angle + alpha
    a, dd = m.points["A"], m.points["D"]
    height = np.abs(-(a.x - dd.x) * np.sin(th) + (a.y - dd.y) * np.cos(th) - 0.1 * d)
    rod = float(height.max()) * reach + 1e-3 * d
    lk = lk.rrp("C", ("A", rod), guide=(("D", "B"), alpha), offset=0.1 * d, branch=branch)
    lk = lk.rpr("lever", about="B", through="A", offset=0.05 * d)
    m = lk.motion(PHI)
    p = lk.parameters
    th = m.links["DB"].angle + alpha
    dd, c = m.points["D"], m.points["C"]
    off = -(c.x - dd.x) * np.sin(th) + (c.y - dd.y) * np.cos(th)
    lev = m.links["lever"].angle
    a, b = m.points["A"], m.points["B"]
    slot = -(a.x - b.x) * np.sin(lev) + (a.y - b.y) * np.cos(lev)
    _closure([_dist(m, "A", "C") - p["AC"], off - p["C_guide_offset"], slot - p["lever_offset"]])
    _check_analogs(lk)


# --------------------------------------------------------------------------- CasADi
def test_casadi_derivatives_equal_differences_of_the_numpy_model():
    """d(slider acceleration at 7 angles)/d(dimensions) by CasADi equals central differences of
    the numpy model, for the six-link with a guide through a ground point at an offset."""
    lk = (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05, left=0.01)
        .rrp("N", ("K", 0.10), guide=("D", ms.deg(57)), offset=-0.04)
    )
    names = ["OA", "AB", "DB", "K_along", "KN", "N_guide_angle", "N_guide_offset", "D_x"]
    x = ca.SX.sym("x", len(names))
    phi = np.linspace(0.1, 6.0, 7)
    sym = lk(**{n: x[i] for i, n in enumerate(names)})
    m = sym.motion(ca.DM(phi), speed=ms.rpm(1500))
    out = ca.vertcat(m.sliders["N"].acceleration, m.pressure_angles["B"], m.links["KN"].omega)
    jac = ca.Function("j", [x], [ca.jacobian(out, x)])
    x0 = np.array([lk.parameters[n] for n in names])
    J = np.asarray(jac(x0))

    def f(v):
        mm = lk(**dict(zip(names, v))).motion(phi, speed=ms.rpm(1500))
        return np.concatenate(
            [mm.sliders["N"].acceleration, mm.pressure_angles["B"], mm.links["KN"].omega]
        )

    for i in range(len(names)):
        h = 1e-6
        e = np.zeros(len(names))
        e[i] = h
        fd = (f(x0 + e) - f(x0 - e)) / (2 * h)
        np.testing.assert_allclose(J[:, i], fd, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd)) + 1e-9)

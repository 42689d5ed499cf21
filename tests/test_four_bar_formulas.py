"""Paper 000's four-bar formulas (6)-(7), (11) and the corrected U2', U3' against the RRR dyad model
(FourBar) and finite differences; the printed (13)-(14) and the printed sign of U2 shown wrong."""

import casadi as ca
import numpy as np
import pytest

from mechsynth.errors import MechanismError
from mechsynth.kinematics import FourBar
from mechsynth.kinematics.four_bar_formulas import (
    paper_four_bar,
    position_coefficients,
    position_functions,
    printed_velocity_ratio_derivatives,
    printed_velocity_ratios,
    velocity_ratio_derivatives,
    velocity_ratios,
)

PHI = np.linspace(0.0, 2.0 * np.pi, 73)[:-1]
# Paper 000, variant 2a of the Lufkin Mark II study: r = 1.068 m, l = 4.3 m, X_O2 = 5.0 m (k and the
# pivot height are not given in the paper; k = 3.0 m and d = 5.0 m are a representative choice).
MARK_II_2A = dict(r=1.068, l=4.3, k=3.0, d=5.0)


def _wrap(x):
    return np.angle(np.exp(1j * x))


def _random_designs(n, seed, kind):
    """Random full-turn designs as column arrays (crank-rockers or double-cranks)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        r, l, k, d = rng.uniform(0.2, 3.0, 4)
        if kind == "double-crank":
            r, d = max(r, d), min(r, d)  # ground shortest makes q < 0 reachable
        try:
            fb = FourBar(r, l, k, d)
        except MechanismError:
            continue
        if fb.grashof.kind == kind:
            out.append((r, l, k, d))
    return [np.array(c)[:, None] for c in zip(*out, strict=True)]


@pytest.mark.parametrize("kind", ["crank-rocker", "double-crank"])
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_formulas_agree_with_dyad(kind, branch):
    r, l, k, d = _random_designs(30, 1 if kind == "crank-rocker" else 2, kind)
    if kind == "double-crank":
        assert np.any(d - r * np.cos(PHI) < 0)  # the q < 0 region is exercised
    res = paper_four_bar(PHI, r, l, k, d, branch)
    _, _, coupler, rocker = FourBar(r, l, k, d, branch=branch).jets(PHI)
    np.testing.assert_allclose(_wrap(res.phi2 - coupler.value), 0.0, atol=1e-10)
    np.testing.assert_allclose(_wrap(res.phi3 - rocker.value), 0.0, atol=1e-10)
    np.testing.assert_allclose(res.u2, coupler.d1, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(res.u3, rocker.d1, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(res.du2, coupler.d2, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(res.du3, rocker.d2, rtol=1e-8, atol=1e-9)


def _central(f, phi, h):
    return (f(phi + h) - f(phi - h)) / (2.0 * h)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_ratios_and_derivatives_are_finite_differences(branch):
    r, l, k, d = _random_designs(20, 3, "crank-rocker")
    h = 1e-5
    res = paper_four_bar(PHI, r, l, k, d, branch)

    def angles(phi):
        return np.stack(position_functions(phi, r, l, k, d, branch))

    def ratios(phi):
        return np.stack(velocity_ratios(phi, *position_functions(phi, r, l, k, d, branch), r, l, k))

    fd_u = _central(angles, PHI, h)
    np.testing.assert_allclose(fd_u[0], res.u2, atol=1e-8)
    np.testing.assert_allclose(fd_u[1], res.u3, atol=1e-8)
    fd_du = _central(ratios, PHI, h)
    scale = np.max(np.abs(fd_du))
    np.testing.assert_allclose(fd_du[0], res.du2, atol=1e-7 * scale)
    np.testing.assert_allclose(fd_du[1], res.du3, atol=1e-7 * scale)


def test_angular_accelerations_match_four_bar_motion():
    omega, eps = 8.0, -3.0
    r, l, k, d = MARK_II_2A.values()
    res = paper_four_bar(PHI, r, l, k, d)
    m = FourBar(r, l, k, d).motion(PHI, speed=omega, epsilon=eps)
    w2, w3 = res.angular_velocities(omega)
    e2, e3 = res.angular_accelerations(omega, eps)
    np.testing.assert_allclose(w2, m.links["coupler"].omega, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(w3, m.links["rocker"].omega, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(e2, m.links["coupler"].epsilon, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(e3, m.links["rocker"].epsilon, rtol=1e-9, atol=1e-10)


def test_printed_u2_has_the_wrong_sign_and_u3_is_right():
    # Erratum of paper 000, (9) and (11): U2 printed with sin(phi1 - phi3), not sin(phi3 - phi1)
    r, l, k, d = MARK_II_2A.values()
    phi2, phi3 = position_functions(PHI, r, l, k, d)
    u2, u3 = velocity_ratios(PHI, phi2, phi3, r, l, k)
    p2, p3 = printed_velocity_ratios(PHI, phi2, phi3, r, l, k)
    np.testing.assert_allclose(p3, u3, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(p2, -u2, rtol=1e-14, atol=1e-15)
    assert np.max(np.abs(p2 - u2)) > 0.1


def test_printed_derivatives_are_wrong():
    # Errata of paper 000, (13)-(14): r misplaced, and wrong angles in U3'. Fed with the correct
    # ratios and with the paper's own (printed) ratios, both disagree with the exact derivatives.
    r, l, k, d = MARK_II_2A.values()
    phi2, phi3 = position_functions(PHI, r, l, k, d)
    u2, u3 = velocity_ratios(PHI, phi2, phi3, r, l, k)
    du2, du3 = velocity_ratio_derivatives(PHI, phi2, phi3, u2, u3, r, l, k)
    scale = np.max(np.abs([du2, du3]))
    for ratios in [(u2, u3), printed_velocity_ratios(PHI, phi2, phi3, r, l, k)]:
        p2, p3 = printed_velocity_ratio_derivatives(PHI, phi2, phi3, *ratios, r, l, k)
        assert np.max(np.abs(p2 - du2)) > 0.05 * scale
        assert np.max(np.abs(p3 - du3)) > 0.05 * scale


def test_printed_coefficients_give_the_same_products():
    r, l, k, d = MARK_II_2A.values()
    q, p, beta, a, b = position_coefficients(PHI, r, l, k, d)
    np.testing.assert_allclose(np.tan(beta), p / q, rtol=1e-12, atol=1e-14)
    phi2, phi3 = position_functions(PHI, r, l, k, d)
    # (6)-(7) with the printed a, b
    np.testing.assert_allclose(_wrap(np.arccos(a * np.cos(beta)) - beta - phi2), 0.0, atol=1e-12)
    np.testing.assert_allclose(
        _wrap(np.pi - np.arccos(b * np.cos(beta)) - beta - phi3), 0.0, atol=1e-12
    )


def test_broadcasts_over_design_batches():
    r = np.array([[1.0], [1.068], [0.9]])
    res = paper_four_bar(PHI, r, 4.3, 3.0, 5.0)
    assert res.phi2.shape == res.du3.shape == (3, PHI.size)
    single = paper_four_bar(PHI, 1.068, 4.3, 3.0, 5.0)
    np.testing.assert_array_equal(res.du3[1], single.du3)


def test_not_assemblable_raises_with_numbers():
    # 1 + 5 > 1.5 + 2 at phi = 0 ... |AO2| = 4 > l + k = 3.5
    with pytest.raises(MechanismError, match=r"cos\(beta\) = .* outside \[-1, 1\] at crank angle"):
        position_functions(PHI, 1.0, 1.5, 2.0, 5.0)


@pytest.mark.parametrize("name", ["r", "l", "k", "d"])
@pytest.mark.parametrize("value", [0.0, -1.0, np.nan, np.inf])
def test_bad_lengths_raise_value_error(name, value):
    args = dict(MARK_II_2A)
    args[name] = value
    with pytest.raises(ValueError, match=rf"^{name} must be"):
        paper_four_bar(PHI, **args)


def test_bad_branch():
    with pytest.raises(ValueError, match="branch"):
        position_functions(PHI, *MARK_II_2A.values(), branch="up")


def test_casadi_symbols_give_numpy_values_and_exact_jacobian():
    r, l, k, d = (ca.SX.sym(n) for n in "rlkd")
    phi = ca.SX.sym("phi")
    res = paper_four_bar(phi, r, l, k, d)
    out = ca.vertcat(res.phi3, res.u3, res.du3)
    x = ca.vertcat(r, l, k, d)
    f = ca.Function("f", [phi, x], [out, ca.jacobian(out, x)])
    x0 = np.array(list(MARK_II_2A.values()))
    for ph in (0.3, 2.0, 4.5):
        val, jac = (np.array(v) for v in f(ph, x0))
        num = paper_four_bar(ph, *x0)
        np.testing.assert_allclose(val.ravel(), [num.phi3, num.u3, num.du3], rtol=1e-12)
        h = 1e-6
        for j in range(4):
            xp, xm = x0.copy(), x0.copy()
            xp[j] += h
            xm[j] -= h
            fp, fm = paper_four_bar(ph, *xp), paper_four_bar(ph, *xm)
            fd = (np.array([fp.phi3, fp.u3, fp.du3]) - np.array([fm.phi3, fm.u3, fm.du3])) / (2 * h)
            np.testing.assert_allclose(jac[:, j], fd, rtol=1e-6, atol=1e-8)

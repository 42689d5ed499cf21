"""Paper 001's printed kinematic formulas (1)-(10), implemented as written, and their check
against the exact linkage model.

Each ``eqN_*`` function is the printed formula in the paper's symbols (SI, rad). The check
functions evaluate them on the exact motion of a :func:`~.model.six_link` or
:func:`~.model.five_link` and report, for every formula, the largest deviation over the cycle
from the exact value, as printed and with the correction that makes it exact (the errata).

Mapping of the paper's symbols onto the model (our frame: base line along +x, angles
counter-clockwise): ``phi3`` is the angle of the rocker arm D->K from the base line, ``rho``
the guide's angle, ``h`` the guide's distance to the left of D (:func:`~.model.
guide_offset_from_D`), ``V_K = omega3 L_KD`` and ``a_K^t = eps3 L_KD``, ``a_K^n = omega3^2
L_KD`` (K on its circle about D), ``a_KN^n = omega4^2 L_KN``; for the five-link, ``R_EB`` is D's
distance from the guide (the involute's base radius) and ``L_EB`` the distance along the guide
from the foot of that perpendicular to the contact point (the paper's point P).
"""

from __future__ import annotations

import numpy as np

from .model import guide_offset_from_D

__all__ = [
    "eq1_eta",
    "eq3_v_kn",
    "eq4_v_n",
    "eq5_u41",
    "eq6_a_kn_t",
    "eq7_a_n",
    "eq8_l_dp",
    "eq9_phi3r",
    "eq9_v_py",
    "eq10_a_py",
    "eq11_gravity_moment",
    "eq12_reduced_inertia",
    "eq20_f43",
    "eq21_f45",
    "six_link_quantities",
    "check_six_link",
    "five_link_quantities",
    "check_five_link",
    "rho_finding",
    "ERRATA",
]


# ----------------------------------------------------------------------------- as printed
def eq1_eta(phi3, rho, l_kd, l_kn, h):
    """(1) angle of the extra rod KN: ``eta = arcsin((L_KD sin(phi3 + rho) - h) / L_KN)``."""
    with np.errstate(invalid="ignore"):
        return np.arcsin((l_kd * np.sin(phi3 + rho) - h) / l_kn)


def eq3_v_kn(v_k, phi3, rho, eta):
    """(3) velocity of N relative to K: ``V_KN = V_K cos(phi3 - rho) / cos(eta)``."""
    return v_k * np.cos(phi3 - rho) / np.cos(eta)


def eq4_v_n(v_k, phi3, rho, eta):
    """(4) striker velocity: ``V_N = -V_K sin(eta - phi3 + rho) / cos(eta)``."""
    return -v_k * np.sin(eta - phi3 + rho) / np.cos(eta)


def eq5_u41(v_k, v_b, phi3, rho, eta, lambda5):
    """(5) ratio of the extra rod's to the crank's angular speed:
    ``U41 = V_K cos(phi3 - rho) / (lambda5 V_B cos(eta))``, ``lambda5 = L_KN / L1``,
    ``V_B = omega1 L1`` (the paper calls it the crank's linear speed)."""
    return v_k * np.cos(phi3 - rho) / (lambda5 * v_b * np.cos(eta))


def eq6_a_kn_t(a_k_t, a_k_n, a_kn_n, phi3, rho, eta):
    """(6) ``a_KN^t = (a_K^t cos(phi3-rho) + a_KN^n sin(eta) - a_K^n sin(phi3-rho)) / cos(eta)``."""
    return (
        a_k_t * np.cos(phi3 - rho) + a_kn_n * np.sin(eta) - a_k_n * np.sin(phi3 - rho)
    ) / np.cos(eta)


def eq7_a_n(a_k_t, a_k_n, a_kn_n, a_kn_t, phi3, rho, eta):
    """(7) ``a_N = a_KN^n cos(eta) + a_KN^t sin(eta) - a_K^n cos(phi3-rho)
    - a_K^t sin(phi3-rho)``."""
    return (
        a_kn_n * np.cos(eta)
        + a_kn_t * np.sin(eta)
        - a_k_n * np.cos(phi3 - rho)
        - a_k_t * np.sin(phi3 - rho)
    )


def eq8_l_dp(l_eb, r_eb):
    """(8) printed ``L_EB = sqrt(L_EB^2 + R_EB^2)``: the left side can only be the distance
    D-P from the rocker's pivot to the contact point, ``L_DP``."""
    return np.sqrt(l_eb**2 + r_eb**2)


def eq9_phi3r(l_eb, r_eb):
    """(9) ``phi3R = arctg(R_EB / L_EB)``."""
    return np.arctan(r_eb / l_eb)


def eq9_v_py(v_p, phi3r):
    """The striker's speed along its guide, printed after (9): ``V_Py = V_P cos(phi3R)``, with
    ``V_P = omega3 L_DP`` the speed of the rocker's point P."""
    return v_p * np.cos(phi3r)


def eq10_a_py(a_p_n, a_p_t, phi3r):
    """(10) ``a_Py = a_P cos(arctg(a_P^n / a_P^t) + phi3K)`` with ``a_P = |(a_P^n, a_P^t)|``;
    the printed ``phi3K`` is read as ``phi3R`` (no other angle of that name is defined)."""
    a_p = np.hypot(a_p_n, a_p_t)
    return a_p * np.cos(np.arctan(a_p_n / a_p_t) + phi3r)


def eq11_gravity_moment(g4, v_py_over_omega, psi, gamma):
    """(11) the striker's reduced gravity moment ``M_G4 = G4 (-V_Py / omega1) cos(psi + gamma)``
    (N m; G4 its weight in N, V_Py/omega1 its velocity analog along the guide, m/rad; psi the
    machine's tilt, gamma the mechanism's in the housing)."""
    return g4 * (-v_py_over_omega) * np.cos(psi + gamma)


def eq12_reduced_inertia(j_1a, m2, v_s2, j_2s, u21, j_3d, u31, m4, v_py):
    """(12) ``J_red = J_1A + m2 (V_S2/omega1)^2 + J_2S U21^2 + J_3D U31^2 + m4 (V_Py/omega1)^2``
    with the velocities given as analogs (per unit crank speed)."""
    return j_1a + m2 * v_s2**2 + j_2s * u21**2 + j_3d * u31**2 + m4 * v_py**2


def eq20_f43(g4, phi4, psi, gamma):
    """(20) ``F43 = -G4 cos(psi + gamma) - Phi4`` (N; ``Phi4 = -m4 a_N`` the striker's inertia
    force; the axis pointing down the guide, the way gravity pulls the striker at zero tilt):
    the rocker's force on the striker (the text says the striker's on the rocker)."""
    return -g4 * np.cos(psi + gamma) - phi4


def eq21_f45(g4, psi, gamma):
    """(21) the guide's normal force on the striker ``F45 = -G4 sin(psi + gamma)`` (N)."""
    return -g4 * np.sin(psi + gamma)


# ----------------------------------------------------------------------------- exact values
def six_link_quantities(linkage, phi, speed=1.0):
    """Exact values of the paper's six-link symbols at crank angles ``phi`` (rad) and crank
    speed ``speed`` (rad/s): a dict of arrays (``phi3, rho, h, l_kd, l_kn, eta, v_k, v_b,
    v_kn, v_n, u41, a_k_t, a_k_n, a_kn_n, a_kn_t, a_n``). ``eta`` is the exact angle between
    the guide and the rod, signed as the printed (1) defines it (``sin eta`` = K's distance
    from the guide over ``L_KN``), ``v_kn = omega4 L_KN`` and ``a_kn_t = eps4 L_KN`` signed
    counter-clockwise."""
    p = linkage.parameters
    m = linkage.motion(phi, speed=speed)
    d, k = m.points["D"], m.points["K"]
    rho = float(p["N_guide_angle"])
    h = float(guide_offset_from_D(linkage))
    l_kd = float(np.hypot(p["K_along"], p["K_left"]))
    l_kn = float(p["KN"])
    phi3 = np.arctan2(k.y - d.y, k.x - d.x)
    w3, e3 = m.links["DB"].omega, m.links["DB"].epsilon
    w4, e4 = m.links["KN"].omega, m.links["KN"].epsilon
    dist = -(k.x - d.x) * np.sin(rho) + (k.y - d.y) * np.cos(rho) - h
    return {
        "phi": np.asarray(phi, dtype=float),
        "phi3": phi3,
        "rho": rho,
        "h": h,
        "l_kd": l_kd,
        "l_kn": l_kn,
        "eta": np.arcsin(dist / l_kn),
        "v_k": w3 * l_kd,
        "v_b": speed * float(p["OA"]),
        "lambda5": l_kn / float(p["OA"]),
        "v_kn": w4 * l_kn,
        "u41": w4 / speed,
        "v_n": m.sliders["N"].velocity,
        "a_k_t": e3 * l_kd,
        "a_k_n": w3 * w3 * l_kd,
        "a_kn_n": w4 * w4 * l_kn,
        "a_kn_t": e4 * l_kn,
        "a_n": m.sliders["N"].acceleration,
        "branch": int(linkage.groups[-1].branch),
    }


def _dev(printed, exact):
    """Largest deviation relative to the exact quantity's largest magnitude."""
    printed, exact = np.asarray(printed, float), np.asarray(exact, float)
    if not np.all(np.isfinite(printed)):
        return float("inf")  # the printed formula cannot be evaluated (arcsin beyond 1)
    return float(np.max(np.abs(printed - exact)) / max(np.max(np.abs(exact)), 1e-300))


def _row(formula, quantity, printed, exact, corrected, corrected_value):
    """One line of a formula check: the printed form's and the corrected form's deviations
    from the exact model."""
    dp = _dev(printed, exact)
    return {
        "formula": formula,
        "quantity": quantity,
        "printed_deviation": dp,
        "agrees": dp < 1e-9,
        "corrected": corrected,
        "corrected_deviation": _dev(corrected_value, exact),
    }


def check_six_link(linkage, phi=None, speed=1.0):
    """Each printed six-link formula against the exact model over ``phi`` (default 720 angles).

    Returns a list of rows ``{"formula", "quantity", "printed_deviation", "corrected",
    "corrected_deviation", "agrees"}``: deviations are relative to the exact quantity's peak;
    ``agrees`` when the printed formula is within 1e-9.
    """
    phi = np.linspace(0, 2 * np.pi, 720, endpoint=False) if phi is None else phi
    q = six_link_quantities(linkage, phi, speed)
    br = q["branch"]
    phi3, rho, eta = q["phi3"], q["rho"], q["eta"]
    rows = []

    def row(*args):
        rows.append(_row(*args))

    eta1 = eq1_eta(phi3, rho, q["l_kd"], q["l_kn"], q["h"])
    row(
        "(1)",
        "eta",
        eta1,
        eta,
        "eta = arcsin((L_KD sin(phi3 - rho) - h) / L_KN) (rho and phi3 counter-clockwise)",
        np.arcsin((q["l_kd"] * np.sin(phi3 - rho) - q["h"]) / q["l_kn"]),
    )
    # (3)-(7) take the exact eta, so that each is judged on its own
    v3 = eq3_v_kn(q["v_k"], phi3, rho, eta)
    row(
        "(3)",
        "V_KN = omega4 L_KN",
        v3,
        q["v_kn"],
        "V_KN = -br V_K cos(phi3 - rho) / cos(eta)  (br = +1: N ahead of K along the guide)",
        -br * q["v_k"] * np.cos(phi3 - rho) / np.cos(eta),
    )
    v4 = eq4_v_n(q["v_k"], phi3, rho, eta)
    row(
        "(4)",
        "V_N along the guide",
        v4,
        q["v_n"],
        "V_N = -V_K sin(phi3 - rho + br eta) / cos(eta): for br = -1 the printed (4) with the "
        "opposite sign",
        -q["v_k"] * np.sin(phi3 - rho + br * eta) / np.cos(eta),
    )
    u5 = eq5_u41(q["v_k"], q["v_b"], phi3, rho, eta, q["lambda5"])
    row(
        "(5)",
        "U41 = omega4 / omega1",
        u5,
        q["u41"],
        "U41 = -br V_K cos(phi3 - rho) / (lambda5 V_B cos(eta))",
        -br * u5,
    )
    a6 = eq6_a_kn_t(q["a_k_t"], q["a_k_n"], q["a_kn_n"], phi3, rho, eta)
    a6c = -br * a6
    row(
        "(6)",
        "a_KN^t = eps4 L_KN",
        a6,
        q["a_kn_t"],
        "a_KN^t = -br (a_K^t cos(phi3-rho) + a_KN^n sin(eta) - a_K^n sin(phi3-rho)) / cos(eta)",
        a6c,
    )
    a7 = eq7_a_n(q["a_k_t"], q["a_k_n"], q["a_kn_n"], q["a_kn_t"], phi3, rho, eta)
    a7c = (
        -br * q["a_kn_n"] * np.cos(eta)
        + q["a_kn_t"] * np.sin(eta)
        - q["a_k_n"] * np.cos(phi3 - rho)
        - q["a_k_t"] * np.sin(phi3 - rho)
    )
    row(
        "(7)",
        "a_N along the guide",
        a7,
        q["a_n"],
        "a_N = -br a_KN^n cos(eta) + a_KN^t sin(eta) - a_K^n cos(phi3-rho) - a_K^t sin(phi3-rho)",
        a7c,
    )
    return rows


def five_link_quantities(linkage, phi, speed=1.0):
    """Exact values of the paper's five-link symbols: ``l_eb`` (signed distance along the guide
    from the foot of D's perpendicular to the contact point P), ``r_eb`` (D's distance from the
    guide), ``omega3, eps3``, the rocker point P's speed and accelerations ``v_p, a_p_t, a_p_n``,
    the contact point's acceleration projected on the guide ``a_p_proj``, and the striker's
    ``v_n, a_n`` along its guide."""
    p = linkage.parameters
    m = linkage.motion(phi, speed=speed)
    rho = float(p["N_guide_angle"])
    g = np.array([np.cos(rho), np.sin(rho)])
    d, c = m.points["D"], m.points["N_contact"]
    r_eb = float(p["N_guide_offset"])
    foot = (d.x - r_eb * g[1], d.y + r_eb * g[0])
    rx, ry = c.x - d.x, c.y - d.y
    l_eb = (c.x - foot[0]) * g[0] + (c.y - foot[1]) * g[1]
    w3, e3 = m.links["DB"].omega, m.links["DB"].epsilon
    l_dp = np.hypot(rx, ry)
    # acceleration of the rocker's material point at P: eps x r - omega^2 r
    ax, ay = -e3 * ry - w3 * w3 * rx, e3 * rx - w3 * w3 * ry
    return {
        "l_eb": l_eb,
        "r_eb": r_eb,
        "l_dp": l_dp,
        "omega3": w3,
        "eps3": e3,
        "v_p": w3 * l_dp,
        "a_p_t": e3 * l_dp,
        "a_p_n": w3 * w3 * l_dp,
        "a_p_proj": ax * g[0] + ay * g[1],
        "v_n": m.sliders["N"].velocity,
        "a_n": m.sliders["N"].acceleration,
    }


def check_five_link(linkage, phi=None, speed=1.0):
    """The printed five-link formulas (8)-(10) against the exact model (rows as
    :func:`check_six_link`). With an involute profile the exact striker motion is
    ``V_N = -omega3 R_EB``, ``a_N = -eps3 R_EB`` (signs: guide direction against the
    rocker's counter-clockwise turn)."""
    phi = np.linspace(0, 2 * np.pi, 720, endpoint=False) if phi is None else phi
    q = five_link_quantities(linkage, phi, speed)
    rows = []

    def row(*args):
        rows.append(_row(*args))

    l_eb, r_eb = np.abs(q["l_eb"]), q["r_eb"]
    row(
        "(8)",
        "L_DP",
        eq8_l_dp(l_eb, r_eb),
        q["l_dp"],
        "L_DP = sqrt(L_EB^2 + R_EB^2)",
        eq8_l_dp(l_eb, r_eb),
    )
    phi3r = eq9_phi3r(l_eb, r_eb)
    v9 = eq9_v_py(np.abs(q["v_p"]), phi3r)
    row(
        "(9)",
        "|V_N| (involute)",
        v9,
        np.abs(q["v_n"]),
        "V_Py = V_P sin(phi3R) = omega3 R_EB (phi3R is the angle at P, not at D)",
        np.abs(q["v_p"]) * np.sin(phi3r),
    )
    a10 = eq10_a_py(q["a_p_n"], q["a_p_t"], phi3r)
    row(
        "(10)",
        "|a_N| (involute)",
        np.abs(a10),
        np.abs(q["a_n"]),
        "a_N = eps3 R_EB: the striker's acceleration is not the projection of the contact "
        "point's (that misses -omega3^2 L_EB)",
        np.abs(q["eps3"]) * r_eb,
    )
    row(
        "(10')",
        "|a_N| vs the projection of the rocker point P's acceleration",
        np.abs(q["a_p_proj"]),
        np.abs(q["a_n"]),
        "a_N = eps3 R_EB",
        np.abs(q["eps3"]) * r_eb,
    )
    return rows


def rho_finding(linkage, speed=1.0):
    """Paper 001's finding at the special position (Figs. 2-4): the striker's speed V_N against
    the rocker point's V_K where the arm D-K lies along the base line.

    Returns a dict: ``rho_deg``, ``phi_deg`` (the special crank angles), ``v_k``, ``v_n``
    (m/s, magnitudes), ``ratio`` = |V_N| / |V_K|, ``eta_deg`` (the rod's angle there, as (1)
    defines it), ``predicted_ratio`` = ``|sin(br eta - rho)| / cos(eta)`` (the velocity plan
    at phi3 = 0), and ``paper`` -- what the paper states: ``"="`` for rho = 90 deg, ``">"``
    (V_N > V_K) below 90 deg, ``"<"`` above -- with ``holds`` whether the model agrees."""
    from .model import special_angles

    phi = special_angles(linkage)
    q = six_link_quantities(linkage, phi, speed)
    v_k, v_n = np.abs(q["v_k"]), np.abs(q["v_n"])
    ratio = v_n / v_k
    rho = q["rho"]
    eta = q["eta"]
    predicted = np.abs(np.sin(q["branch"] * eta - rho)) / np.cos(eta)
    rho_deg = float(np.degrees(rho))
    if abs(rho_deg - 90.0) < 1e-9:
        paper, holds = "=", bool(np.all(np.abs(ratio - 1.0) < 1e-9))
    elif rho_deg < 90.0:
        paper, holds = ">", bool(np.all(ratio > 1.0))
    else:
        paper, holds = "<", bool(np.all(ratio < 1.0))
    return {
        "rho_deg": rho_deg,
        "phi_deg": np.degrees(phi).tolist(),
        "v_k": v_k.tolist(),
        "v_n": v_n.tolist(),
        "ratio": ratio.tolist(),
        "eta_deg": np.degrees(eta).tolist(),
        "predicted_ratio": predicted.tolist(),
        "paper": paper,
        "holds": holds,
    }


ERRATA = [
    "(1): with the rocker angle phi3 and the guide angle rho measured the same way, K's distance "
    "from the guide is L_KD sin(phi3 - rho) - h; the printed sin(phi3 + rho) holds only if rho is "
    "measured the opposite way from phi3, which (2)-(7) do not do (as printed, the arcsin's "
    "argument leaves [-1, 1] on the representative machine).",
    "(4): for the assembly in which (3), (5), (6) and (7) hold as printed (the striker N behind K "
    "along the guide direction), the printed V_N = -V_K sin(eta - phi3 + rho)/cos(eta) has the "
    "wrong sign: it takes V_N positive against the direction in which (7) takes a_N positive.",
    "(3), (5), (6), (7): exact as printed for the striker behind K along the guide; with the "
    "striker ahead of K (the other assembly of the same links) V_KN, U41 and a_KN^t change sign "
    "and so does the a_KN^n term of (7) -- the velocity and acceleration plans were drawn for "
    "one assembly only.",
    "(8): printed L_EB = sqrt(L_EB^2 + R_EB^2); the left side is the distance D-P from the "
    "rocker's pivot to the contact point.",
    "(9): with phi3R = arctg(R_EB/L_EB) (the angle at the contact point P between P-D and the "
    "guide) the striker's speed is V_P sin(phi3R) = omega3 R_EB, not V_P cos(phi3R).",
    "(10): projecting the rocker point's acceleration on the guide is not the striker's "
    "acceleration (the contact slides along the profile); for the involute a_N = eps3 R_EB "
    "exactly, while the projection gives eps3 R_EB - omega3^2 L_EB (and the printed form, with "
    "cos, eps3 L_EB - omega3^2 R_EB).",
    "(20): the d'Alembert sum (19) is over the striker's forces, so F43 = -G4 cos(psi+gamma) - "
    "Phi4 is the rocker's force on the striker (projected on the axis pointing down the guide), "
    "not the striker's force on the rocker as the text says; (21) is exact as printed. (22)-(28) "
    "(the rocker's joint forces) refer to figures missing from the text and are not checked "
    "term by term: the joint forces come from the general kinetostatics, power-balanced.",
    "(14): the work of the position-dependent moments enters with the wrong sign: from (13) with "
    "trapezoidal works, J_i w_i^2/dphi - J_0 w_0^2/dphi - M_w0 - 2 A_phi/dphi = M_wi (printed "
    "+2 A_phi/dphi).",
    "(16): Kloss's denominator must be s_k^2 + (1 - w/w_c,red)^2 (the square of the slip is "
    "missing). (17)-(18): the quartic's coefficients are garbled -- e.g. its w^4 term is "
    "J_i / (2 w_c,red^2), not J_i / w_c,red; the correct quartic is derived in docs/dynamics.md "
    "(quartic_coefficients) and has exactly one positive real root at every step of the "
    "study's steady state, as the paper says.",
    "Force findings: the joint forces peak about 16 deg before a dead centre (where the rocker's "
    "acceleration peaks), near but not at the alignment of the links; the rocker-striker force "
    "is 0.36-0.43 of the four-bar's joint forces with a 3 kg striker -- smaller, not 'many "
    "times' smaller.",
    "Findings at the special position (rho = 90: V_N = V_K; rho > 90: V_N < V_K; rho < 90: "
    "V_N > V_K): the first is exact for any rod (K moves along the guide there); the other two "
    "hold only for the striker behind K and a rod leaning by more than |90 deg - rho| / 2 from "
    "the guide the right way -- in general |V_N| / |V_K| = |sin(br eta - rho)| / cos(eta) (br = "
    "-1 behind, +1 ahead of K); with the striker ahead of K they are reversed.",
]

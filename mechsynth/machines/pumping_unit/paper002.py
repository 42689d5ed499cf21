"""Paper 002's printed equations, written out in its own notation and evaluated on our solution.

Senchishak, Popovych, Prozur (2016) analyse the spatial drive with vector contours and d'Alembert
equilibrium. Every printed equation is here as a *residual* (a vector that vanishes when the
equation holds) of the quantities computed by :mod:`.spatial_unit` and :mod:`.spatial_forces`;
where the print is wrong, both the corrected and the printed forms are given (``printed=True``)
and the difference is listed in :data:`ERRATA`. The tests evaluate all of them.

Notation (paper -> code): links 1 crank, 2 left pitman AB, 3 right pitman A1B1, 4 equalizer,
5 beam; ``l1 = OA``, ``l11 = O1A1``, ``l2 = AB``, ``l3 = A1B1``, ``l4 = BD``, ``l41 = B1D``,
``l5 = DC``; frame points N (shaft centre), M (the foot of the Samson post below C);
``R_ij`` the force of body i on body j; ``G`` weights, ``Phi = -m a_S`` inertia forces,
``M_i = -J eps - omega x J omega`` inertia moments; ``l_S2``, ``l_S3`` from the pitmans' centres
of mass to B, B1 (the minus signs of (27), (29) turn them round); ``lambda3 = CE / CS_bal``,
``lambda4 = CE / CS_gb``; ``l_E`` along the beam for the masses and ``l_sht`` (horizontal, length
A) for the polished-rod force ``F_sht``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...kinematics.spatial import Y, cross, dot, unit
from .spatial_forces import SpatialForces, SpatialMasses, _axisymmetric
from .torque import GRAVITY, Counterbalance

__all__ = [
    "ERRATA",
    "paper_torsion_moment",
    "paper_bending_moment",
    "angle_between_pitmans",
    "vectors",
    "kinematic_residuals",
    "point_kinematics",
    "kinetostatic_residuals",
    "crank_residuals",
]

#: errors in the print of paper 002, one sentence each (numbers found by the study are added there)
ERRATA = [
    "Eq. (12) writes eps4 x l4 for eps4 x l41 (the second contour runs through B1D); it only "
    "shows when the equalizer turns (any deviation).",
    "Eq. (20)-(21): 3 E J_z sin(dbeta/2) / l^2 has the dimension of a force, not a moment: it is "
    "the end force of a cantilever whose end is deflected by l sin(dbeta/2); the moment at its "
    "clamp is 3 E J_z sin(dbeta/2) / l. And a moment along e_BD (the pin axis of B) is one a "
    "frictionless revolute pair cannot carry: bending of the pitmans in the plane of motion is "
    "not constrained by pins whose axes are normal to that plane.",
    "Eqs. (17), (27), (29), (35), (37) add the elastic moments M_F, M_kp to the pitmans' own "
    "equilibrium as if they were external loads; they are internal. A pitman's elasticity "
    "reaches its free body only through the reaction moments of the pairs at its ends, which "
    "the compatibility of the deformations fixes (here: the force method with the pitmans' "
    "6 x 6 compliance).",
    "Eqs. (29) and (37) take the moment of R42 about B (its own point: zero arm); the force at A, "
    "R12, belongs there: M_R12 - l2 x R12 + ..., as in (27) for the other pitman.",
    "Eqs. (23), (31), (39), (41), (42) place the beam's and the head's centres of mass at "
    "lambda3 l_E and lambda4 l_E with lambda3 = CE/CS_bal, lambda4 = CE/CS_gb: the arms are "
    "l_E / lambda3 = CS_bal and l_E / lambda4 = CS_gb.",
    "Eqs. (31) and (42), moments about D, give the polished-rod force the arm l_E; about D it is "
    "l5 + l_E (as (23) has it).",
    "Eq. (41), moments about C, has + l5 x R45; the arm from C to D is -l5 (as in (39)).",
    "Eq. (42) defines l_E = (l_CE, 0, 0) (horizontal) while (13) puts E on the beam line "
    "(l_CE e_DC): the horizontal arm is right for the polished-rod load hanging from the "
    "horsehead, the beam line for the beam's masses.",
    "Eq. (47) counts the rotary inertia of the counterweights and crank arms twice: once in "
    "M_i1 = -eps1 J_z with J_z containing m_pr OS_pr^2 and m1 OS1^2, and again through the "
    "tangential inertia forces 2 l_pr x Phi_pr and 2 l_S1 x Phi_1; J_z may hold only the arms' "
    "own central inertia (2 m1 L^2/12).",
    "Eqs. (40)-(42) do not determine R05, R45 and M_R05 (about D is about C plus l5 x the force "
    "sum: 6 independent equations for 8 unknowns), nor do (43)-(46) fix the split along the "
    "equalizer axis between B and B1 (the moment equation (44) has no component along e_BD); "
    "the pitmans' moment equations, left out of the rational mechanism, close the system.",
    "The revolute drive is 5 times, not 4 times, statically indeterminate: W = 6*5 - 5*6 - 3*1 "
    "= -3, but with B, D, B1 on one line the equalizer can spin idly about it (revolutes B, B1 "
    "and the spherical D all allow it), so the drive's actual mobility is 2 and q = 2 - (-3) = 5 "
    "(the equilibrium matrix has rank 29 for 34 unknowns).",
    "M_R05 = 0 (after (39)) holds only for the ideal unit: with a deviation the saddle bearing "
    "carries a moment across its axis.",
]


def paper_torsion_moment(G, J_p, twist, length):
    """Eqs. (18)-(19): ``M_kp = G J_p phi_k / l_AB`` (N m) for a twist ``phi_k`` (rad)."""
    return G * J_p * np.asarray(twist) / length


def paper_bending_moment(E, J_z, dbeta, length):
    """Eqs. (20)-(21) as printed: ``3 E J_z sin(dbeta/2) / l_AB^2`` -- dimensionally a force (N),
    see :data:`ERRATA`."""
    return 3.0 * E * J_z * np.sin(np.asarray(dbeta) / 2.0) / length**2


def angle_between_pitmans(motion) -> Any:
    """``dbeta23``: the angle (rad) between the two pitmans in the xy plane when both end at the
    equalizer bearing's projection (the paper's picture: B and B1 over D), i.e. between the
    projections of A->D and A1->D. Positive when the right pitman is turned counter-clockwise
    from the left one."""
    P = motion.points
    u = P["D"].position - P["A"].position
    v = P["D"].position - P["A1"].position
    a = np.arctan2(v[..., 1], v[..., 0]) - np.arctan2(u[..., 1], u[..., 0])
    return np.arctan2(np.sin(a), np.cos(a))


def vectors(unit_, forces: SpatialForces, masses: SpatialMasses | None = None, gravity=GRAVITY):
    """Paper 002's vectors, weights, inertia forces and moments on our solution (a dict)."""
    masses = forces.info["masses"] if masses is None else masses
    m = forces.motion
    P = {k: p.position for k, p in m.points.items()}
    K = m.links
    g = np.array([0.0, -gravity, 0.0])
    v = dict(
        l1=P["A"] - P["O"],
        l11=P["A1"] - P["O1"],
        l2=P["B"] - P["A"],
        l3=P["B1"] - P["A1"],
        l4=P["D"] - P["B"],
        l41=P["D"] - P["B1"],
        l5=P["C"] - P["D"],
        l_ON=P["N"] - P["O"],
        l_NO1=P["O1"] - P["N"],
    )
    M = P["C"] * np.array([1.0, 0.0, 1.0])
    v.update(l_NM=M - P["N"], l_MC=P["C"] - M)
    for i, name in (
        (1, "crank"),
        (2, "pitman_left"),
        (3, "pitman_right"),
        (4, "equalizer"),
        (5, "beam"),
    ):
        v[f"w{i}"], v[f"eps{i}"] = K[name].omega, K[name].epsilon
    A = float(np.asarray(unit_.front_arm))
    head = (P["E"] - P["C"]) / A
    v["l_E"] = A * head  # along the beam, to the horsehead
    v["l_sht"] = A * unit(cross(Y, K["beam"].axis))  # horizontal: the polished-rod arm
    v["F_sht"] = -forces.load[..., None] * Y
    up = cross(K["beam"].axis, head)
    for key, mass, (cu, cv), lam in (
        ("bal", masses.beam, masses.beam_com, "lambda3"),
        ("gb", masses.head, masses.head_com, "lambda4"),
    ):
        r = cu * head + cv * up
        acc = cross(v["eps5"], r) + cross(v["w5"], cross(v["w5"], r))
        v[f"G_{key}"] = mass * g + 0.0 * r
        v[f"Phi_{key}"] = -mass * acc
        v[f"r_{key}"] = r  # C -> centre of mass
        v[lam] = A / abs(cu) if cu else np.inf
    v["M_ibal"] = -(masses.beam_inertia + masses.head_inertia) * v["eps5"]
    # equalizer (centre of mass at D: no offset)
    J4 = _axisymmetric(
        masses.equalizer_transverse(unit_.equalizer_width),
        masses.equalizer_axial_inertia,
        K["equalizer"].axis,
    )
    v["G_tr"] = masses.equalizer * g + 0.0 * P["D"]
    v["Phi_tr"] = -masses.equalizer * m.points["D"].acceleration
    v["M_itr"] = _inertia_moment(J4, v["w4"], v["eps4"])
    L = unit_.lengths
    for i, a, b, side in ((2, "A", "B", "left"), (3, "A1", "B1", "right")):
        r = masses.pitman_com * (P[b] - P[a])
        acc = (
            m.points[a].acceleration
            + cross(v[f"eps{i}"], r)
            + cross(v[f"w{i}"], cross(v[f"w{i}"], r))
        )
        v[f"G{i}"] = masses.pitman * g + 0.0 * r
        v[f"Phi{i}"] = -masses.pitman * acc
        v[f"l_S{i}"] = P[b] - (P[a] + r)  # centre of mass -> B (B1)
        J = _axisymmetric(
            masses.pitman_transverse(L[f"pitman_{side}"]),
            masses.pitman_axial_inertia,
            K[f"pitman_{side}"].axis,
        )
        v[f"M_i{i}"] = _inertia_moment(J, v[f"w{i}"], v[f"eps{i}"])
    for name, r in forces.reactions.items():
        v[name], v[f"M_{name}"] = r.force, r.moment
    return v


def _inertia_moment(J, w, e):
    return -np.einsum("...ij,...j->...i", J, e) - cross(w, np.einsum("...ij,...j->...i", J, w))


def kinematic_residuals(v, e_bd=None) -> dict[str, Any]:
    """Eqs. (5)-(6) (= (1)-(4)) and (9)-(12), corrected; ``"12_printed"`` as printed."""
    out = {
        "5": v["l1"] + v["l2"] + v["l4"] + v["l5"] - (v["l_ON"] + v["l_NM"] + v["l_MC"]),
        "6": v["l_NO1"] + v["l11"] + v["l3"] + v["l41"] + v["l5"] - (v["l_NM"] + v["l_MC"]),
        "9": cross(v["w1"], v["l1"])
        + cross(v["w2"], v["l2"])
        + cross(v["w4"], v["l4"])
        + cross(v["w5"], v["l5"]),
        "10": cross(v["w1"], v["l11"])
        + cross(v["w3"], v["l3"])
        + cross(v["w4"], v["l41"])
        + cross(v["w5"], v["l5"]),
    }

    def acc(i, l):
        w, e = v[f"w{i}"], v[f"eps{i}"]
        return cross(e, l) + cross(w, cross(w, l))

    out["11"] = acc(1, v["l1"]) + acc(2, v["l2"]) + acc(4, v["l4"]) + acc(5, v["l5"])
    out["12"] = acc(1, v["l11"]) + acc(3, v["l3"]) + acc(4, v["l41"]) + acc(5, v["l5"])
    out["12_printed"] = (
        acc(1, v["l11"])
        + acc(3, v["l3"])
        + cross(v["eps4"], v["l4"])
        + cross(v["w4"], cross(v["w4"], v["l41"]))
        + acc(5, v["l5"])
    )
    return out


def point_kinematics(v, unit_class="conventional", l_cs=None, l_osnp=None) -> dict[str, Any]:
    """Eqs. (13)-(16): velocities and accelerations of E, of the equalizer's centre (D), of a
    point of the beam at ``l_cs`` (C -> point, e.g. the head's centre of mass) and of a point of
    the crank at ``l_osnp`` (N -> point, e.g. the counterweights). ``l_CE = l_CE e_DC`` for a
    conventional unit (E ahead of C, D behind), ``-l_CE e_DC`` for a Mark II."""
    w5, e5, w1, e1 = v["w5"], v["eps5"], v["w1"], v["eps1"]
    sign = 1.0 if unit_class == "conventional" else -1.0
    l_dc = v["l5"]
    l_ce = sign * float(np.max(np.linalg.norm(v["l_E"], axis=-1))) * unit(l_dc)
    out = {
        "13_V": cross(w5, l_ce),
        "13_a": cross(e5, l_ce) + cross(w5, cross(w5, l_ce)),
        "14_V": -cross(w5, l_dc),
        "14_a": -cross(e5, l_dc) - cross(w5, cross(w5, l_dc)),
    }
    if l_cs is not None:
        out["15_V"] = cross(w5, l_cs)
        out["15_a"] = cross(e5, l_cs) + cross(w5, cross(w5, l_cs))
    if l_osnp is not None:
        vel = cross(w1, l_osnp)
        out["16_V"] = vel
        out["16_a"] = cross(w1, vel) + cross(e1, l_osnp)
    return out


def kinetostatic_residuals(v, rational=False, elastic=None) -> dict[str, Any]:
    """Eqs. (22)-(39) (revolute drive) or (40)-(46) (``rational=True``), corrected, plus the
    printed forms that differ (``"23_printed"`` ...). ``elastic`` = ``(M_F2 + M_kp2, M_F3 +
    M_kp3)`` for the printed (27), (29) (the paper's elastic moments as loads on the pitmans)."""
    lam3, lam4 = v["lambda3"], v["lambda4"]
    gb, gh = v["G_bal"] + v["Phi_bal"], v["G_gb"] + v["Phi_gb"]
    l5, lE, lsht, F = v["l5"], v["l_E"], v["l_sht"], v["F_sht"]
    R45, R05, R24, R34, R12, R13 = (v[k] for k in ("R45", "R05", "R24", "R34", "R12", "R13"))
    MR05, MR24, MR34, MR12, MR13 = (v[f"M_{k}"] for k in ("R05", "R24", "R34", "R12", "R13"))
    # the centres of mass from C: r_bal = -l_E / lambda3 (behind C), r_gb = l_E / lambda4
    r_bal, r_gb = v["r_bal"], v["r_gb"]
    out = {}
    beam_forces = R45 + gb + gh + R05 + F
    about_d = MR05 + cross(l5, R05) + v["M_ibal"] + cross(l5 + r_bal, gb) + cross(l5 + r_gb, gh)
    about_c = MR05 - cross(l5, R45) + v["M_ibal"] + cross(r_bal, gb) + cross(r_gb, gh)
    # printed arms of the masses: lambda * l_E instead of l_E / lambda
    s_bal = np.sign(np.nan_to_num(dot(r_bal, lE)))[..., None]
    s_gb = np.sign(np.nan_to_num(dot(r_gb, lE)))[..., None]
    pr_bal = s_bal * (lam3 if np.isfinite(lam3) else 0.0) * lE
    pr_gb = s_gb * (lam4 if np.isfinite(lam4) else 0.0) * lE
    about_d_printed_masses = (
        MR05 + cross(l5, R05) + v["M_ibal"] + cross(l5 + pr_bal, gb) + cross(l5 + pr_gb, gh)
    )
    eq_forces = R24 + v["G_tr"] + v["Phi_tr"] - R45 + R34
    p3_forces = R13 + v["G3"] + v["Phi3"] - R34
    p2_forces = R12 + v["G2"] + v["Phi2"] - R24
    if not rational:
        out["22"] = out["30"] = beam_forces
        out["23"] = about_d + cross(l5 + lsht, F)
        out["23_printed"] = about_d_printed_masses + cross(l5 + lsht, F)
        out["31"] = out["23"]
        out["31_printed"] = about_d_printed_masses + cross(lsht, F)
        out["24"] = out["32"] = eq_forces
        out["25"] = out["33"] = (
            MR24 - cross(v["l4"], R24) + v["M_itr"] - cross(v["l41"], R34) + MR34
        )
        out["26"] = out["34"] = p3_forces
        out["27"] = out["35"] = (
            MR13 - cross(v["l3"], R13) + v["M_i3"] - cross(v["l_S3"], v["G3"] + v["Phi3"]) - MR34
        )
        out["28"] = out["36"] = p2_forces
        out["29"] = out["37"] = (
            MR12 - cross(v["l2"], R12) + v["M_i2"] - cross(v["l_S2"], v["G2"] + v["Phi2"]) - MR24
        )
        out["29_printed"] = out["37_printed"] = (
            MR12 - cross(v["l2"], -R24) + v["M_i2"] - cross(v["l_S2"], v["G2"] + v["Phi2"]) - MR24
        )
        if elastic is not None:
            out["27_printed"] = out["35"] + elastic[1]
            out["29_printed_elastic"] = out["29"] + elastic[0]
        out["38"] = (
            R12
            + v["G2"]
            + v["Phi2"]
            + v["G3"]
            + v["Phi3"]
            + R13
            + v["G_tr"]
            + v["Phi_tr"]
            + gb
            + gh
            + R05
            + F
        )
        out["39"] = about_c + cross(lsht, F)
        out["39_printed"] = (
            MR05
            - cross(l5, R45)
            + v["M_ibal"]
            + cross(pr_bal, gb)
            + cross(pr_gb, gh)
            + cross(lsht, F)
        )
    else:
        out["40"] = beam_forces
        out["41"] = about_c + cross(lsht, F)
        out["41_printed"] = out["41"] + 2.0 * cross(l5, R45)
        out["42"] = about_d + cross(l5 + lsht, F)
        out["42_printed"] = about_d + cross(lsht, F)
        out["43"] = eq_forces
        out["44"] = -cross(v["l4"], R24) + v["M_itr"] - cross(v["l41"], R34)
        out["45"] = p2_forces
        out["46"] = p3_forces
    return out


def crank_residuals(unit_, forces: SpatialForces, counterbalance: Counterbalance, gravity=GRAVITY):
    """Eqs. (47) (component along the shaft) and (48) for cranks whose counterweights are the
    point masses ``masses.counterweight`` (arms massless, their own inertia in
    ``masses.crank_inertia``). ``"47_printed"`` uses J_z as printed (with m_pr OS_pr^2)."""
    masses = forces.info["masses"]
    m = forces.motion
    K = m.links
    n = K["crank"].axis
    w1, e1 = K["crank"].omega, K["crank"].epsilon
    rs, _ = unit_.axes()
    th = np.asarray(forces.theta)
    phi = unit_.sense * (th - counterbalance.phase) + np.pi / 2.0
    radius = counterbalance.moment / (masses.counterweight * gravity)
    l_pr = radius * (
        np.cos(phi)[..., None] * rs[..., :, 0] + np.sin(phi)[..., None] * rs[..., :, 1]
    )
    g = np.array([0.0, -gravity, 0.0])
    m_pr = masses.counterweight / 2.0  # one weight per arm
    G_pr = m_pr * g + 0.0 * l_pr
    Phi_pr = -m_pr * (cross(e1, l_pr) + cross(w1, cross(w1, l_pr)))
    P = {k: p.position for k, p in m.points.items()}
    R21, R31 = -forces.reactions["R12"].force, -forces.reactions["R13"].force
    M1 = forces.reactions["R01"].moment
    M_i1 = -masses.crank_inertia * e1
    M_i1_printed = -(masses.crank_inertia + 2.0 * m_pr * radius**2) * e1
    rest = (
        2.0 * cross(l_pr, Phi_pr + G_pr)
        + cross(P["A"] - P["N"], R21)
        + cross(P["A1"] - P["N"], R31)
    )
    return {
        "47": dot(M1 + M_i1 + rest, n),
        "47_printed": dot(M1 + M_i1_printed + rest, n),
        "48": forces.reactions["R01"].force + 2.0 * G_pr + 2.0 * Phi_pr + R21 + R31,
    }

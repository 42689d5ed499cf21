"""Balancing the AB4115 nail header: shaking force and moment, crank counterweights, and their
trade-off against the joint reactions (paper 003, first part: balancing is the paper's stated aim).

A counterweight of mass ``m_c`` (kg) at the position ``p`` (m) in the crank's frame (x along O->A)
enters the crank body as the mass moment ``C = m_c p`` (kg m). At the machine's constant crank
speed the crank has no angular acceleration, so the shaking force, every joint reaction and the
balancing torque are affine in ``C`` and in the slider mass ``m3`` (its weight enters linearly,
the counterweight's weight is a constant for a fixed ``m_c``): the minimax of ``|F_sh|`` over the
cycle is a second-order cone program, and so is every trade-off with a peak reaction as a
constraint. The affine maps are built from kinetostatic solutions at a few designs and checked
at a further design (to 1e-8 relative), never assumed.

The shaking moment about the crank centre O is unchanged by a crank counterweight (its inertia
force passes through O at constant speed); :func:`balance_maps` reports it, the tests check it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...dynamics.inertia import LinkInertia
from ...dynamics.kinetostatics import kinetostatics
from ...dynamics.shaking import frame_load, shaking
from ...errors import MechanismError
from ...synthesis.convex import AffineMap, ConvexResult, minimax_affine
from .model import NailHeader

__all__ = [
    "CW_MASS",
    "CW_MAX_RADIUS",
    "counterweighted_model",
    "BalanceMaps",
    "balance_maps",
    "balance_counterweight",
    "balance_front",
]

#: counterweight mass (kg) of the balancing study and the largest radius (m) it may sit at
CW_MASS = 20.0
CW_MAX_RADIUS = 0.15


def counterweighted_model(nh: NailHeader, mass: float, moment, gravity: bool = True):
    """``nh``'s force model with a counterweight of ``mass`` (kg) and mass moment ``moment``
    ``(Cx, Cy)`` (kg m, crank frame: x along O->A) merged into the crank body."""
    if not mass > 0:
        raise MechanismError(f"counterweight mass must be positive, got {mass}")
    cx, cy = (float(v) for v in moment)
    model = nh.force_model(gravity)
    crank = model.bodies["crank"]
    total = crank.mass + mass
    u, v = crank.com
    gx, gy = (crank.mass * u + cx) / total, (crank.mass * v + cy) / total
    px, py = cx / mass, cy / mass
    inertia = (
        crank.inertia
        + crank.mass * ((u - gx) ** 2 + (v - gy) ** 2)
        + mass * ((px - gx) ** 2 + (py - gy) ** 2)
    )
    return model.with_body("crank", LinkInertia("crank", "O", total, (gx, gy), inertia))


@dataclass(frozen=True)
class BalanceMaps:
    """Affine maps over the crank angles ``phi`` in ``x = (m3, Cx, Cy)`` (kg, kg m, kg m).

    Attributes
    ----------
    shaking : AffineMap of the shaking force (N, 2-vector per angle).
    reactions : ``{joint: AffineMap}`` of the reactions R10, R21, R32 (N, 2-vectors).
    moment : the shaking moment about O (N m) at every angle; it does not depend on ``x``.
    phi : crank angles (rad, counter-clockwise; the machine turns clockwise).
    cw_mass : the counterweight mass (kg) the maps hold for.
    affine_deviation : largest deviation (N) of the maps from a direct solve at a check design.
    """

    shaking: AffineMap
    reactions: dict
    moment: np.ndarray
    phi: np.ndarray
    cw_mass: float
    affine_deviation: float


JOINTS = ("R10", "R21", "R32")


def _solve(nh, x, cw_mass, motion):
    model = counterweighted_model(replace(nh, m3=float(x[0])), cw_mass, (x[1], x[2]))
    res = kinetostatics(model, motion)
    sh = shaking(model, motion)
    out = {"shaking": np.stack([sh.fx, sh.fy], axis=-1)}
    out.update({j: np.stack(res.reactions[j], axis=-1) for j in JOINTS})
    return out, sh.moment, (model, res)


def balance_maps(nh: NailHeader | None = None, phi=None, cw_mass: float = CW_MASS) -> BalanceMaps:
    """The exact affine maps of the shaking force and the train's reactions in ``(m3, Cx, Cy)``
    for the header ``nh`` (default: the paper's) at crank angles ``phi`` (default: 1440 over a
    clockwise turn) at its 600 rpm."""
    from ...units import cycle

    nh = NailHeader() if nh is None else nh
    if nh.counterweight != 0:
        raise MechanismError("balance_maps: give a header without its own counterweight")
    phi = -cycle(1440) if phi is None else np.asarray(phi, dtype=float).ravel()
    motion = nh.motion(phi, speed=nh.omega)
    x0 = np.array([float(nh.m3), 0.0, 0.0])
    y0, moment, _ = _solve(nh, x0, cw_mass, motion)
    steps = np.array([10.0, 1.0, 1.0])
    cols = {k: [] for k in y0}
    for j in range(3):
        yj, _, _ = _solve(nh, x0 + steps[j] * np.eye(3)[j], cw_mass, motion)
        for k in y0:
            cols[k].append((yj[k] - y0[k]) / steps[j])
    maps = {}
    for k in y0:
        A = np.stack(cols[k], axis=-1)
        maps[k] = AffineMap(A, y0[k] - A @ x0, phi)
    xc = x0 + np.array([37.0, 0.83, -0.61])
    yc, moment_c, _ = _solve(nh, xc, cw_mass, motion)
    dev = max(float(np.max(np.abs(maps[k](xc) - yc[k]))) for k in y0)
    scale = max(float(np.max(np.abs(y0[k]))) for k in y0)
    dev_m = float(np.max(np.abs(moment_c - moment)))
    if dev > 1e-8 * scale or dev_m > 1e-8 * float(np.max(np.abs(moment)) + 1.0):
        raise MechanismError(
            f"balance_maps: the loads are not affine in (m3, Cx, Cy) (deviation {dev:.3g} N, "
            f"moment {dev_m:.3g} N m)"
        )
    return BalanceMaps(
        maps["shaking"], {j: maps[j] for j in JOINTS}, np.asarray(moment), phi, cw_mass, dev
    )


def _stack(maps: BalanceMaps, joints):
    A = np.concatenate([maps.reactions[j].A for j in joints])
    b = np.concatenate([maps.reactions[j].b for j in joints])
    return A, b


def balance_counterweight(
    maps: BalanceMaps,
    m3: float | tuple = 15.0,
    reaction_limit: float | None = None,
    joints=JOINTS,
    max_radius: float = CW_MAX_RADIUS,
) -> ConvexResult:
    """Minimize the peak shaking force over the counterweight moment ``C`` (an SOCP).

    ``m3`` fixes the slider mass (kg) or, as ``(low, high)``, leaves it free within bounds.
    ``reaction_limit`` (N) bounds the peak reaction at ``joints``: the trade-off against the
    joint reactions. ``|C| <= cw_mass * max_radius``. Variables ``m3, Cx, Cy``."""
    import cvxpy as cp

    lo, hi = (m3, m3) if np.ndim(m3) == 0 else m3
    c_max = maps.cw_mass * max_radius
    A, b = _stack(maps, joints)
    scale = float(np.max(np.abs(b)))

    def extra(x):
        cons = [cp.norm(x[1:], 2) <= c_max]
        if reaction_limit is not None:
            y = [(A[:, k, :] @ x + b[:, k]) / scale for k in range(2)]
            cons.append(cp.SOC(np.full(A.shape[0], reaction_limit / scale), cp.vstack(y), axis=0))
        return cons

    return minimax_affine(
        maps.shaking,
        norm="euclidean",
        bounds=[(lo, hi), (-c_max, c_max), (-c_max, c_max)],
        constraints=extra,
        names=["m3", "Cx", "Cy"],
    )


def peak_reaction(maps: BalanceMaps, x, joints=JOINTS) -> float:
    """Largest reaction magnitude (N) at ``joints`` over the cycle for ``x = (m3, Cx, Cy)``."""
    A, b = _stack(maps, joints)
    return float(np.max(np.linalg.norm(A @ np.asarray(x, dtype=float) + b, axis=-1)))


def peak_shaking(maps: BalanceMaps, x) -> float:
    """Largest shaking-force magnitude (N) over the cycle for ``x = (m3, Cx, Cy)``."""
    return float(np.max(np.linalg.norm(maps.shaking(x), axis=-1)))


def balance_front(maps: BalanceMaps, n: int = 7, mass_bounds=(1.0, 200.0), joints=JOINTS):
    """Trade-off between the peak shaking force and the peak reaction at ``joints``, with the
    slider mass and the counterweight free: the epsilon-constraint on the reaction from its own
    minimum to its value at the shaking optimum (``n`` SOCPs). Returns a list of dicts
    (``reaction_limit``, ``shaking``, ``reaction``, ``m3``, ``Cx``, ``Cy``, ``status``, and the
    anchors' solver statuses ``anchor_status``)."""
    import cvxpy as cp

    A, b = _stack(maps, joints)
    c_max = maps.cw_mass * CW_MAX_RADIUS
    # the reaction's own minimum over the same box
    r_min = minimax_affine(
        AffineMap(A, b),
        norm="euclidean",
        bounds=[mass_bounds, (-c_max, c_max), (-c_max, c_max)],
        constraints=lambda x: [cp.norm(x[1:], 2) <= c_max],
        names=["m3", "Cx", "Cy"],
    )
    s_min = balance_counterweight(maps, mass_bounds, joints=joints)
    if r_min.x is None or s_min.x is None:
        raise MechanismError(f"balance_front: anchors failed ({r_min.status}, {s_min.status})")
    # an anchor the solver calls inaccurate still gives a feasible design: its peak (recomputed)
    # bounds the front's end from above, which is all the epsilon grid needs
    lo = peak_reaction(maps, r_min.x, joints)
    hi = peak_reaction(maps, s_min.x, joints)
    rows = []
    for eps in np.linspace(lo * (1 + 1e-6), hi, n):
        res = balance_counterweight(maps, mass_bounds, reaction_limit=eps, joints=joints)
        row = {
            "reaction_limit": float(eps),
            "status": res.status,
            "anchor_status": [r_min.status, s_min.status],
        }
        if res.x is not None:
            row.update(
                shaking=float(res.value),
                reaction=peak_reaction(maps, res.x, joints),
                **{k: float(v) for k, v in zip(("m3", "Cx", "Cy"), res.x)},
            )
        rows.append(row)
    return rows


def check_against_frame_load(nh: NailHeader, x, cw_mass: float = CW_MASS, phi=None):
    """Largest difference (N, N m) between :func:`shaking` and :func:`frame_load` (from the
    ground reactions) for the design ``x = (m3, Cx, Cy)``: the two independent computations."""
    from ...units import cycle

    phi = -cycle(360) if phi is None else phi
    motion = nh.motion(phi, speed=nh.omega)
    model = counterweighted_model(replace(nh, m3=float(x[0])), cw_mass, (x[1], x[2]))
    res = kinetostatics(model, motion)
    a, b = shaking(model, motion), frame_load(model, motion, res)
    force = float(max(np.max(np.abs(a.fx - b.fx)), np.max(np.abs(a.fy - b.fy))))
    return force, float(np.max(np.abs(a.moment - b.moment)))

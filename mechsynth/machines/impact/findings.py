"""Paper 001's arguments checked on a machine: what the extra rod's length and the support
position do to the striker and its guide (conclusions 3-4), the rocker's profile built for a
given width (Fig. 13), the per-link reduced inertias and gravity moments (Figs. 17-18) and the
five-link's force findings (Figs. 25-26, conclusion 9).

Every function takes an :class:`~.drive.ImpactMachine` (e.g.
:func:`~.design.representative_machine`) and returns plain numbers and arrays with the paper's
verdict computed, never typed in. Conventions as in :mod:`.model` and :mod:`.forces`: SI, crank
angles from +x counter-clockwise; a reduced moment is positive when it drives the crank forward;
a driving torque is the crankshaft's balancing torque of the kinetostatics.
"""

from __future__ import annotations

import numpy as np

from ... import validate
from ...dynamics.inertia import reduced_inertia
from ...dynamics.reduced import gravity_moment
from ...errors import MechanismError
from .drive import ImpactMachine
from .forces import cycle_forces, dead_centres
from .impact import _bodies
from .model import six_link

__all__ = [
    "six_link_variant",
    "extra_rod_effect",
    "support_position_effect",
    "rocker_profile",
    "reduced_terms",
    "gravity_assist",
    "pair_force_findings",
    "circular_links",
]

BODY_NAMES = {"OA": "crank", "AB": "rod", "DB": "rocker", "KN": "extra rod", "N": "striker"}


def _phi(n):
    return np.linspace(0.0, 2.0 * np.pi, validate.integer("n", n, lo=36), endpoint=False)


def six_link_variant(machine: ImpactMachine, rho=None, extra_rod=None) -> ImpactMachine:
    """``machine`` (a six-link) with another guide angle ``rho`` (rad) and/or extra rod K-N
    (m); the anvil goes back to the special position of the new linkage, the rod keeps its
    mass as a uniform bar of the new length (the other bodies as they are). Raises
    MechanismError where the rod cannot reach the guide."""
    p = machine.linkage.parameters
    if "KN" not in p:
        raise MechanismError("six_link_variant needs a six-link machine (a rod K-N)")
    rho = float(p["N_guide_angle"]) if rho is None else validate.angle("rho", rho)
    kn = float(p["KN"]) if extra_rod is None else validate.length("extra_rod", extra_rod)
    lk = six_link(
        rho,
        kn,
        float(p["N_guide_offset"]),
        ground=float(p["D_x"]),
        crank=float(p["OA"]),
        rod=float(p["AB"]),
        rocker=float(p["DB"]),
        arm=float(np.hypot(p["K_along"], p["K_left"])),
        arm_angle=float(np.arctan2(p["K_left"], p["K_along"])),
    )
    lk.motion(_phi(360))  # raises where it cannot assemble
    inertias = dict(machine.inertias)
    mass = machine.inertias["KN"][0]  # the rod's mass kept, a uniform bar of the new length
    inertias["KN"] = (mass, (0.5 * kn, 0.0), mass * kn * kn / 12.0)
    return machine.replace(linkage=lk, inertias=inertias, anvil=None, sense=None)


def _six_measures(machine: ImpactMachine, phi):
    mo = machine.linkage.motion(phi, speed=machine.omega)
    f = cycle_forces(machine, phi)
    n = mo.sliders["N"]
    return {
        "stroke": float(np.ptp(n.position)),
        "peak_velocity": float(np.max(np.abs(n.velocity))),
        "impact_velocity": float(machine.blow().striker_before),
        "peak_guide_force": float(np.max(np.abs(f.guide))),
        "peak_pressure_angle_deg": float(np.degrees(np.max(mo.pressure_angles["N"]))),
    }


def _trend(x, y):
    """+1 rising, -1 falling, 0 not monotone (relative changes under 1e-6 count as flat)."""
    d = np.diff(np.asarray(y, float))
    scale = max(float(np.max(np.abs(y))), 1e-300)
    d = np.where(np.abs(d) <= 1e-6 * scale, 0.0, d)
    if np.all(d >= 0) and np.any(d > 0):
        return 1
    if np.all(d <= 0) and np.any(d < 0):
        return -1
    return 0


def extra_rod_effect(machine: ImpactMachine, lengths, rhos=None, n=360) -> dict:
    """The extra rod's length K-N against the striker's stroke, peak and impact speed and the
    guide's peak side force, at each guide angle of ``rhos`` (rad; default the machine's).

    Returns ``{"lengths": m, "rho_deg": [...], "rows": {rho_deg: {measure: array}},
    "verdict": {rho_deg: {...}}}``; lengths at which the rod cannot reach the guide are NaN in
    the arrays and listed in ``"unassembled"``. The verdict checks paper 001's conclusion 4 (a
    longer rod lowers the guide force and raises the striker's speed and stroke): each measure's
    trend over the assembled lengths (+1 rising, -1 falling, 0 flat or not monotone)."""
    lengths = np.sort(np.atleast_1d(np.asarray(lengths, dtype=float)))
    for v in lengths:
        validate.length("lengths", v)
    p = machine.linkage.parameters
    rhos = [float(p["N_guide_angle"])] if rhos is None else list(np.atleast_1d(rhos))
    phi = _phi(n)
    keys = ("stroke", "peak_velocity", "impact_velocity", "peak_guide_force")
    rows, verdict, unassembled = {}, {}, {}
    for rho in rhos:
        r = {k: np.full(lengths.shape, np.nan) for k in keys}
        bad = []
        for i, kn in enumerate(lengths):
            try:
                mach = six_link_variant(machine, rho, kn)
                meas = _six_measures(mach, phi)
            except MechanismError:
                bad.append(float(kn))
                continue
            for k in keys:
                r[k][i] = meas[k]
        key = round(float(np.degrees(rho)), 6)
        rows[key], unassembled[key] = r, bad
        ok = np.isfinite(r["stroke"])
        if ok.sum() >= 2:
            t = {k: _trend(lengths[ok], r[k][ok]) for k in keys}
            verdict[key] = {
                "trends": t,
                "guide_force_falls": t["peak_guide_force"] == -1,
                "speed_rises": t["peak_velocity"] == 1,
                "stroke_rises": t["stroke"] == 1,
                "stroke_change_rel": float(np.ptp(r["stroke"][ok]) / np.mean(r["stroke"][ok])),
                "speed_change_rel": float(
                    np.ptp(r["peak_velocity"][ok]) / np.mean(r["peak_velocity"][ok])
                ),
                "guide_force_change_rel": float(
                    np.ptp(r["peak_guide_force"][ok]) / np.mean(r["peak_guide_force"][ok])
                ),
            }
    return {
        "lengths": lengths,
        "rho_deg": list(rows),
        "rows": rows,
        "verdict": verdict,
        "unassembled": unassembled,
    }


def support_position_effect(machine: ImpactMachine, rhos, n=360) -> dict:
    """The rocker's support moved on its arc about O (the guide's angle rho to the base line,
    rad) against the striker's stroke, speeds and the guide's peak side force, the rod K-N as
    in ``machine`` (paper 001's conclusion 3). Returns the arrays (NaN where it cannot
    assemble), the rho of the least guide force and the ranges of stroke and speed."""
    rhos = np.sort(np.atleast_1d(np.asarray(rhos, dtype=float)))
    phi = _phi(n)
    keys = ("stroke", "peak_velocity", "impact_velocity", "peak_guide_force")
    r = {k: np.full(rhos.shape, np.nan) for k in keys}
    for i, rho in enumerate(rhos):
        try:
            meas = _six_measures(six_link_variant(machine, rho), phi)
        except MechanismError:
            continue
        for k in keys:
            r[k][i] = meas[k]
    ok = np.isfinite(r["stroke"])
    if not np.any(ok):
        raise MechanismError("the six-link assembles at none of the guide angles given")
    best = int(np.nanargmin(r["peak_guide_force"]))
    return {
        "rho_deg": np.degrees(rhos),
        **r,
        "least_guide_force_rho_deg": float(np.degrees(rhos[best])),
        "least_guide_force_N": float(r["peak_guide_force"][best]),
        "stroke_range": (float(np.nanmin(r["stroke"])), float(np.nanmax(r["stroke"]))),
        "speed_range": (
            float(np.nanmin(r["peak_velocity"])),
            float(np.nanmax(r["peak_velocity"])),
        ),
    }


def rocker_profile(machine: ImpactMachine, width, n=721) -> dict:
    """The five-link rocker's working surfaces for a given ``width`` (m), built from the motion
    (paper 001, Fig. 13: outer surface, axis, inner surface) and compared with the involute.

    The *axis* is the track of the striker's contact centre N in the rocker's frame (D at the
    origin, D->B along +x) over the forward swing; the surfaces lie ``width/2`` on either side of
    it along the guide's direction seen from the rocker (the contact normal). Their radii of
    curvature are measured from the points by finite differences and set beside the
    involute's, ``sqrt(r^2 - rb^2)`` (``r`` the distance from D, ``rb`` the base radius), and
    the axis's ``+- width/2``: the paper found them equal. Returns the curves (``(x, y)``
    arrays, m), the radii (m) and the largest relative differences (ends trimmed by 5 % where
    the rocker turns slowly)."""
    width = validate.length("width", width)
    p = machine.linkage.parameters
    if "N_profile_base_radius" not in p:
        raise MechanismError("rocker_profile needs a five-link with an involute profile")
    rb = float(p["N_profile_base_radius"])
    lo, hi = dead_centres(machine.linkage)[:2]
    phi = np.linspace(lo, hi, validate.integer("n", n, lo=21))
    mo = machine.linkage.motion(phi)
    th = np.asarray(mo.links["DB"].angle)
    if abs(th[-1] - th[0]) < 1e-6:
        raise MechanismError("the rocker does not swing between the dead centres")
    nn, dd = mo.points["N"], mo.points["D"]
    c, s = np.cos(th), np.sin(th)
    gx, gy = nn.x - dd.x, nn.y - dd.y
    ax, ay = c * gx + s * gy, -s * gx + c * gy  # the axis in the rocker frame
    rho = float(p["N_guide_angle"])
    ux, uy = np.cos(rho - th), np.sin(rho - th)  # the guide direction in the rocker frame
    h = 0.5 * width
    curves = {
        "outer": (ax + h * ux, ay + h * uy),
        "axis": (ax, ay),
        "inner": (ax - h * ux, ay - h * uy),
    }
    keep = slice(int(0.05 * phi.size), phi.size - int(0.05 * phi.size))
    out = {"base_radius": rb, "width": width, "rocker_angle": th, "curves": curves}
    r_axis = np.sqrt(np.maximum(ax**2 + ay**2 - rb * rb, 0.0))
    worst = 0.0
    for name, (x, y) in curves.items():
        x1, y1 = np.gradient(x, th), np.gradient(y, th)
        x2, y2 = np.gradient(x1, th), np.gradient(y1, th)
        measured = (x1**2 + y1**2) ** 1.5 / np.abs(x1 * y2 - y1 * x2)
        own = np.sqrt(np.maximum(x**2 + y**2 - rb * rb, 0.0))  # an involute of the same circle
        sign = {"outer": 1.0, "axis": 0.0, "inner": -1.0}[name]
        offset = np.abs(r_axis + sign * h)
        dev = np.max(np.abs(measured[keep] / own[keep] - 1.0))
        dev_off = np.max(np.abs(own[keep] / offset[keep] - 1.0))
        out[name] = {
            "radius_measured": measured,
            "radius_involute": own,
            "max_rel_difference": float(dev),
            "max_rel_vs_axis_offset": float(dev_off),
            "radius_range": (float(np.min(own[keep])), float(np.max(own[keep]))),
        }
        worst = max(worst, dev, dev_off)
    out["max_rel_difference"] = worst
    return out


def reduced_terms(machine: ImpactMachine, n=720) -> dict:
    """Per-link reduced moments of inertia ``J_i(phi)`` (kg m^2) and reduced gravity moments
    ``M_Gi(phi)`` (N m, positive driving the crank) of ``machine`` at its tilt (paper 001,
    eqs. (11)-(12) and Figs. 17-18, for every body; the crank's includes the drive's inertia
    at the crank). Returns ``phi`` and ``{body: array}`` for both, and their sums."""
    phi = _phi(n)
    lk = machine.linkage
    _, bodies = _bodies(lk, machine.inertias, machine.drive_inertia())
    j, mg = {}, {}
    for name, b in bodies.items():
        jj, _ = reduced_inertia(lk, [b], phi)
        gg, _ = gravity_moment(lk, [b], phi, tilt=machine.tilt)
        j[name] = np.broadcast_to(np.asarray(jj, float), phi.shape).copy()
        mg[name] = np.broadcast_to(np.asarray(gg, float), phi.shape).copy()
    return {
        "phi": phi,
        "inertia": j,
        "gravity": mg,
        "inertia_total": sum(j.values()),
        "gravity_total": sum(mg.values()),
    }


def gravity_assist(machine: ImpactMachine, n=1440) -> dict:
    """Paper 001's Figs. 17-18 finding: from 60 deg of crank angle to the blow the links'
    gravity moments turn the crank forward. Measured: the arc of crank angle before the blow
    over which the total reduced gravity moment is positive (it starts where the striker leaves
    its extreme away from the tool), the arc for each body, and the gravity's work over it.
    The paper's origin of the crank angle is in a figure missing from the text, so its 60 deg
    is compared through the arc's length: the paper's arc is ``blow - 60 deg`` in its origin."""
    t = reduced_terms(machine, n)
    phi, total = t["phi"], t["gravity_total"]
    blow = float(machine.blow_angle())
    back = np.mod(blow - phi, 2 * np.pi)  # crank angle before the blow
    order = np.argsort(back)
    b_sorted, g_sorted = back[order], total[order]
    pos = g_sorted > 0
    arc = float(b_sorted[np.argmin(pos)]) if not np.all(pos) else 2 * np.pi
    per_body = {}
    for name, g in t["gravity"].items():
        gs = g[order]
        if np.max(np.abs(gs)) < 1e-12 * max(1.0, np.max(np.abs(total))):
            per_body[name] = None  # no gravity moment (a balanced crank, a centred striker)
            continue
        p_ = gs > 0
        per_body[name] = float(np.degrees(b_sorted[np.argmin(p_)])) if not np.all(p_) else 360.0
    inside = b_sorted < arc
    step = 2 * np.pi / phi.size
    tilt = machine.tilt
    dx, dy = machine.blow().direction
    return {
        "blow_along_gravity": float(dx * np.sin(tilt) - dy * np.cos(tilt)),
        "blow_deg": float(np.degrees(blow)),
        "assist_arc_deg": float(np.degrees(arc)),
        "assist_from_deg": float(np.degrees(np.mod(blow - arc, 2 * np.pi))),
        "assist_arc_per_body_deg": per_body,
        "work_over_arc_J": float(np.sum(g_sorted[inside]) * step),
        "peak_gravity_moment_Nm": float(np.max(np.abs(total))),
        "holds_up_to_the_blow": bool(arc > np.radians(5.0)),
    }


def pair_force_findings(machine: ImpactMachine, n=720, window_deg=20.0) -> dict:
    """The five-link's (or six-link's) force findings of paper 001 (Figs. 25-26, conclusion 9):

    * *the pair forces, inertia and gravity assist the driving moment at the rocker's extreme
      positions and before the blow*: the crank's driving torque there (N m; negative means the
      machine's own forces drive the crank) -- at each dead centre and over the ``window_deg``
      before the blow;
    * *the main joint loads are normal forces along the links*: for the rod's joints A and B the
      share of the force along A-B, and for the rocker's pivot D the share along D-B, each as
      the cosine of the angle between force and link at the force's peak and the force-weighted
      mean over the cycle;
    * the rocker-striker force against the four-bar's joint forces (Fig. 26).
    """
    phi = _phi(n)
    f = cycle_forces(machine, phi)
    mo, res = f.motion, f.result
    tq = np.asarray(res.torque, float) * np.ones(phi.shape)
    dc = dead_centres(machine.linkage)
    at_dc = [float(np.interp(d, phi, tq, period=2 * np.pi)) for d in dc]
    blow = float(machine.blow_angle())
    before = np.mod(blow - phi, 2 * np.pi) <= np.radians(window_deg)
    a, b, d = mo.points["A"], mo.points["B"], mo.points["D"]
    links = {"A": (b.x - a.x, b.y - a.y), "B": (b.x - a.x, b.y - a.y), "D": (b.x - d.x, b.y - d.y)}
    along = {}
    for j, (lx, ly) in links.items():
        fx, fy = (np.asarray(v, float) * np.ones(phi.shape) for v in res.reactions[j])
        mag = np.hypot(fx, fy)
        cos = np.abs(fx * lx + fy * ly) / (mag * np.hypot(lx, ly) + 1e-300)
        k = int(np.argmax(mag))
        along[j] = {
            "link": "AB" if j in "AB" else "DB",
            "cos_at_peak": float(cos[k]),
            "mean_cos_weighted": float(np.sum(cos * mag) / np.sum(mag)),
            "peak_N": float(mag[k]),
        }
    contact = f"{machine.striker}_contact"
    joint = contact if contact in res.reactions else ("K" if "K" in res.reactions else None)
    rs = None
    if joint is not None:
        rs = float(np.max(res.magnitude(joint)))
    four_bar = max(float(np.max(res.magnitude(j))) for j in ("A", "B", "D"))
    return {
        "dead_centres_deg": np.degrees(dc).tolist(),
        "torque_at_dead_centres_Nm": at_dc,
        "torque_before_blow_Nm": (float(np.min(tq[before])), float(np.max(tq[before]))),
        "assist_at_dead_centres": [t < 0 for t in at_dc],
        "assist_before_blow_fraction": float(np.mean(tq[before] < 0)),
        "torque_range_Nm": (float(np.min(tq)), float(np.max(tq))),
        "along_links": along,
        "rocker_striker_joint": joint,
        "rocker_striker_peak_N": rs,
        "four_bar_peak_N": four_bar,
        "rocker_striker_ratio": None if rs is None else rs / four_bar,
    }


def circular_links(machine: ImpactMachine, shaft=0.008, wall=0.003) -> dict:
    """Paper 001's circular-link embodiments (Figs. 5 and 7): every pair enlarged to a disc
    turning in a bore, the links nested -- the crank an eccentric disc about A in the rod's
    bore, the rod a disc about B in the rocker's recess, the rocker on its axis D (five-link,
    Fig. 7) or, in the six-link (Fig. 5), an eccentric disc about K in the bore of the extra
    rod, itself a disc about N in the rectangular slider.

    A pair of any radius is still a revolute pair about its centre, so the embodiment moves as
    the lever scheme with the same centre distances (the paper's claim, true by construction).
    What it adds are the nesting conditions, with ``shaft`` (m) the crankshaft's and the
    rocker axis's radius and ``wall`` (m) the least wall between a bore and a rim:

    * the crank disc holds the shaft: ``r_A = OA + shaft + wall``;
    * the rod's disc holds the crank's bore: ``r_B = AB + r_A + wall``;
    * the rocker's axis D lies outside the recess: ``DB >= r_B + shaft + wall``;
    * six-link: the rocker's disc about K holds the recess and the axis D:
      ``r_K = max(KB + r_B, KD + shaft) + wall``, and the extra rod's disc
      ``r_N = KN + r_K + wall``.

    Returns the radii (m), each condition's margin (m, negative where it fails) and
    ``"feasible"``; ``"rocker_needed"`` is the least rocker D-B for these walls.
    """
    shaft = validate.positive("shaft", shaft, "m")
    wall = validate.nonnegative("wall", wall, "m")
    p = machine.linkage.parameters
    oa, ab, db = float(p["OA"]), float(p["AB"]), float(p["DB"])
    r_a = oa + shaft + wall
    r_b = ab + r_a + wall
    need = r_b + shaft + wall
    out = {
        "r_A": r_a,
        "r_B": r_b,
        "rocker": db,
        "rocker_needed": need,
        "margins": {"axis D outside the recess": db - need},
    }
    if "KN" in p:
        ku, kv, kn = float(p["K_along"]), float(p["K_left"]), float(p["KN"])
        kb = float(np.hypot(ku - db, kv))
        kd = float(np.hypot(ku, kv))
        r_k = max(kb + r_b, kd + shaft) + wall
        out.update(r_K=r_k, r_N=kn + r_k + wall)
    out["feasible"] = all(m >= 0.0 for m in out["margins"].values())
    return out

"""The impact mechanisms of paper 001 as linkages: the base crank-rocker whose rocker carries the
striker, the six-link (extra rod KN and striker N on a straight guide) and the five-link (the
rocker's extension is a cam profile, an involute or a circular arc, pushing the striker).

Frame and conventions
---------------------
The mechanism's *base line* is the x axis through the crank centre O = (0, 0) and the rocker
pivot D = (d, 0). The crank O-A turns counter-clockwise, the rod A-B drives the rocker D-B. A
striker point K sits on the rocker at ``arm`` (m) from D, its arm D-K turned ``arm_angle`` (rad)
counter-clockwise from D-B. The guide of the striker N makes the angle ``rho`` with the base line
(the paper's rho); it is fixed in the housing and lies ``offset`` (m) to the left of the crank
centre O (the paper adjusts rho by moving the rocker's support on an arc about O, which is a
rotation of the four-bar about O relative to a fixed guide: in the base-line frame, the guide
turns about O at a constant distance). The paper's ``h`` (the guide's distance from D) is
:func:`guide_offset_from_D`.

The *special position* of the rocker (paper 001, Fig. 2) is taken as the position where the
arm D-K lies along the base line, pointing away from O: there K moves perpendicular to the base
line, along a guide at rho = 90 deg.

Parameter names (``linkage.parameters``): ``D_x`` (the ground distance d), ``OA`` (crank),
``AB`` (rod), ``DB`` (rocker), ``K_along``/``K_left`` (K in the rocker frame D->B), ``KN`` (the
extra rod), ``N_guide_offset``/``N_guide_angle`` (the guide's offset from O and rho); for the
five-link ``N_profile_*`` (the cam), ``N_guide_offset`` (from D) and ``N_roller``.
"""

from __future__ import annotations

import numpy as np

from ... import validate
from ...errors import MechanismError
from ...kinematics import ops
from ...kinematics.curves import Circle, Involute
from ...kinematics.linkage import Linkage
from ...units import deg

__all__ = [
    "REPRESENTATIVE",
    "crank_rocker",
    "six_link",
    "five_link",
    "guide_offset_from_D",
    "special_angles",
    "rocker_swing",
]

#: the representative machine's four-bar and six-link (see docs/impact.md for the sources)
REPRESENTATIVE = {
    "ground": 0.080,  # m, O-D
    "crank": 0.011,  # m, O-A
    "rod": 0.062,  # m, A-B
    "rocker": 0.036,  # m, D-B
    "arm": 0.060,  # m, D-K
    "extra_rod": 0.070,  # m, K-N
    "rho_deg": 90.0,
    "speed_rpm": 2000.0,  # one blow per crank turn: 2000 blows/min
}


def _four_bar(ground, crank, rod, rocker, name, branch=1):
    return (
        Linkage(ground={"O": (0.0, 0.0), "D": (ground, 0.0)}, name=name)
        .crank("A", about="O", length=crank)
        .rrr("B", ("A", rod), ("D", rocker), branch=branch)
    )


def rocker_swing(ground=None, crank=None, rod=None, rocker=None, n=720):
    """Extreme angles (rad) of the rocker D->B over a turn of the base four-bar."""
    r = REPRESENTATIVE
    fb = _four_bar(
        r["ground"] if ground is None else ground,
        r["crank"] if crank is None else crank,
        r["rod"] if rod is None else rod,
        r["rocker"] if rocker is None else rocker,
        "four-bar",
    )
    th = np.unwrap(np.asarray(fb.motion(np.linspace(0, 2 * np.pi, n + 1)).links["DB"].angle))
    return float(th.min()), float(th.max())


def _default_arm_angle(ground, crank, rod, rocker):
    """The arm angle that puts D-K along the base line (away from O) at mid-swing."""
    lo, hi = rocker_swing(ground, crank, rod, rocker)
    return float(-0.5 * (lo + hi))


def crank_rocker(
    ground=None,
    crank=None,
    rod=None,
    rocker=None,
    arm=None,
    arm_angle=None,
    name="crank-rocker",
) -> Linkage:
    """The base machine of paper 001: a crank-rocker whose rocker carries the striker K.

    Parameters
    ----------
    ground, crank, rod, rocker : O-D, O-A, A-B, D-B (m); defaults :data:`REPRESENTATIVE`.
    arm : D-K (m), the striker's distance from the rocker pivot.
    arm_angle : angle of D-K from D-B (rad, counter-clockwise); default: D-K along the base
        line at the middle of the rocker's swing.

    The striker is the point ``"K"`` (it swings on an arc: the transverse load on the housing
    that the paper's new schemes remove).
    """
    r = REPRESENTATIVE
    ground = r["ground"] if ground is None else ground
    crank = r["crank"] if crank is None else crank
    rod = r["rod"] if rod is None else rod
    rocker = r["rocker"] if rocker is None else rocker
    arm = r["arm"] if arm is None else arm
    if arm_angle is None:
        arm_angle = _default_arm_angle(ground, crank, rod, rocker)
    elif not ops.is_symbolic(arm_angle):
        arm_angle = validate.real("arm_angle", arm_angle, "rad")
    lk = _four_bar(ground, crank, rod, rocker, name).attach(
        "K", on=("D", "B"), along=arm * np.cos(arm_angle), left=arm * np.sin(arm_angle)
    )
    return lk.with_output("K")


def six_link(
    rho=None,
    extra_rod=None,
    offset=None,
    *,
    ground=None,
    crank=None,
    rod=None,
    rocker=None,
    arm=None,
    arm_angle=None,
    branch=-1,
) -> Linkage:
    """Paper 001's six-link (Fig. 1): the crank-rocker plus the extra rod K-N and the striker N
    on a fixed straight guide.

    Parameters
    ----------
    rho : angle of the guide to the base line (rad); default 90 deg.
    extra_rod : K-N (m).
    offset : the guide's distance to the left of O along its direction (m); default: the
        guide through K's special position when rho = 90 deg, ``-(d + arm)``.
    ground, crank, rod, rocker, arm, arm_angle : the base machine, as :func:`crank_rocker`.
    branch : the striker's assembly: ``-1`` (default) puts N behind K along the guide
        direction (below K for rho near 90 deg), ``+1`` ahead.

    Raises
    ------
    MechanismError
        (on motion) where the rod K-N cannot reach the guide, naming the crank angle and the
        distances.
    """
    r = REPRESENTATIVE
    base = crank_rocker(ground, crank, rod, rocker, arm, arm_angle, name="six-link")
    rho = deg(r["rho_deg"]) if rho is None else rho
    extra_rod = r["extra_rod"] if extra_rod is None else extra_rod
    if offset is None:
        p = base.parameters
        offset = -(p["D_x"] + float(np.hypot(p["K_along"], p["K_left"])))
    return base.rrp("N", ("K", extra_rod), guide=("O", rho), offset=offset, branch=branch)


def guide_offset_from_D(linkage: Linkage):
    """The paper's h: the signed distance (m) of the six-link's guide from D, to the left of
    the guide direction (``offset + d sin(rho)`` for a guide ``offset`` to the left of O)."""
    p = linkage.parameters
    rho = p["N_guide_angle"]
    return p["N_guide_offset"] + p["D_x"] * ops.sin(rho) - p["D_y"] * ops.cos(rho)


def five_link(
    profile="involute",
    base_radius=None,
    rho=None,
    roller=0.004,
    *,
    ground=None,
    crank=None,
    rod=None,
    rocker=None,
    margin=0.25,
) -> Linkage:
    """Paper 001's five-link (Figs. 6-7): the rocker's extension is a cam profile pushing the
    striker N along a fixed guide (a yoke: the contact is held on both sides).

    Parameters
    ----------
    profile : ``"involute"`` -- an involute of the circle of ``base_radius`` about D, with the
        guide tangent to that circle, so the profile's normal lies along the guide (no side load
        on it) and the striker moves ``base_radius`` times the rocker's rotation; or ``"arc"`` --
        for comparison, the circular arc osculating that involute at the middle of the swing
        (centre on the base circle, radius ``base_radius * sigma_mid``).
    base_radius : m; default 0.055 (a stroke comparable to the six-link's).
    rho : the guide's angle to the base line (rad); default 90 deg.
    roller : the striker's roller radius (m).
    ground, crank, rod, rocker : the base four-bar (:data:`REPRESENTATIVE`).
    margin : roll angle (rad) kept between the swing's contact and the involute's cusp.
    """
    r = REPRESENTATIVE
    ground = r["ground"] if ground is None else ground
    crank = r["crank"] if crank is None else crank
    rod = r["rod"] if rod is None else rod
    rocker = r["rocker"] if rocker is None else rocker
    rb = 0.055 if base_radius is None else validate.length("base_radius", base_radius)
    rho = deg(r["rho_deg"]) if rho is None else validate.angle("rho", rho)
    margin = validate.positive("margin", margin, "rad")
    lo, hi = rocker_swing(ground, crank, rod, rocker)
    # the contact's roll angle: sigma = rho + pi/2 - phase - theta3 (rocker angle theta3)
    phase = rho + np.pi / 2 - hi - margin
    roll = (margin * 0.5, hi - lo + 1.5 * margin)
    fb = _four_bar(ground, crank, rod, rocker, "five-link")
    if profile == "involute":
        curve = Involute(rb, phase=phase, roll=roll)
    elif profile == "arc":
        s_mid = margin + 0.5 * (hi - lo)
        a = s_mid + phase
        centre = (rb * np.cos(a), rb * np.sin(a))
        curve = Circle(rb * s_mid, center=centre)
    else:
        raise MechanismError(f"profile must be 'involute' or 'arc', got {profile!r}")
    return fb.follower("N", on="DB", profile=curve, guide=("D", rho), offset=rb, roller=roller)


def special_angles(linkage: Linkage, n=720):
    """Crank angles (rad, in [0, 2 pi)) of the special position, two per turn (the rocker
    passing forth and back), each refined by Newton steps: where the arm D-K lies along the base
    line pointing away from O; for a linkage without a point K (the five-link), where the rocker
    D-B is at the middle of its swing. Raises MechanismError if the rocker never gets there."""
    phi = np.linspace(0.0, 2 * np.pi, int(n) + 1)
    if "K" in linkage.points:

        def angle(ph):
            m = linkage.motion(ph)
            k, d = m.points["K"], m.points["D"]
            rx, ry = k.x - d.x, k.y - d.y
            return np.arctan2(ry, rx), (rx * k.vy - ry * k.vx) / (rx * rx + ry * ry)

    else:
        th = np.unwrap(np.asarray(linkage.motion(phi).links["DB"].angle))
        mid = 0.5 * (th.min() + th.max())

        def angle(ph):
            lk = linkage.motion(ph).links["DB"]
            return np.angle(np.exp(1j * (np.asarray(lk.angle) - mid))), lk.omega

    a = np.asarray(angle(phi)[0])
    roots = []
    for i in np.flatnonzero((np.sign(a[:-1]) != np.sign(a[1:])) & (np.abs(a[:-1]) < 1.0)):
        x = phi[i] - a[i] * (phi[i + 1] - phi[i]) / (a[i + 1] - a[i])
        for _ in range(20):
            f, df = angle(x)
            step = float(f / df)
            x -= step
            if abs(step) < 1e-15:
                break
        roots.append(float(np.mod(x, 2 * np.pi)))
    if not roots:
        raise MechanismError(
            "the rocker arm D-K never lies along the base line: no special position "
            f"(arm angle over the turn {np.degrees(a.min()):.3g} .. {np.degrees(a.max()):.3g} deg)"
        )
    return np.array(sorted(roots))

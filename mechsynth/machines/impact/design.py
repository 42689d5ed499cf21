"""The representative machine of the impact study and its sources.

Paper 001 gives no dimensions or masses. The study takes a hand-held electric breaker of the
15-20 J class: catalogue machines of this class deliver about 17-19 J (EPTA) at 1900 blows/min
from a 1.5 kW motor (e.g. Makita HM1203C: 1510 W, 950-1900 blows/min; Bosch GSH 11 E: 1500 W,
900-1890 blows/min, 16.8 J -- the manufacturers' published data). Makers do not publish
striker masses; the issue's range (2-4 kg) is taken at its middle, 3 kg, with a 1 kg chisel.
The crank turns at 2000 rpm (one blow per turn: 2000 blows/min), the striker's stroke is about
40 mm, the link masses are those of steel links of these lengths. Every number here is an
assumption of the study, stated so that it can be changed (``ImpactMachine.replace``).
"""

from __future__ import annotations

from ...errors import MechanismError
from ...units import deg
from .drive import ImpactMachine
from .impact import Tool
from .model import crank_rocker, five_link, six_link

__all__ = ["SOURCES", "MASSES", "inertias_for", "representative_machine"]

SOURCES = (
    "representative machine (paper 001 gives no numbers): a hand-held electric breaker of the "
    "15-20 J class -- about 17-19 J at 1900 blows/min from 1.5 kW in the makers' data (Makita "
    "HM1203C 1510 W, 950-1900 blows/min; Bosch GSH 11 E 1500 W, 900-1890 blows/min, 16.8 J); "
    "striker 3 kg (the 2-4 kg range; makers publish no striker mass), chisel 1.0 kg, "
    "restitution 0.5, 2000 blows/min, a 1.5 kW two-pole induction motor through a gear, a "
    "0.01 kg m^2 flywheel on the crankshaft; link masses of steel links of these lengths"
)

#: body masses (kg), centres of mass in the body frames (m), inertias about them (kg m^2)
MASSES = {
    "striker": 3.0,
    "tool": 1.0,
    "restitution": 0.5,
    "flywheel": 0.01,
    "crank": (0.4, (0.0, 0.0), 2.0e-4),  # an eccentric balanced about O
    "rod": 0.25,  # uniform bar A-B
    "rocker": (0.5, (0.012, 0.0), 4.0e-4),  # D-B frame
    "extra_rod": 0.15,  # uniform bar K-N
    "profile_rocker": (0.7, (0.015, 0.0), 6.0e-4),  # the five-link's rocker with its profile
}


def _bar(mass, length):
    return (mass, (0.5 * length, 0.0), mass * length * length / 12.0)


def inertias_for(linkage, masses=None) -> dict:
    """Mass properties of every body of a :func:`~.model.six_link`, :func:`~.model.five_link`
    or :func:`~.model.crank_rocker` (whose rocker carries the striker's mass at K)."""
    m = dict(MASSES if masses is None else masses)
    p = linkage.parameters
    out = {"OA": m["crank"], "AB": _bar(m["rod"], p["AB"])}
    bodies = linkage.topology().bodies
    if "KN" in bodies:
        out["DB"] = m["rocker"]
        out["KN"] = _bar(m["extra_rod"], p["KN"])
        out["N"] = (m["striker"], (0.0, 0.0), 0.0)
    elif "N" in bodies:
        out["DB"] = m["profile_rocker"]
        out["N"] = (m["striker"], (0.0, 0.0), 0.0)
    else:
        mr, (cu, cv), jr = m["rocker"]
        ms_ = m["striker"]
        ku, kv = p["K_along"], p["K_left"]
        total = mr + ms_
        cx, cy = (mr * cu + ms_ * ku) / total, (mr * cv + ms_ * kv) / total
        j = jr + mr * ((cu - cx) ** 2 + (cv - cy) ** 2) + ms_ * ((ku - cx) ** 2 + (kv - cy) ** 2)
        out["DB"] = (total, (cx, cy), j)
    return out


def representative_machine(kind="six", rho_deg=90.0, **changes) -> ImpactMachine:
    """The study's machine: ``kind`` ``"six"`` (six-link at ``rho_deg``), ``"five"``
    (involute), ``"arc"`` (five-link with the circular arc) or ``"base"`` (the crank-rocker
    carrying the striker); ``changes`` go to :class:`~.drive.ImpactMachine` (e.g. ``psi``)."""
    if kind == "six":
        lk, striker = six_link(deg(rho_deg)), "N"
    elif kind == "five":
        lk, striker = five_link("involute", rho=deg(rho_deg)), "N"
    elif kind == "arc":
        lk, striker = five_link("arc", rho=deg(rho_deg)), "N"
    elif kind == "base":
        lk, striker = crank_rocker(), "K"
    else:
        raise MechanismError(f"kind must be 'six', 'five', 'arc' or 'base', got {kind!r}")
    tool = Tool(MASSES["tool"], MASSES["restitution"])
    base = dict(
        inertias=inertias_for(lk),
        tool=tool,
        striker=striker,
        flywheel=MASSES["flywheel"],
        speed_rpm=2000.0,
    )
    base.update(changes)
    return ImpactMachine(lk, **base)

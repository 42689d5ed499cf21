"""The force model of a general :class:`~mechsynth.kinematics.Linkage`.

Every moving body of the linkage becomes a body of a
:class:`~mechsynth.dynamics.kinetostatics.ForceModel` (its frame: origin at the body's base point,
x axis along its angle in ``motion.links``), every kinematic pair a joint (revolute, prismatic or
the one-unknown :class:`~mechsynth.dynamics.kinetostatics.Contact` of a cam), and the crank the
driver -- or a driving slider's block, pushed along its guide by the driving force
(:class:`~mechsynth.dynamics.kinetostatics.DrivingForce`) instead of a balancing torque.
Joint names are the linkage's (:meth:`Linkage.joints`): a revolute joint is named after
its point, a guide ``"<slider>_guide"``, an RPR slot ``"<link>_slot"``, a cam contact
``"<follower>_contact"``; each reports the force on its ``on`` body from its ``by`` body.

This module registers :func:`linkage_force_model` as :meth:`Linkage.force_model` (the forces
belong to this layer, the geometry to :mod:`mechsynth.kinematics`).
"""

from __future__ import annotations

from collections.abc import Mapping

from ..errors import MechanismError
from ..kinematics.linkage import Linkage, register_force_builder
from .inertia import LinkInertia
from .kinetostatics import FRAME, Contact, DrivingForce, ForceModel, Prismatic, Revolute

__all__ = ["linkage_force_model"]


def _inertia(lk: Linkage, name: str, spec) -> LinkInertia:
    body = lk.topology().bodies[name]
    if spec is None:
        return LinkInertia(name, body.base, 0.0)
    if isinstance(spec, LinkInertia):
        return spec
    if isinstance(spec, Mapping):
        unknown = set(spec) - {"mass", "com", "inertia"}
        if unknown:
            raise MechanismError(
                f"inertia of {name}: unknown keys {sorted(unknown)}; use mass, com, inertia"
            )
        return LinkInertia(
            name,
            body.base,
            spec.get("mass", 0.0),
            spec.get("com", (0.0, 0.0)),
            spec.get("inertia", 0.0),
        )
    try:
        mass, com, inertia = spec
    except (TypeError, ValueError):
        raise MechanismError(
            f"inertia of {name}: give a LinkInertia, {{'mass', 'com', 'inertia'}} or "
            f"(mass, (u, v), inertia), got {spec!r}"
        ) from None
    return LinkInertia(name, body.base, mass, com, inertia)


def linkage_force_model(lk: Linkage, inertias: Mapping | None = None, loads=()) -> ForceModel:
    """Bodies, joints and loads of ``lk`` for :func:`~mechsynth.dynamics.kinetostatics`.

    Parameters
    ----------
    lk : the linkage.
    inertias : ``{body: spec}``: a :class:`LinkInertia`, a dict ``{"mass", "com", "inertia"}``
        or a tuple ``(mass, (u, v), inertia)`` with the centre of mass ``(u, v)`` (m) in the
        body's frame (origin at its base point, x axis along its angle; a slider's x axis is
        its guide's direction) and the moment of inertia (kg m^2) about the centre of mass.
        Bodies not listed are massless.
    loads : loads of :mod:`mechsynth.dynamics.loads` on the linkage's bodies and points.

    Returns
    -------
    ForceModel with the crank as the driver (the balancing torque), or for a linkage driven by
    a slider its block pushed along the guide (:class:`DrivingForce`: the driving force).
    """
    topo = lk.topology()
    inertias = dict(inertias or {})
    unknown = set(inertias) - set(topo.bodies)
    if unknown:
        raise MechanismError(
            f"inertias name unknown links {sorted(unknown)}; links: {', '.join(topo.bodies)}"
        )
    bodies = {name: _inertia(lk, name, inertias.get(name)) for name in topo.bodies}
    joints = []
    for j in topo.joints:
        by = FRAME if j.by == "frame" else j.by
        if j.kind == "revolute":
            joints.append(Revolute(j.name, j.on, by, j.point))
        elif j.kind == "prismatic":
            joints.append(Prismatic(j.name, j.on, by, j.point, j.direction))
        else:
            joints.append(Contact(j.name, j.on, by, j.point, j.normal))
    drive = None
    if lk.driver == "slider":  # a linear input: the driving force along its guide
        drive = DrivingForce(lk.groups[0].key, topo.driver)
    return ForceModel(bodies, tuple(joints), tuple(loads), topo.driver, drive)


register_force_builder(linkage_force_model)

"""Force measures: peak joint reactions and the balancing crank torque over the cycle.

The per-angle values come from :func:`mechsynth.dynamics.kinetostatics` for a force model built
from the design (``model(mechanism)``; default ``mechanism.force_model()``). Measures need a
time motion: evaluate them with a speed (``measure.evaluate(mech, phi, speed=...)``).

For the convex (cvxpy) path, :func:`reaction_affine_map` exposes a reaction as the exact affine
map ``R(phi) = A(phi) x + b(phi)`` in decision variables that enter linearly (masses, mass
moments, load magnitudes), for :func:`mechsynth.synthesis.convex.minimax_affine`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..dynamics.kinetostatics import kinetostatics
from ..errors import MechanismError
from ..kinematics import ops
from .base import CycleMeasure

__all__ = [
    "peak_reaction",
    "peak_torque",
    "peak_driving_force",
    "rms_torque",
    "reaction_affine_map",
]


def _model_of(model):
    if model is None:
        return lambda mech: mech.force_model()
    return model


def _joints(joints) -> tuple[str, ...]:
    joints = (joints,) if isinstance(joints, str) else tuple(joints)
    if not joints:
        raise MechanismError("joints: name at least one joint")
    return joints


def peak_reaction(joints, model: Callable | None = None) -> CycleMeasure:
    """Largest reaction magnitude (N) over the cycle at ``joints`` (a name or several: the
    largest over all of them)."""
    joints = _joints(joints)
    build = _model_of(model)

    def per_angle(mech, motion):
        res = kinetostatics(build(mech), motion)
        out = res.magnitude(joints[0])
        for j in joints[1:]:
            out = ops.fmax(out, res.magnitude(j))
        return out

    return CycleMeasure(f"peak reaction {'/'.join(joints)}", per_angle, "max", "N")


def peak_torque(model: Callable | None = None) -> CycleMeasure:
    """Peak absolute balancing torque (N m) on the crank over the cycle."""
    build = _model_of(model)
    return CycleMeasure(
        "peak crank torque",
        lambda mech, motion: ops.fabs(kinetostatics(build(mech), motion).torque),
        "max",
        "N m",
    )


def peak_driving_force(model: Callable | None = None) -> CycleMeasure:
    """Peak absolute driving force (N) over the travel of a linkage driven by a slider (a
    linear input, whose force model pushes its block along the guide)."""
    build = _model_of(model)

    def per_angle(mech, motion):
        res = kinetostatics(build(mech), motion)
        return ops.fabs(res.driving_force)

    return CycleMeasure("peak driving force", per_angle, "max", "N")


def rms_torque(model: Callable | None = None) -> CycleMeasure:
    """Root-mean-square balancing torque (N m) over the cycle (equal angle steps)."""
    build = _model_of(model)
    return CycleMeasure(
        "rms crank torque",
        lambda mech, motion: kinetostatics(build(mech), motion).torque,
        "rms",
        "N m",
    )


def reaction_affine_map(
    design: Callable[[np.ndarray], object],
    joints,
    x0: Sequence[float],
    angles=720,
    speed: Callable[[object], float] | float | None = None,
):
    """The reactions at ``joints`` as an exact affine map of decision variables ``x``.

    Parameters
    ----------
    design : ``x -> mechanism`` whose force model is affine in ``x`` (masses, mass moments,
        load magnitudes at a fixed geometry); the mechanism provides ``force_model()``.
    joints : joint name(s); with several, their rows are stacked (angles repeated per joint).
    x0 : a reference decision vector (positive masses: the check points lie forward of it).
    angles : number of equal steps or the crank angles (rad).
    speed : crank speed (rad/s), or ``mech -> speed``; default ``mech.omega``.

    Returns
    -------
    (A, b, phi) : ``A`` of shape ``(m * len(joints), 2, n)`` (N per unit of ``x``), ``b`` of shape
        ``(m * len(joints), 2)`` and the crank angle of every row; feed them to
        ``minimax_affine(A, b, angles=phi, norm="euclidean")``.

    Raises
    ------
    ValueError
        if the reactions are not affine in ``x`` (checked at a further point to 1e-8 relative).
    """
    from ..units import cycle

    joints = _joints(joints)
    x0 = np.atleast_1d(np.asarray(x0, dtype=float))
    phi = cycle(int(angles)) if np.ndim(angles) == 0 else np.asarray(angles, dtype=float).ravel()

    def func(x):
        mech = design(x)
        w = mech.omega if speed is None else (speed(mech) if callable(speed) else speed)
        res = kinetostatics(mech.force_model(), mech.motion(phi, speed=w))
        return np.concatenate([np.stack(res.reactions[j], axis=-1) for j in joints])

    y0 = func(x0)
    h = np.maximum(np.abs(x0), 1.0)
    cols = [(func(x0 + h[j] * np.eye(x0.size)[j]) - y0) / h[j] for j in range(x0.size)]
    A = np.stack(cols, axis=-1)
    b = y0 - A @ x0
    xc = x0 + 1.7 * h
    dev = np.max(np.abs(A @ xc + b - func(xc)))
    if dev > 1e-8 * (np.max(np.abs(y0)) + 1.0):
        raise MechanismError(f"the reactions are not affine in x (deviation {dev:.3g} N)")
    return A, b, np.tile(phi, len(joints))

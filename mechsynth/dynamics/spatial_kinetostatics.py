"""Kinetostatics of spatial linkages, with redundant constraints closed by elastic compatibility.

Every moving body is in d'Alembert equilibrium (6 equations: forces, and moments about the body's
reference point). Each pair between two bodies contributes unknown reactions:

* ``"spherical"`` — a force (3 components), no moment;
* ``"revolute"`` — a force (3) and a moment perpendicular to the pair's axis (2 components: a
  revolute pair transmits no moment about its own axis);
* ``"driven"`` — a revolute pair whose moment about the axis is the unknown driving torque (3
  moment components).

The equations of all bodies form ``E lam = -f`` at every crank angle (``f`` the applied, gravity
and inertia loads). When the pairs impose more constraints than the mechanism needs, ``E`` has a
null space: its vectors are the **self-stress states** (reactions in equilibrium with no load) and
the reactions are not fixed by statics. They are fixed by compatibility: the elastic bodies
deform so that every pair closes. With ``lam = lam_p + N x`` (``N`` the self-stress basis) the
principle of complementary virtual work gives, for every self-stress,

    N^T (H lam + g) = 0,    x = -(N^T H N)^-1 N^T (H lam_p + g),

where ``H`` is the compliance of the elastic bodies seen at their pairs (``Pi C Pi^T``, ``C``
the 6x6 end compliance of an elastic body, ``Pi`` the pair's reaction components) and ``g`` the
misfit of the pairs in the rigid reference configuration (the relative rotation of two pin axes
that should coincide, for instance). This is the force method of structural mechanics applied
per crank angle, for all angles at once (batched SVD).

Where ``E`` has fewer independent rows than bodies' equations (a local mobility such as a link
spinning idly about its own axis), the loads may have a component that no reaction can balance;
it is returned as ``residual`` (zero for a consistent model; the least-squares reactions
otherwise).

Conventions: SI units, right-handed axes; a joint ``name`` reports the force and moment **on**
body ``on`` **from** body ``by`` (the frame is ``"frame"``); moments about the joint's point.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError
from ..kinematics.mechanism import check_length
from ..kinematics.spatial import perpendicular_basis, skew

__all__ = [
    "FRAME",
    "JOINT_KINDS",
    "SpatialJoint",
    "BeamSection",
    "cantilever_compliance",
    "SpatialSolution",
    "solve_spatial",
]

FRAME = "frame"
#: pair kind -> number of moment components it transmits
JOINT_KINDS = {"spherical": 0, "revolute": 2, "driven": 3}


@dataclass(frozen=True)
class SpatialJoint:
    """Pair ``name`` between the bodies ``on`` and ``by`` (``"frame"`` allowed); ``kind`` is
    ``"spherical"``, ``"revolute"`` or ``"driven"`` (see the module notes)."""

    name: str
    on: str
    by: str
    kind: str

    def __post_init__(self):
        if self.kind not in JOINT_KINDS:
            raise MechanismError(
                f"joint {self.name}: kind must be one of {sorted(JOINT_KINDS)}, got {self.kind!r}"
            )
        if self.on == self.by:
            raise MechanismError(f"joint {self.name} joins body {self.on!r} to itself")

    @property
    def size(self) -> int:
        """Number of unknown reaction components."""
        return 3 + JOINT_KINDS[self.kind]


@dataclass(frozen=True)
class BeamSection:
    """Elastic section of a straight prismatic bar (SI: Pa, m^2, m^4).

    ``E`` Young's modulus, ``G`` shear modulus, ``area``, ``J_y`` and ``J_z`` the second moments
    of area for bending about the section's local y and z axes, ``J_p`` the torsion constant
    (the polar moment ``J_y + J_z`` for a round section).
    """

    E: float
    G: float
    area: float
    J_y: float
    J_z: float
    J_p: float

    def __post_init__(self):
        for name in ("E", "G", "area", "J_y", "J_z", "J_p"):
            object.__setattr__(self, name, check_length(f"section {name}", getattr(self, name)))

    @classmethod
    def round(cls, diameter, E=2.1e11, poisson=0.3, J=None) -> BeamSection:
        """A solid round bar of ``diameter`` (m); or, with ``J`` (m^4) given, the round bar with
        that second moment of area (``diameter = (64 J / pi)^(1/4)``)."""
        if J is not None:
            J = check_length("J", J)
            diameter = (64.0 * J / np.pi) ** 0.25
        d = check_length("diameter", diameter)
        j = np.pi * d**4 / 64.0
        return cls(E, E / (2.0 * (1.0 + poisson)), np.pi * d * d / 4.0, j, j, 2.0 * j)


def cantilever_compliance(length, section: BeamSection) -> np.ndarray:
    """6x6 compliance of a straight bar clamped at one end, in its local frame (x along the bar,
    y and z the section's principal axes): ``[dx, dy, dz, rx, ry, rz] = C [Fx, Fy, Fz, Mx, My,
    Mz]`` for the force and moment applied at the free end (Euler-Bernoulli bending, Saint-Venant
    torsion, axial stretch).

    ``length`` and the section's numbers may be arrays (designs); the result has their
    broadcast shape followed by ``(6, 6)``.
    """
    l = np.asarray(check_length("length", length), dtype=float)
    s = section
    shape = np.broadcast_shapes(
        l.shape, *(np.shape(getattr(s, k)) for k in ("E", "G", "area", "J_y", "J_z", "J_p"))
    )
    l = np.broadcast_to(l, shape)
    C = np.zeros(shape + (6, 6))
    C[..., 0, 0] = l / (s.E * s.area)
    C[..., 3, 3] = l / (s.G * s.J_p)
    # bending in the x-y plane (about z): tip force Fy and moment Mz
    C[..., 1, 1] = l**3 / (3.0 * s.E * s.J_z)
    C[..., 5, 5] = l / (s.E * s.J_z)
    C[..., 1, 5] = C[..., 5, 1] = l**2 / (2.0 * s.E * s.J_z)
    # bending in the x-z plane (about y): a tip force Fz turns the end about -y
    C[..., 2, 2] = l**3 / (3.0 * s.E * s.J_y)
    C[..., 4, 4] = l / (s.E * s.J_y)
    C[..., 2, 4] = C[..., 4, 2] = -(l**2) / (2.0 * s.E * s.J_y)
    return C


@dataclass(frozen=True)
class SpatialSolution:
    """Reactions of a spatial kinetostatic solve (arrays over the leading axes).

    Attributes
    ----------
    force, moment : ``{joint: (..., 3)}`` on the joint's ``on`` body from its ``by`` body (N, N m).
        For a driven pair ``moment`` is the whole moment, torque included.
    torque : ``{joint: (...)}`` the driving torque of each driven pair about its axis (N m).
    residual : the load (N; moments divided by the model's characteristic length) left
        unbalanced by the local mobilities, largest over the equations (zero for a consistent
        model).
    unbalanced : ``{body: (force, moment)}`` the net load left on each body, reactions included
        (N, N m about the body's reference point; ``E lam + f`` in the notation above), zero
        when every body is balanced.
    rank, nullity : rank of the equilibrium matrix and the number of self-stress states (the
        degree of static indeterminacy).
    elastic_energy : complementary energy ``1/2 lam^T H lam`` stored in the elastic bodies (J),
        zero without compliance.
    """

    force: dict[str, Any]
    moment: dict[str, Any]
    torque: dict[str, Any]
    residual: Any
    rank: int
    nullity: int
    elastic_energy: Any = 0.0
    unbalanced: dict = field(default_factory=dict)


def _layout(joints):
    cols, k = {}, 0
    for j in joints:
        cols[j.name] = k
        k += j.size
    return cols, k


def solve_spatial(
    bodies,
    refs: dict[str, Any],
    joints,
    points: dict[str, Any],
    axes: dict[str, Any],
    loads: dict[str, tuple[Any, Any]],
    *,
    compliance: dict[str, tuple[str, Any]] | None = None,
    misfit: dict[str, tuple[Any, Any]] | None = None,
    length: float = 1.0,
    rtol: float = 1e-9,
) -> SpatialSolution:
    """Reactions of a spatial linkage at every sample (leading axes) in one batched solve.

    Parameters
    ----------
    bodies : names of the moving bodies.
    refs : ``{body: (..., 3)}`` the point about which each body's moments are taken.
    joints : :class:`SpatialJoint` pairs.
    points : ``{joint: (..., 3)}`` the pair's centre.
    axes : ``{joint: (..., 3)}`` the unit axis of revolute and driven pairs.
    loads : ``{body: (force, moment)}`` the resultant applied load on each body (gravity,
        inertia, external), the moment taken about ``refs[body]``; arrays (..., 3).
    compliance : ``{joint: (body, C)}``: ``body`` (one of the joint's two) is elastic and ``C``
        (..., 6, 6) is its end compliance at this joint in global axes (force and moment at the
        pair's centre -> displacement and rotation of that end relative to the body's reference
        frame). Needed when the pairs are redundant.
    misfit : ``{joint: (translation, rotation)}``: in the rigid reference configuration, the
        element of the ``on`` body sits displaced by ``translation`` (m) and turned by the small
        rotation vector ``rotation`` (rad) from that of the ``by`` body; only the constrained
        components count.
    length : a characteristic length (m) to scale moments against forces in the rank decision.
    rtol : singular values below ``rtol`` times the largest count as zero.

    Returns
    -------
    SpatialSolution

    Raises
    ------
    ValueError
        if the pairs are redundant and the compliance does not close them, or the rank changes
        between samples (a singular position).
    """
    bodies = list(bodies)
    joints = tuple(joints)
    row = {b: 6 * i for i, b in enumerate(bodies)}
    cols, n = _layout(joints)
    m = 6 * len(bodies)
    arrays = [np.asarray(v, dtype=float) for v in (*points.values(), *refs.values())]
    arrays += [np.asarray(v, dtype=float) for f, t in loads.values() for v in (f, t)]
    shape = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
    L = float(length)

    def b3(v):
        return np.broadcast_to(np.asarray(v, dtype=float), shape + (3,))

    E = np.zeros(shape + (m, n))
    f = np.zeros(shape + (m,))
    basis = {}  # joint -> (..., 3, k) moment directions
    for j in joints:
        for b in (j.on, j.by):
            if b != FRAME and b not in row:
                raise MechanismError(f"joint {j.name} names an unknown body {b!r}")
        c = cols[j.name]
        p = b3(points[j.name])
        if j.kind != "spherical":
            a = b3(axes[j.name])
            t1, t2 = perpendicular_basis(a)
            dirs = [t1, t2] + ([a] if j.kind == "driven" else [])
            basis[j.name] = np.stack(dirs, axis=-1)
        for sign, b in ((1.0, j.on), (-1.0, j.by)):
            if b == FRAME:
                continue
            r = row[b]
            E[..., r : r + 3, c : c + 3] += sign * np.eye(3)
            # moment of a unit force e_k at the pair about the body's point: lever x e_k
            E[..., r + 3 : r + 6, c : c + 3] += (sign / L) * skew(p - b3(refs[b]))
            if j.name in basis:
                # the unknown moments are scaled by L: entry (1/L row scale) * L = 1
                k = basis[j.name].shape[-1]
                E[..., r + 3 : r + 6, c + 3 : c + 3 + k] += sign * basis[j.name]
    for b, (force, moment) in loads.items():
        if b not in row:
            raise MechanismError(f"load on an unknown body {b!r}")
        f[..., row[b] : row[b] + 3] += b3(force)
        f[..., row[b] + 3 : row[b] + 6] += b3(moment) / L

    # a body held by a driven pair to the frame (6 unknowns, 6 equations) is solved last: its
    # pair carries whatever the rest leaves, which keeps the batched SVD small
    held = {}
    for j in joints:
        if j.kind == "driven" and FRAME in (j.on, j.by):
            held[j.name] = j.on if j.by == FRAME else j.by
    drop_r = [row[b] + k for b in held.values() for k in range(6)]
    drop_c = [cols[jn] + k for jn in held for k in range(6)]
    keep_r = np.array([i for i in range(m) if i not in drop_r], dtype=int)
    keep_c = np.array([i for i in range(n) if i not in drop_c], dtype=int)
    Er = E[..., keep_r[:, None], keep_c]
    U, s, Vt = np.linalg.svd(Er, full_matrices=True)
    smax = s[..., :1]
    ranks = np.sum(s > rtol * smax, axis=-1)
    rank = int(ranks.flat[0]) if ranks.size else min(keep_r.size, keep_c.size)
    if np.any(ranks != rank):
        i = np.unravel_index(int(np.argmax(ranks != rank)), ranks.shape)
        raise MechanismError(
            f"spatial kinetostatics: the equilibrium matrix changes rank ({rank} -> "
            f"{int(ranks[i])}) at sample {tuple(int(k) for k in i)}: a singular position"
        )
    Ur, sr, Vr = U[..., :, :rank], s[..., :rank], np.swapaxes(Vt[..., :rank, :], -1, -2)
    lam_s = np.zeros(shape + (n,))
    lam_s[..., keep_c] = (
        Vr @ ((np.swapaxes(Ur, -1, -2) @ (-f[..., keep_r])[..., None])[..., 0] / sr)[..., None]
    )[..., 0]
    nullity = keep_c.size - rank
    rank += len(drop_c)

    # back to physical units: moments were scaled by L
    scale = np.ones(n)
    for j in joints:
        scale[cols[j.name] + 3 : cols[j.name] + j.size] = L
    lam = lam_s * scale
    energy = np.zeros(shape)
    if nullity:
        if not compliance:
            raise MechanismError(
                f"the pairs are redundant ({nullity} self-stress states): the reactions are "
                "statically indeterminate; give the compliance of the elastic bodies"
            )
        N = np.zeros(shape + (n, nullity))
        N[..., keep_c, :] = np.swapaxes(Vt[..., keep_c.size - nullity :, :], -1, -2)
        N = N * scale[:, None]  # (..., n, nullity)
        H = np.zeros(shape + (n, n))
        for name, (body, C) in compliance.items():
            j = next((jj for jj in joints if jj.name == name), None)
            if j is None or body not in (j.on, j.by):
                raise MechanismError(f"compliance at {name!r}: no such joint with body {body!r}")
            P = np.zeros(shape + (6, j.size))  # reaction components -> (force, moment)
            P[..., :3, :3] = np.eye(3)
            if name in basis:
                P[..., 3:, 3:] = basis[name]
            Cg = np.broadcast_to(np.asarray(C, dtype=float), shape + (6, 6))
            c = cols[name]
            H[..., c : c + j.size, c : c + j.size] += np.swapaxes(P, -1, -2) @ Cg @ P
        g = np.zeros(shape + (n,))
        for name, (trans, rot) in (misfit or {}).items():
            j = next((jj for jj in joints if jj.name == name), None)
            if j is None:
                raise MechanismError(f"misfit at an unknown joint {name!r}")
            c = cols[name]
            g[..., c : c + 3] = b3(trans)
            if name in basis:
                g[..., c + 3 : c + j.size] = np.einsum("...i,...ik->...k", b3(rot), basis[name])
        NT = np.swapaxes(N, -1, -2)
        S = NT @ H @ N
        rhs = NT @ (H @ lam[..., None] + g[..., None])
        try:
            x = np.linalg.solve(S, -rhs)
        except np.linalg.LinAlgError as exc:
            raise MechanismError(
                "the compliance does not reach every self-stress state (N^T H N singular): "
                "a redundant constraint with no elastic body in its loop"
            ) from exc
        lam = lam + (N @ x)[..., 0]
        energy = 0.5 * np.einsum("...i,...ij,...j->...", lam, H, lam)
    # the held bodies' pairs from their own six equations (scaled units)
    lam_s = lam / scale
    for jn, b in held.items():
        r, c = row[b], cols[jn]
        rows, jc = slice(r, r + 6), slice(c, c + 6)
        rest = E[..., rows, :] @ lam_s[..., None]
        rest = rest[..., 0] - (E[..., rows, jc] @ lam_s[..., jc, None])[..., 0]
        lam_s[..., jc] = np.linalg.solve(E[..., rows, jc], (-f[..., rows] - rest)[..., None])[
            ..., 0
        ]
    lam = lam_s * scale
    residual = -f - (E @ lam_s[..., None])[..., 0]

    force, moment, torque = {}, {}, {}
    for j in joints:
        c = cols[j.name]
        force[j.name] = lam[..., c : c + 3]
        if j.name in basis:
            comps = lam[..., c + 3 : c + j.size]
            moment[j.name] = np.einsum("...ik,...k->...i", basis[j.name], comps)
            if j.kind == "driven":
                torque[j.name] = comps[..., 2]
        else:
            moment[j.name] = np.zeros(shape + (3,))
    res = np.max(np.abs(residual), axis=-1) if m else np.zeros(shape)
    # E lam_s = -f - residual: the net load on each body is E lam + f = -residual
    unbalanced = {
        b: (-residual[..., row[b] : row[b] + 3], -residual[..., row[b] + 3 : row[b] + 6] * L)
        for b in bodies
    }
    return SpatialSolution(force, moment, torque, res, rank, nullity, energy, unbalanced)

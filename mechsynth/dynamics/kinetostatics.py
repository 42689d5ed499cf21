"""Kinetostatics of planar linkages: joint reactions and the balancing crank torque.

Every moving body is in d'Alembert equilibrium: applied loads, joint reactions, the inertia force
``-m a_S`` at its centre of mass and the inertia torque ``-J_S eps``. For a mechanism built from a
crank and dyads the three equations of every body (forces in x and y, moment about the origin)
form one square linear system per crank angle in the unknowns

* the reaction of every revolute joint (two components),
* the normal force and the moment of every prismatic pair (two numbers),
* the normal force of every higher-pair contact (one number, along the common normal),
* the balancing (driving) torque on the crank -- or, for a linear input (a driving slider,
  :class:`DrivingForce`), the driving force along its guide,

and all angles are solved at once by one batched ``numpy.linalg.solve``.

Conventions
-----------
A joint named ``"Rij"`` reports the force **on** body ``on`` **from** body ``by`` (N); the force on
``by`` is its opposite. The frame is the body ``"frame"``. Moments and torques are
counter-clockwise positive (N m). The balancing torque is the torque the frame (the drive) applies
to the driving body so that it follows the given motion; its power ``T omega`` equals the rate of
change of the kinetic energy minus the power of the applied loads.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError
from ..kinematics import ops
from ..kinematics.tracks import Motion
from .inertia import LinkInertia, com_track

__all__ = [
    "Revolute",
    "Prismatic",
    "Contact",
    "DrivingForce",
    "ForceModel",
    "ForceResult",
    "kinetostatics",
    "applied_power",
    "kinetic_energy_rate",
    "slider_crank_model",
    "four_bar_model",
]

FRAME = "frame"


@dataclass(frozen=True)
class Revolute:
    """Pin joint ``name`` at the motion point ``point`` between bodies ``on`` and ``by``."""

    name: str
    on: str
    by: str
    point: str


@dataclass(frozen=True)
class Prismatic:
    """Sliding pair ``name`` between ``on`` and ``by``: the guide has the direction ``direction``
    (a link name in ``motion.links`` whose angle it follows, or a constant angle in rad); the
    normal force ``N`` acts along the guide's left normal through ``point`` together with a
    moment ``M`` (how the pair spreads its pressure). Frictionless."""

    name: str
    on: str
    by: str
    point: str
    direction: Any = 0.0


@dataclass(frozen=True)
class Contact:
    """Higher pair ``name`` (a cam and its follower) between ``on`` and ``by`` at the moving
    contact point ``point``: one unknown, the normal force ``F`` along the common normal, whose
    angle (rad) is ``motion.extra[normal]`` (a name) or a constant; the force on ``on`` is
    ``F (cos, sin)`` of that angle (positive: the pair is pressed together when the normal
    points from ``by`` into ``on``). Frictionless."""

    name: str
    on: str
    by: str
    point: str
    normal: Any = 0.0


@dataclass(frozen=True)
class DrivingForce:
    """A linear input: the driving body is pushed along ``direction`` (a link name in
    ``motion.links`` whose angle it follows, or a constant angle in rad) through the motion point
    ``point`` by the driving force, the unknown that takes the balancing torque's place
    (``ForceResult.torque`` is then that force, N, and its power is force times the input's
    speed)."""

    point: str
    direction: Any = 0.0


def _unknowns(joint) -> int:
    return 1 if isinstance(joint, Contact) else 2


@dataclass(frozen=True)
class ForceModel:
    """Bodies, joints, applied loads and the driving body of a mechanism.

    Parameters
    ----------
    bodies : ``{name: LinkInertia}`` of every moving body (massless ones with mass 0).
    joints : Revolute and Prismatic pairs (two unknowns each) and Contact pairs (one); with
        the drive they must give exactly ``3 * len(bodies)`` unknowns.
    loads : objects with ``contributions(motion, bodies) -> [Wrench]`` (see ``dynamics.loads``).
    driver : the body that receives the balancing torque (the crank).
    drive : None for a balancing torque on ``driver``; a :class:`DrivingForce` for a driving
        force along a guide (a driving slider).
    """

    bodies: dict[str, LinkInertia]
    joints: tuple
    loads: tuple = ()
    driver: str = "crank"
    drive: DrivingForce | None = None

    def __post_init__(self):
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "loads", tuple(self.loads))
        names = set(self.bodies)
        if self.driver not in names:
            raise MechanismError(f"driver {self.driver!r} is not a body ({sorted(names)})")
        for j in self.joints:
            for b in (j.on, j.by):
                if b != FRAME and b not in names:
                    raise MechanismError(f"joint {j.name} names an unknown body {b!r}")
        n = sum(_unknowns(j) for j in self.joints) + 1
        if n != 3 * len(self.bodies):
            raise MechanismError(
                f"{len(self.joints)} joints and the drive give {n} unknowns, but "
                f"{len(self.bodies)} bodies give {3 * len(self.bodies)} equations"
            )

    def replace_loads(self, loads) -> ForceModel:
        return ForceModel(self.bodies, self.joints, tuple(loads), self.driver, self.drive)

    def with_body(self, name, body: LinkInertia) -> ForceModel:
        """A copy with the mass properties of body ``name`` replaced."""
        bodies = dict(self.bodies)
        bodies[name] = body
        return ForceModel(bodies, self.joints, self.loads, self.driver, self.drive)


@dataclass(frozen=True)
class ForceResult:
    """Reactions and balancing torque over the crank angles ``phi``.

    Attributes
    ----------
    phi : crank angles (rad).
    reactions : ``{joint: (fx, fy)}`` force on the joint's ``on`` body from its ``by`` body (N)
        for revolute joints, and the normal force as a vector for prismatic pairs.
    normals : ``{joint: (N, M)}`` normal force (N) and moment (N m) of prismatic pairs; for a
        contact ``(F, 0)``, its normal force.
    torque : balancing torque on the driving body (N m, counter-clockwise positive); for a
        linear input (``drive == "force"``) the driving force along its guide (N, positive in
        the direction of growing input), also as :attr:`driving_force`.
    drive : ``"torque"`` or ``"force"``.
    """

    phi: Any
    reactions: dict[str, tuple]
    normals: dict[str, tuple]
    torque: Any
    omega: Any = None
    extra: dict = field(default_factory=dict)
    drive: str = "torque"

    @property
    def driving_force(self):
        """The driving force (N) of a linear input along its guide at every input."""
        if self.drive != "force":
            raise MechanismError("the input is a crank: its drive is the balancing torque (torque)")
        return self.torque

    def magnitude(self, joint: str):
        """Magnitude of the reaction at ``joint`` (N) at every angle."""
        if joint not in self.reactions:
            from ..errors import UsageError

            raise UsageError(
                f"no joint {joint!r} with a reaction; the joints: {', '.join(self.reactions)}"
            )
        fx, fy = self.reactions[joint]
        return ops.hypot(fx, fy)

    def peak(self, joint: str) -> tuple[float, float]:
        """(largest magnitude in N, crank angle in rad where it occurs)."""
        r = self.magnitude(joint)
        i = int(np.argmax(r))
        return float(r[i]), float(np.asarray(self.phi)[i])

    # -------------------------------------------------------------- tables
    def _table(self):
        from .. import tables

        def arr(x):
            return tables.per_angle(x, self.phi)

        cols = [("phi", "rad", arr(self.phi))]
        for j, (fx, fy) in self.reactions.items():
            cols += [
                (f"{j} x", "N", arr(fx)),
                (f"{j} y", "N", arr(fy)),
                (f"{j} magnitude", "N", arr(self.magnitude(j))),
            ]
        for j, (n, m) in self.normals.items():
            cols += [(f"{j} normal force", "N", arr(n)), (f"{j} moment", "N m", arr(m))]
        if self.drive == "force":
            cols.append(("driving force", "N", arr(self.torque)))
        else:
            cols.append(("balancing torque", "N m", arr(self.torque)))
        return tables.table(cols)

    def to_dict(self) -> dict[str, list]:
        """Columns ``{"name [unit]": values}`` in display units: the crank angle ``phi``, each
        joint's reaction x, y and magnitude, each sliding pair's normal force and moment, the
        balancing torque."""
        from .. import tables

        return tables.as_lists(self._table())

    def to_csv(self, path=None):
        """The columns of :meth:`to_dict` as CSV, one row per crank angle: written to ``path``
        (returns the path) or returned as text when ``path`` is None."""
        from .. import tables

        return tables.write_csv(self._table(), path)

    # -------------------------------------------------------------- figures
    def plot(self, joints=None, ax=None, angle=None, label="", unit=None, xlabel=None):
        """Reaction magnitudes against the crank angle. ``angle`` maps phi to the plotted angle
        in deg (default: degrees of phi); ``unit`` ``(divisor, name)`` of the force axis
        (default: kN for large forces, else the display force unit). Returns the figure."""
        import matplotlib.pyplot as plt

        from ..plotting import LINESTYLES, force_unit

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4), layout="constrained")
        joints = list(joints or self.reactions)
        mags = {j: np.asarray(self.magnitude(j), dtype=float) for j in joints}
        div, name = unit or force_unit(np.concatenate(list(mags.values())))
        x = np.rad2deg(np.asarray(self.phi)) if angle is None else angle(self.phi)
        for i, j in enumerate(joints):
            ax.plot(x, mags[j] / div, ls=LINESTYLES[i % len(LINESTYLES)], label=f"{j}{label}")
        ax.set_xlabel(xlabel or "crank angle, deg")
        ax.set_ylabel(f"reaction magnitude, {name}")
        ax.grid(True, alpha=0.35, ls=":")
        ax.legend()
        return ax.figure

    def hodograph(self, joint: str, ax=None, label=None, unit=None, **style):
        """Hodograph of the reaction vector at ``joint`` (its tip over the cycle), equal axes
        fitted to the curve; ``unit`` ``(divisor, name)`` (default: kN for large forces).
        Returns the figure."""
        import matplotlib.pyplot as plt

        from ..plotting import equal_axes, force_unit

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
        fx, fy = (np.asarray(c, dtype=float) for c in self.reactions[joint])
        div, name = unit or force_unit(np.hypot(fx, fy))
        x, y = np.append(fx, fx[:1]) / div, np.append(fy, fy[:1]) / div
        ax.plot(x, y, label=label or joint, **style)
        ax.plot([0], [0], "k+", ms=8)
        equal_axes(ax, "box")  # directions matter: marked for the figure checks
        ax.set_xlabel(f"{joint} x, {name}")
        ax.set_ylabel(f"{joint} y, {name}")
        ax.grid(True, alpha=0.35, ls=":")
        return ax.figure


def _as(values, shape):
    return np.broadcast_to(np.asarray(values, dtype=float), shape)


def _normal(motion: Motion, normal):
    if isinstance(normal, str):
        return motion.extra[normal]
    return normal


def _columns(model: ForceModel):
    """First unknown's column of every joint, and the count (the torque is the last)."""
    cols, c = [], 0
    for j in model.joints:
        cols.append(c)
        c += _unknowns(j)
    return cols, c + 1


def _entries(model: ForceModel, motion: Motion):
    """Sparse entries of the equilibrium system ``A X + f = 0``: ``{(row, col): value}`` and
    ``{row: value}``, each value a per-angle array, a number or a CasADi expression."""
    names = list(model.bodies)
    row = {b: 3 * i for i, b in enumerate(names)}
    n = 3 * len(names)
    first, _ = _columns(model)
    A: dict = {}
    f: dict = {}

    def acc(d, key, value):
        d[key] = d[key] + value if key in d else value

    def add_known(body, fx, fy, x, y, tz):
        r = row[body]
        acc(f, r, fx)
        acc(f, r + 1, fy)
        acc(f, r + 2, x * fy - y * fx + tz)

    for name, body in model.bodies.items():
        s = com_track(motion, body)
        add_known(name, -body.mass * s.ax, -body.mass * s.ay, s.x, s.y, 0.0)
        if body.link is not None:
            add_known(name, 0.0, 0.0, 0.0, 0.0, -body.inertia * motion.links[body.link].epsilon)
    for load in model.loads:
        for w in load.contributions(motion, model.bodies):
            add_known(w.body, w.fx, w.fy, w.x, w.y, w.tz)
    for k, j in enumerate(model.joints):
        c = first[k]
        p = motion.points[j.point]
        x, y = p.x, p.y
        if isinstance(j, Revolute):
            cols = ((1.0, 0.0, -y), (0.0, 1.0, x))  # unit Rx, unit Ry
        elif isinstance(j, Prismatic):
            th = motion.links[j.direction].angle if isinstance(j.direction, str) else j.direction
            nx, ny = -ops.sin(th), ops.cos(th)
            cols = ((nx, ny, x * ny - y * nx), (0.0, 0.0, 1.0))
        elif isinstance(j, Contact):
            th = _normal(motion, j.normal)
            nx, ny = ops.cos(th), ops.sin(th)
            cols = ((nx, ny, x * ny - y * nx),)
        else:
            raise MechanismError(f"unknown joint type {type(j).__name__}")
        for sign, body in ((1.0, j.on), (-1.0, j.by)):
            if body == FRAME:
                continue
            r = row[body]
            for dc, col in enumerate(cols):
                for dr in range(3):
                    if not (isinstance(col[dr], float) and col[dr] == 0.0):
                        acc(A, (r + dr, c + dc), sign * col[dr])
    if model.drive is None:
        acc(A, (row[model.driver] + 2, n - 1), 1.0)
    else:
        d = model.drive.direction
        th = motion.links[d].angle if isinstance(d, str) else d
        p = motion.points[model.drive.point]
        ux, uy = ops.cos(th), ops.sin(th)
        r = row[model.driver]
        acc(A, (r, n - 1), ux)
        acc(A, (r + 1, n - 1), uy)
        acc(A, (r + 2, n - 1), p.x * uy - p.y * ux)
    return A, f, n


def _blocks(A, n):
    """Row and column index blocks of the equilibrium system's block-triangular form (one per
    irreducible subsystem: the driver, each Assur group), in solving order; None when the
    system is structurally singular (left to the dense solve and its error)."""
    import casadi as ca

    rows, cols = zip(*A) if A else ((), ())
    sp = ca.Sparsity.triplet(n, n, list(rows), list(cols))
    if ca.sprank(sp) < n:
        return None
    nb, rp, cp, rb, cb, _, _ = sp.btf()
    return [(rp[rb[k] : rb[k + 1]], cp[cb[k] : cb[k + 1]]) for k in range(nb)]


#: pivots of the symbolic elimination: constant entries at least this large (a unit vector's
#: component of 6e-17 is a zero written by rounding, not a pivot)
_PIVOT_MIN = 1e-9


def _block_function(pattern, k):
    """A CasADi Function of one ``k x k`` block of the equilibrium system: its varying entries
    and right-hand sides in, its unknowns out (scalars; :func:`_solve_symbolic` maps it over the
    angles).

    ``pattern``: ``((i, j, value), ...)`` over the block's nonzeros in local indices, ``value``
    the number of an entry that is the same at every angle (the unit components of a revolute
    joint's reaction), else None (an input, in this order, then the ``k`` right-hand sides).
    Gaussian elimination pivots first on the constant entries (exact and never zero: the force
    rows of every revolute joint), the sparsest row and column first; the Schur complement that
    remains (the moment rows: two for a dyad) is solved by ``casadi.solve`` (minors up to
    3 x 3, a QR factorization beyond). No determinant is expanded: the expression grows with the
    block's size, not factorially."""
    import casadi as ca

    inputs, M = [], {}
    for i, j, value in pattern:
        if value is None:
            M[i, j] = ca.SX.sym(f"a{i}_{j}")
            inputs.append(M[i, j])
        else:
            M[i, j] = value
    b = {i: ca.SX.sym(f"b{i}") for i in range(k)}
    inputs += [b[i] for i in range(k)]
    rows, cols = set(range(k)), set(range(k))
    steps = []  # (column, pivot, the pivot row's other entries, its right-hand side)
    while True:
        best = None
        for (i, j), v in M.items():
            if i in rows and j in cols and isinstance(v, float) and abs(v) >= _PIVOT_MIN:
                n_row = sum(1 for (r, c) in M if r == i and c in cols)
                n_col = sum(1 for (r, c) in M if c == j and r in rows)
                cost = ((n_row - 1) * (n_col - 1), -abs(v), i, j)
                best = cost if best is None or cost < best else best
        if best is None:
            break
        i, j = best[2], best[3]
        p = M[i, j]
        row = {c: M[i, c] for c in cols if c != j and (i, c) in M}
        steps.append((j, p, row, b[i]))
        rows.discard(i)
        cols.discard(j)
        for r in rows:
            if (r, j) in M:
                factor = M.pop((r, j)) / p
                for c, v in row.items():
                    M[r, c] = M[r, c] - factor * v if (r, c) in M else -factor * v
                b[r] = b[r] - factor * b[i]
    x = {}
    if rows:
        rr, cc = sorted(rows), sorted(cols)
        dense = ca.SX(len(rr), len(cc))
        for a, r in enumerate(rr):
            for e, c in enumerate(cc):
                if (r, c) in M:
                    dense[a, e] = M[r, c]
        sol = ca.solve(dense, ca.vertcat(*[b[r] for r in rr]))
        x.update({c: sol[e] for e, c in enumerate(cc)})
    for j, p, row, rhs in reversed(steps):
        s = rhs
        for c, v in row.items():
            s = s - v * x[c]
        x[j] = s / p
    return ca.Function("block", [ca.vertcat(*inputs)], [ca.vertcat(*[x[j] for j in range(k)])])


_BLOCK_FUNCTIONS: dict = {}


def _block_solver(pattern, k):
    """:func:`_block_function`, built once per pattern (a few dozen small patterns exist)."""
    key = (pattern, k)
    if key not in _BLOCK_FUNCTIONS:
        if len(_BLOCK_FUNCTIONS) > 256:
            _BLOCK_FUNCTIONS.clear()
        _BLOCK_FUNCTIONS[key] = _block_function(pattern, k)
    return _BLOCK_FUNCTIONS[key]


def _solve_symbolic(A, f, n, motion):
    """CasADi path: the system solved block by block in its block-triangular order
    (:func:`_blocks`), every block for all angles at once: its elimination
    (:func:`_block_function`) written once as a Function of the block's entries and mapped over
    the angles. Returns the unknowns as an ``m x n`` SX (a row per angle)."""
    import casadi as ca

    values = list(A.values()) + list(f.values()) + [motion.phi]
    m = max((v.shape[0] if hasattr(v, "shape") and len(v.shape) else 1) for v in values)

    def row(v):
        """``v`` (a number, a per-angle array or a CasADi column) as a 1 x m SX row."""
        if ops.is_symbolic(v):
            v = ca.SX(v)
            return ca.repmat(v, 1, m) if v.numel() == 1 else ca.reshape(v, 1, m)
        v = np.broadcast_to(np.asarray(v, dtype=float).ravel(), (m,))
        return ca.SX(ca.DM(v.reshape(1, m)))

    def constant(v):
        if ops.is_symbolic(v):
            return None
        a = np.asarray(v, dtype=float)
        if a.size == 1 or np.all(a == a.ravel()[0]):
            return float(a.ravel()[0])
        return None

    blocks = _blocks(A, n)
    if blocks is None:  # structurally singular: one block, casadi.solve's error or NaN
        blocks = [(list(range(n)), list(range(n)))]
    by_row: dict = {}
    for r, c in A:
        by_row.setdefault(r, []).append(c)
    x: list = [None] * n
    for rows, cols in blocks:
        rows, cols = list(rows), list(cols)
        local_c = {c: e for e, c in enumerate(cols)}
        pattern, inputs = [], []
        for a, r in enumerate(rows):
            for c in sorted(by_row.get(r, ())):
                if c in local_c:
                    value = constant(A[r, c])
                    if value == 0.0:
                        continue
                    pattern.append((a, local_c[c], value))
                    if value is None:
                        inputs.append(row(A[r, c]))
        for r in rows:
            s = -row(f[r]) if r in f else ca.SX.zeros(1, m)
            for c in by_row.get(r, ()):
                if c not in local_c:
                    s = s - row(A[r, c]) * x[c]
            inputs.append(s)
        solver = _block_solver(tuple(pattern), len(rows))
        X = solver.map(m)(ca.vertcat(*inputs))
        for e, c in enumerate(cols):
            x[c] = X[e, :]
    return ca.vertcat(*x).T  # m x n


def kinetostatics(model: ForceModel, motion: Motion) -> ForceResult:
    """Solve the d'Alembert equilibrium of every body at every angle of ``motion``.

    ``motion`` must be a time motion (``mechanism.motion(phi, speed=...)``). Returns a
    :class:`ForceResult`. Raises ValueError where the system is singular (a toggle position or a
    badly posed model), naming the first such angle.

    With CasADi symbols anywhere (design parameters, masses, loads) the same equations are
    solved symbolically, block by block in the system's block-triangular order (each block by
    an elimination written once and mapped over the angles: :func:`_block_function`); the
    result's arrays are then CasADi columns over the angles, exactly differentiable.
    """
    A_ent, f_ent, n = _entries(model, motion)
    if ops.is_symbolic(*A_ent.values(), *f_ent.values()):
        X = _solve_symbolic(A_ent, f_ent, n, motion)
        cols = [X[:, k] for k in range(n)]
        reactions, normals = _reactions(model, motion, cols, lambda th: th)
        return ForceResult(
            motion.phi, reactions, normals, cols[n - 1], motion.omega, drive=_drive_kind(model)
        )

    phi = np.asarray(motion.phi, dtype=float)
    shape = np.broadcast_shapes(
        phi.shape, *(np.shape(v) for v in list(A_ent.values()) + list(f_ent.values()))
    )
    A = np.zeros(shape + (n, n))
    f = np.zeros(shape + (n,))
    for (r, c), v in A_ent.items():
        A[..., r, c] = v
    for r, v in f_ent.items():
        f[..., r] = v

    try:
        X = np.linalg.solve(A, -f[..., None])[..., 0]
    except np.linalg.LinAlgError:
        X = None
    if X is None or not np.all(np.isfinite(X)):
        cond = np.linalg.cond(A)
        i = np.unravel_index(int(np.argmax(~np.isfinite(cond) | (cond > 1e14))), cond.shape)
        at = np.broadcast_to(phi, shape)[i]
        where = (
            f"crank angle {np.rad2deg(at):.6g} deg"
            if model.drive is None
            else f"input {at:.6g} (m of the driving slider)"
        )
        raise MechanismError(
            f"kinetostatics: singular equilibrium system at {where} (toggle or ill-posed model)"
        )
    cols = [X[..., k] for k in range(n)]
    reactions, normals = _reactions(model, motion, cols, lambda th: _as(th, shape))
    return ForceResult(
        motion.phi, reactions, normals, X[..., n - 1], motion.omega, drive=_drive_kind(model)
    )


def _drive_kind(model: ForceModel) -> str:
    return "torque" if model.drive is None else "force"


def _reactions(model, motion, cols, shaped):
    """Reaction vectors and normal forces of the joints from the solved unknowns."""
    first, _ = _columns(model)
    reactions, normals = {}, {}
    for k, j in enumerate(model.joints):
        a = cols[first[k]]
        if isinstance(j, Revolute):
            reactions[j.name] = (a, cols[first[k] + 1])
        elif isinstance(j, Prismatic):
            d = j.direction
            th = shaped(motion.links[d].angle if isinstance(d, str) else d)
            reactions[j.name] = (-a * ops.sin(th), a * ops.cos(th))
            normals[j.name] = (a, cols[first[k] + 1])
        else:
            th = shaped(_normal(motion, j.normal))
            reactions[j.name] = (a * ops.cos(th), a * ops.sin(th))
            normals[j.name] = (a, 0.0 * a)
    return reactions, normals


def _point_velocity(motion: Motion, body: LinkInertia, x, y):
    """Velocity of the material point of ``body`` now at (x, y)."""
    p = motion.points[body.base]
    if body.link is None:
        return p.vx, p.vy
    w = motion.links[body.link].omega
    return p.vx - w * (y - p.y), p.vy + w * (x - p.x)


def applied_power(model: ForceModel, motion: Motion):
    """Power (W) of the applied loads of ``model`` at every angle of ``motion``."""
    total = 0.0
    for load in model.loads:
        for w in load.contributions(motion, model.bodies):
            body = model.bodies[w.body]
            vx, vy = _point_velocity(motion, body, w.x, w.y)
            om = 0.0 if body.link is None else motion.links[body.link].omega
            total = total + w.fx * vx + w.fy * vy + w.tz * om
    return total


def kinetic_energy_rate(model: ForceModel, motion: Motion):
    """dT/dt (W) of the bodies: ``sum m v_S . a_S + J w eps``."""
    total = 0.0
    for body in model.bodies.values():
        s = com_track(motion, body)
        total = total + body.mass * (s.vx * s.ax + s.vy * s.ay)
        if body.link is not None:
            lk = motion.links[body.link]
            total = total + body.inertia * lk.omega * lk.epsilon
    return total


def slider_crank_model(crank_body=None, rod_body=None, slider_body=None, loads=()) -> ForceModel:
    """Force model of a :class:`~mechsynth.SliderCrank`: bodies ``crank`` (about O), ``rod``
    (from A) and ``slider`` (at B); joints ``R10`` (frame on crank at O), ``R21`` (crank on rod
    at A), ``R32`` (rod on slider at B) and the guide ``R30`` (frame on slider)."""
    bodies = {
        "crank": crank_body or LinkInertia("crank", "O", 0.0),
        "rod": rod_body or LinkInertia("rod", "A", 0.0),
        "slider": slider_body or LinkInertia(None, "B", 0.0),
    }
    joints = (
        Revolute("R10", "crank", FRAME, "O"),
        Revolute("R21", "rod", "crank", "A"),
        Revolute("R32", "slider", "rod", "B"),
        Prismatic("R30", "slider", FRAME, "B", 0.0),
    )
    return ForceModel(bodies, joints, tuple(loads), "crank")


def four_bar_model(crank_body=None, coupler_body=None, rocker_body=None, loads=()) -> ForceModel:
    """Force model of a :class:`~mechsynth.FourBar`: bodies ``crank`` (about O1), ``coupler``
    (from A), ``rocker`` (about O2); joints ``R10`` (frame on crank at O1), ``R21`` (crank on
    coupler at A), ``R32`` (coupler on rocker at B), ``R30`` (frame on rocker at O2)."""
    bodies = {
        "crank": crank_body or LinkInertia("crank", "O1", 0.0),
        "coupler": coupler_body or LinkInertia("coupler", "A", 0.0),
        "rocker": rocker_body or LinkInertia("rocker", "O2", 0.0),
    }
    joints = (
        Revolute("R10", "crank", FRAME, "O1"),
        Revolute("R21", "coupler", "crank", "A"),
        Revolute("R32", "rocker", "coupler", "B"),
        Revolute("R30", "rocker", FRAME, "O2"),
    )
    return ForceModel(bodies, joints, tuple(loads), "crank")

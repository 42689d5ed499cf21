"""Results of path generation: one design (:class:`PathSolution`) and the search's outcome
(:class:`PathResult`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import MechanismError

__all__ = ["NAMES", "ERROR_DEFINITION", "PathSolution", "PathResult", "placed_linkage"]

#: the four-bar's design variables, in the solver's order
NAMES = ("crank", "coupler", "rocker", "ground", "u", "v", "x0", "y0", "angle")

ERROR_DEFINITION = {
    "squares": "sum over the targets of the squared distance between target and coupler point "
    "(m^2)",
    "max": "largest squared distance between a target and the coupler point (m^2)",
}


@dataclass(frozen=True)
class PathSolution:
    """One design: a four-bar, its coupler point and its placement, with the crank angle at
    each target.

    Attributes
    ----------
    crank, coupler, rocker, ground : link lengths (m).
    u, v : the coupler point, ``u`` along the coupler A -> B from A, ``v`` to its left (m).
    x0, y0 : the crank pivot O1 (m); ``angle``: direction of O1 -> O2 (rad from +x).
    branch : ``"open"`` or ``"crossed"`` (the four-bar's convention).
    angles : crank angle at each target (rad, from the ground line O1 -> O2,
        counter-clockwise).
    error : the error of the problem's objective (m^2); ``sum_squares``, ``max_distance``
        (m) for both measures.
    transmission : (smallest, largest) transmission angle over the turn (rad; the smallest
        counts an obtuse angle as pi minus it, the largest is the angle itself).
    note : e.g. ``"cognate of #1"``.
    certificate : with measure constraints, each one's
        :class:`~mechsynth.synthesis.path_measures.MeasureCertificate` (the certifier's value
        over the continuous crank angle); empty without.
    """

    crank: float
    coupler: float
    rocker: float
    ground: float
    u: float
    v: float
    x0: float
    y0: float
    angle: float
    branch: str
    angles: np.ndarray
    error: float
    sum_squares: float
    max_distance: float
    transmission: tuple[float, float]
    note: str = ""
    certificate: tuple = ()

    @property
    def fourbar(self):
        """The four-bar in its own frame (a :class:`~mechsynth.FourBar`)."""
        from ..kinematics.four_bar import FourBar

        return FourBar(
            crank=self.crank,
            coupler=self.coupler,
            rocker=self.rocker,
            ground=self.ground,
            branch=self.branch,
        )

    @property
    def coupler_point(self) -> tuple[float, float]:
        """``(u, v)`` of the tracing point on the coupler (m)."""
        return (self.u, self.v)

    @property
    def linkage(self):
        """The design placed in the plane as a :class:`~mechsynth.Linkage`: ground points O1
        and O2, crank O1A (its ``phase`` is the ground angle, so the linkage's crank angle is
        this solution's), dyad A-B-O2 and the tracing point P on the coupler (its output)."""
        return placed_linkage({k: getattr(self, k) for k in NAMES}, self.branch)

    def trace(self, phi) -> np.ndarray:
        """Coupler-point positions ``(len(phi), 2)`` (m) at crank angles ``phi`` (rad)."""
        return self.positions(phi)["P"]

    def positions(self, phi=None) -> dict[str, np.ndarray]:
        """Joint positions ``{"O1", "A", "B", "O2", "P"}``, each ``(n, 2)`` (m), at crank
        angles ``phi`` (rad; default: at the targets)."""
        phi = self.angles if phi is None else np.atleast_1d(np.asarray(phi, dtype=float))
        m = self.fourbar.motion(phi, coupler_points={"P": (self.u, self.v)})
        c, s = np.cos(self.angle), np.sin(self.angle)
        out = {}
        for name in ("O1", "A", "B", "O2", "P"):
            pt = m.points[name]
            x, y = np.broadcast_to(pt.x, phi.shape), np.broadcast_to(pt.y, phi.shape)
            out[name] = np.column_stack([self.x0 + c * x - s * y, self.y0 + s * x + c * y])
        return out

    def as_dict(self) -> dict:
        """JSON-ready values (SI: m, m^2, rad)."""
        d = {k: getattr(self, k) for k in (*NAMES, "branch", "error", "sum_squares")}
        d.update(
            max_distance=self.max_distance,
            angles=[float(a) for a in self.angles],
            transmission_min=float(self.transmission[0]),
            transmission_max=float(self.transmission[1]),
            note=self.note,
            certificate=[c.as_dict() for c in self.certificate],
        )
        return d


def placed_linkage(vals, branch="open"):
    """The four-bar ``vals`` (``{name: value}`` of :data:`NAMES`; numbers or CasADi symbols)
    placed in the plane as a Linkage with the tracing point ``"P"``."""
    from ..kinematics import ops
    from ..kinematics.linkage import Linkage

    c, s = ops.cos(vals["angle"]), ops.sin(vals["angle"])
    x0, y0, g = vals["x0"], vals["y0"], vals["ground"]
    return (
        Linkage(ground={"O1": (x0, y0), "O2": (x0 + g * c, y0 + g * s)}, name="path generator")
        .crank("A", about="O1", length=vals["crank"], phase=vals["angle"])
        .rrr("B", ("A", vals["coupler"]), ("O2", vals["rocker"]),
             branch=1 if branch == "open" else -1)
        .attach("P", on=("A", "B"), along=vals["u"], left=vals["v"])
        .with_output("P")
    )  # fmt: skip


@dataclass(frozen=True)
class PathResult:
    """What :func:`path_generation` found.

    Attributes
    ----------
    targets : ``(N, 2)`` target points (m).
    best : the best design (a :class:`PathSolution`); ``design`` (a Linkage), ``fourbar``,
        ``coupler_point``, ``error``, ``angles``, ``positions``, ``transmission`` read it.
    solutions : distinct designs, best first (local optima of the starts, and the best
        design's crank-driven cognate, named as such).
    timing, objective, closed : the problem's settings; ``error_definition`` in words.
    min_transmission : the smallest transmission angle asked (rad, 0 for none).
    starts : local solves run; ``distinct``: distinct optima among them.
    status : ``"optimal"``, ``"infeasible"`` (no start ended feasible), ``"interrupted"``.
    seconds : wall time.
    bound : with ``bound=``, the proved lower bound on the error and the gap to the best
        (a :class:`~mechsynth.synthesis.path_bound.PathBound`), else None.
    """

    targets: np.ndarray
    best: PathSolution | None
    solutions: tuple[PathSolution, ...]
    timing: str
    objective: str
    closed: bool
    min_transmission: float
    starts: int
    distinct: int
    status: str
    seconds: float
    error_definition: str
    bounds: dict = field(default_factory=dict)
    message: str = ""
    bound: object = None

    @property
    def success(self) -> bool:
        return self.best is not None and self.status in ("optimal", "interrupted")

    def _best(self) -> PathSolution:
        if self.best is None:
            raise MechanismError(f"path generation found no feasible design: {self.message}")
        return self.best

    @property
    def design(self):
        """The best design as a :class:`~mechsynth.Linkage` (tracing point ``"P"``)."""
        return self._best().linkage

    @property
    def fourbar(self):
        return self._best().fourbar

    @property
    def coupler_point(self):
        return self._best().coupler_point

    @property
    def error(self) -> float:
        return self._best().error

    @property
    def angles(self) -> np.ndarray:
        return self._best().angles

    @property
    def positions(self) -> dict[str, np.ndarray]:
        return self._best().positions()

    @property
    def transmission(self) -> tuple[float, float]:
        return self._best().transmission

    def summary(self) -> str:
        """A readable report."""
        lines = [
            f"path generation: {len(self.targets)} targets ({'closed' if self.closed else 'open'}"
            f" path), {self.timing} timing, objective {self.objective}",
            f"error: {self.error_definition}",
            f"starts: {self.starts}, distinct optima: {self.distinct}, status: {self.status}, "
            f"{self.seconds:.2f} s",
        ]
        if self.min_transmission > 0:
            mu = np.rad2deg(self.min_transmission)
            lines.append(f"smallest transmission angle asked: {mu:.4g} deg")
        if self.best is None:
            lines.append(f"no feasible design: {self.message}")
            return "\n".join(lines)
        unit = "" if self.timing == "shape" else " m^2"
        for k, s in enumerate(self.solutions[:5], start=1):
            mu0, mu1 = np.rad2deg(s.transmission)
            lines.append(
                f"#{k}: error {s.error:.6g}{unit} (sum of squares {s.sum_squares:.6g}, largest "
                f"distance {s.max_distance:.4g} m), min transmission angle {mu0:.2f} deg "
                + ("(coupler-rocker angle up to " if isinstance(s, PathSolution)
                   else "(largest ")
                + f"{mu1:.2f} deg), "
                f"{s.branch or 'linkage'}" + (f", {s.note}" if s.note else "")
            )
        b = self.best
        if isinstance(b, PathSolution):
            text = ", ".join(f"{k} {getattr(b, k):.6g}" for k in NAMES) + f", {b.branch} branch"
        else:
            text = ", ".join(f"{k} {v:.6g}" for k, v in b.values.items())
        lines.append("best: " + text)
        for c in getattr(b, "certificate", ()):
            lines.append(f"certified: {c}")
        if self.bound is not None:
            lines.append(self.bound.summary())
        return "\n".join(lines)

    def as_dict(self) -> dict:
        return {
            "targets": self.targets.tolist(),
            "timing": self.timing,
            "objective": self.objective,
            "closed": self.closed,
            "error_definition": self.error_definition,
            "min_transmission": float(self.min_transmission),
            "starts": self.starts,
            "distinct": self.distinct,
            "status": self.status,
            "success": self.success,
            "seconds": self.seconds,
            "message": self.message,
            "best": None if self.best is None else self.best.as_dict(),
            "solutions": [s.as_dict() for s in self.solutions],
            "bound": None if self.bound is None else self.bound.as_dict(),
        }

    def figure(self, n: int = 360, show: int | None = None):
        """Targets, the traced curve and the linkage drawn at the targets (at most ``show`` of
        them, default up to 4). Returns the matplotlib figure."""
        from .path_figures import path_figure

        return path_figure(self, n=n, show=show)

    def animate(self, frames: int = 72, **kwargs):
        """The best design moving over one turn (the library's animation of a Linkage)."""
        return self.design.animate(frames=frames, **kwargs)

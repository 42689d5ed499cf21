"""Literature cases of four-bar path generation: targets, formulation, source, published value.

Each :class:`PathCase` carries what the benchmark (``benchmarks/bench_path_generation.py``),
the slow tests and ``docs/path_generation.md`` run. Published errors are the sum of squared
distances between the targets and the coupler point with free timing, the crank angles in the
given order within one counter-clockwise turn, and the crank turning fully (Grashof crank); the
published design's smallest transmission angle goes with each as the constraint to meet.

Where the published linkage's dimensions are known (the reference files of four-bar-rs, K.
Chang's synthesis program, ``test-fb/refer/*.ron``: crank pivot ``p1x, p1y``, ground angle
``a``, links ``l1`` ground, ``l2`` crank, ``l3`` coupler, ``l4`` rocker, coupler point at
``l5`` from the crank pin at ``g`` from the coupler), :func:`design_error` recomputes its error
by the library's model with ordered free timing (:func:`ordered_error`); for the cases whose
published error we could not read (Yu et al.), that recomputed value is the reference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PathCase", "CASES", "exact_case", "ordered_error", "design_error", "fourbar_rs"]


@dataclass(frozen=True)
class PathCase:
    """A path-generation case: ``targets`` (N, 2), ``published_error`` (sum of squared
    distances; None where the source's value was not available to us), ``published_mu`` (deg,
    the published design's smallest transmission angle: the source's, or computed from its
    dimensions where ``published_error`` is None), ``source``; ``published_design``: the
    published linkage (``{name: value}`` of the four-bar's variables and ``branch``) where its
    dimensions are known, ``design_source`` where they come from."""

    name: str
    targets: np.ndarray
    published_error: float | None
    published_mu: float
    source: str
    timing: str = "free"
    published_design: dict | None = None
    design_source: str = ""

    @property
    def reference_error(self) -> float:
        """The error to beat: the published one, else the published design's recomputed."""
        if self.published_error is not None:
            return self.published_error
        return design_error(self)[0]


def fourbar_rs(p1x, p1y, a, l1, l2, l3, l4, l5, g, branch="open") -> dict:
    """The four-bar's variables of a four-bar-rs ``FourBar`` (its coupler point ``l5`` from the
    crank pin at angle ``g`` from the coupler A -> B: ``u = l5 cos g``, ``v = l5 sin g``; its
    circuit ``c1`` puts B to the left of A -> O2, this library's ``open`` branch)."""
    return dict(crank=l2, coupler=l3, rocker=l4, ground=l1, u=l5 * np.cos(g), v=l5 * np.sin(g),
                x0=p1x, y0=p1y, angle=a, branch=branch)  # fmt: skip


_FBRS = ("K. Chang (KmolYuan), four-bar-rs, test-fb/refer/{}.closed.ron (the published "
         "linkage's dimensions, 4-5 digits)")  # fmt: skip


def ordered_error(design, targets, grid: int = 720):
    """``(sum of squares, angles)``: the smallest error of the fixed four-bar ``design``
    (``{name: value}`` with ``branch``) over crank angles visited in the targets' order within
    one counter-clockwise turn: dynamic programming over ``grid`` equal steps, then each angle
    refined within a step by golden sections (80 rounds, vectorized). The refined angles keep
    the order (checked: a MechanismError when they do not)."""
    from ..errors import MechanismError
    from .path_generation import evaluated
    from .path_linkage import _ordered_nearest

    t = np.asarray(targets, dtype=float)
    br = design.get("branch", "open")
    phi = np.linspace(0.0, 2.0 * np.pi, grid, endpoint=False)
    sol = evaluated(design, br, phi[:1], t[:1])
    if sol is None:
        raise MechanismError("the design's crank does not turn fully")
    a = _ordered_nearest(sol.trace(phi), phi, t)
    h = 2.0 * np.pi / grid
    lo, hi = a - h, a + h
    g = (np.sqrt(5.0) - 1.0) / 2.0

    def f(x):
        return np.sum((sol.trace(x) - t) ** 2, axis=1)

    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = f(x1), f(x2)
    for _ in range(80):
        left = f1 < f2
        hi, lo = np.where(left, x2, hi), np.where(left, lo, x1)
        x1, x2 = np.where(left, hi - g * (hi - lo), x2), np.where(left, x1, lo + g * (hi - lo))
        f1, f2 = f(x1), f(x2)
    out = 0.5 * (lo + hi)
    if np.diff(out).min() < -1e-12 or out[-1] - out[0] > 2.0 * np.pi + 1e-12:
        raise MechanismError("the refined crank angles left the targets' order")
    return float(f(out).sum()), out


def design_error(case: PathCase):
    """``(error, smallest transmission angle in deg)`` of ``case``'s published linkage by the
    library's model with ordered free timing (:func:`ordered_error`)."""
    from .path_generation import _transmission_range
    from .path_result import PathSolution

    if case.published_design is None:
        raise ValueError(f"{case.name}: no published design")
    d = case.published_design
    err, ang = ordered_error(d, case.targets)
    fb = PathSolution(**{k: v for k, v in d.items() if k != "branch"}, branch=d["branch"],
                      angles=ang, error=err, sum_squares=err, max_distance=0.0,
                      transmission=(0.0, 0.0)).fourbar  # fmt: skip
    return err, float(np.rad2deg(_transmission_range(fb)[0]))


CASES = {
    "bulatovic-18": PathCase(
        "bulatovic-18",
        np.array(
            [
                (0.5, 1.1),
                (0.4, 1.1),
                (0.3, 1.1),
                (0.2, 1.0),
                (0.1, 0.9),
                (0.05, 0.75),
                (0.02, 0.6),
                (0.0, 0.5),
                (0.0, 0.4),
                (0.03, 0.3),
                (0.1, 0.25),
                (0.15, 0.2),
                (0.2, 0.3),
                (0.3, 0.4),
                (0.4, 0.5),
                (0.5, 0.7),
                (0.6, 0.9),
                (0.6, 1.0),
            ]
        ),  # fmt: skip
        4.961e-3,
        24.7,
        "Bulatovic, Miodragovic and Boskovic, Modified Krill Herd (MKH) algorithm and its "
        "application in dimensional synthesis of a four-bar linkage, Mech. Mach. Theory 95 "
        "(2016) 1-21 (the 18-point closed path, also Cabrera, Simon and Prado, Mech. Mach. "
        "Theory 37 (2002) 1165-1177); error recomputed with ordered free timing",
        published_design=fourbar_rs(0.26886, 0.17715, 0.29294, 1.00429, 0.42180, 0.87821,
                                    0.58013, 0.5234, 0.8148),  # fmt: skip
        design_source=_FBRS.format("mkh1"),
    ),
    "bulatovic-12": PathCase(
        "bulatovic-12",
        np.array(
            [
                (4.15, 2.21),
                (4.5, 2.18),
                (4.53, 1.83),
                (4.13, 1.68),
                (3.67, 1.58),
                (2.96, 1.33),
                (2.67, 1.06),
                (2.63, 0.82),
                (2.92, 0.81),
                (3.23, 1.07),
                (3.49, 1.45),
                (3.76, 1.87),
            ]
        ),  # fmt: skip
        1.515e-4,
        21.3,
        "Bulatovic, Miodragovic and Boskovic, Mech. Mach. Theory 95 (2016) 1-21: the 12-point "
        "closed path",
        published_design=fourbar_rs(1.14265, 0.48237, 0.16502, 2.87645, 1.14644, 4.40713,
                                    4.75773, 2.6666, -1.1364),  # fmt: skip
        design_source=_FBRS.format("mkh2"),
    ),
    "yu-20a": PathCase(
        "yu-20a",
        np.array(
            [(-27.0, 1.0), (-21.857, -3.214), (-16.7, -7.428), (-11.571, -11.642),
             (-6.428, -15.857), (-1.285, -20.071), (3.857, -24.285), (9.0, -28.5),
             (15.0, -29.9), (20.0, -30.0), (27.2, -25.0), (29.2, -20.0), (28.0, -10.0),
             (22.7, 2.0), (15.0, 10.6), (5.0, 16.5), (-10.0, 19.6), (-22.0, 17.0),
             (-28.0, 11.0), (-29.0, 5.0)]
        ),  # fmt: skip
        None,
        41.27,
        "Yu, Tang and Wang, Study on a new computer path synthesis method of a four-bar "
        "linkage, Mech. Mach. Theory 42 (2007) 383-392: the first 20-point closed path (the "
        "source's units); the published error was not available to us: the reference is the "
        "published linkage's error recomputed here (3.4297) and its smallest transmission "
        "angle computed from its dimensions (41.27 deg)",
        published_design=fourbar_rs(-11.55, -20.14, 2.981022362406315, 65.87, 17.43, 25.46,
                                    64.57, 23.47, 2.834414705238791),  # fmt: skip
        design_source=_FBRS.format("yu1"),
    ),
    "yu-20b": PathCase(
        "yu-20b",
        np.array(
            [(-24.0, 40.0), (-30.0, 41.0), (-34.0, 40.0), (-38.0, 36.0), (-36.0, 30.0),
             (-28.0, 29.0), (-21.0, 31.0), (-17.0, 32.0), (-8.0, 34.0), (3.0, 37.0),
             (10.0, 41.0), (17.0, 41.0), (26.0, 39.0), (28.0, 33.0), (29.0, 26.0),
             (26.0, 23.0), (17.0, 23.0), (11.0, 24.0), (6.0, 27.0), (0.0, 31.0)]
        ),  # fmt: skip
        None,
        42.42,
        "Yu, Tang and Wang, Mech. Mach. Theory 42 (2007) 383-392: the second 20-point closed "
        "path (the source's units); the published error was not available to us: the "
        "reference is the published linkage's error recomputed here (18.646) and its smallest "
        "transmission angle computed from its dimensions (42.42 deg)",
        published_design=fourbar_rs(-44.87, 71.09, 5.187118536927147, 76.77, 27.31, 46.44,
                                    72.55, 60.42, 5.489060497522167),  # fmt: skip
        design_source=_FBRS.format("yu2"),
    ),
}


def exact_case(n: int = 9):
    """``(targets, design, angles)``: ``n`` points on the coupler curve of a known crank-rocker
    (crank 1, coupler 3, rocker 2.5, ground 3.2 m; coupler point u 1.2, v 0.9 m; crank pivot
    (0.3, -0.2) m, ground at 0.4 rad; open branch) at uneven crank angles; the error of a
    four-bar through them can reach round-off."""
    from .path_generation import evaluated

    design = dict(crank=1.0, coupler=3.0, rocker=2.5, ground=3.2, u=1.2, v=0.9, x0=0.3,
                  y0=-0.2, angle=0.4)  # fmt: skip
    angles = np.array([0.1, 0.7, 1.5, 2.2, 2.9, 3.8, 4.6, 5.3, 5.9])[:n]
    sol = evaluated(design, "open", angles, np.zeros((len(angles), 2)))
    return sol.trace(angles), design, angles

"""Literature cases of four-bar path generation: targets, formulation, source, published value.

Each :class:`PathCase` carries what the benchmark (``benchmarks/bench_path_generation.py``),
the slow tests and ``docs/path_generation.md`` run. Published errors are the sum of squared
distances between the targets and the coupler point with free timing, the crank angles in the
given order within one counter-clockwise turn, and the crank turning fully (Grashof crank); the
published smallest transmission angle goes with each as the constraint to meet.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PathCase", "CASES", "exact_case"]


@dataclass(frozen=True)
class PathCase:
    """A path-generation case: ``targets`` (N, 2), ``published_error`` (sum of squared
    distances), ``published_mu`` (deg, the published design's smallest transmission angle),
    ``source``."""

    name: str
    targets: np.ndarray
    published_error: float
    published_mu: float
    source: str
    timing: str = "free"


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

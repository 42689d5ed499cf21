"""Function generation: a four-bar (or slider-crank) whose output follows ``y = f(x)``.

Conventions
-----------
* ``x`` on ``[x0, x1]`` maps linearly to the input crank angle
  ``phi = phi0 + (x - x0) / (x1 - x0) * input_range`` and ``y`` to the output
  ``psi = psi0 + (y - y0) / (y1 - y0) * output_range`` with ``y0 = f(x0)``, ``y1 = f(x1)``.
  Angles are :class:`~mechsynth.kinematics.FourBar`'s: crank O1 -> A and rocker O2 -> B from
  +x, counter-clockwise, O1 at the origin, O2 at ``(ground, 0)``. For a slider-crank the output
  is the slider position ``s`` (the x of B, m) and ``output_range`` is in m.
* ``phi0, psi0`` (the *phases*, where the ranges start) are given, or chosen by a scan in 5 deg
  steps (half a turn of each: a phase half a turn on gives the same four-bar with that link
  reflected): the most accurate design that assembles over the whole range on one branch with
  a transmission angle of at least ``min_transmission`` and links within a ratio of 20.
* Three precision points give the exact solution of Freudenstein's equation
  (:mod:`.freudenstein`), more a least-squares fit of it; ``optimize=True`` then minimizes the
  worst true output error over the whole range (:mod:`.function_minmax`).
* The structural error is the designed linkage's true output (its motion, on ``n_eval`` points
  of the range) minus the ideal ``psi(x)``: rad (m for a slider-crank), and in units of ``y``.

>>> import mechsynth as ms
>>> fg = ms.function_generation("x**2", x=(0, 1), input_range=ms.deg(90),
...                             output_range=ms.deg(90), phases=(ms.deg(140), ms.deg(245)))
>>> fg.method, fg.design.branch, round(ms.to_deg(fg.max_error), 4)
('exact', 'crossed', 0.1665)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import validate
from ..errors import MechanismError
from .freudenstein import (
    chebyshev_spacing,
    four_bar_lengths,
    freudenstein_k,
    slider_crank_coefficients,
    slider_crank_lengths,
)

__all__ = ["function_generation", "FunctionGeneration"]

_MECHANISMS = ("four-bar", "slider-crank")
_SCAN_STEP = 5.0  # deg, of the phase scan
_MAX_RATIO = 20.0  # longest / shortest link of a scanned design
_POINT_TOL = 1e-7  # rad (relative to the crank for a slider), exact precision points
_SCAN_POINTS = 121  # points of the range where scanned candidates are compared
_SCAN_RETRIES = 8  # best scanned candidates checked on the whole grid
_CHUNK = 1024  # candidates evaluated at once
_SOLUTIONS = 20  # scanned designs listed in ``solutions``


@dataclass(frozen=True)
class FunctionGeneration:
    """A function generator and how well it generates.

    Attributes
    ----------
    design : the :class:`~mechsynth.kinematics.FourBar` (``full_turn`` True when its crank
        turns fully) or :class:`~mechsynth.kinematics.SliderCrank`.
    mechanism : ``"four-bar"`` or ``"slider-crank"``.
    method : ``"exact"`` (three precision points), ``"least squares"`` or ``"min-max"``.
    phases : ``(phi0, psi0)`` (rad) or ``(phi0, s0)`` (rad, m): the design's crank angle and
        output where the ranges start, in the design's own convention.
    spans : ``(input_range, output_range)`` (rad, and rad or m).
    k : Freudenstein's ``(K1, K2, K3)`` of the design; for a slider-crank ``(s0, offset, K)``
        of its loop equation (:mod:`.freudenstein`).
    precision_points : ``(n, 2)`` array of ``(crank angle, output)`` the design was made to
        pass through (rad; rad or m).
    precision_x : their ``x`` (None for a design from pairs).
    x : where the error is evaluated: ``n_eval`` points of ``[x0, x1]`` (for pairs: the
        pairs' crank angles, rad).
    error : true output minus ideal output at ``x`` (rad, or m for a slider-crank).
    error_y : the same in units of ``y`` (None for pairs).
    max_error : ``max |error|``.
    min_transmission_angle : smallest transmission angle over the input range (rad, an obtuse
        angle counted as its supplement).
    domain, y_range : ``(x0, x1)`` and ``(f(x0), f(x1))`` (None for pairs).
    function : the function's text (or a callable's name).
    start_max_error, start_error : for ``"min-max"``, ``max_error`` and ``error`` of the
        least-squares or exact start.
    solve : the certified :class:`~mechsynth.synthesis.Result` of the min-max stage.
    solutions : the precision-point designs considered, most accurate first, as dicts (phases,
        lengths, branch, ``max_error``, ``min_transmission_angle``; SI): the best admissible
        ones of a phase scan (up to 20), else the one design; ``solutions.csv`` of
        :meth:`write`.
    """

    design: Any
    mechanism: str
    method: str
    phases: tuple[float, float]
    spans: tuple[float, float]
    k: tuple[float, float, float]
    precision_points: np.ndarray
    precision_x: np.ndarray | None
    x: np.ndarray
    error: np.ndarray
    error_y: np.ndarray | None
    max_error: float
    min_transmission_angle: float
    domain: tuple[float, float] | None = None
    y_range: tuple[float, float] | None = None
    function: str | None = None
    start_max_error: float | None = None
    start_error: np.ndarray | None = field(default=None, repr=False)
    solve: Any = field(default=None, repr=False)
    solutions: tuple = field(default=(), repr=False)

    # ------------------------------------------------------------------ views
    @property
    def max_error_y(self) -> float | None:
        """``max |error_y|`` (units of ``y``), None for pairs."""
        return None if self.error_y is None else float(np.max(np.abs(self.error_y)))

    @property
    def angular(self) -> bool:
        return self.mechanism == "four-bar"

    @property
    def linkage(self):
        """The design as a :class:`~mechsynth.kinematics.Linkage` (ground O1, O2; crank A;
        an RRR group B for a four-bar, an RRP slider B for a slider-crank): the same motion,
        for forces, charts, drawings and the explorer."""
        from ..kinematics.linkage import Linkage

        d = self.design
        if self.angular:
            return (
                Linkage(ground={"O1": (0.0, 0.0), "O2": (float(d.ground), 0.0)})
                .crank("A", about="O1", length=float(d.crank))
                .rrr("B", ("A", float(d.coupler)), ("O2", float(d.rocker)), branch=d.sigma)
            )
        return (
            Linkage(ground={"O": (0.0, 0.0)})
            .crank("A", about="O", length=float(d.crank))
            .rrp("B", ("A", float(d.rod)), guide=((0.0, float(d.offset)), 0.0))
        )

    def generator(self):
        """The design as a :mod:`.function_minmax` generator (input: rotation from the start
        of the range), e.g. to start a :class:`~mechsynth.synthesis.Problem` of one's own."""
        from .function_minmax import (
            CrankFourBarGenerator,
            FourBarGenerator,
            SliderCrankGenerator,
        )

        d = self.design
        if self.angular:
            cls = CrankFourBarGenerator if d.full_turn else FourBarGenerator
            return cls(d.crank, d.coupler, d.rocker, d.ground, *self.phases, self.spans[0],
                       d.branch)  # fmt: skip
        return SliderCrankGenerator(d.crank, d.rod, d.offset, *self.phases, self.spans[0])

    def summary(self) -> str:
        """The design and its accuracy, in display units."""
        from .. import display

        out_unit = "rad" if self.angular else "m"
        lines = [
            f"Function generator ({self.mechanism}, {self.method}"
            + (f", y = {self.function}" if self.function else "")
            + ")",
            f"  {self.design.describe()}"
            + (f", {self.design.branch} branch" if self.angular else ""),
            f"  phases: crank {display.fmt(self.phases[0], 'rad', 6)}, output "
            f"{display.fmt(self.phases[1], out_unit, 6)}; ranges: input "
            f"{display.fmt(self.spans[0], 'rad', 6)}, output "
            f"{display.fmt(self.spans[1], out_unit, 6)}",
            "  K = (" + ", ".join(f"{v:.8g}" for v in self.k) + ")",
            f"  max structural error {display.fmt(self.max_error, out_unit, 4)}"
            + (f" ({self.max_error_y:.4g} in y)" if self.error_y is not None else ""),
            f"  min transmission angle {display.fmt(self.min_transmission_angle, 'rad', 4)}",
        ]
        if self.start_max_error is not None:
            lines.append(
                "  max error before the min-max stage "
                f"{display.fmt(self.start_max_error, out_unit, 4)}; certified: "
                f"{self.solve.certification.certified}, status {self.solve.status}"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """JSON-ready numbers (SI)."""
        return {
            "mechanism": self.mechanism,
            "method": self.method,
            "function": self.function,
            "design": self.design.as_dict(),
            "phases": [float(v) for v in self.phases],
            "spans": [float(v) for v in self.spans],
            "k": [float(v) for v in self.k],
            "precision_points": np.asarray(self.precision_points).tolist(),
            "precision_x": None if self.precision_x is None else self.precision_x.tolist(),
            "max_error": float(self.max_error),
            "max_error_y": self.max_error_y,
            "min_transmission_angle": float(self.min_transmission_angle),
            "start_max_error": self.start_max_error,
            "success": True if self.solve is None else bool(self.solve.success),
            "status": "exact" if self.solve is None else self.solve.status,
        }

    # ------------------------------------------------------------------ figure and files
    def plot(self, ax=None):
        """The structural error over the range with the precision points marked; returns the
        figure."""
        import matplotlib.pyplot as plt

        from .. import display
        from ..plotting import PALETTE, style

        unit = "rad" if self.angular else "m"
        with style():
            if ax is None:
                fig, ax = plt.subplots(figsize=(6.4, 3.8))
            else:
                fig = ax.figure
            err, shown = display.convert(np.asarray(self.error), unit)
            xlabel = "x" if self.precision_x is not None else display.label("crank angle", "rad")
            xs = self.x if self.precision_x is not None else display.convert(self.x, "rad")[0]
            marker = "-" if self.precision_x is not None else "o"  # pairs: no curve between
            start = None
            first = "exact" if len(self.precision_points) == 3 else "least squares"
            if self.start_error is not None:
                start, _ = display.convert(np.asarray(self.start_error), unit)
                ax.plot(xs, start, "--", color=PALETTE[0], lw=1.0, label=f"start ({first})")
            ax.plot(xs, err, marker, color=PALETTE[4], label=f"structural error ({self.method})")
            ax.axhline(0.0, color=PALETTE[0], lw=0.8)
            if self.precision_x is not None:
                what = "precision points" + ("" if first == "exact" else " (fitted)")
                ax.plot(self.precision_x, np.zeros(len(self.precision_x)), "o", ms=6,
                        color=PALETTE[5], zorder=3, label=what)  # fmt: skip
            if start is not None:
                err = np.concatenate([err, start])
            ax.set_xlabel(xlabel)
            ax.set_ylabel(f"output error, {shown}")
            lo, hi = float(np.min(err)), float(np.max(err))
            pad = 0.12 * max(hi - lo, 1e-12)
            ax.set_ylim(lo - pad, hi + 2.5 * pad)
            xl = float(np.min(xs)), float(np.max(xs))
            ax.set_xlim(xl[0] - 0.02 * (xl[1] - xl[0]), xl[1] + 0.02 * (xl[1] - xl[0]))
            what = f"y = {self.function}" if self.function else "precision pairs"
            ax.set_title(
                f"{self.mechanism} function generator, {what} ({self.method}): max error "
                f"{display.fmt(self.max_error, unit, 3)}",
                fontsize=9,
            )
            ax.legend(loc="upper center", ncols=2)
        return fig

    def to_toml(self) -> str:
        """A design file of the design (``mechsynth animate`` reads it), with the function
        generator's phases and accuracy as comments."""
        d = self.design.as_dict()
        name = self.mechanism
        lines = [
            f"# function generator ({self.method}): y = {self.function or 'precision pairs'}",
            f"# phases: crank {self.phases[0]!r} rad, output {self.phases[1]!r}"
            + (" rad" if self.angular else " m"),
            f"# ranges: input {self.spans[0]!r} rad, output {self.spans[1]!r}"
            + (" rad" if self.angular else " m"),
            f"# max structural error {self.max_error!r}" + (" rad" if self.angular else " m"),
            f'mechanism = "{name}"',
            'trace = ["B"]',
            "",
            "[design]",
        ]
        for k, v in d.items():
            if isinstance(v, bool):
                lines.append(f"{k} = {'true' if v else 'false'}")
            elif isinstance(v, str):
                lines.append(f'{k} = "{v}"')
            else:
                lines.append(f"{k} = {float(v)!r}")
        return "\n".join(lines) + "\n"

    def problem_toml(self, bounds: dict | None = None, min_transmission="auto",
                     angles: int = 33, starts: int = 8) -> str:  # fmt: skip
        """A problem file for ``mechsynth optimize`` (``mechanism = "function-generator"``,
        :mod:`.function_problem`): the min-max stage around this design, to edit (its boxes,
        its constraints) and solve. ``min_transmission`` (rad): a lower bound of the
        transmission angle over the range; ``"auto"`` takes 30 deg, or the design's own
        minimum if lower (so that it is feasible); None none. A design from precision pairs has
        no function: MechanismError."""
        from ..tomlwrite import to_toml
        from .function_problem import problem_data

        if isinstance(min_transmission, str) and min_transmission == "auto":
            min_transmission = None
            if self.angular:
                min_transmission = min(np.radians(30.0), self.min_transmission_angle * (1 - 1e-6))
        data = problem_data(self, bounds=bounds, min_transmission=min_transmission,
                            angles=angles)  # fmt: skip
        data = {"starts": int(starts), **data}
        head = (
            f"# The min-max stage of the function generator y = {self.function} "
            f"({self.mechanism}, {self.method}):\n#\n#   mechsynth optimize problem.toml\n#\n"
            "# The input is the crank's rotation from the range's start (0 .. input_range); "
            "phi0 and the\n# output's phase are variables. structural_error is the worst "
            "|output - ideal| over the\n# range (rad, or m for a slider-crank); SI numbers.\n"
        )
        return head + to_toml(data)

    def write(self, out) -> list:
        """Write ``design.toml``, ``error.csv`` (the error curve), ``precision_points.csv``,
        ``solutions.csv``, ``result.json``, ``error.png`` and, for a design from a function,
        ``problem.toml`` (:meth:`problem_toml`, for ``mechsynth optimize``) into ``out``;
        returns the paths."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from ..fileio import output_dir, save_figure, write_csv, write_text
        from ..jsonutil import dumps

        out = output_dir(out)
        unit = out_unit = "rad" if self.angular else "m"
        files = [write_text(out / "design.toml", self.to_toml())]
        head = ["x" if self.precision_x is not None else "crank angle [rad]", f"error [{unit}]"]
        cols = [self.x, self.error]
        if self.error_y is not None:
            head.append("error [y]")
            cols.append(self.error_y)
        files.append(write_csv(out / "error.csv", head, np.column_stack(cols).tolist()))
        pp = np.asarray(self.precision_points)
        head = ["crank angle [rad]", f"output [{unit}]"]
        rows = pp.tolist()
        if self.precision_x is not None:
            head = ["x", *head]
            rows = np.column_stack([self.precision_x, pp]).tolist()
        files.append(write_csv(out / "precision_points.csv", head, rows))
        if self.solutions:
            keys = list(self.solutions[0])
            units = {"phi0": "rad", "psi0": "rad", "max_error": out_unit,
                     "min_transmission_angle": "rad", "branch": ""}  # fmt: skip
            head = [f"{k} [{units.get(k, 'm')}]" if units.get(k, "m") else k for k in keys]
            files.append(
                write_csv(
                    out / "solutions.csv", head, [[r[k] for k in keys] for r in self.solutions]
                )
            )
        files.append(write_text(out / "result.json", dumps(self.to_dict()) + "\n"))
        fig = self.plot()
        files.append(save_figure(fig, out / "error.png", dpi=120))
        plt.close(fig)
        if self.function is not None and self.domain is not None:
            files.append(write_text(out / "problem.toml", self.problem_toml()))
        return files


# ---------------------------------------------------------------------------------- input
def _function(function):
    from .function_expr import parse_function

    if isinstance(function, str):
        return parse_function(function), function
    if callable(function):
        return function, getattr(function, "__name__", "f")
    raise MechanismError(
        f"function must be an expression in x (str) or a callable, got {function!r}"
    )


def _values(f, x, what):
    try:
        with np.errstate(all="ignore"):
            y = np.asarray(f(np.asarray(x, dtype=float)), dtype=float)
    except (TypeError, ValueError, ArithmeticError) as exc:
        raise MechanismError(f"the function cannot be evaluated on {what} ({exc})") from None
    y = np.broadcast_to(y, np.shape(x)).astype(float)
    bad = ~np.isfinite(y)
    if bad.any():
        i = int(np.argmax(bad))
        raise MechanismError(
            f"the function is not finite on {what}: f({float(np.ravel(x)[i]):.6g}) = "
            f"{float(np.ravel(y)[i])}"
        )
    return y


def _range(name, value, limit=None, unit="rad"):
    v = validate.number(name, value, unit)
    if v == 0.0:
        raise MechanismError(f"{name} must be non-zero, got 0")
    if limit is not None and abs(v) >= limit:
        raise MechanismError(
            f"{name} ({np.degrees(v):.6g} deg) must be below 360 deg in magnitude: a four-bar's "
            "motion repeats every turn of its crank, so no four-bar spans it"
        )
    return v


def _precision_x(spacing, points, x0, x1):
    if isinstance(spacing, str):
        n = validate.integer("points", points, 3, 1000)
        if spacing == "chebyshev":
            return chebyshev_spacing(x0, x1, n)
        if spacing == "uniform":
            return x0 + (x1 - x0) * (np.arange(n) + 0.5) / n
        validate.option("spacing", spacing, ("chebyshev", "uniform"))
    xs = np.ravel(validate.real("spacing", spacing))
    if xs.size < 3:
        raise MechanismError(f"spacing: give at least 3 precision points, got {xs.size}")
    lo, hi = min(x0, x1), max(x0, x1)
    out = (xs < lo) | (xs > hi)
    if out.any():
        raise MechanismError(
            f"precision point x = {float(xs[np.argmax(out)]):.6g} is outside the range "
            f"[{lo:.6g}, {hi:.6g}]"
        )
    return xs


def _check_distinct(values, what, scale):
    v = np.sort(np.asarray(values, float))
    gaps = np.diff(v)
    if gaps.size and gaps.min() <= 1e-9 * max(scale, 1e-300):
        i = int(np.argmin(gaps))
        raise MechanismError(
            f"two equal precision points ({what} = {float(v[i]):.9g} twice): the precision "
            "points must be distinct"
        )


# ------------------------------------------------------------------------ candidate designs
def _turn(a) -> float:
    """An angle (rad) in [0, 2 pi)."""
    return float(np.mod(a, 2.0 * np.pi))


def _wrap(a):
    return np.arctan2(np.sin(a), np.cos(a))


def _four_bar_candidates(phi, psi, phi_d, psi_d, ground, exact):
    """Every candidate phase pair at once (rows). ``phi, psi``: precision pairs ``(C, n)``,
    ``phi_d, psi_d``: the ideal over the range ``(C, m)``. Returns a dict of arrays (one entry
    per candidate) and the reason each invalid one failed."""
    from ..kinematics.four_bar import FourBar

    C = phi.shape[0]
    k = freudenstein_k(phi, psi)
    a, b2, c, sa, sc = four_bar_lengths(k, ground)
    with np.errstate(invalid="ignore"):
        b = np.sqrt(np.where(b2 > 0, b2, np.nan))
    reason = np.full(C, "", dtype=object)
    ok = np.isfinite(a) & np.isfinite(c) & np.isfinite(b) & (a > 0) & (c > 0)
    reason[~ok] = "no coupler closes the loop (coupler^2 <= 0) or a link is infinite"
    with np.errstate(invalid="ignore"):
        ls = np.stack([a, b, c, np.full_like(a, ground)])
        sane = (ls.max(axis=0) <= 1e6 * ls.min(axis=0)) & (2 * ls.max(axis=0) < ls.sum(axis=0))
    reason[ok & ~sane] = "its links cannot be assembled (or differ by more than 1e6 times)"
    ok &= sane
    # assembly over the whole range: |cos(transmission angle)| < 1 at every angle
    ang = np.concatenate([phi, phi_d], axis=1) + sa[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        r2 = a[:, None] ** 2 + ground**2 - 2 * a[:, None] * ground * np.cos(ang)
        cmu = (b[:, None] ** 2 + c[:, None] ** 2 - r2) / (2 * b[:, None] * c[:, None])
    cmu = np.where(ok[:, None], cmu, 2.0)
    assembles = np.all(np.abs(cmu) < 1.0 - 1e-12, axis=1)
    reason[ok & ~assembles] = "it cannot be assembled over the whole input range (a toggle inside)"
    ok &= assembles
    err = np.full(C, np.inf)
    branch = np.full(C, "open", dtype=object)
    curves = np.full(psi_d.shape, np.nan)
    idx = np.flatnonzero(ok)
    n = phi.shape[1]
    if idx.size:
        target = np.concatenate([psi, psi_d], axis=1)[idx] + sc[idx, None]
        best = np.full(idx.size, np.inf)
        for br in ("open", "crossed"):
            fb = FourBar(a[idx, None], b[idx, None], c[idx, None], ground, br, False)
            e = _wrap(fb.motion(ang[idx]).links["rocker"].angle - target)
            worst = np.nanmax(np.abs(e), axis=1)  # NaN: no ideal between pairs
            if exact:  # the precision points themselves decide the branch
                worst = np.where(np.max(np.abs(e[:, :n]), axis=1) < _POINT_TOL, worst, np.inf)
            better = worst < best
            best = np.where(better, worst, best)
            branch[idx[better]] = br
            curves[idx[better]] = e[better, n:]
        err[idx] = best
        mixed = idx[~np.isfinite(best)]
        reason[mixed] = "its precision points lie on different assembly branches"
        ok[mixed] = False
    mu = np.arccos(np.clip(np.abs(cmu), 0.0, 1.0))
    return {
        "ok": ok, "reason": reason, "lengths": (a, b, c), "shifts": (sa, sc), "k": k,
        "branch": branch, "error": err, "curves": curves, "mu": np.min(mu, axis=1),
    }  # fmt: skip


def _slider_candidates(phi, u, phi_d, u_d, crank, exact):
    """As :func:`_four_bar_candidates` for a slider-crank (``u``: the output's travel)."""
    from ..kinematics.slider_crank import SliderCrank

    C = phi.shape[0]
    coef = slider_crank_coefficients(phi, u, crank)
    s0, e, L2 = slider_crank_lengths(coef, crank)
    with np.errstate(invalid="ignore"):
        L = np.sqrt(np.where(L2 > 0, L2, np.nan))
    reason = np.full(C, "", dtype=object)
    ok = np.isfinite(L) & np.isfinite(e) & np.isfinite(s0)
    reason[~ok] = "no rod closes the loop (rod^2 <= 0)"
    turns = np.where(ok, L > crank + np.abs(e), False)
    reason[ok & ~turns] = "the rod is not longer than crank + |offset| (the crank cannot turn)"
    ok &= turns
    err = np.full(C, np.inf)
    curves = np.full(u_d.shape, np.nan)
    mu = np.full(C, np.nan)
    idx = np.flatnonzero(ok)
    n = phi.shape[1]
    if idx.size:
        sc = SliderCrank(crank, L[idx, None], e[idx, None])
        ang = np.concatenate([phi, phi_d], axis=1)[idx]
        m = sc.motion(ang)
        d = m.slider.position - s0[idx, None] - np.concatenate([u, u_d], axis=1)[idx]
        worst = np.nanmax(np.abs(d), axis=1)  # NaN: no ideal between pairs
        if exact:
            worst = np.where(np.max(np.abs(d[:, :n]), axis=1) < _POINT_TOL * crank, worst, np.inf)
        err[idx] = worst
        curves[idx] = d[:, n:]
        t = m.transmission_angle
        mu[idx] = np.min(np.minimum(t, np.pi - t), axis=1)
        bad = idx[~np.isfinite(worst)]
        reason[bad] = (
            "its precision points need the slider behind the crank pin (the other "
            "assembly, which SliderCrank does not model)"
        )
        ok[bad] = False
    return {
        "ok": ok, "reason": reason, "lengths": (L, e, s0), "k": coef, "error": err,
        "curves": curves, "mu": mu,
    }  # fmt: skip


# ---------------------------------------------------------------------------------- public
def function_generation(
    function=None,
    x=None,
    *,
    pairs=None,
    input_range=None,
    output_range=None,
    phases=None,
    points: int = 3,
    spacing="chebyshev",
    mechanism: str = "four-bar",
    ground: float = 1.0,
    crank: float = 1.0,
    optimize: bool = False,
    require_crank: bool = False,
    min_transmission: float | None = np.radians(30.0),
    n_eval: int = 401,
    starts: int = 1,
    bounds: dict | None = None,
) -> FunctionGeneration:
    """Design a four-bar or slider-crank that generates ``y = f(x)`` (see the module notes).

    Parameters
    ----------
    function : an expression in ``x`` (``"log10(x)"``; see :mod:`.function_expr`) or a
        callable taking numpy arrays (and CasADi symbols, for ``optimize``).
    x : ``(x0, x1)``, the range of ``x``.
    pairs : instead of a function, precision pairs ``[(phi_i, psi_i), ...]`` (rad; a
        slider-crank's ``s_i`` in m), at least three, in the design's angle convention.
    input_range : crank rotation over ``[x0, x1]`` (rad, signed; below a turn).
    output_range : output rotation (rad, signed; below a turn) or slider travel (m, signed).
    phases : ``(phi0, psi0)`` (rad) or ``(phi0, s0)``: crank angle and output where the ranges
        start; None scans them (module notes). A slider-crank's ``s0`` comes out of the
        solution: give ``phases=(phi0,)`` or ``(phi0, None)``.
    points : number of precision points (3 exact, more least squares).
    spacing : ``"chebyshev"`` (default), ``"uniform"`` (midpoints of equal cells), or the
        ``x`` of the precision points.
    mechanism : ``"four-bar"`` or ``"slider-crank"``.
    ground : the four-bar's ground length (m), its scale. crank : the slider-crank's (m).
    optimize : then minimize the certified worst structural error over the whole range with
        the phases and the other lengths free (needs a function).
    require_crank : the four-bar's crank must make full turns (Grashof crank-rocker or
        double-crank); also kept by the min-max stage.
    min_transmission : least transmission angle (rad) of scanned designs and of the min-max
        stage; None for no limit.
    n_eval : points of the range where the structural error is evaluated.
    starts : multi-starts of the min-max stage (its start design is tried first).
    bounds : ``{name: (lo, hi)}`` of the min-max stage's variables (``crank``, ``coupler``,
        ``rocker``, ``phi0``, ``psi0``; a slider-crank's ``rod``, ``offset``, ``phi0``, ``s0``)
        replacing its default box around the start (lengths within a factor 4, phases within
        60 deg, ``s0`` within a crank length). The stage is a local solve from the start: more
        starts in a wider box may find a smaller worst error.

    Returns
    -------
    FunctionGeneration

    Raises
    ------
    MechanismError : bad input (equal precision points, a range no four-bar can span, a
        function not finite on the range, an unparseable expression) or no valid design.
    """
    validate.option("mechanism", mechanism, _MECHANISMS)
    four_bar = mechanism == "four-bar"
    scale = validate.positive("ground" if four_bar else "crank", ground if four_bar else crank,
                              "m")  # fmt: skip
    n_eval = validate.integer("n_eval", n_eval, 16, 100_000)
    if min_transmission is not None:
        min_transmission = validate.angle("min_transmission", min_transmission)
    if pairs is not None:
        if function is not None:
            raise MechanismError("give either a function or precision pairs, not both")
        if optimize:
            raise MechanismError(
                "optimize needs a function: the min-max stage bounds the error over the whole "
                "range, which precision pairs alone do not define"
            )
        return _from_pairs(pairs, four_bar, scale, require_crank, n_eval)
    if function is None:
        raise MechanismError("give a function (and x=(x0, x1)) or pairs=[(phi, psi), ...]")
    f, text = _function(function)
    if x is None or np.ndim(x) != 1 or len(x) != 2:
        raise MechanismError(f"x must be (x0, x1), the range of x, got {x!r}")
    x0, x1 = (validate.number("x0", x[0]), validate.number("x1", x[1]))
    if x0 == x1:
        raise MechanismError(f"x0 and x1 must differ, got {x0} twice")
    if input_range is None or output_range is None:
        raise MechanismError("give input_range (rad) and output_range (rad, or m for a slider)")
    dphi = _range("input_range", input_range, 2 * np.pi)
    dout = _range("output_range", output_range, 2 * np.pi if four_bar else None,
                  "rad" if four_bar else "m")  # fmt: skip
    xp = _precision_x(spacing, points, x0, x1)
    _check_distinct(xp, "x", abs(x1 - x0))
    xd = np.linspace(x0, x1, n_eval)
    y_d = _values(f, xd, f"[{x0:.6g}, {x1:.6g}]")
    y_p = _values(f, xp, "the precision points")
    y0, y1 = float(y_d[0]), float(y_d[-1])
    if y0 == y1:
        raise MechanismError(
            f"f(x0) = f(x1) = {y0:.6g}: the output range cannot be mapped linearly onto y"
        )
    rel_in = lambda v: (v - x0) / (x1 - x0) * dphi  # noqa: E731
    rel_out = lambda y: (y - y0) / (y1 - y0) * dout  # noqa: E731
    phi0s, out0s = _phase_candidates(phases, four_bar)
    exact = xp.size == 3
    out_p = rel_out(y_p)

    def evaluate(rows, xs, ys):
        """Candidates ``rows`` evaluated on ``xs`` (ideal outputs ``ys``), in chunks."""
        parts = []
        for lo in range(0, rows.size, _CHUNK):
            r = rows[lo : lo + _CHUNK]
            phi = phi0s[r, None] + rel_in(xp)[None, :]
            phi_d = phi0s[r, None] + rel_in(xs)[None, :]
            out = out0s[r, None] + out_p[None, :]
            out_d = out0s[r, None] + rel_out(ys)[None, :]
            if four_bar:
                parts.append(_four_bar_candidates(phi, out, phi_d, out_d, scale, exact))
            else:
                parts.append(_slider_candidates(phi, out, phi_d, out_d, scale, exact))
        return _merge(parts)

    scanned = phi0s.size > 1
    if scanned:  # a coarse grid first, the chosen ones on the whole grid afterwards
        xs = np.linspace(x0, x1, min(n_eval, _SCAN_POINTS))
        order = _choose(
            evaluate(np.arange(phi0s.size), xs, _values(f, xs, "the range")),
            four_bar, scale, require_crank, min_transmission, True,
        )  # fmt: skip
    else:
        order = np.array([0])
    for i in order[:_SCAN_RETRIES]:
        cand = evaluate(np.array([i]), xd, y_d)
        if cand["ok"][0]:
            break
    if not cand["ok"][0]:
        _choose(cand, four_bar, scale, require_crank, min_transmission, False)
    if four_bar:
        (a, b, c), (sa, sc) = cand["lengths"], cand["shifts"]
        design = _four_bar(a[0], b[0], c[0], scale, cand["branch"][0])
        ph = (_turn(phi0s[i] + sa[0]), _turn(out0s[i] + sc[0]))
        pp = np.column_stack([ph[0] + rel_in(xp), ph[1] + out_p])
    else:
        from ..kinematics.slider_crank import SliderCrank

        L, e, s0 = cand["lengths"]
        design = SliderCrank(scale, float(L[0]), float(e[0]))
        ph = (_turn(phi0s[i]), float(s0[0]))
        pp = np.column_stack([ph[0] + rel_in(xp), s0[0] + out_p])
    rows = order[:_SOLUTIONS] if scanned else np.array([i])
    solutions = _solution_rows(evaluate(rows, xd, y_d), phi0s[rows], out0s[rows], four_bar, scale)
    err = np.asarray(cand["curves"][0], float)
    res = FunctionGeneration(
        design=design,
        mechanism=mechanism,
        method="exact" if exact else "least squares",
        phases=ph,
        spans=(dphi, dout),
        k=_k_of(design, ph),
        precision_points=pp,
        precision_x=xp,
        x=xd,
        error=err,
        error_y=err * (y1 - y0) / dout,
        max_error=float(np.max(np.abs(err))),
        min_transmission_angle=float(cand["mu"][0]),
        domain=(x0, x1),
        y_range=(y0, y1),
        function=text,
        solutions=solutions,
    )
    if optimize:
        return _optimize(res, f, rel_in, rel_out, dphi, require_crank, min_transmission,
                         starts, bounds)  # fmt: skip
    return res


def _solution_rows(cand, phi0s, out0s, four_bar, scale) -> tuple[dict, ...]:
    """The valid candidates as rows (SI, the design's convention), most accurate first."""
    rows = []
    for j in np.flatnonzero(cand["ok"]):
        if four_bar:
            (a, b, c), (sa, sc) = cand["lengths"], cand["shifts"]
            row = {
                "phi0": _turn(phi0s[j] + sa[j]), "psi0": _turn(out0s[j] + sc[j]),
                "crank": float(a[j]), "coupler": float(b[j]), "rocker": float(c[j]),
                "ground": float(scale), "branch": str(cand["branch"][j]),
            }  # fmt: skip
        else:
            L, e, s0 = cand["lengths"]
            row = {
                "phi0": _turn(phi0s[j]), "s0": float(s0[j]), "crank": float(scale),
                "rod": float(L[j]), "offset": float(e[j]),
            }  # fmt: skip
        row["max_error"] = float(np.max(np.abs(cand["curves"][j])))
        row["min_transmission_angle"] = float(cand["mu"][j])
        rows.append(row)
    unique = {}  # scanned phases half a turn apart can give one design twice
    for r in sorted(rows, key=lambda r: r["max_error"]):
        key = tuple(round(v, 9) if isinstance(v, float) else v for v in r.values())
        unique.setdefault(key, r)
    return tuple(unique.values())


def _phase_candidates(phases, four_bar):
    if phases is None:
        grid = np.radians(np.arange(0.0, 360.0, _SCAN_STEP))
        if not four_bar:
            return grid, np.zeros_like(grid)
        # phi0 + pi flips the signs of K1 and K3 (psi0 + pi: of K2 and K3): the same four-bar
        # with its crank (rocker) reflected, so half a turn of each covers every design
        half = grid[grid < np.pi]
        p, q = np.meshgrid(half, half, indexing="ij")
        return p.ravel(), q.ravel()
    ph = list(phases) if isinstance(phases, (list, tuple, np.ndarray)) else None
    if ph is None or not 1 <= len(ph) <= 2:
        raise MechanismError(f"phases must be (phi0, psi0) in rad, got {phases!r}")
    phi0 = validate.number("phases[0] (phi0)", ph[0], "rad")
    if not four_bar:
        if len(ph) == 2 and ph[1] is not None:
            raise MechanismError(
                "a slider-crank's s0 comes out of the solution: give phases=(phi0,)"
            )
        return np.array([phi0]), np.zeros(1)
    if len(ph) != 2:
        raise MechanismError(f"phases must be (phi0, psi0) in rad, got {phases!r}")
    return np.array([phi0]), np.array([validate.number("phases[1] (psi0)", ph[1], "rad")])


def _crank_turns(a, b, c, d):
    return (a + d < b + c) & (np.abs(d - a) > np.abs(b - c))


def _choose(cand, four_bar, scale, require_crank, min_transmission, scanned):
    ok = cand["ok"].copy()
    if four_bar:
        a, b, c = cand["lengths"]
        if require_crank:
            turns = np.where(ok, _crank_turns(a, b, c, scale), False)
            cand["reason"][ok & ~turns] = "its crank cannot make full turns (require_crank)"
            ok &= turns
        lengths = np.stack([a, b, c, np.full_like(a, scale)])
    else:
        L, e, _ = cand["lengths"]
        lengths = np.stack([L, np.full_like(L, scale)])
    if not scanned:
        if not ok[0]:
            raise MechanismError(f"no valid design for these phases: {cand['reason'][0]}")
        return np.array([0])
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.max(lengths, axis=0) / np.min(lengths, axis=0)
    good = ok & (ratio <= _MAX_RATIO)
    if min_transmission is not None:
        good &= cand["mu"] >= min_transmission
    if not good.any():
        raise MechanismError(
            f"no phases in a {_SCAN_STEP:g} deg scan give a design that assembles over the "
            f"range with links within a ratio of {_MAX_RATIO:g}"
            + (f" and transmission angles of at least {np.degrees(min_transmission):.4g} deg"
               if min_transmission is not None else "")
            + f" ({int(ok.sum())} of {ok.size} assemble); widen the limits or give phases"
        )  # fmt: skip
    idx = np.flatnonzero(good)
    return idx[np.argsort(cand["error"][idx], kind="stable")]


def _merge(parts):
    """One candidate dict from chunks of them."""
    out = {}
    for key, v in parts[0].items():
        if isinstance(v, tuple):
            out[key] = tuple(np.concatenate([p[key][j] for p in parts]) for j in range(len(v)))
        else:
            out[key] = np.concatenate([p[key] for p in parts])
    return out


def _four_bar(a, b, c, d, branch):
    from ..kinematics.four_bar import FourBar

    a, b, c = float(a), float(b), float(c)
    return FourBar(a, b, c, float(d), branch, bool(_crank_turns(a, b, c, d)))


def _k_of(design, phases):
    if hasattr(design, "coupler"):
        a, b, c, d = design.crank, design.coupler, design.rocker, design.ground
        return (d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c))
    r, L, e = design.crank, design.rod, design.offset
    s0 = phases[1]
    return (float(s0), float(e), float(s0 * s0 + r * r + e * e - L * L))


def _from_pairs(pairs, four_bar, scale, require_crank, n_eval):
    arr = np.asarray(validate.real("pairs", pairs), dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 3:
        raise MechanismError(
            f"pairs must be at least 3 rows (input angle, output), got shape {arr.shape}"
        )
    phi, out = arr[:, 0], arr[:, 1]
    _check_distinct(phi, "input angle", 2 * np.pi)
    exact = arr.shape[0] == 3
    lo, hi = float(phi.min()), float(phi.max())
    grid = np.linspace(lo, hi, n_eval)[None, :]
    if four_bar:
        # the range between the pairs is checked for assembly; its ideal is unknown (NaN)
        cand = _four_bar_candidates(phi[None], out[None], grid, np.nan * grid, scale, exact)
        if not cand["ok"][0]:
            raise MechanismError(f"no valid four-bar through these pairs: {cand['reason'][0]}")
        (a, b, c), (sa, sc) = cand["lengths"], cand["shifts"]
        if require_crank and not _crank_turns(a[0], b[0], c[0], scale):
            raise MechanismError("the four-bar through these pairs cannot make full turns")
        design = _four_bar(a[0], b[0], c[0], scale, cand["branch"][0])
        ang, target = phi + sa[0], out + sc[0]
        err = _wrap(design.motion(ang).links["rocker"].angle - target)
        mu = float(cand["mu"][0])
        phases = (float(ang[0]), float(target[0]))
    else:
        u = out - out[0]
        cand = _slider_candidates(phi[None], u[None], grid, np.nan * grid, scale, exact)
        if not cand["ok"][0]:
            raise MechanismError(f"no valid slider-crank through these pairs: {cand['reason'][0]}")
        L, e, s0 = cand["lengths"]
        from ..kinematics.slider_crank import SliderCrank

        design = SliderCrank(scale, float(L[0]), float(e[0]))
        ang, target = phi, s0[0] + u
        err = design.motion(ang).slider.position - target
        mu = float(cand["mu"][0])
        phases = (float(ang[0]), float(target[0]))
    order = np.argsort(ang)
    return FunctionGeneration(
        design=design,
        mechanism="four-bar" if four_bar else "slider-crank",
        method="exact" if exact else "least squares",
        phases=phases,
        spans=(float(hi - lo), float(np.ptp(target))),
        k=_k_of(design, phases),
        precision_points=np.column_stack([ang, target]),
        precision_x=None,
        x=ang[order],
        error=err[order],
        error_y=None,
        max_error=float(np.max(np.abs(err))),
        min_transmission_angle=mu,
    )


def _optimize(res, f, rel_in, rel_out, dphi, require_crank, min_transmission, starts, bounds):
    """The min-max stage from ``res`` (exact or least squares)."""
    from .function_minmax import minmax

    x0, x1 = res.domain

    def target(t):
        return rel_out(f(x0 + t / dphi * (x1 - x0)))

    start = res.generator()
    if require_crank and res.angular and not res.design.full_turn:
        raise MechanismError("require_crank: the start design's crank cannot make full turns")
    if min_transmission is not None:  # the start must be feasible
        min_transmission = min(min_transmission, res.min_transmission_angle * (1 - 1e-6))
    if bounds is not None and not isinstance(bounds, dict):
        raise MechanismError(f"bounds must be a dict {{name: (lo, hi)}}, got {bounds!r}")
    sol = minmax(start, target, bounds=bounds, min_transmission=min_transmission, starts=starts)
    if sol.design is None:
        return _replace(res, sol, res.design, res.phases, res.error, res.min_transmission_angle)
    g = sol.design
    t = rel_in(res.x)
    m = g.motion(t)
    e = g.output(m) - target(t)
    if res.angular:
        e = _wrap(e)
        design = _four_bar(g.crank, g.coupler, g.rocker, g.ground, g.branch)
        phases = (_turn(g.phi0), _turn(g.psi0))
    else:
        from ..kinematics.slider_crank import SliderCrank

        design = SliderCrank(float(g.crank), float(g.rod), float(g.offset))
        phases = (_turn(g.phi0), float(g.s0))
    tr = m.transmission_angle
    mu = float(np.min(np.minimum(tr, np.pi - tr)))
    return _replace(res, sol, design, phases, e, mu)


def _replace(res, sol, design, phases, err, mu):
    from dataclasses import replace

    scale = (res.y_range[1] - res.y_range[0]) / res.spans[1]
    tp = np.asarray(res.precision_x)
    x0, x1 = res.domain
    return replace(
        res,
        design=design,
        method="min-max",
        phases=phases,
        k=_k_of(design, phases),
        precision_points=np.column_stack(
            [
                phases[0] + (tp - x0) / (x1 - x0) * res.spans[0],
                res.precision_points[:, 1] - res.phases[1] + phases[1],
            ]
        ),  # fmt: skip
        error=np.asarray(err, float),
        error_y=np.asarray(err, float) * scale,
        max_error=float(np.max(np.abs(err))),
        min_transmission_angle=mu,
        start_max_error=res.max_error,
        start_error=res.error,
        solve=sol,
    )

"""Gearbox torque of a beam pumping unit, counterbalance and the permissible load diagram.

Sign conventions (SI: N, N m, m, rad; crank angle ``theta`` as in
:mod:`mechsynth.machines.pumping_unit.beam_unit`: from 12 o'clock in the direction of rotation)
-------------------------------------------------------------------------------------------
* Polished-rod load ``W`` (N) acts downward on the rod; a dynamometer card gives it against the
  polished-rod position (up from the bottom of the stroke).
* Structural unbalance ``SU`` (N): the force at the polished rod that holds the beam horizontal
  with the pitmans disconnected, positive when that force is downward (tail-heavy beam, which
  helps to lift the rods). It is taken constant over the stroke, as on the industry's forms.
* Counterbalance: crank counterweights whose moment about the crankshaft is ``M`` (N m, weight x
  arm of the whole set) with their centre of mass lagging the crank pin by the phase angle
  ``tau`` (rad), i.e. at crank angle ``theta - tau``. Their gravity torque in the direction of
  rotation is ``M sin(theta - tau)``.
* Net gearbox (crank) torque, positive when the gearbox drives the crank forwards:

      T(theta) = TF(theta) (W(theta) - SU) - M sin(theta - tau)
                 + J_crank * epsilon + (I_beam / A^2) TF(theta) a_PR(theta)

  The first term is virtual work (TF = d(PR)/d(theta)); the last two are the rotary inertia of
  the cranks and counterweights and the articulating inertia of the beam (``I_beam`` about the
  centre bearing; ``a_PR`` the polished-rod acceleration, including the crank-speed variation).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import MechanismError
from ...kinematics.mechanism import check_finite
from .beam_unit import BeamPumpingUnit

__all__ = [
    "DynamometerCard",
    "TorqueCurve",
    "Counterbalance",
    "net_torque",
    "torque_curve",
    "optimal_counterbalance",
    "scan_counterbalance",
    "permissible_load",
    "torque_factor_table",
    "GRAVITY",
]

GRAVITY = 9.80665


def _angles(theta):
    theta = np.asarray(theta, dtype=float)
    if theta.ndim != 1 or theta.size < 8 or not np.all(np.isfinite(theta)):
        raise MechanismError("theta must be a 1-D array of at least 8 finite crank angles (rad)")
    return theta


# ---------------------------------------------------------------------------------- cards
#: most (position, load) points of a card
MAX_CARD_POINTS = 100_000
#: a card's position may travel this much more than twice its stroke around the loop (noise)
CARD_TRAVEL_LIMIT = 1.5


@dataclass(frozen=True)
class DynamometerCard:
    """A surface dynamometer card: polished-rod load (N) against position (m), one closed loop
    in the order recorded.

    The card is split at its lowest and highest positions into the upstroke branch (rod rising)
    and the downstroke branch. :meth:`load_at` maps it onto the unit's crank angles: at each angle
    the load is interpolated in position on the branch that the rod's direction of motion selects
    (the torque factor's sign), with the card's stroke scaled to the unit's stroke.
    """

    position: np.ndarray
    load: np.ndarray
    source: str = ""

    def __post_init__(self):
        x = np.asarray(self.position, dtype=float).ravel()
        w = np.asarray(self.load, dtype=float).ravel()
        if x.size != w.size:
            raise MechanismError(
                f"card: {x.size} positions but {w.size} loads; give (position, load) pairs"
            )
        if x.size < 8:
            raise MechanismError(f"card: need at least 8 (position, load) points, got {x.size}")
        for name, v in (("position", x), ("load", w)):
            bad = ~np.isfinite(v)
            if np.any(bad):
                raise MechanismError(f"card: {name} {int(np.argmax(bad)) + 1} is not finite")
        if x.size > MAX_CARD_POINTS:
            raise MechanismError(
                f"card: {x.size} points; a card has at most {MAX_CARD_POINTS} (resample it)"
            )
        if not np.ptp(x) > 0:
            raise MechanismError("card: the positions do not move (zero stroke)")
        if np.any(w < 0.0):
            i = int(np.argmax(w < 0.0))
            raise MechanismError(
                f"card: load {i + 1} is negative ({w[i]:.6g} N): a polished-rod load is the "
                "rod string's tension (check the sign and the columns: position, load)"
            )
        # one closed loop: the rod goes up once and down once, so the position's total
        # variation around the loop is twice the stroke (shuffled rows give far more)
        travel = float(np.sum(np.abs(np.diff(np.append(x, x[0])))))
        if travel > CARD_TRAVEL_LIMIT * 2.0 * np.ptp(x):
            raise MechanismError(
                f"card: the positions go up and down {travel / (2 * np.ptp(x)):.3g} times "
                "around the loop, not once: the rows are not one loop in recorded order "
                "(shuffled or sorted?)"
            )
        # the pump lifts on the upstroke: the loop encloses positive work, sum W dx > 0
        work = float(np.sum(np.diff(np.append(x, x[0])) * (w + np.roll(w, -1)) / 2.0))
        if work < 0.0:
            raise MechanismError(
                f"card: the loop runs backwards (net work {work:.6g} J < 0: the downstroke "
                "carries more load than the upstroke); are the rows in reverse order?"
            )
        object.__setattr__(self, "position", x)
        object.__setattr__(self, "load", w)

    @classmethod
    def from_csv(cls, path, position_scale=1.0, load_scale=1.0) -> DynamometerCard:
        """Read a card from a CSV file of ``position, load`` rows (a header line is allowed).

        ``position_scale`` and ``load_scale`` convert the file's units to m and N (e.g.
        ``0.0254`` and ``4.4482216`` for inches and pounds)."""
        from ...fileio import read_text

        text, path = read_text(path, "card")
        rows = []
        for i, row in enumerate(csv.reader(text.splitlines())):
            cells = [c.strip() for c in row if c.strip()]
            if not cells or cells[0].startswith("#"):
                continue
            try:
                values = [float(c) for c in cells]
            except ValueError as exc:
                if not rows and i == 0:
                    continue  # header
                raise MechanismError(
                    f"{path}: line {i + 1}: expected two numbers, got {row!r}"
                ) from exc
            if len(values) != 2:
                raise MechanismError(f"{path}: line {i + 1}: expected position, load; got {row!r}")
            rows.append(values)
        if not rows:
            raise MechanismError(f"{path}: no (position, load) rows")
        data = np.asarray(rows)
        return cls(data[:, 0] * position_scale, data[:, 1] * load_scale, str(path))

    @property
    def stroke(self) -> float:
        return float(np.ptp(self.position))

    def branches(self):
        """``(up, down)``: each a pair of arrays (position from the bottom, load), sorted by
        position. The loop is rolled to start at its lowest point; the lowest and highest points
        count to the upstroke."""
        x, w = self.position - self.position.min(), self.load
        start = int(np.argmin(x))
        x, w = np.roll(x, -start), np.roll(w, -start)
        top = int(np.argmax(x))
        up = (x[: top + 1], w[: top + 1])
        # the loop's top and bottom points belong to the upstroke branch; the downstroke branch
        # holds the points strictly after the top (np.interp holds its end values beyond them)
        down = (x[top + 1 :], w[top + 1 :])
        if down[0].size < 2 or up[0].size < 2:
            raise MechanismError(
                "card: need at least two points on each of the up and down strokes"
            )
        out = []
        for bx, bw in (up, down):
            order = np.argsort(bx, kind="stable")
            out.append((bx[order], bw[order]))
        return out[0], out[1]

    def load_at(self, unit: BeamPumpingUnit, theta) -> np.ndarray:
        """Polished-rod load (N) at the unit's crank angles ``theta``."""
        theta = np.asarray(theta, dtype=float)
        return self.load_on(unit.motion(theta), unit.stroke)

    def load_on(self, motion, stroke) -> np.ndarray:
        """Polished-rod load (N) along a unit's ``motion`` (anything with ``polished_rod`` and
        ``torque_factor``) of the given ``stroke`` (m; an array for a batch of designs)."""
        frac = np.asarray(motion.polished_rod.position) / np.asarray(stroke, dtype=float)
        x = frac * self.stroke
        (xu, wu), (xd, wd) = self.branches()
        rising = np.asarray(motion.torque_factor) >= 0.0
        return np.where(rising, np.interp(x, xu, wu), np.interp(x, xd, wd))


# ---------------------------------------------------------------------------------- torque
@dataclass(frozen=True)
class Counterbalance:
    """Crank counterbalance: moment ``moment`` (N m) and phase angle ``phase`` (rad, the
    counterweights lag the crank pin by it)."""

    moment: float
    phase: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "moment", check_finite("counterbalance moment", self.moment))
        object.__setattr__(self, "phase", check_finite("counterbalance phase", self.phase))

    def torque(self, theta):
        """The counterweights' gravity torque in the direction of rotation (N m)."""
        return self.moment * np.sin(np.asarray(theta, dtype=float) - self.phase)


@dataclass(frozen=True)
class TorqueCurve:
    """Gearbox torque over the cycle and its parts (arrays over ``theta``; N m, N, m/rad).

    Attributes
    ----------
    theta, position, torque_factor, load : crank angle, polished-rod position, TF, rod load.
    well : ``TF (W - SU)``; counterbalance : ``M sin(theta - tau)``; inertia : rotary +
    articulating; net : ``well - counterbalance + inertia``.
    """

    theta: np.ndarray
    position: np.ndarray
    torque_factor: np.ndarray
    load: np.ndarray
    well: np.ndarray
    counterbalance: np.ndarray
    inertia: np.ndarray
    net: np.ndarray
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def peak(self) -> float:
        """Largest |net torque| (N m) over the samples."""
        return float(np.max(np.abs(self.net)))

    def to_dict(self) -> dict[str, Any]:
        return {
            "peak_net_torque": self.peak,
            "max_net_torque": float(self.net.max()),
            "min_net_torque": float(self.net.min()),
            "peak_well_torque": float(np.max(np.abs(self.well))),
            **self.info,
        }

    def plot(self, ax=None, scale=1.0, unit="N m"):
        """Plot the net torque and its parts against the crank angle from 12 o'clock (deg), the
        legend below the axes; ``scale`` converts N m into ``unit``. Returns the figure."""
        import matplotlib.pyplot as plt

        from ...plotting import PALETTE, crank_axis, style

        with style():
            if ax is None:
                fig, ax = plt.subplots(figsize=(7.5, 4.8), layout="constrained")
            x = np.rad2deg(self.theta)
            ax.plot(x, self.well * scale, "--", color=PALETTE[4], label="well load TF(W - SU)")
            ax.plot(x, -self.counterbalance * scale, ":", color=PALETTE[5], label="counterbalance")
            if np.any(self.inertia):
                ax.plot(x, self.inertia * scale, "-.", color=PALETTE[3], label="inertia")
            ax.plot(x, self.net * scale, "k-", lw=2, label="net")
            ax.axhline(0.0, color="0.4", lw=0.6)
            crank_axis(ax, "crank angle θ from 12 o'clock in the direction of rotation")
            ax.set_ylabel(f"gearbox torque, {unit}")
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=4)
        return ax.figure


def net_torque(tf, load, structural_unbalance=0.0, counterbalance=None, theta=None):
    """``TF (W - SU) - M sin(theta - tau)`` for arrays (no inertia)."""
    t = np.asarray(tf, dtype=float) * (np.asarray(load, dtype=float) - structural_unbalance)
    if counterbalance is not None:
        t = t - counterbalance.torque(theta)
    return t


def torque_curve(
    unit: BeamPumpingUnit,
    theta,
    load,
    structural_unbalance=0.0,
    counterbalance: Counterbalance | None = None,
    speed=None,
    epsilon=0.0,
    beam_inertia=0.0,
    crank_inertia=0.0,
) -> TorqueCurve:
    """Gearbox torque of ``unit`` over crank angles ``theta``.

    Parameters
    ----------
    load : polished-rod load (N): a number, an array over ``theta``, or a
        :class:`DynamometerCard`.
    structural_unbalance : SU (N), see the module notes.
    counterbalance : :class:`Counterbalance` or None.
    speed, epsilon : crank speed (rad/s) and acceleration (rad/s^2), numbers or arrays over
        ``theta``; needed only with inertia.
    beam_inertia : moment of inertia (kg m^2) of the beam, horsehead and equalizer about the
        centre bearing (articulating inertia).
    crank_inertia : moment of inertia (kg m^2) of cranks and counterweights about the crankshaft
        (rotary inertia).
    """
    theta = _angles(theta)
    su = check_finite("structural_unbalance", structural_unbalance)
    jb = check_finite("beam_inertia", beam_inertia)
    jc = check_finite("crank_inertia", crank_inertia)
    if jb < 0 or jc < 0:
        raise MechanismError(f"inertias must be >= 0, got beam {jb}, crank {jc}")
    if isinstance(load, DynamometerCard):
        w = load.load_at(unit, theta)
    else:
        w = np.broadcast_to(np.asarray(check_finite("load", load), dtype=float), theta.shape)
    if (jb or jc) and speed is None:
        raise MechanismError("inertia torques need the crank speed (speed=...)")
    m = unit.motion(theta, speed=speed, epsilon=epsilon if speed is not None else 0.0)
    tf = np.asarray(m.torque_factor, dtype=float)
    well = tf * (w - su)
    cb = np.zeros_like(theta) if counterbalance is None else counterbalance.torque(theta)
    inertia = np.zeros_like(theta)
    if jb:
        inertia = inertia + jb / float(unit.front_arm) ** 2 * tf * m.polished_rod.acceleration
    if jc:
        inertia = inertia + jc * np.broadcast_to(np.asarray(m.epsilon, dtype=float), theta.shape)
    info = {}
    if counterbalance is not None:
        info = {"counterbalance_moment": counterbalance.moment, "phase": counterbalance.phase}
    return TorqueCurve(
        theta,
        np.asarray(m.polished_rod.position, dtype=float),
        tf,
        np.asarray(w, dtype=float),
        well,
        cb,
        inertia,
        well - cb + inertia,
        info,
    )


@dataclass(frozen=True)
class CounterbalanceResult:
    """Optimal counterbalance: ``counterbalance``, the peak net torque it leaves (N m), the solver
    status and the scan cross-check."""

    counterbalance: Counterbalance
    peak_torque: float
    status: str
    success: bool
    scan_peak_torque: float | None = None
    scan_counterbalance: Counterbalance | None = None

    def to_dict(self):
        d = {
            "counterbalance_moment": self.counterbalance.moment,
            "phase": self.counterbalance.phase,
            "peak_net_torque": self.peak_torque,
            "status": self.status,
            "success": self.success,
        }
        if self.scan_counterbalance is not None:
            d["scan_counterbalance_moment"] = self.scan_counterbalance.moment
            d["scan_phase"] = self.scan_counterbalance.phase
            d["scan_peak_net_torque"] = self.scan_peak_torque
        return d


def optimal_counterbalance(
    theta, base_torque, phase=0.0, free_phase=False, cross_check=True
) -> CounterbalanceResult:
    """The counterbalance moment that minimizes the peak |net torque| over ``theta``, as a linear
    program (cvxpy): minimize ``t`` subject to ``-t <= T0(theta_i) - M sin(theta_i - tau) <= t``.

    Parameters
    ----------
    theta : crank angles (rad).
    base_torque : the torque without counterbalance at those angles (N m): ``TF (W - SU)`` plus
        any inertia torque (:attr:`TorqueCurve.well` + :attr:`TorqueCurve.inertia`).
    phase : the fixed phase angle tau (rad) when ``free_phase`` is False.
    free_phase : optimize the phase too; ``M sin(theta - tau) = a sin(theta) - b cos(theta)``
        with ``a = M cos(tau)``, ``b = M sin(tau)`` is still linear in ``(a, b)``.
    cross_check : also scan the moment (and the phase) on a grid and report it.

    Notes
    -----
    With a fixed phase the moment is not bounded below: a negative optimum means the weights
    belong on the other side of the crank (phase + 180 deg). With a free phase the moment is
    returned positive with its phase in (-pi, pi].
    """
    import cvxpy as cp

    theta = _angles(theta)
    t0 = np.asarray(base_torque, dtype=float)
    if t0.shape != theta.shape or not np.all(np.isfinite(t0)):
        raise MechanismError("base_torque must be finite and have the shape of theta")
    phase = check_finite("phase", phase)
    s, c = np.sin(theta), np.cos(theta)
    t = cp.Variable()
    if free_phase:
        a, b = cp.Variable(), cp.Variable()
        net = t0 - (a * s - b * c)
    else:
        mvar = cp.Variable()
        net = t0 - mvar * np.sin(theta - phase)
    prob = cp.Problem(cp.Minimize(t), [net <= t, -net <= t])
    try:
        prob.solve()
    except cp.error.SolverError:  # pragma: no cover - solver installation problem
        return CounterbalanceResult(Counterbalance(0.0, phase), np.nan, "solver_failed", False)
    status = prob.status
    if status not in ("optimal", "optimal_inaccurate") or t.value is None:
        return CounterbalanceResult(Counterbalance(0.0, phase), float("inf"), status, False)
    if free_phase:
        av, bv = float(a.value), float(b.value)
        cb = Counterbalance(float(np.hypot(av, bv)), float(np.arctan2(bv, av)))
    else:
        cb = Counterbalance(float(mvar.value), phase)
    peak = float(np.max(np.abs(t0 - cb.torque(theta))))
    res = CounterbalanceResult(cb, peak, "optimal", True)
    if cross_check:
        scb, speak = scan_counterbalance(theta, t0, phase=None if free_phase else phase)
        res = CounterbalanceResult(cb, peak, "optimal", True, speak, scb)
    return res


def scan_counterbalance(theta, base_torque, phase=0.0, n=401, zooms=8):
    """Brute-force cross-check of :func:`optimal_counterbalance`: the peak |net torque| on a grid
    of moments (fixed ``phase``), or of ``(a, b) = (M cos tau, M sin tau)`` when ``phase`` is
    None (the peak is convex in them), zoomed ``zooms`` times around the best grid point.
    Returns ``(Counterbalance, peak)``."""
    theta = _angles(theta)
    t0 = np.asarray(base_torque, dtype=float)
    span = 2.0 * float(np.max(np.abs(t0))) + 1e-300
    s, c = np.sin(theta), np.cos(theta)

    def peaks_ab(a, b):
        return np.max(np.abs(t0 - (a[..., None] * s - b[..., None] * c)), axis=-1)

    if phase is not None:
        u = np.sin(theta - phase)
        lo, hi = 0.0, span
        for _ in range(zooms):
            moments = np.linspace(lo, hi, n)
            pk = np.max(np.abs(t0 - moments[:, None] * u), axis=-1)
            k = int(np.argmin(pk))
            step = (hi - lo) / (n - 1)
            lo, hi = max(moments[k] - 4 * step, 0.0), moments[k] + 4 * step
        return Counterbalance(float(moments[k]), float(phase)), float(pk[k])
    m = int(np.sqrt(n * 36))  # a 2-D grid of about 120 x 120
    ca, cb, half = 0.0, 0.0, span
    for _ in range(zooms):
        grid = np.linspace(-half, half, m)
        a, b = np.meshgrid(ca + grid, cb + grid)
        pk = peaks_ab(a, b)
        k = np.unravel_index(int(np.argmin(pk)), pk.shape)
        ca, cb = float(a[k]), float(b[k])
        half = 8.0 * half / (m - 1)
    return Counterbalance(float(np.hypot(ca, cb)), float(np.arctan2(cb, ca))), float(pk[k])


# ---------------------------------------------------------------------------------- ratings
def permissible_load(
    unit: BeamPumpingUnit,
    theta,
    rating,
    counterbalance: Counterbalance | None = None,
    structural_unbalance=0.0,
    tf_min=1e-6,
):
    """Permissible load diagram for a gearbox ``rating`` (N m): at each crank angle the range of
    polished-rod loads for which ``|net torque| <= rating``.

    Returns a dict of arrays over ``theta``: ``position`` (m), ``torque_factor``, ``upper`` and
    ``lower`` (N). Where ``|TF| < tf_min * stroke`` (at the dead centres) the load is not
    limited by the gearbox: ``upper = +inf`` and ``lower = -inf`` there.
    """
    theta = _angles(theta)
    rating = check_finite("rating", rating)
    if not rating > 0:
        raise MechanismError(f"rating must be a positive torque (N m), got {rating}")
    su = check_finite("structural_unbalance", structural_unbalance)
    m = unit.motion(theta)
    tf = np.asarray(m.torque_factor, dtype=float)
    cb = np.zeros_like(theta) if counterbalance is None else counterbalance.torque(theta)
    small = np.abs(tf) < tf_min * float(unit.stroke)
    safe = np.where(small, 1.0, tf)
    w1 = su + (rating + cb) / safe
    w2 = su + (-rating + cb) / safe
    upper = np.where(small, np.inf, np.maximum(w1, w2))
    lower = np.where(small, -np.inf, np.minimum(w1, w2))
    return {
        "theta": theta,
        "position": np.asarray(m.polished_rod.position, dtype=float),
        "torque_factor": tf,
        "upper": upper,
        "lower": lower,
    }


def torque_factor_table(unit: BeamPumpingUnit, step_deg=15.0):
    """The industry's torque-factor table: every ``step_deg`` degrees of crank angle, the torque
    factor (m/rad = torque per unit load), the polished-rod position (m and fraction of stroke)
    and the beam angle (rad from horizontal, horsehead up positive).

    Returns a list of dicts, one per crank angle from 0 (12 o'clock) to 360 - step.
    """
    step = check_finite("step_deg", step_deg)
    if not 0 < step <= 90 or abs(360.0 / step - round(360.0 / step)) > 1e-9:
        raise MechanismError(f"step_deg must divide 360 and lie in (0, 90], got {step_deg}")
    deg = np.arange(0.0, 360.0, step)
    theta = np.deg2rad(deg)
    m = unit.motion(theta)
    pos = np.asarray(m.polished_rod.position, dtype=float)
    rows = []
    for i, d in enumerate(deg):
        rows.append(
            {
                "crank_angle_deg": float(d),
                "torque_factor": float(m.torque_factor[i]),
                "position": float(pos[i]),
                "position_fraction": float(pos[i] / unit.stroke),
                "beam_angle_deg": float(np.rad2deg(m.beam.angle[i])),
            }
        )
    return rows

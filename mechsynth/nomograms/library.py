"""Built-in nomograms of the library's models.

Each builder takes its declared options (:mod:`mechsynth.options`; ``mechsynth nomogram NAME
--set help``) and returns a :class:`~mechsynth.nomograms.nomogram.Nomogram` whose accuracy report
compares its readings with the model it stands for -- ``SliderCrank``, ``FourBar``, the pumping
unit's torque -- not with the formula it was built from:

============================ ==================================================================
``slider-crank``             stroke / crank and time ratio of an offset slider-crank over
                             rod / crank and offset / crank (fitted)
``slider-crank-acceleration`` peak slider acceleration from rod / crank, offset / crank, crank
                             and speed (compound: a fitted block and a parallel chain)
``extreme-velocity``         paper 004: the extreme slider velocity analogs per unit crank over
                             b/a and e/a (fitted; maximum on the line, minimum on a curve)
``four-bar``                 crank-rocker design: rocker swing and time ratio -> the link ratios
                             of the best minimum transmission angle (fitted)
``pump-displacement``        pump displacement from plunger diameter, stroke and strokes per
                             minute (parallel chain of logarithmic scales, oilfield units)
``pump-torque``              gearbox torque from torque factor and net load (Z chart)
============================ ==================================================================
"""

from __future__ import annotations

import numpy as np

from ..errors import MechanismError
from ..options import Option, Options
from .forms import Var, parallel, z_chart
from .nomogram import Nomogram

__all__ = [
    "NOMOGRAMS",
    "build",
    "options_of",
    "preferred_units",
    "displacement_constant",
    "crank_rocker_design",
]

def _span(name, default, help, unit="", minimum=None, maximum=None, positive=False):
    """A ``LOW:HIGH`` option; ``positive``: both ends above ``minimum`` (0 by default)."""
    if positive and minimum is None:
        minimum = 0.0
    return Option(name, default, help, unit=unit, kind="span", minimum=minimum, maximum=maximum,
                  exclusive=positive)


# ---------------------------------------------------------------------------- slider-crank
def _slider_crank_ratios(rod_crank, offset_crank):
    from ..kinematics import SliderCrank

    sc = SliderCrank(crank=1.0, rod=rod_crank, offset=offset_crank)
    return sc.stroke, sc.time_ratio


def slider_crank(rod_crank=(2.5, 6.0), offset_crank=(0.05, 1.0), degree=6, paper="a4"):
    """Stroke / crank and time ratio of an offset slider-crank (``SliderCrank(crank=1, rod,
    offset)``) over rod / crank and offset / crank: a fitted chart, the stroke ratio on the
    straight line graduated by ``log(stroke / crank - 2)`` (it grows from 2 about as
    ``(e/a)^2 / ((b/a)^2 - 1)``), the time ratio on a curve."""
    from .fitting import fitted

    lo, hi = offset_crank
    if rod_crank[0] <= 1.0 + hi + 0.05:
        raise MechanismError(
            f"slider-crank nomogram: rod/crank from {rod_crank[0]:g} needs offset/crank below "
            f"{rod_crank[0] - 1.05:g} (rod > crank + offset for a full turn), got {hi:g}"
        )
    if lo <= 0.0:
        raise MechanismError(
            "slider-crank nomogram: offset/crank must start above 0 (a centric slider-crank's "
            f"stroke is 2 crank and its time ratio 1), got {lo:g}"
        )

    def stroke(rod_crank, offset_crank):
        return _slider_crank_ratios(rod_crank, offset_crank)[0]

    def time_ratio(rod_crank, offset_crank):
        return _slider_crank_ratios(rod_crank, offset_crank)[1]

    return fitted(
        _slider_crank_ratios,
        Var("rod_crank", tuple(rod_crank), title="rod / crank"),
        Var("offset_crank", tuple(offset_crank), title="offset / crank"),
        [
            Var("stroke_crank", None, lambda k: np.log(k - 2.0), title="stroke / crank"),
            Var("time_ratio", None, lambda q: np.log(q - 1.0), title="time ratio"),
        ],
        degree=degree,
        model={"stroke_crank": stroke, "time_ratio": time_ratio},
        title="Offset slider-crank: stroke and time ratio",
        relation="stroke = crank x (stroke / crank) of SliderCrank(crank, rod, offset); time "
        "ratio = slower stroke / quicker stroke at constant crank speed",
        paper=paper,
        notes=["Fitted chart (curved scales): its reading error against the model is printed "
               "above. Stroke = crank x the reading."],
    )


def _peak_acceleration_analog(rod_crank, offset_crank, crank=1.0, angles=3600):
    """max |d2 x_B / d phi2| (m/rad^2) of ``SliderCrank(crank, rod_crank crank, offset_crank
    crank)`` on ``angles`` crank angles (relative error of the sampled peak below 1e-6)."""
    from ..kinematics import SliderCrank
    from ..units import cycle

    r = np.asarray(crank, dtype=float)
    lam, eps = np.broadcast_arrays(np.asarray(rod_crank, float), np.asarray(offset_crank, float))
    r = np.broadcast_to(r, lam.shape)
    phi = cycle(angles)
    out = np.empty(lam.shape)
    flat = [x.ravel() for x in (lam, eps, r)]
    res = out.ravel()
    step = max(1, 2_000_000 // angles)
    for i in range(0, len(flat[0]), step):  # chunks bound the memory of the batch
        sl = slice(i, i + step)
        sc = SliderCrank(crank=flat[2][sl, None], rod=(flat[0] * flat[2])[sl, None],
                         offset=(flat[1] * flat[2])[sl, None])
        res[sl] = np.abs(sc.motion(phi).slider.acceleration).max(axis=-1)
    return res.reshape(lam.shape)


def slider_crank_acceleration(rod_crank=(2.5, 6.0), offset_crank=(0.0, 1.0),
                              crank=(0.02, 0.2), rpm=(100.0, 3000.0), degree=6, paper="a4"):
    """Peak slider acceleration ``crank omega^2 A(rod/crank, offset/crank)``: a compound chart,
    the fitted block of A (its line an unlabelled turning axis graduated by log A) chained
    with the crank and the speed on logarithmic parallel scales."""
    from .fitting import fitted_chain

    if rod_crank[0] <= 1.0 + offset_crank[1] + 0.05:
        raise MechanismError(
            f"slider-crank-acceleration: rod/crank from {rod_crank[0]:g} needs offset/crank "
            f"below {rod_crank[0] - 1.05:g}, got {offset_crank[1]:g}"
        )
    w = 2.0 * np.pi / 60.0
    grid = np.meshgrid(np.linspace(*rod_crank, 9), np.linspace(*offset_crank, 9))
    A = _peak_acceleration_analog(*grid)
    a_lo = float(A.min()) * crank[0] * (rpm[0] * w) ** 2 * 0.99
    a_hi = float(A.max()) * crank[1] * (rpm[1] * w) ** 2 * 1.01

    def model(rod_crank, offset_crank, crank, speed):
        return _peak_acceleration_analog(rod_crank, offset_crank, crank) * np.asarray(speed) ** 2

    return fitted_chain(
        lambda lam, eps: _peak_acceleration_analog(lam, eps, angles=1440),
        Var("rod_crank", tuple(rod_crank), title="rod / crank"),
        Var("offset_crank", tuple(offset_crank), title="offset / crank"),
        Var("A", None, np.log, title="A"),
        [
            Var("crank", tuple(crank), np.log, title="crank", unit="m"),
            Var("speed", (rpm[0] * w, rpm[1] * w), lambda s: 2.0 * np.log(s), title="speed",
                shown={"*": (w, "rpm")}),
        ],
        Var("acceleration", (a_lo, a_hi), np.log, title="peak acceleration", unit="m/s^2"),
        degree=degree,
        model=model,
        title="Offset slider-crank: peak slider acceleration",
        relation="a_peak = crank omega^2 A(rod/crank, offset/crank), A = max |x_B''| / crank of "
        "SliderCrank over a turn",
        paper=paper,
        example={"rod_crank": 4.0, "offset_crank": 0.5, "crank": 0.05, "speed": 600 * w},
        notes=["Compound chart: rod / crank and offset / crank give A on the unlabelled "
               "turning axis (fitted block); from there the crank, then the speed."],
    )


# ---------------------------------------------------------------------------- paper 004
def _extremes(rod_crank, offset_crank):
    """Paper 004's extreme velocity analogs per unit crank: the paper's offset e0 = e/a is
    ``-offset / crank`` in the model's convention."""
    from ..kinematics import SliderCrank

    ev = SliderCrank(crank=1.0, rod=rod_crank, offset=-np.asarray(offset_crank)).extreme_velocity()
    return ev.maximum.value, ev.minimum.value


def extreme_velocity(rod_crank=(2.0, 6.0), offset_crank=(0.0, 0.8), extreme="max", degree=6,
                     paper="a4"):
    """Paper 004's chart: the maximum (or minimum) slider velocity analog ``dx_B / dphi`` per
    unit crank (exact, from ``SliderCrank.extreme_velocity``) over b/a and e/a (the paper's
    offset e0 >= 0). The two extremes are separate charts: they are two functions of the same
    inputs, and one set of isopleths cannot carry both."""
    from .fitting import fitted

    if rod_crank[0] < 1.0 + offset_crank[1] + 0.05:
        raise MechanismError(
            f"extreme-velocity: b/a from {rod_crank[0]:g} needs e/a below "
            f"{rod_crank[0] - 1.05:g} (paper 004's chart margin 0.05), got {offset_crank[1]:g}"
        )
    k = {"max": 0, "min": 1}[extreme]
    word = {"max": "maximum", "min": "minimum"}[extreme]

    def f(rod_crank, offset_crank):
        return _extremes(rod_crank, offset_crank)[k]

    return fitted(
        f,
        Var("rod_crank", tuple(rod_crank), title="b / a"),
        Var("offset_crank", tuple(offset_crank), title="e / a"),
        [Var(f"v_{extreme}", None, title=f"{word} velocity analog / a")],
        degree=degree,
        title=f"Paper 004: {word} slider velocity",
        relation=f"{word} of dx_B / dphi over a turn per unit crank (the exact degree-6 "
        "polynomial of paper 004, corrected), offset e0 = e/a as in the paper",
        paper=paper,
        notes=["Fitted chart (curved scales); the paper's s0 = -dx_B/dphi swaps the names of "
               "maximum and minimum. Velocity = crank x crank speed x the reading."],
    )


# ---------------------------------------------------------------------------- four-bar
def crank_rocker_design(swing, time_ratio, max_ratio=5.0, n=1201):
    """The crank-rocker of rocker swing ``swing`` (rad) and time ratio ``time_ratio`` with the
    best minimum transmission angle, links per unit ground.

    The classical construction: rocker 1 about the origin, its two limit positions ``B1, B2``
    (a chord of length ``2 sin(swing / 2)``); the crank pivot sees the chord under
    ``theta = pi (Q - 1) / (Q + 1)``, on either side, at an angle ``beta`` of the chord at B1
    (law of sines: ``|O2 B1| = L sin(theta + beta) / sin(theta)``, ``|O2 B2| = L sin(beta) /
    sin(theta)``), so crank and coupler are half the difference and half the sum of those.
    ``n`` values of beta per side; the candidates must be Grashof crank-rockers whose swing and
    time ratio are the ones asked (checked from their dead centres), the longest link at most
    ``max_ratio`` cranks. Returns ``(mu_min, crank, coupler, rocker)`` (rad, per unit ground).
    """
    psi = np.asarray(swing, dtype=float)[..., None]
    Q = np.asarray(time_ratio, dtype=float)[..., None]
    th = np.pi * (Q - 1.0) / (Q + 1.0)
    L = 2.0 * np.sin(psi / 2.0)
    beta = np.linspace(0.0, 1.0, n + 2)[1:-1] * (np.pi - th)
    p = L * np.sin(th + beta) / np.sin(th)
    q = L * np.sin(beta) / np.sin(th)
    a, b = np.abs(q - p) / 2.0, (q + p) / 2.0
    best = None
    for side in (1.0, -1.0):
        d = np.hypot(np.sin(psi / 2.0) - p * np.cos(beta),
                     np.cos(psi / 2.0) - side * p * np.sin(beta))
        with np.errstate(invalid="ignore", divide="ignore"):
            cos1 = (b * b + 1.0 - (d - a) ** 2) / (2.0 * b)
            cos2 = (b * b + 1.0 - (d + a) ** 2) / (2.0 * b)
            # dead centres: rocker angles and crank directions from the triangles (d, 1, b -+ a)
            g1 = np.arccos((d * d + 1.0 - (b - a) ** 2) / (2.0 * d))
            g2 = np.arccos((d * d + 1.0 - (b + a) ** 2) / (2.0 * d))
            t1 = np.arccos((d * d + (b - a) ** 2 - 1.0) / (2.0 * d * (b - a)))
            t2 = np.arccos((d * d + (b + a) ** 2 - 1.0) / (2.0 * d * (b + a)))
        mu1, mu2 = np.arccos(np.clip(cos1, -1, 1)), np.arccos(np.clip(cos2, -1, 1))
        mu = np.minimum(np.minimum(mu1, np.pi - mu1), np.minimum(mu2, np.pi - mu2))
        longest = np.maximum(np.maximum(b, 1.0), d)
        ok = (np.abs(cos1) <= 1) & (np.abs(cos2) <= 1)
        ok &= (a < np.minimum(np.minimum(b, 1.0), d)) & (2.0 * (a + longest) <= a + b + 1.0 + d)
        ok &= (longest <= max_ratio * a) & (np.abs(np.abs(g1 - g2) - psi) < 1e-7)
        ok &= np.abs(np.abs(t1 - t2) - th) < 1e-7
        mu = np.where(ok, mu, -1.0)
        k = mu.argmax(axis=-1)[..., None]
        with np.errstate(invalid="ignore", divide="ignore"):  # d = 0 only where not ok
            cand = [np.take_along_axis(x, k, -1)[..., 0] for x in (mu, a / d, b / d, 1.0 / d)]
        if best is None:
            best = cand
        else:
            take = cand[0] > best[0]
            best = [np.where(take, x, y) for x, y in zip(cand, best, strict=True)]
    if np.any(best[0] < 0):
        raise MechanismError("crank_rocker_design: no crank-rocker for some swing and time "
                             "ratio of the range (try a smaller swing or time ratio)")
    return tuple(best)


FOUR_BAR_OUTPUTS = {
    "transmission": (0, "best minimum transmission angle", "rad"),
    "crank": (1, "crank / ground", ""),
    "coupler": (2, "coupler / ground", ""),
    "rocker": (3, "rocker / ground", ""),
}


def four_bar(swing_deg=(40.0, 90.0), time_ratio=(1.1, 1.5), read="crank", degree=6,
             paper="a4"):
    """Crank-rocker design chart: rocker swing and time ratio -> the link ratio ``read``
    (crank, coupler or rocker per unit ground) or the minimum transmission angle of the
    crank-rocker with the best minimum transmission angle (:func:`crank_rocker_design`); one
    fitted chart per quantity (one set of isopleths cannot carry four functions)."""
    from .fitting import fitted

    k, title, unit = FOUR_BAR_OUTPUTS[read]
    sw = (np.radians(swing_deg[0]), np.radians(swing_deg[1]))

    def f(swing, time_ratio):
        return crank_rocker_design(swing, time_ratio)[k]

    return fitted(
        f,
        Var("swing", sw, title="rocker swing", unit="rad"),
        Var("time_ratio", tuple(time_ratio), title="time ratio"),
        [Var(read, None, title=title, unit=unit)],
        degree=degree,
        title=f"Crank-rocker design: {title}",
        relation="the crank-rocker of the given rocker swing and time ratio whose minimum "
        "transmission angle is largest (links per unit ground, longest link at most 5 cranks)",
        paper=paper,
        notes=["Fitted chart. Build the design as FourBar(crank, coupler, rocker, ground=1) "
               "from the four charts (--set read=crank|coupler|rocker|transmission)."],
    )


# ---------------------------------------------------------------------------- pumping unit
#: 1 bbl = 42 US gal x 231 in^3; a day has 1440 minutes
BARREL_IN3 = 42.0 * 231.0
BARREL_M3 = BARREL_IN3 * 0.0254**3


def displacement_constant() -> float:
    """The field formula's constant: ``Q [bbl/d] = C D[in]^2 S[in] N[spm]`` with ``C = (pi /
    4) x 1440 / 9702 = 0.116575...`` (plunger area x stroke per stroke, 1440 minutes a day,
    9702 in^3 a barrel; 100 % volumetric efficiency). The field rounds it to 0.1166."""
    return np.pi / 4.0 * 1440.0 / BARREL_IN3


def pump_displacement_si(plunger, stroke, speed):
    """Theoretical pump displacement (m^3/s): plunger area x stroke per stroke, ``speed`` in
    rad/s of the crank (one stroke a turn)."""
    return np.pi / 4.0 * np.asarray(plunger) ** 2 * np.asarray(stroke) * np.asarray(speed) / (
        2.0 * np.pi
    )


def pump_displacement(plunger=(1.0, 4.75), stroke=(30.0, 300.0), spm=(4.0, 20.0), paper="a4"):
    """Pump displacement from the field formula ``Q = 0.1166 D^2 S N`` (bbl/d; D, S in in, N
    in strokes a minute): a parallel chain of logarithmic scales (the constant derived in
    :func:`displacement_constant`). Options in oilfield units; values inside are SI."""
    inch, w = 0.0254, 2.0 * np.pi / 60.0
    C = displacement_constant()
    bbl_d = BARREL_M3 / 86400.0
    q_lo = C * plunger[0] ** 2 * stroke[0] * spm[0] * bbl_d
    q_hi = C * plunger[1] ** 2 * stroke[1] * spm[1] * bbl_d

    def model(plunger, stroke, speed):
        return pump_displacement_si(plunger, stroke, speed)

    return parallel(
        [
            Var("plunger", (plunger[0] * inch, plunger[1] * inch),
                lambda d: 2.0 * np.log(np.asarray(d) / inch), title="plunger diameter D",
                unit="m", spacing="log"),
            Var("stroke", (stroke[0] * inch, stroke[1] * inch),
                lambda s: np.log(np.asarray(s) / inch), title="stroke S", unit="m",
                spacing="log"),
            Var("speed", (spm[0] * w, spm[1] * w), lambda n: np.log(np.asarray(n) / w),
                title="pumping speed N", shown={"*": (w, "spm")}, spacing="log"),
        ],
        Var("displacement", (q_lo, q_hi), lambda q: np.log(np.asarray(q) / bbl_d),
            title="pump displacement Q", spacing="log",
            shown={"oilfield": (bbl_d, "bbl/d"), "*": (1.0 / 86400.0, "m^3/d")}),
        constant=float(np.log(C)),
        model=model,
        title="Beam pump: pump displacement",
        relation="Q = 0.1166 D^2 S N (bbl/d; D and S in in, N in strokes/min)",
        paper=paper,
        example={"plunger": 2.0 * inch, "stroke": 120.0 * inch, "speed": 8.0 * w},
        notes=[f"Constant: 0.1166 = (pi/4) x 1440 min/d / 9702 in^3/bbl = {C:.6f} (plunger area "
               "x stroke once a stroke, 100 % volumetric efficiency); the chart uses the "
               "derived value."],
    )


def pump_torque(torque_factor=(10.0, 70.0), load=(2000.0, 30000.0), paper="a4"):
    """Gearbox torque ``T = TF x (W - SU)`` from the torque factor and the net load at a crank
    angle (a Z chart; at the angle of the peak it reads the peak torque). Options in oilfield
    units (in, lbf); the model is the pumping unit's ``torque.net_torque``."""
    from ..machines.pumping_unit.torque import net_torque

    inch, lbf = 0.0254, 4.4482216152605
    tf = (torque_factor[0] * inch, torque_factor[1] * inch)
    w = (load[0] * lbf, load[1] * lbf)

    def model(torque_factor, load):
        return net_torque(torque_factor, load)

    return z_chart(
        Var("torque", (tf[0] * w[0], tf[1] * w[1]), title="gearbox torque T", unit="N m"),
        Var("torque_factor", tf, title="torque factor TF", unit="m"),
        Var("load", w, title="net load W - SU", unit="N"),
        output="torque",
        model=model,
        title="Beam pump: gearbox torque",
        relation="T = TF (W - SU): torque factor (in, per radian of crank) times the net "
        "polished-rod load (lbf) gives in-lb",
        paper=paper,
        example={"torque_factor": 40.0 * inch, "load": 15000.0 * lbf},
    )


# ---------------------------------------------------------------------------- registry
#: name -> (builder, description, options, preferred display units)
NOMOGRAMS = {
    "slider-crank": (
        slider_crank,
        "offset slider-crank: stroke / crank and time ratio over rod / crank and offset / crank "
        "(fitted)",
        Options(
            _span("rod_crank", (2.5, 6.0), "range of rod / crank", minimum=1.1),
            _span("offset_crank", (0.05, 1.0), "range of offset / crank (above 0)", minimum=0),
            Option("degree", 6, "degree of the fitted curves", minimum=2, maximum=12),
        ),
        "si",
    ),
    "slider-crank-acceleration": (
        slider_crank_acceleration,
        "offset slider-crank: peak slider acceleration from rod / crank, offset / crank, crank "
        "and speed (compound)",
        Options(
            _span("rod_crank", (2.5, 6.0), "range of rod / crank", minimum=1.1),
            _span("offset_crank", (0.0, 1.0), "range of offset / crank", minimum=0),
            _span("crank", (0.02, 0.2), "range of the crank", unit="m", maximum=100, positive=True),
            _span("rpm", (100.0, 3000.0), "range of the crank speed", unit="rpm", maximum=1e6,
                  positive=True),
            Option("degree", 6, "degree of the fitted curves", minimum=2, maximum=12),
        ),
        "si",
    ),
    "extreme-velocity": (
        extreme_velocity,
        "paper 004: extreme slider velocity analogs per unit crank over b/a and e/a (fitted)",
        Options(
            _span("rod_crank", (2.0, 6.0), "range of b/a", minimum=1.1),
            _span("offset_crank", (0.0, 0.8), "range of e/a (paper's e0)", minimum=0),
            Option("extreme", "max", "which extreme", choices=("max", "min")),
            Option("degree", 6, "degree of the fitted curves", minimum=2, maximum=12),
        ),
        "si",
    ),
    "four-bar": (
        four_bar,
        "crank-rocker: rocker swing and time ratio -> link ratios and minimum transmission "
        "angle of the best transmission (fitted; one chart per quantity)",
        Options(
            _span("swing_deg", (40.0, 90.0), "range of rocker swings", unit="deg", minimum=5,
                  maximum=150),
            _span("time_ratio", (1.1, 1.5), "range of time ratios", minimum=1.001,
                  maximum=3),
            Option("read", "crank", "the quantity read", choices=tuple(FOUR_BAR_OUTPUTS)),
            Option("degree", 6, "degree of the fitted curves", minimum=2, maximum=12),
        ),
        "si",
    ),
    "pump-displacement": (
        pump_displacement,
        "beam pump: displacement from plunger diameter, stroke and strokes/min (parallel "
        "chain)",
        Options(
            _span("plunger", (1.0, 4.75), "range of plunger diameters", unit="in", maximum=100,
                  positive=True),
            _span("stroke", (30.0, 300.0), "range of strokes", unit="in", maximum=10000,
                  positive=True),
            _span("spm", (4.0, 20.0), "range of pumping speeds", unit="spm", maximum=1000,
                  positive=True),
        ),
        "oilfield",
    ),
    "pump-torque": (
        pump_torque,
        "beam pump: gearbox torque from torque factor and net load (Z chart)",
        Options(
            _span("torque_factor", (10.0, 70.0), "range of torque factors", unit="in",
                  maximum=10000, positive=True),
            _span("load", (2000.0, 30000.0), "range of net loads W - SU", unit="lbf",
                  maximum=1e7, positive=True),
        ),
        "oilfield",
    ),
}


def _entry(name):
    if name not in NOMOGRAMS:
        raise MechanismError(
            f"unknown nomogram {name!r}; built-in nomograms: {', '.join(NOMOGRAMS)}"
        )
    return NOMOGRAMS[name]


def options_of(name) -> Options:
    """The declared options of the built-in nomogram ``name``."""
    return _entry(name)[2]


def preferred_units(name) -> str:
    """The display-units preset the nomogram ``name`` is drawn in unless told otherwise."""
    return _entry(name)[3]


def build(name: str, paper="a4", **options) -> Nomogram:
    """The built-in nomogram ``name`` on ``paper`` (``"a4"`` or ``"letter"``) with ``options``
    (text or Python values, checked against its declaration; defaults for the rest)."""
    from .layout import paper as paper_of

    builder, _, opts, _ = _entry(name)
    values = opts.resolve(options, f"nomogram {name!r}")
    return builder(**values, paper=paper_of(paper))

"""Paper 002: the spatial drive of a 7SK12-class pumping unit, redundant against rational.

The unit (every number an assumption of this study unless the paper prints it)
-------------------------------------------------------------------------------
The paper analyses a 7SK12-2.5-5600 (stroke 2.5 m, 12 t polished-rod load, 5600 kgf m = 54.9 kN m
reducer torque) but prints none of its dimensions, masses or its card. Here:

* **geometry**: the API 11E geometry of a conventional unit of the same class (structure 256 =
  25,600 lb = 11.6 t, the SLB catalogue's C-320D-256-120: A = 155, C = 111.06, I = 111.02,
  P = 132.01, H = 231.97, G = 95.98 in) with the crank radius solved so that the exact stroke is
  2.5 m (R = 34.548 in = 0.8775 m); clockwise with the well on the right;
* **spatial drive**: crank arms and equalizer bearings 1.2 m apart (parallel pitmans);
* **pitmans**: paper 002's section, E = 2.1e11 Pa, J_z = 1.176e-6 m^4 (round, d = 70 mm, taken
  for J_y and the torsion too), mass 7850 kg/m^3 x area x length = 101 kg each;
* **masses**: beam 1500 kg (centre of mass 0.6 m behind the saddle bearing, 6000 kg m^2),
  horsehead 500 kg (3.6 m ahead, 150 kg m^2), equalizer 150 kg, cranks and counterweights
  6000 kg m^2 about the shaft: a structural unbalance of about 1.2 kN, typical of the class;
* **card**: predicted by the damped wave equation of the rod string
  (:mod:`mechsynth.machines.pumping_unit.rod_string`): 1700 m of 22 mm steel rods, a 56 mm
  pump, 1500 m net lift, fluid 900 kg/m^3, damping factor 0.15, at 6 strokes/min, driven by this
  unit's exact polished-rod motion (peak 90 kN, minimum 31 kN). It is bundled
  (``data/spatial_pump_card.csv``, regenerated and compared in the tests); ``card=PATH`` takes
  another (CSV of position m, load N);
* **assembly deviations** of the "as built" case (study options): phase mismatch 0.25 deg, crank
  radii 1 mm apart, pitmans 2 mm apart, shaft 0.5 mrad out of level and 1 mrad out of square,
  saddle-bearing axis 0.5 mrad / 0.5 mrad, equalizer bearing 2 mm off centre.

What is computed
----------------
The ideal drive (checked against the planar unit), the redundant (revolute) and rational
(spherical) drives as built over the cycle: pitman forces and their split, the reactions at A and
A1 against the paper's reported differences, the crank torque, the pitmans' twisting and bending
moments; the split against each deviation alone; the tolerance of each (split <= ``limit``); a
tolerance chart over phase mismatch and crank-radius difference together; a design chart of the
tolerances against the equalizer width and the pitmans' bending stiffness; the counterbalance
that minimizes the peak crank torque of each drive (certified LP).
"""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np

from ..errors import MechanismError
from ..fileio import atomic, save_figure, write_text
from ..machines.pumping_unit import BeamPumpingUnit, DynamometerCard, optimal_counterbalance
from ..machines.pumping_unit.paper002 import ERRATA, angle_between_pitmans, paper_bending_moment
from ..machines.pumping_unit.rod_string import RodString, wave_equation_card
from ..machines.pumping_unit.spatial_design import (
    limit_contour,
    size_counterbalance,
    split_curves,
    split_map,
    tolerance,
    tolerance_design_chart,
)
from ..machines.pumping_unit.spatial_drawing import animate_drive
from ..machines.pumping_unit.spatial_forces import SpatialMasses, planar_torque, power_balance
from ..machines.pumping_unit.spatial_unit import DEVIATIONS, SpatialPumpingUnit
from ..options import Option, takes_options
from ..plotting import LINESTYLES
from ..units import spm as spm_to_rad
from . import StudyResult
from .coverage import Coverage, Item

#: API 11E geometry (in) of the 256-structure conventional unit; R is solved for the stroke
API_GEOMETRY = {"A": 155.0, "C": 111.06, "I": 111.02, "P": 132.01, "H": 231.97, "G": 95.98}
STROKE = 2.5  # m
RATED_LOAD = 12e3 * 9.80665  # N (12 t)
RATED_TORQUE = 5600.0 * 9.80665  # N m (5600 kgf m)
STEEL_DENSITY = 7850.0
WELL = RodString(
    depth=1700.0,
    diameter=0.022,
    pump_diameter=0.056,
    lift=1500.0,
    fluid_density=900.0,
    damping=0.15,
)
CARD_SPM = 6.0
CARD_NODES = 50  # grid-converged: 50, 100 and 200 nodes agree to 0.02 % in peak load
CARD_POINTS = 360  # one sample per degree of crank angle
CARD_FILE = Path(__file__).with_name("data") / "spatial_pump_card.csv"
#: the paper's reported differences (kN, kN m): reactions vs rational, between pitmans, torque
PAPER_DIFFERENCES = {
    "R12y_vs_rational": 6.9,
    "R13y_vs_rational": 5.6,
    "R12y_vs_R13y": 10.0,
    "R12x_vs_R13x_near_dead_centres": 6.7,
    "crank_torque_vs_rational": 20.0,
}
#: study option -> (deviation, factor to SI)
OPTION_UNITS = {
    "phase_mismatch_deg": ("phase_mismatch", np.pi / 180.0),
    "crank_difference_mm": ("crank_difference", 1e-3),
    "pitman_difference_mm": ("pitman_difference", 1e-3),
    "shaft_tilt_mrad": ("shaft_tilt", 1e-3),
    "shaft_skew_mrad": ("shaft_skew", 1e-3),
    "beam_tilt_mrad": ("beam_tilt", 1e-3),
    "beam_skew_mrad": ("beam_skew", 1e-3),
    "equalizer_offset_mm": ("equalizer_offset", 1e-3),
}
DISPLAY = {dev: (opt.rsplit("_", 1)[1], 1.0 / f) for opt, (dev, f) in OPTION_UNITS.items()}
#: the largest value of each deviation swept (SI)
SWEEP_MAX = {
    "phase_mismatch": np.deg2rad(1.0),
    "crank_difference": 8e-3,
    "pitman_difference": 8e-3,
    "shaft_tilt": 4e-3,
    "shaft_skew": 50e-3,  # the skew of the shaft matters an order of magnitude less
    "beam_tilt": 4e-3,
    "beam_skew": 4e-3,
    "equalizer_offset": 10e-3,
}


def unit_7sk12() -> BeamPumpingUnit:
    """The planar 7SK12-class unit: the 256-structure API geometry with the crank radius that
    gives an exact 2.5 m stroke (brentq on the analysed stroke)."""
    from scipy.optimize import brentq

    def stroke_error(r_in):
        return float(BeamPumpingUnit.from_api(R=r_in, units="in", **API_GEOMETRY).stroke) - STROKE

    r = brentq(stroke_error, 20.0, 45.0, xtol=1e-13, rtol=1e-15)
    return BeamPumpingUnit.from_api(R=r, units="in", **API_GEOMETRY)


def masses_7sk12(unit: SpatialPumpingUnit) -> SpatialMasses:
    """The study's assumed masses (module notes); the pitman's from its section."""
    pitman = STEEL_DENSITY * unit.pitman_section.area * float(unit.pitman)
    return SpatialMasses(
        pitman=pitman,
        equalizer=150.0,
        beam=1500.0,
        beam_com=(-0.6, 0.0),
        beam_inertia=6000.0,
        head=500.0,
        head_com=(3.6, 0.0),
        head_inertia=150.0,
        crank_inertia=6000.0,
    )


def make_example_card(path=None):
    """Compute the bundled card (wave equation, :data:`WELL`, 6 SPM) and write it to ``path``
    (default: the bundled file). Returns ``(card, info)``."""
    card, info = wave_equation_card(
        unit_7sk12(), WELL, spm_to_rad(CARD_SPM), nodes=CARD_NODES, points=CARD_POINTS
    )
    if path is not None:
        with atomic(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["position_m", "load_N"])
            fh.write(f"# {card.source}; one cycle from the bottom of the stroke\n")
            for x, f in zip(card.position, card.load):
                w.writerow([f"{x:.9f}", f"{f:.6f}"])
    return card, info


def example_card() -> DynamometerCard:
    """The bundled example card of the study (m, N)."""
    return DynamometerCard.from_csv(CARD_FILE)


def _deviations(options) -> dict[str, float]:
    out = {}
    for opt, (dev, factor) in OPTION_UNITS.items():
        v = float(options[opt])
        if not np.isfinite(v):
            raise MechanismError(f"option {opt} must be finite, got {v}")
        out[dev] = v * factor
    return out


def _near(theta, centres, half_width):
    d = np.abs(np.angle(np.exp(1j * (theta[:, None] - np.asarray(centres)[None, :]))))
    return np.min(d, axis=1) <= half_width


def _paper_comparison(theta, rev, rat, dead):
    r12, r13 = rev.reactions["R12"].force, rev.reactions["R13"].force
    o12, o13 = rat.reactions["R12"].force, rat.reactions["R13"].force
    near = _near(theta, dead, np.deg2rad(15.0))
    d12 = r12[:, 1] - o12[:, 1]
    d13 = r13[:, 1] - o13[:, 1]
    i12, i13 = int(np.argmax(np.abs(d12))), int(np.argmax(np.abs(d13)))
    return {
        "R12y_vs_rational": float(np.abs(d12).max()) / 1e3,
        "R12y_vs_rational_sign": float(np.sign(d12[i12])),
        "R13y_vs_rational": float(np.abs(d13).max()) / 1e3,
        "R13y_vs_rational_sign": float(np.sign(d13[i13])),
        "R12y_vs_R13y": float(np.abs(r12[:, 1] - r13[:, 1]).max()) / 1e3,
        "R12x_vs_R13x_near_dead_centres": float(np.abs(r12[near, 0] - r13[near, 0]).max()) / 1e3,
        "crank_torque_vs_rational": float(np.abs(rev.crank_torque - rat.crank_torque).max()) / 1e3,
        "max_M_R12x": float(np.abs(rev.reactions["R12"].moment[:, 0]).max()),
        "max_R12z": float(np.abs(r12[:, 2]).max()) / 1e3,
    }


@takes_options(
    Option("n_angles", 360, "crank angles of the cycle", minimum=3, maximum=100_000),
    Option(
        "spm", 6.0, "pumping speed", unit="strokes/min", minimum=0.0, exclusive=True, maximum=60.0
    ),
    Option(
        "card", "", 'dynamometer card CSV (position m, load N); "": the bundled card', kind="path"
    ),
    Option(
        "crank_spacing",
        1.2,
        "spacing of the two crank arms along the shaft",
        unit="m",
        minimum=0.0,
        exclusive=True,
    ),
    Option(
        "equalizer_width",
        1.2,
        "width of the equalizer between the pitmans",
        unit="m",
        minimum=0.0,
        exclusive=True,
    ),
    Option("phase_mismatch_deg", 0.25, "phase mismatch of the crank arms", unit="deg"),
    Option("crank_difference_mm", 1.0, "difference of the crank radii", unit="mm"),
    Option("pitman_difference_mm", 2.0, "difference of the pitman lengths", unit="mm"),
    Option("shaft_tilt_mrad", 0.5, "tilt of the crankshaft", unit="mrad"),
    Option("shaft_skew_mrad", 1.0, "skew of the crankshaft", unit="mrad"),
    Option("beam_tilt_mrad", 0.5, "tilt of the beam's axis", unit="mrad"),
    Option("beam_skew_mrad", 0.5, "skew of the beam's axis", unit="mrad"),
    Option("equalizer_offset_mm", 2.0, "offset of the equalizer's bearing", unit="mm"),
    Option("limit", 0.05, "tolerated pitman load split (fraction)"),
    Option("sweep_angles", 90, "crank angles of the deviation sweeps", minimum=3, maximum=100_000),
    Option("sweep_points", 6, "points per deviation sweep", minimum=3, maximum=1000),
    Option("chart_points", 9, "points per axis of the tolerance chart", minimum=3, maximum=200),
    Option("design_points", 6, "points per axis of the design chart", minimum=3, maximum=200),
    Option(
        "stiffness_factors",
        (0.5, 1.0, 2.0, 4.0),
        "multiples of the pitmans' bending stiffness in the design chart",
    ),
    Option(
        "sizing_angles",
        120,
        "crank angles of the counterbalance sizing",
        minimum=3,
        maximum=100_000,
    ),
    owner="study 'spatial-pump'",
)
def run(
    out=None,
    n_angles=360,
    spm=6.0,
    card="",
    crank_spacing=1.2,
    equalizer_width=1.2,
    phase_mismatch_deg=0.25,
    crank_difference_mm=1.0,
    pitman_difference_mm=2.0,
    shaft_tilt_mrad=0.5,
    shaft_skew_mrad=1.0,
    beam_tilt_mrad=0.5,
    beam_skew_mrad=0.5,
    equalizer_offset_mm=2.0,
    limit=0.05,
    sweep_angles=90,
    sweep_points=6,
    chart_points=9,
    design_points=6,
    stiffness_factors=(0.5, 1.0, 2.0, 4.0),
    sizing_angles=120,
):
    """Run the study (see the module notes). Deviation options are in deg, mm and mrad;
    ``limit`` is the tolerated pitman load split (fraction); ``card`` a CSV path (m, N) or ""
    for the bundled card; the ``*_points`` and ``*_angles`` options set the sweeps' resolution;
    ``stiffness_factors`` the multiples of the pitmans' bending stiffness in the design chart."""
    t0 = time.perf_counter()
    options = dict(locals())
    for name in (
        "n_angles",
        "sweep_angles",
        "sweep_points",
        "chart_points",
        "design_points",
        "sizing_angles",
    ):
        if int(options[name]) < 3:
            raise MechanismError(f"option {name} must be at least 3, got {options[name]}")
    if not 0.0 < float(limit) < 1.0:
        raise MechanismError(f"option limit must be a fraction in (0, 1), got {limit}")
    if not float(spm) > 0.0:
        raise MechanismError(f"option spm must be positive, got {spm}")
    if not np.all(np.asarray(stiffness_factors, dtype=float) > 0.0):
        raise MechanismError(f"option stiffness_factors must be positive, got {stiffness_factors}")
    dev = _deviations(options)
    speed = spm_to_rad(float(spm))
    theta = np.linspace(0.0, 2.0 * np.pi, int(n_angles), endpoint=False)
    sweep_theta = np.linspace(0.0, 2.0 * np.pi, int(sweep_angles), endpoint=False)
    planar = unit_7sk12()
    if card:
        path = Path(card)
        if not path.is_file():
            raise MechanismError(f"card file {card!r} not found")
        load = DynamometerCard.from_csv(path)
        card_source = str(path)
    else:
        load = example_card()
        card_source = "bundled wave-equation card (data/spatial_pump_card.csv)"
    ideal = SpatialPumpingUnit.from_planar(planar, crank_spacing, equalizer_width)
    masses = masses_7sk12(ideal)
    built = ideal.replace(**dev)
    units = {
        ("revolute", "ideal"): ideal,
        ("spherical", "ideal"): ideal.with_joints("spherical"),
        ("revolute", "built"): built,
        ("spherical", "built"): built.with_joints("spherical"),
    }

    # the counterbalance: of the planar unit (LP; the ideal spatial drive has its torque), used
    # for every cycle below; then sized anew for each drive as built (certified LP)
    t0_planar = planar_torque(ideal, theta, speed, load=load, masses=masses)
    planar_cb = optimal_counterbalance(theta, t0_planar, phase=0.0, cross_check=False)
    cb = planar_cb.counterbalance
    sizing = {}
    for key, label in (
        (("revolute", "built"), "revolute as built"),
        (("spherical", "built"), "rational as built"),
    ):
        sizing[label] = size_counterbalance(
            units[key],
            speed,
            load,
            masses,
            phase=0.0,
            angles=int(sizing_angles),
            n_dense=4 * int(sizing_angles),
        )
    forces = {
        k: u.forces(theta, speed, load=load, counterbalance=cb, masses=masses)
        for k, u in units.items()
    }
    t_planar = planar_torque(ideal, theta, speed, load=load, counterbalance=cb, masses=masses)
    dead = np.asarray(planar.dead_centres, dtype=float)

    checks = {}
    for joints in ("revolute", "spherical"):
        f = forces[(joints, "ideal")]
        checks[f"ideal_{joints}_torque_vs_planar"] = float(
            np.max(np.abs(f.crank_torque - t_planar)) / np.max(np.abs(t_planar))
        )
        checks[f"ideal_{joints}_split"] = float(f.peak_split)
        checks[f"ideal_{joints}_rod_motion_vs_planar"] = float(
            np.max(
                np.abs(f.motion.polished_rod.position - planar.motion(theta).polished_rod.position)
            )
        )
        for state in ("ideal", "built"):
            pb = power_balance(forces[(joints, state)], cb)
            checks[f"power_balance_{joints}_{state}"] = float(
                np.max(np.abs(pb["error"])) / np.max(np.abs(pb["drive"]))
            )
            if state == "built":
                checks[f"pair_moment_power_{joints}_built_W"] = float(
                    np.max(np.abs(pb["pair_moments"]))
                )
                checks[f"unbalanced_power_{joints}_built_W"] = float(
                    np.max(np.abs(pb["unbalanced"]))
                )
        checks[f"self_stress_states_{joints}"] = int(forces[(joints, "built")].info["nullity"])
        checks[f"loop_closure_{joints}_built_m"] = float(
            np.max(forces[(joints, "built")].motion.extra["residual"])
        )
    checks["rational_built_unbalanced_N"] = float(np.max(forces[("spherical", "built")].residual))

    rev, rat = forces[("revolute", "built")], forces[("spherical", "built")]
    comparison = _paper_comparison(theta, rev, rat, dead)
    ideal_rev = forces[("revolute", "ideal")]
    stated = {
        "max_M_R12x_Nm": {
            "paper": 10.0,
            "ideal": float(np.abs(ideal_rev.reactions["R12"].moment[:, 0]).max()),
            "as_built": comparison["max_M_R12x"],
        },
        "max_R12z_kN": {
            "paper": 0.0,
            "ideal": float(np.abs(ideal_rev.reactions["R12"].force[:, 2]).max()) / 1e3,
            "as_built": comparison["max_R12z"],
        },
    }
    clearance = _clearance(built, sweep_theta, speed, load, masses, cb, float(limit))

    # the phase mismatch alone that gives the paper's 10 kN between the pitmans' y reactions
    probe = np.deg2rad(0.1)
    fp = ideal.replace(phase_mismatch=probe).forces(
        theta, speed, load=load, counterbalance=cb, masses=masses
    )
    dy = np.max(np.abs(fp.reactions["R12"].force[:, 1] - fp.reactions["R13"].force[:, 1]))
    phase_10kn = probe * 10e3 / dy
    dy_chk = np.nan
    if phase_10kn < 8 * SWEEP_MAX["phase_mismatch"]:  # else: not a small deviation (None)
        fchk = ideal.replace(phase_mismatch=phase_10kn).forces(
            theta, speed, load=load, counterbalance=cb, masses=masses
        )
        r12, r13 = fchk.reactions["R12"].force, fchk.reactions["R13"].force
        dy_chk = np.max(np.abs(r12[:, 1] - r13[:, 1]))
    else:
        phase_10kn = None

    # the paper's bending formula (20) against the compatible solution, as built
    dbeta = angle_between_pitmans(rev.motion)
    sec = ideal.pitman_section
    paper_force = paper_bending_moment(sec.E, sec.J_z, dbeta, float(ideal.pitman))
    bending_b = np.maximum(rev.elastic["left"]["bending_B"], rev.elastic["right"]["bending_B"])

    # sweeps of each deviation alone, both drives (each drive one batch)
    values = {n: np.linspace(0.0, SWEEP_MAX[n], int(sweep_points)) for n in DEVIATIONS}
    sweep = {
        joints: split_curves(ideal.with_joints(joints), values, sweep_theta, speed, load, masses)
        for joints in ("revolute", "spherical")
    }
    curves = {
        n: {
            "values": values[n],
            "revolute": sweep["revolute"][n],
            "spherical": sweep["spherical"][n],
        }
        for n in DEVIATIONS
    }
    # tolerances: the (nearly linear) sweep gives the first guess; a drive whose split stays
    # far below the limit over the sweep is reported as tolerating more than the sweep's end
    tols = {}
    for joints in ("revolute", "spherical"):
        reach = {n: sweep[joints][n][-1] for n in DEVIATIONS}
        search = [n for n in DEVIATIONS if reach[n] > limit / 8.0]
        starts = {n: SWEEP_MAX[n] * limit / reach[n] for n in search}
        found = tolerance(
            ideal.with_joints(joints),
            search,
            sweep_theta,
            speed,
            load,
            masses,
            limit=limit,
            start=starts,
            maximum={n: 8 * SWEEP_MAX[n] for n in search},
        )
        for n in DEVIATIONS:
            if n not in found:
                found[n] = {
                    "value": None,
                    "split": float(reach[n]),
                    "bracket": (SWEEP_MAX[n], None),
                    "evaluations": 0,
                }
        tols[joints] = found
    tol_rev, tol_rat = tols["revolute"], tols["spherical"]

    # tolerance chart: phase mismatch and crank-radius difference together
    cp = int(chart_points)
    v1 = np.linspace(
        0.0, 2.0 * _finite(tol_rev["phase_mismatch"]["value"], SWEEP_MAX["phase_mismatch"]), cp
    )
    v2 = np.linspace(
        0.0, 2.0 * _finite(tol_rev["crank_difference"]["value"], SWEEP_MAX["crank_difference"]), cp
    )
    chart = split_map(
        ideal, "phase_mismatch", v1, "crank_difference", v2, sweep_theta, speed, load, masses
    )
    # its limit line solved on rays (the grid's linear interpolation drew it kinked)
    contour = limit_contour(
        ideal, "phase_mismatch", v1[-1], "crank_difference", v2[-1], sweep_theta, speed, load,
        masses, limit=float(limit), rays=max(13, 3 * cp),
    )  # fmt: skip

    # design chart: tolerance against the equalizer width and the pitmans' bending stiffness
    widths = np.linspace(0.8, 1.6, int(design_points))
    factors = np.atleast_1d(np.asarray(stiffness_factors, dtype=float))
    design = {}
    for name in ("phase_mismatch", "crank_difference", "shaft_tilt"):
        tol, chk = tolerance_design_chart(
            ideal,
            name,
            widths,
            factors,
            sweep_theta,
            speed,
            load,
            masses,
            limit=limit,
            maximum=8 * SWEEP_MAX[name],
        )
        design[name] = {"tolerance": tol, "check": chk}

    tables = {
        "tolerance": {
            n: {
                "revolute": tol_rev[n]["value"],
                "revolute_split": tol_rev[n]["split"],
                "rational": tol_rat[n]["value"],
                "rational_split": tol_rat[n]["split"],
                "rational_bracket_low": tol_rat[n]["bracket"][0],
            }
            for n in DEVIATIONS
        }
    }
    fl, fr = rev.pitman_force["left"], rev.pitman_force["right"]
    cycle_summary = {k: forces[k].to_dict() for k in forces}
    data = {
        "success": bool(all(s.success for s in sizing.values())),
        "unit": {
            "crank_m": float(planar.crank),
            "pitman_m": float(planar.pitman),
            "rear_arm_m": float(planar.rear_arm),
            "front_arm_m": float(planar.front_arm),
            "pivot_m": [float(planar.pivot_x), float(planar.pivot_y)],
            "stroke_m": float(planar.stroke),
            "crank_spacing_m": float(crank_spacing),
            "equalizer_width_m": float(equalizer_width),
            "pitman_section": {
                "E": sec.E,
                "J_z": sec.J_z,
                "J_y": sec.J_y,
                "J_p": sec.J_p,
                "area": sec.area,
            },
            "masses": {k: v for k, v in masses.__dict__.items()},
            "speed_spm": float(spm),
            "rated_load_N": RATED_LOAD,
            "rated_torque_Nm": RATED_TORQUE,
        },
        "card": {
            "source": card_source,
            "peak_load_N": float(np.max(load.load)),
            "min_load_N": float(np.min(load.load)),
            "load_fraction_of_rating": float(np.max(load.load) / RATED_LOAD),
        },
        "deviations_as_built": {k: float(v) for k, v in dev.items()},
        "checks": checks,
        "cycles": {f"{j}_{s}": v for (j, s), v in cycle_summary.items()},
        "paper_comparison": {"computed_as_built": comparison, "published": PAPER_DIFFERENCES},
        "phase_mismatch_for_10kN_deg": None
        if phase_10kn is None
        else float(np.rad2deg(phase_10kn)),
        "phase_mismatch_for_10kN_check_kN": None if np.isnan(dy_chk) else float(dy_chk / 1e3),
        "paper_eq20_vs_compatible": {
            "max_paper_eq20_N": float(np.max(np.abs(paper_force))),
            "max_paper_eq20_as_moment_Nm": float(np.max(np.abs(paper_force)) * float(ideal.pitman)),
            "max_bending_at_B_Nm": float(np.max(bending_b)),
            "max_dbeta23_deg": float(np.rad2deg(np.max(np.abs(dbeta)))),
        },
        "paper_stated_values": stated,
        "clearance": {k: v for k, v in clearance.items() if k not in ("plays", "splits")}
        | {"plays_mrad": (1e3 * clearance["plays"]).tolist(), "splits": clearance["splits"]},
        "tolerances": tables["tolerance"],
        "limit": float(limit),
        "counterbalance_planar_ideal": planar_cb.to_dict(),
        "counterbalance": {k: s.to_dict() for k, s in sizing.items()},
        "gearbox_loading": {k: s.peak_torque / RATED_TORQUE for k, s in sizing.items()},
        "pitman_split_as_built": {
            "revolute_peak": float(rev.peak_split),
            "rational_peak": float(rat.peak_split),
            "revolute_max_difference_kN": float(np.max(np.abs(fl - fr)) / 1e3),
        },
        "run_time_s": None,
        "options": {k: v for k, v in options.items() if k != "out"},
    }
    data["coverage"] = COVERAGE.to_dict()  # also in spatial_pump.json
    errata = list(ERRATA) + _computed_errata(data)
    data["run_time_s"] = time.perf_counter() - t0  # the computation, figures not included
    files = []
    if out is not None:
        results = dict(
            theta=theta, planar=planar, forces=forces, t_planar=t_planar, cb=cb, curves=curves,
            tol_rev=tol_rev, tol_rat=tol_rat, v1=v1, v2=v2, chart=chart, widths=widths,
            contour=contour, drive=built,
            factors=factors, design=design, load=load, data=data, limit=limit, dbeta=dbeta,
            paper_force=paper_force, clearance=clearance,
        )  # fmt: skip
        files = _write(Path(out), results)
    result = StudyResult("spatial-pump", _summary(data, tol_rev, tol_rat), data, files, errata)
    return COVERAGE.attach(result, out)


#: bearing length (m) of the pitman pins for the clearance in mm (the paper gives none)
PIN_BEARING = 0.1


def _clearance(built, theta, speed, load, masses, cb, limit, n=9):
    """Wear clearance in the pins A, A1, B, B1 of the redundant drive as built: the tilt each
    pin needs in its hole for the rigid motion (``misfit_angle``), the pitman split against the
    play (a dead zone per pair, :func:`spatial_forces`), the play under which the split is
    within ``limit`` and the play that makes the drive the rational one (every misfit freed)."""
    f0 = built.forces(theta, speed, load=load, counterbalance=cb, masses=masses)
    rat = built.with_joints("spherical").forces(
        theta, speed, load=load, counterbalance=cb, masses=masses
    )
    need = {k: float(np.max(v)) for k, v in f0.info["misfit_angle"].items()}
    full = max(need.values())
    plays = np.linspace(0.0, full, int(n))
    splits = []
    for p in plays:
        f = (
            f0
            if p == 0.0
            else built.forces(theta, speed, load=load, counterbalance=cb, masses=masses, pin_play=p)
        )
        splits.append(float(f.peak_split))
    free = built.forces(theta, speed, load=load, counterbalance=cb, masses=masses, pin_play=full)
    sp = np.asarray(splits)
    within = None
    if sp[0] <= limit:
        within = 0.0
    elif np.any(sp <= limit):
        i = int(np.argmax(sp <= limit))
        within = float(np.interp(limit, [sp[i], sp[i - 1]], [plays[i], plays[i - 1]]))
    return {
        "misfit_mrad": {k: 1e3 * v for k, v in need.items()},
        "play_for_rational_mrad": 1e3 * full,
        "play_for_limit_mrad": None if within is None else 1e3 * within,
        "bearing_length_m": PIN_BEARING,
        "clearance_for_rational_mm": 1e3 * full * PIN_BEARING,
        "clearance_for_limit_mm": None if within is None else 1e3 * within * PIN_BEARING,
        "split_rational": float(rat.peak_split),
        "freed_split": float(free.peak_split),
        "freed_torque_vs_rational_Nm": float(np.max(np.abs(free.crank_torque - rat.crank_torque))),
        "freed_R12_vs_rational_N": float(
            np.max(np.abs(free.reactions["R12"].force - rat.reactions["R12"].force))
        ),
        "plays": plays,
        "splits": splits,
    }


def _finite(v, default):
    return float(v) if v is not None and np.isfinite(v) else float(default)


def _computed_errata(data) -> list[str]:
    c = data["paper_comparison"]["computed_as_built"]
    out = [
        "The balancing torque of the drive with redundant constraints cannot differ from the "
        "rational one by 20 kN m: by the energy balance the difference is the power the pairs' "
        "reaction moments absorb on the rigid motion (the rate of the pitmans' strain energy), "
        f"here at most {data['checks']['pair_moment_power_revolute_built_W']:.3g} W; the computed "
        f"torques differ by {c['crank_torque_vs_rational'] * 1e3:.3g} N m as built.",
        "Conclusion 2 contradicts the body: it puts the difference between the two pitmans' "
        "reactions at about 5 kN, where the body (Fig. 13) reports up to 10 kN in y and 6.7 kN "
        "in x near the dead centres (the 5 kN matches no figure; 5.6 kN is R13y against the "
        "rational drive); and the body's Fig. 4 has R12x and R13x overlap and R12z = R13z = 0 "
        "for the same redundant drive whose x reactions it later finds 6.7 kN apart. As built "
        f"here: {c['R12y_vs_R13y']:.2f} kN in y, {c['R12x_vs_R13x_near_dead_centres']:.2f} kN "
        f"in x near the dead centres, R12z up to {c['max_R12z']:.3g} kN.",
    ]
    return out


def _fmt_dev(name, value):
    unit, factor = DISPLAY[name]
    return f"{value * factor:.3g} {unit}"


def _fmt_tol(name, entry):
    """A tolerance, or "> x" when the split stayed within the limit up to x."""
    if entry["value"] is None:
        return "> " + _fmt_dev(name, entry["bracket"][0])
    return _fmt_dev(name, entry["value"])


def _summary(data, tol_rev, tol_rat) -> str:
    u, ch, cmp = data["unit"], data["checks"], data["paper_comparison"]["computed_as_built"]
    lines = [
        "Paper 002: the spatial drive of a 7SK12-class unit (stroke 2.5 m, 12 t, 5600 kgf m)",
        f"unit: R {u['crank_m']:.4f} m, P {u['pitman_m']:.4f} m, C {u['rear_arm_m']:.4f} m, "
        f"A {u['front_arm_m']:.4f} m, stroke {u['stroke_m']:.6f} m; cranks and equalizer "
        f"{u['crank_spacing_m']:g} / {u['equalizer_width_m']:g} m; {u['speed_spm']:g} SPM",
        f"card: {data['card']['source']}: {data['card']['min_load_N'] / 1e3:.1f} .. "
        f"{data['card']['peak_load_N'] / 1e3:.1f} kN "
        f"({data['card']['load_fraction_of_rating']:.0%} "
        "of the rated load)",
        "",
        "checks: ideal drive vs planar unit -- crank torque "
        f"{ch['ideal_revolute_torque_vs_planar']:.1e} (revolute), "
        f"{ch['ideal_spherical_torque_vs_planar']:.1e} (rational) relative; pitman split "
        f"{ch['ideal_revolute_split']:.1e} / {ch['ideal_spherical_split']:.1e}; power balance "
        f"<= {max(v for k, v in ch.items() if k.startswith('power_balance_revolute')):.1e} "
        f"(revolute), {ch['power_balance_spherical_built']:.1e} (rational as built, whose "
        f"equalizer yaw leaves {ch['rational_built_unbalanced_N']:.2g} N unbalanced); "
        f"self-stress states {ch['self_stress_states_revolute']} (revolute), "
        f"{ch['self_stress_states_spherical']} (rational)",
        "",
        "as built (deviations: "
        + ", ".join(f"{k} {_fmt_dev(k, v)}" for k, v in data["deviations_as_built"].items())
        + ")",
        f"  pitman load split: revolute {data['pitman_split_as_built']['revolute_peak']:.2%}, "
        f"rational {data['pitman_split_as_built']['rational_peak']:.2%}; largest difference "
        f"{data['pitman_split_as_built']['revolute_max_difference_kN']:.2f} kN",
        "  against the paper (computed / published, kN and kN m):",
    ]
    for k, pub in PAPER_DIFFERENCES.items():
        lines.append(f"    {k:32s} {cmp[k]:8.3f} / {pub:g}")
    if data["phase_mismatch_for_10kN_deg"] is None:
        lines.append(
            "  no small phase mismatch alone gives the paper's 10 kN between R12y and R13y"
        )
    else:
        lines.append(
            f"  a phase mismatch of {data['phase_mismatch_for_10kN_deg']:.3f} deg alone gives the "
            "paper's 10 kN between R12y and R13y "
            f"(check: {data['phase_mismatch_for_10kN_check_kN']:.2f} kN)"
        )
    p20 = data["paper_eq20_vs_compatible"]
    lines.append(
        f"  eq. (20) with dbeta23 up to {p20['max_dbeta23_deg']:.3f} deg: "
        f"{p20['max_paper_eq20_N']:.4g} "
        f"(N, a force), x l = {p20['max_paper_eq20_as_moment_Nm']:.4g} N m; the compatible bending "
        f"moment at B reaches {p20['max_bending_at_B_Nm']:.4g} N m"
    )
    st = data["paper_stated_values"]
    lines.append(
        f"  paper: |M_R12x| <= 10 N m and R12z = 0 (its Figs. 4-6); ours: ideal "
        f"{st['max_M_R12x_Nm']['ideal']:.2g} N m and {st['max_R12z_kN']['ideal']:.2g} kN, as "
        f"built {st['max_M_R12x_Nm']['as_built']:.4g} N m and {st['max_R12z_kN']['as_built']:.3g}"
        " kN: the paper's values are the ideal drive's (no deviation strains the pins), while "
        "its differences above need deviations that make both non-zero"
    )
    c = data["clearance"]
    lim = c["play_for_limit_mrad"]
    lines.append(
        "  wear clearance in the pins A, A1, B, B1 (as built): the rigid motion tilts the pins by "
        + ", ".join(f"{k} {v:.2f}" for k, v in c["misfit_mrad"].items())
        + f" mrad; a play of {c['play_for_rational_mrad']:.2f} mrad "
        f"({c['clearance_for_rational_mm']:.2f} mm diametral in a {c['bearing_length_m'] * 1e3:g}"
        f" mm bearing) makes the redundant drive the rational one (split "
        f"{c['freed_split']:.2%} vs {c['split_rational']:.2%}, torques within "
        f"{c['freed_torque_vs_rational_Nm']:.2g} N m)"
        + (
            f"; {lim:.2f} mrad ({c['clearance_for_limit_mm']:.2f} mm) brings the split within "
            f"{data['limit']:.0%}"
            if lim is not None
            else ""
        )
    )
    lines.append("")
    lines.append(f"tolerance for a pitman split <= {data['limit']:.0%} (each deviation alone):")
    lines.append(f"  {'deviation':20s} {'revolute drive':>16s} {'rational drive':>16s}")
    for n in DEVIATIONS:
        lines.append(f"  {n:20s} {_fmt_tol(n, tol_rev[n]):>16s} {_fmt_tol(n, tol_rat[n]):>16s}")
    lines.append("")
    pc = data["counterbalance_planar_ideal"]
    lines.append("counterbalance for the minimum peak crank torque (certified LP, phase 0):")
    lines.append(
        f"  {'planar (ideal)':18s} M = {pc['counterbalance_moment'] / 1e3:8.3f} kN m, peak torque "
        f"{pc['peak_net_torque'] / 1e3:7.3f} kN m (grid of the cycle)"
    )
    for k, s in data["counterbalance"].items():
        lines.append(
            f"  {k:18s} M = {s['counterbalance_moment'] / 1e3:8.3f} kN m, peak torque "
            f"{s['peak_torque'] / 1e3:7.3f} kN m ({data['gearbox_loading'][k]:.0%} of the rating), "
            f"pitman split {s['peak_split']:.2%}; {s['status']}"
        )
    return "\n".join(lines)


def _write(out, results):
    """Figures and tables of the study into ``out`` (the ``results`` of :func:`run`), in the
    house style (its colour-blind-safe cycle: the "C0".."C6" colours below are the palette's)."""
    from ..plotting import style

    with style():
        return _write_all(out, results)


def _write_all(out, results):
    r = results
    theta, planar, forces, t_planar, cb = (
        r[k] for k in ("theta", "planar", "forces", "t_planar", "cb")
    )
    curves, tol_rev, v1, v2, chart = (r[k] for k in ("curves", "tol_rev", "v1", "v2", "chart"))
    widths, factors, design, load, data = (
        r[k] for k in ("widths", "factors", "design", "load", "data")
    )
    limit, dbeta, paper_force, tol_rat = r["limit"], r["dbeta"], r["paper_force"], r["tol_rat"]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..jsonutil import dumps

    files = []
    x = np.rad2deg(theta)
    rev, rat = forces[("revolute", "built")], forces[("spherical", "built")]
    dead = np.rad2deg(np.asarray(planar.dead_centres, dtype=float))

    def save(fig, name):
        save_figure(fig, out / name, dpi=110)
        plt.close(fig)
        files.append(out / name)

    def mark(ax):
        for k, d in enumerate(dead):  # dotted: the planar unit's dead centres
            ax.axvline(d, color="0.6", lw=0.8, ls=":", label="dead centres" if k == 0 else None)

    # the card
    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    ax.plot(load.position, load.load / 1e3, "k-")
    ax.set_xlabel("polished-rod position, m")
    ax.set_ylabel("polished-rod load, kN")
    ax.set_title(f"Dynamometer card: {data['card']['source']}", fontsize=9)
    ax.grid(True, alpha=0.4)
    save(fig, "spatial_pump_card.png")

    # the polished rod (the paper's kinematic figure): position, speed, acceleration
    pr = rev.motion.polished_rod
    pl = planar.motion(
        theta,
        speed=float(
            rev.motion.omega if np.ndim(rev.motion.omega) == 0 else np.mean(rev.motion.omega)
        ),
    ).polished_rod
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7.5, 7.5), constrained_layout=True)
    for ax, a, b, label in (
        (axes[0], pr.position, pl.position, "position, m"),
        (axes[1], pr.velocity, pl.velocity, "speed, m/s"),
        (axes[2], pr.acceleration, pl.acceleration, "acceleration, m/s²"),
    ):
        ax.plot(x, b, color="0.6", lw=3, label="planar unit")
        ax.plot(x, a, "C0-", lw=1, label="spatial drive as built")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.4)
        mark(ax)
    axes[0].legend(fontsize=8)
    axes[0].set_title(
        f"Polished rod at {data['options']['spm']:g} strokes/min (dotted: dead centres)"
    )
    axes[2].set_xlabel("crank angle, deg")
    save(fig, "spatial_pump_polished_rod.png")

    # wear clearance in the pins
    cl = r["clearance"]
    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    ax.plot(
        1e3 * cl["plays"],
        100 * np.asarray(cl["splits"]),
        "C0o-",
        ms=3,
        label="redundant drive as built",
    )
    ax.axhline(100 * cl["split_rational"], color="C3", ls="--", label="rational drive")
    ax.axhline(100 * limit, color="C1", lw=1, label=f"{limit:.0%} limit")
    ax.set_xlabel(
        "pin play = diametral clearance / bearing length, mrad\n"
        f"(1 mrad is {cl['bearing_length_m'] * 1e3:g} µm in a {cl['bearing_length_m'] * 1e3:g} mm"
        " bearing)"
    )
    ax.set_ylabel("peak pitman split, %")
    ax.set_title("Wear clearance in the pins A, A1, B, B1 against the pitman split", fontsize=9)
    ax.grid(True, alpha=0.4)
    ax.legend(fontsize=8)
    save(fig, "spatial_pump_clearance.png")

    # pitman forces and split
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 6.5), constrained_layout=True)
    # left wide, right thin over it (where they agree both show); drive by the dash
    for f, ls, name in ((rev, "-", "revolute"), (rat, "--", "rational")):
        a1.plot(x, f.pitman_force["left"] / 1e3, "C0" + ls, lw=2.6, label=f"left, {name}")
        a1.plot(x, f.pitman_force["right"] / 1e3, "C3" + ls, lw=1.0, label=f"right, {name}")
        fl, fr = f.pitman_force["left"], f.pitman_force["right"]
        # relative to the cycle's peak mean force: the measure of the tolerances (peak_split)
        ref = np.max(0.5 * (np.abs(fl) + np.abs(fr)))
        a2.plot(x, 100 * (fl - fr) / ref, "k" + ls, label=f"{name} (peak {f.peak_split:.2%})")
    a2.axhline(100 * limit, color="C1", lw=1, ls="-.")
    a2.axhline(-100 * limit, color="C1", lw=1, ls="-.", label=f"±{limit:.0%} (the tolerance limit)")
    lo, hi = a2.get_ylim()  # the limit lines inside the frame, not on it
    a2.set_ylim(min(lo, -130 * limit), max(hi, 130 * limit))
    a1.set_ylabel("pitman axial force, kN")
    a2.set_ylabel("(F_left - F_right) / peak mean force, %", fontsize=9)
    a2.set_xlabel("crank angle, deg (dotted: dead centres)")
    a1.set_title("Pitman forces as built: redundant (revolute) vs rational (spherical) drive")
    for a in (a1, a2):
        a.grid(True, alpha=0.4)
        a.legend(fontsize=8, ncol=2)
        mark(a)
    save(fig, "spatial_pump_pitman_forces.png")

    # reactions at A and A1 (paper Figs. 4, 10-13)
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7.5, 6.5), constrained_layout=True)
    for k, comp in enumerate(("x", "y")):
        ax = axes[k]
        for f, ls, name in ((rev, "-", "revolute"), (rat, "--", "rational")):
            r12, r13 = (f.reactions[j].force[:, k] / 1e3 for j in ("R12", "R13"))
            ax.plot(x, r12, "C0" + ls, lw=2.6, label=f"R12{comp} {name}")  # wide under thin
            ax.plot(x, r13, "C3" + ls, lw=1.0, label=f"R13{comp} {name}")
        ax.set_ylabel(f"{comp} component, kN")
        ax.grid(True, alpha=0.4)
        ax.legend(fontsize=8, ncol=2)
        mark(ax)
    axes[0].set_title("Crank-pin reactions R12 (A, left) and R13 (A1, right) as built")
    axes[1].set_xlabel("crank angle, deg")
    save(fig, "spatial_pump_reactions.png")

    # crank torque (paper Fig. 14)
    fig, (a1, a2) = plt.subplots(
        2,
        1,
        sharex=True,
        figsize=(7.5, 6),
        constrained_layout=True,
        gridspec_kw={"height_ratios": [3, 1.4]},
    )
    a1.plot(x, t_planar / 1e3, color="0.5", lw=3, label="planar unit")
    a1.plot(x, rev.crank_torque / 1e3, "C0-", label="revolute as built")
    a1.plot(x, rat.crank_torque / 1e3, "C3--", label="rational as built")
    rating = f"rating {RATED_TORQUE / 1e3:.1f} kN m (5600 kgf m)"
    a1.axhline(RATED_TORQUE / 1e3, color="C1", lw=1, ls="-.", label=rating)
    a1.axhline(-RATED_TORQUE / 1e3, color="C1", lw=1, ls="-.")
    a1.set_ylabel("crank torque, kN m")
    a1.set_title(f"Crank torque with the counterbalance M = {cb.moment / 1e3:.1f} kN m")
    a2.plot(x, rev.crank_torque - rat.crank_torque, "k-")
    a2.set_ylabel("revolute - rational, N m")
    a2.set_xlabel("crank angle, deg")
    for a in (a1, a2):
        a.grid(True, alpha=0.4)
        mark(a)
    a1.legend(fontsize=8)
    save(fig, "spatial_pump_torque.png")

    # elastic moments (paper Figs. 5-7)
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(10, 6.5), constrained_layout=True)
    # the left pitman's curves wide and pale under the right's: where the two coincide
    # (the bending moments), both stay visible
    for side, c, lw, alpha in (("left", "C0", 4.0, 0.5), ("right", "C3", 1.4, 1.0)):
        e = rev.elastic[side]
        kw = dict(lw=lw, alpha=alpha)
        a1.plot(x, e["torsion"], c + "-", label=f"{side} pitman", **kw)
        a2.plot(x, e["bending_A"], c + "-", label=f"{side}, at the crank pin", **kw)
        a2.plot(x, e["bending_B"], c + "--", label=f"{side}, at the equalizer", **kw)
    a2.plot(x, np.abs(paper_force), "k:", label="paper (20): 3EJ sin(Δβ/2)/l² (N, a force)")
    a1.set_ylabel("twisting moment, N m")
    a2.set_ylabel("bending moment, N m")
    a2.set_xlabel("crank angle, deg")
    a1.set_title("Pitman moments of the revolute drive as built")
    for a in (a1, a2):
        a.grid(True, alpha=0.4)
        mark(a)
        a.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # off the curves
    save(fig, "spatial_pump_elastic.png")

    # split against each deviation
    fig, axes = plt.subplots(2, 4, figsize=(12, 6), constrained_layout=True)
    for ax, name in zip(axes.ravel(), DEVIATIONS):
        cv = curves[name]
        unit, factor = DISPLAY[name]
        ax.plot(cv["values"] * factor, 100 * cv["revolute"], "C0o-", ms=3, label="revolute")
        ax.plot(cv["values"] * factor, 100 * cv["spherical"], "C3s--", ms=3, label="rational")
        ax.axhline(100 * limit, color="C1", lw=1)
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, max(hi, 115 * limit))  # the limit line inside the frame
        t = tol_rev[name]["value"]
        if t is not None and t <= cv["values"][-1]:
            ax.axvline(t * factor, color="C0", lw=0.8, ls=":")
        ax.set_xlabel(f"{name.replace('_', ' ')}, {unit}")
        ax.grid(True, alpha=0.4)
    for ax in axes[:, 0]:
        ax.set_ylabel("peak pitman split, %")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(f"Pitman load split against each deviation alone (line: {limit:.0%})")
    save(fig, "spatial_pump_split_vs_deviation.png")

    # tolerance chart
    from scipy.interpolate import RectBivariateSpline

    fig, ax = plt.subplots(figsize=(6.5, 5), constrained_layout=True)
    # the bands: the grid's values through a cubic spline (its linear contours were kinked)
    k = min(3, v1.size - 1, v2.size - 1)
    fine1, fine2 = np.linspace(v1[0], v1[-1], 121), np.linspace(v2[0], v2[-1], 121)
    smooth = RectBivariateSpline(v2, v1, chart, kx=k, ky=k)(fine2, fine1)
    cs = ax.contourf(np.rad2deg(fine1), fine2 * 1e3, 100 * smooth, levels=12, cmap="viridis")
    fig.colorbar(cs, ax=ax, label="peak pitman split, %")
    c1, c2, _ = r["contour"]
    ax.plot(np.rad2deg(c1), c2 * 1e3, color="w", lw=2.2, label=f"split = {limit:.0%}")
    ok = np.flatnonzero(np.isfinite(c1))
    if ok.size:
        mid = ok[ok.size // 2]
        ax.annotate(
            f"{limit:.0%}",
            (np.rad2deg(c1[mid]), c2[mid] * 1e3),
            xytext=(6, 6),
            textcoords="offset points",
            color="w",
            fontsize=9,
            fontweight="bold",
        )
    ax.set_xlabel("crank phase mismatch, deg")
    ax.set_ylabel("crank radius difference (right - left), mm")
    ax.set_title(
        "Tolerance chart, revolute drive: inside the white line the split stays within "
        f"{limit:.0%}\n(line: solved on {c1.size} rays; bands: a {v1.size} x {v2.size} grid, "
        "cubic spline)",
        fontsize=9,
    )
    save(fig, "spatial_pump_tolerance_chart.png")

    # design chart
    fig, axes = plt.subplots(1, len(design), figsize=(12, 4.2), constrained_layout=True)
    for ax, (name, d) in zip(np.atleast_1d(axes), design.items()):
        unit, factor = DISPLAY[name]
        for i, fct in enumerate(factors):  # told apart by marker and line style, not colour
            ax.plot(
                widths,
                d["tolerance"][i] * factor,
                marker="osD^v"[i % 5],
                ls=LINESTYLES[i % len(LINESTYLES)],
                ms=4,
                label=f"J × {fct:g}",
            )
        ax.set_xlabel("equalizer width = crank spacing, m")
        ax.set_ylabel(f"tolerance of the {name.replace('_', ' ')}, {unit}")
        ax.grid(True, alpha=0.4)
        ax.legend(fontsize=8)
    fig.suptitle(
        f"Design chart: tolerance for a pitman split <= {limit:.0%} (revolute drive; J: "
        "pitman bending stiffness, paper's J = 1.176e-6 m^4)"
    )
    save(fig, "spatial_pump_design_chart.png")

    # tables
    with atomic(out / "spatial_pump_cycle.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "crank_angle_deg",
                "rod_position_m",
                "rod_load_N",
                "torque_planar_Nm",
                "torque_revolute_Nm",
                "torque_rational_Nm",
                "pitman_left_revolute_N",
                "pitman_right_revolute_N",
                "pitman_left_rational_N",
                "pitman_right_rational_N",
                "R12x_rev_N",
                "R12y_rev_N",
                "R13x_rev_N",
                "R13y_rev_N",
                "R12x_rat_N",
                "R12y_rat_N",
                "R13x_rat_N",
                "R13y_rat_N",
                "torsion_left_Nm",
                "torsion_right_Nm",
                "bending_A_left_Nm",
                "bending_B_left_Nm",
                "bending_A_right_Nm",
                "bending_B_right_Nm",
                "dbeta23_deg",
            ]
        )
        for i in range(theta.size):
            w.writerow(
                [
                    x[i],
                    rev.motion.polished_rod.position[i],
                    rev.load[i],
                    t_planar[i],
                    rev.crank_torque[i],
                    rat.crank_torque[i],
                    rev.pitman_force["left"][i],
                    rev.pitman_force["right"][i],
                    rat.pitman_force["left"][i],
                    rat.pitman_force["right"][i],
                    *rev.reactions["R12"].force[i, :2],
                    *rev.reactions["R13"].force[i, :2],
                    *rat.reactions["R12"].force[i, :2],
                    *rat.reactions["R13"].force[i, :2],
                    rev.elastic["left"]["torsion"][i],
                    rev.elastic["right"]["torsion"][i],
                    rev.elastic["left"]["bending_A"][i],
                    rev.elastic["left"]["bending_B"][i],
                    rev.elastic["right"]["bending_A"][i],
                    rev.elastic["right"]["bending_B"][i],
                    np.rad2deg(dbeta[i]),
                ]
            )
    files.append(out / "spatial_pump_cycle.csv")
    with atomic(out / "spatial_pump_tolerances.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["deviation", "unit", "tolerance_revolute", "tolerance_rational", "limit"])
        for n in DEVIATIONS:
            unit, factor = DISPLAY[n]
            rv, rt = tol_rev[n]["value"], tol_rat[n]["value"]
            w.writerow(
                [
                    n,
                    unit,
                    "" if rv is None else rv * factor,
                    "" if rt is None else rt * factor,
                    limit,
                ]
            )
    files.append(out / "spatial_pump_tolerances.csv")
    with atomic(out / "spatial_pump_sweep.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["deviation", "unit", "value", "split_revolute", "split_rational"])
        for n, cv in curves.items():
            unit, factor = DISPLAY[n]
            for val, a, b in zip(cv["values"], cv["revolute"], cv["spherical"]):
                w.writerow([n, unit, val * factor, a, b])
    files.append(out / "spatial_pump_sweep.csv")
    with atomic(out / "spatial_pump_tolerance_chart.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["phase_mismatch_deg", "crank_difference_mm", "peak_split"])
        for j, b in enumerate(v2):
            for i, a in enumerate(v1):
                w.writerow([np.rad2deg(a), b * 1e3, chart[j, i]])
    files.append(out / "spatial_pump_tolerance_chart.csv")
    with atomic(out / "spatial_pump_design_chart.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "deviation",
                "unit",
                "stiffness_factor",
                "equalizer_width_m",
                "tolerance",
                "split_at_tolerance",
            ]
        )
        for n, d in design.items():
            unit, factor = DISPLAY[n]
            for i, fct in enumerate(factors):
                for k, wd in enumerate(widths):
                    w.writerow([n, unit, fct, wd, d["tolerance"][i, k] * factor, d["check"][i, k]])
    files.append(out / "spatial_pump_design_chart.csv")
    # the drive as built in 3-D over one turn at the study's speed
    speed = spm_to_rad(float(data["options"]["spm"]))
    anim = animate_drive(r["drive"], speed=speed, frames=36, dpi=64)
    files.append(anim.save(out / "spatial_pump.gif"))
    write_text(out / "spatial_pump.json", dumps(data) + "\n")
    files.append(out / "spatial_pump.json")
    return files


def _t(name):
    file, _, test = name.partition("::")
    return f"tests/test_spatial_{file}.py::{test}"


_P002 = "paper002::"
_STUDY = _t("pump_study::test_study_run_reduced")

COVERAGE = Coverage(
    "Paper 002 (Senchishak, Popovych, Prozur): the spatial lever drive of a pumping unit",
    "spatial-pump",
    (
        Item(
            "data",
            "data",
            "the 7SK12-2.5-5600's dimensions, masses and dynamometer card",
            "not reproducible",
            "studies.spatial_pump.unit_7sk12, masses_7sk12, example_card",
            note="not printed: API 11E geometry of the class with the 2.5 m stroke, assumed "
            "masses and a wave-equation card (documented in the module)",
        ),
        Item(
            "Fig. 1",
            "figure",
            "kinematic scheme of the spatial six-link drive",
            "reproduced",
            "machines.pumping_unit.SpatialPumpingUnit",
            (_t("kinematics::test_ideal_drive_moves_the_polished_rod_as_the_planar_unit"),),
            "the figure is missing from the text; built from its description (spatial_pump.gif "
            "shows the drive as built in 3-D)",
        ),
        Item(
            "eqs. (1)-(6)",
            "equation",
            "loop closure of the two contours with direction cosines",
            "reproduced",
            "machines.pumping_unit.SpatialPumpingUnit.motion",
            (
                _t("kinematics::test_loop_closure_and_bour_equations_hold_with_every_deviation"),
                _t(_P002 + "test_link_vectors_of_eq_4_in_the_ideal_drive"),
            ),
        ),
        Item(
            "eqs. (7)-(11)",
            "equation",
            "velocities by Bour's formula and accelerations",
            "reproduced",
            "machines.pumping_unit.paper002.kinematic_residuals",
            (
                _t("kinematics::test_loop_closure_and_bour_equations_hold_with_every_deviation"),
                _t("kinematics::test_analogs_against_finite_differences"),
            ),
        ),
        Item(
            "eq. (12)",
            "equation",
            "accelerations of the second contour",
            "erratum",
            "machines.pumping_unit.paper002.kinematic_residuals",
            (
                _t(_P002 + "test_errata_are_listed"),
                _t("kinematics::test_loop_closure_and_bour_equations_hold_with_every_deviation"),
            ),
            "eps4 x l4 for eps4 x l41; shows only when the equalizer turns",
        ),
        Item(
            "eqs. (13)-(16)",
            "equation",
            "point kinematics of E, the centres of mass and the counterweights",
            "reproduced",
            "machines.pumping_unit.paper002.point_kinematics",
            (_t("kinematics::test_paper_point_kinematics_13_to_16"),),
        ),
        Item(
            "Fig. 2",
            "figure",
            "polished rod: position, speed, acceleration",
            "reproduced",
            "spatial_pump_polished_rod.png",
            (
                _t("kinematics::test_ideal_drive_moves_the_polished_rod_as_the_planar_unit"),
                _STUDY,
            ),
            "the figure is missing from the text; drawn for the drive as built beside the "
            "planar unit (equal to 1e-9 m for the ideal drive)",
        ),
        Item(
            "eqs. (17)-(19)",
            "equation",
            "the pitmans' elastic moments added to their equilibrium",
            "erratum",
            "machines.pumping_unit.spatial_forces.spatial_forces",
            (_t(_P002 + "test_the_paper_elastic_moments_as_loads_break_the_pitman_balance"),),
            "internal moments taken as external loads; closed here by compatibility (force "
            "method with the pitmans' compliance)",
        ),
        Item(
            "eqs. (20)-(21)",
            "equation",
            "bending M_F = 3 E J_z sin(dbeta/2) / l^2 and torsion",
            "erratum",
            "machines.pumping_unit.paper002.paper_bending_moment",
            (_t(_P002 + "test_elastic_formulas_18_to_21_against_beam_theory"),),
            "a force, not a moment (x l for the clamp moment); along the pin axis B a pin "
            "carries none",
        ),
        Item(
            "eqs. (22)-(39)",
            "equation",
            "kinetostatics of the redundant drive: beam, equalizer, pitmans",
            "erratum",
            "machines.pumping_unit.paper002.kinetostatic_residuals",
            (_t(_P002 + "test_redundant_drive_equations_22_to_39"),),
            "(23), (29), (31), (37), (39) mis-state arms (errata listed); corrected forms hold "
            "to round-off",
        ),
        Item(
            "redundancy",
            "finding",
            "four redundant constraints in A, A1, B, B1",
            "erratum",
            "machines.pumping_unit.spatial_forces.spatial_forces",
            (
                _t(
                    "forces::test_the_redundant_drive_splits_the_load_and_the_rational_one_"
                    "equalizes_it"
                ),
                _STUDY,
            ),
            "five self-stress states: the equalizer's idle spin about B-B1 makes W = 2",
        ),
        Item(
            "eqs. (40)-(46)",
            "equation",
            "kinetostatics of the rational drive (spherical A, A1, B, B1)",
            "erratum",
            "machines.pumping_unit.paper002.kinetostatic_residuals",
            (_t(_P002 + "test_rational_drive_equations_40_to_46"),),
            "(41)-(42) arms; (40)-(46) leave R05, M_R05 and the split along B-B1 undetermined",
        ),
        Item(
            "eqs. (47)-(48)",
            "equation",
            "the crank's equilibrium and the balancing torque M_z",
            "erratum",
            "machines.pumping_unit.paper002.crank_residuals",
            (_t(_P002 + "test_crank_equations_47_48_and_the_double_counted_inertia"),),
            "(47) counts the arms' and counterweights' rotary inertia twice",
        ),
        Item(
            "Fig. 4, R12z",
            "figure",
            "R12z = R13z = 0 in the redundant drive",
            "reproduced",
            "studies.spatial_pump (paper_stated_values)",
            (_STUDY,),
            "in the ideal drive (0 to round-off); as built the deviations give R12z of the "
            "order of 0.1 kN",
        ),
        Item(
            "Figs. 5-6, M_R12x",
            "figure",
            "|M_R12x|, |M_R13x| <= 10 N m",
            "reproduced",
            "studies.spatial_pump (paper_stated_values)",
            (_STUDY,),
            "0 in the ideal drive; as built the pins' moments reach hundreds of N m: the "
            "paper's figures are of an undeviated drive",
        ),
        Item(
            "Fig. 7",
            "figure",
            "reaction moments M_R24, M_R34 at B, B1",
            "not reproducible",
            "spatial_pump_elastic.png",
            note="the figure is missing from the text; the pitmans' moments are drawn",
        ),
        Item(
            "Figs. 10-13, differences",
            "finding",
            "R12y, R13y differ from the rational drive by 6.9, 5.6 kN; the pitmans by 10 kN "
            "(y) and 6.7 kN (x)",
            "not reproducible",
            "studies.spatial_pump (paper_comparison)",
            note="they depend on the unit's deviations, which the paper does not give; the "
            "phase mismatch that alone gives the 10 kN is computed (under 1 deg)",
        ),
        Item(
            "Fig. 14",
            "finding",
            "the balancing torque differs from the rational drive's by up to 20 kN m",
            "erratum",
            "studies.spatial_pump (computed errata)",
            (_t("forces::test_power_balance_of_the_crank_torque"), _STUDY),
            "by the energy balance the difference is the power of the pairs' moments: watts, "
            "a few N m as built",
        ),
        Item(
            "finding: equalized",
            "finding",
            "removing the redundant constraints equalizes the pitman loads",
            "reproduced",
            "machines.pumping_unit.spatial_forces",
            (
                _t(
                    "forces::test_the_redundant_drive_splits_the_load_and_the_rational_one_"
                    "equalizes_it"
                ),
            ),
            "the rational drive splits only by the equalizer's lever rule",
        ),
        Item(
            "conclusion 2",
            "finding",
            "reactions differ by about 7 kN from the rational; between pitmans about 5 kN",
            "erratum",
            "studies.spatial_pump (computed errata)",
            (_STUDY,),
            "contradicts the body (10 kN in y, 6.7 kN in x between the pitmans)",
        ),
        Item(
            "conclusion 3",
            "finding",
            "the unequal pitman loads load the crank arms unequally and change the torque",
            "reproduced",
            "machines.pumping_unit.spatial_design.tolerance",
            (
                _t(
                    "forces::test_the_redundant_drive_splits_the_load_and_the_rational_one_"
                    "equalizes_it"
                ),
                _STUDY,
            ),
            "the split is reproduced; the torque change is small (see Fig. 14)",
        ),
        Item(
            "wear clearance",
            "finding",
            "local clearances in the pairs (the paper's introduction)",
            "added",
            "machines.pumping_unit.spatial_forces (pin_play)",
            (_t("forces::test_pin_play_frees_the_redundant_drive"), _STUDY),
            "the play that frees every pin makes the redundant drive the rational one "
            "(spatial_pump_clearance.png)",
        ),
        Item(
            "tolerances",
            "recommendation",
            "how much deviation the redundant drive tolerates",
            "added",
            "machines.pumping_unit.spatial_design.tolerance",
            (_STUDY,),
            "each deviation's tolerance for a 5 % split, charts over two deviations and over "
            "the equalizer width and the pitmans' stiffness",
        ),
    ),
)

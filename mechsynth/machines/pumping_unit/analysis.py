"""``mechsynth pump analyze``: the analysis of one beam pumping unit from a TOML description.

Unit file (TOML; top-level keys)::

    designation = "C-320D-256-120"     # free text
    unit_class = "conventional"        # or "mark-ii"
    rotation = "cw"                    # seen with the well on the right
    units = "in"                       # required: of the geometry, and of the loads: "in"
                                       #   (in, lb, in-lb) or "m" (m, N, N m)
    A = 155.00                         # API 11E geometry: A, C, I, P, R and K or (H, G)
    C = 111.06
    I = 111.02
    P = 132.01
    R = 42.01
    H = 231.97
    G = 95.98
    spm = 8.0                          # strokes per minute
    structural_unbalance = 450         # lb (N with units = "m"), optional
    counterbalance_phase = 0.0         # deg, optional: the fixed phase of the counterweights
    free_phase = false                 # optimize the phase too
    gearbox_rating = 320000            # in-lb (N m), optional: loading and permissible load
    beam_inertia_kgm2 = 0.0            # optional, SI whatever ``units``: beam, horsehead and
    crank_inertia_kgm2 = 0.0           #   equalizer about the centre bearing; cranks and
    speed_fluctuation = 0.0            #   counterweights about the crankshaft; (max-min)/mean

A dynamometer card (``--card card.csv``) has ``position, load`` rows in the unit file's units
(in and lb, or m and N). Everything is computed in SI; ``--units oilfield`` prints in, lb, in-lb
and SPM, ``--units si`` m, N, N m and rad/s, ``--units mm-deg`` mm, N and N m.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import MechanismError
from ...fileio import atomic, output_dir, write_text
from ...report import StudyResult
from ...units import spm as spm_to_rad_s
from .beam_unit import BeamPumpingUnit, crank_speed
from .torque import (
    DynamometerCard,
    optimal_counterbalance,
    permissible_load,
    torque_curve,
    torque_factor_table,
)

__all__ = ["load_unit", "analyze", "UNIT_KEYS", "OUTPUT_UNITS"]

INCH = 0.0254
POUND = 4.4482216152605
UNIT_KEYS = {
    "designation", "unit_class", "rotation", "units", "A", "C", "I", "P", "R", "K", "H", "G",
    "spm", "structural_unbalance", "counterbalance_phase", "free_phase", "gearbox_rating",
    "beam_inertia_kgm2", "crank_inertia_kgm2", "speed_fluctuation",
}  # fmt: skip

#: output system -> {quantity: (unit label, factor from SI)}
OUTPUT_UNITS = {
    "si": {
        "length": ("m", 1.0),
        "speed": ("m/s", 1.0),
        "accel": ("m/s^2", 1.0),
        "force": ("N", 1.0),
        "torque": ("N m", 1.0),
        "tf": ("m", 1.0),
    },
    "mm-deg": {
        "length": ("mm", 1e3),
        "speed": ("mm/s", 1e3),
        "accel": ("mm/s^2", 1e3),
        "force": ("N", 1.0),
        "torque": ("N m", 1.0),
        "tf": ("mm", 1e3),
    },
    "oilfield": {
        "length": ("in", 1.0 / INCH),
        "speed": ("in/s", 1.0 / INCH),
        "accel": ("in/s^2", 1.0 / INCH),
        "force": ("lb", 1.0 / POUND),
        "torque": ("in-lb", 1.0 / (POUND * INCH)),
        "tf": ("in", 1.0 / INCH),
    },
}


#: fastest pumping speed accepted (strokes per minute); beam units run at about 2 to 20
MAX_SPM = 60.0
#: card stroke / unit stroke accepted (the card is scaled onto the unit's stroke)
CARD_STROKE_RATIO = (0.5, 2.0)


def load_unit(source) -> tuple[BeamPumpingUnit, dict[str, Any]]:
    """Read a unit file (path or dict). Returns the unit and the operating data in SI:
    ``speed`` (rad/s), ``spm``, ``structural_unbalance`` (N), ``phase`` (rad), ``free_phase``,
    ``rating`` (N m or None), ``load_units`` ("in" or "m"), ``designation``."""
    from ...fileio import read_toml

    data, path = read_toml(source, "unit file")
    where = f"{path}: " if path is not None else ""
    unknown = set(data) - UNIT_KEYS
    if unknown:
        raise MechanismError(f"{where}unknown keys {sorted(unknown)}; known: {sorted(UNIT_KEYS)}")
    if "units" not in data:
        raise MechanismError(
            f"{where}units is required: 'in' (in, lb, in-lb, as API 11E tables give them) or 'm' "
            "(m, N, N m); without it the geometry's numbers could be read in the wrong unit"
        )
    units = data["units"]
    if units not in ("m", "in"):
        raise MechanismError(f"{where}units must be 'm' or 'in', got {units!r}")
    missing = [k for k in ("A", "C", "I", "P", "R", "spm") if k not in data]
    if missing:
        raise MechanismError(f"{where}missing {', '.join(missing)}")

    def num(key, default=None):
        v = data.get(key, default)
        if v is None:
            return None
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise MechanismError(f"{where}{key} must be a number, got {v!r}")
        if not np.isfinite(v):
            raise MechanismError(f"{where}{key} must be finite, got {v!r}")
        return float(v)

    unit = BeamPumpingUnit.from_api(
        A=num("A"),
        C=num("C"),
        I=num("I"),
        P=num("P"),
        R=num("R"),
        K=num("K"),
        H=num("H"),
        G=num("G"),
        unit_class=data.get("unit_class", "conventional"),
        rotation=data.get("rotation", "cw"),
        units=units,
    )
    spm = num("spm")
    if not 0 < spm <= MAX_SPM:
        raise MechanismError(
            f"{where}spm must be above 0 and at most {MAX_SPM:g} strokes per minute, got {spm}"
        )
    force = POUND if units == "in" else 1.0
    torque = POUND * INCH if units == "in" else 1.0
    rating = num("gearbox_rating")
    if rating is not None and not rating > 0:
        raise MechanismError(f"{where}gearbox_rating must be positive, got {rating}")
    free = data.get("free_phase", False)
    if not isinstance(free, bool):
        raise MechanismError(f"{where}free_phase must be true or false, got {free!r}")
    return unit, {
        "designation": str(data.get("designation", "")),
        "spm": spm,
        "speed": spm_to_rad_s(spm),
        "structural_unbalance": num("structural_unbalance", 0.0) * force,
        "phase": np.deg2rad(num("counterbalance_phase", 0.0)),
        "free_phase": free,
        "rating": None if rating is None else rating * torque,
        "load_units": units,
        "beam_inertia": _nonnegative(where, "beam_inertia_kgm2", num("beam_inertia_kgm2", 0.0)),
        "crank_inertia": _nonnegative(where, "crank_inertia_kgm2", num("crank_inertia_kgm2", 0.0)),
        "fluctuation": num("speed_fluctuation", 0.0),
    }


def _nonnegative(where, key, value):
    if value < 0:
        raise MechanismError(f"{where}{key} must be >= 0, got {value}")
    return value


def analyze(unit_file, card=None, out=None, units="oilfield", n=720) -> StudyResult:
    """Analyse a unit (and a dynamometer card): see the module notes. Returns a
    :class:`~mechsynth.studies.StudyResult` whose ``data`` is what ``--json`` prints (values in
    the output ``units``, named in ``data["units"]``); ``data["success"]`` is False when the
    counterbalance optimization fails."""
    if units not in OUTPUT_UNITS:
        raise MechanismError(f"units must be one of {', '.join(OUTPUT_UNITS)}, got {units!r}")
    unit, op = load_unit(unit_file)
    U = OUTPUT_UNITS[units]

    def cv(value, kind):
        return float(value) * U[kind][1]

    theta = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    omega, eps = crank_speed(theta, op["speed"], op["fluctuation"])
    m = unit.motion(theta, speed=omega, epsilon=eps)
    v, a, tf = m.polished_rod.velocity, m.polished_rod.acceleration, m.torque_factor
    bottom, top = unit.dead_centres
    data: dict[str, Any] = {
        "designation": op["designation"],
        "unit_class": unit.unit_class,
        "rotation": unit.rotation,
        "spm": op["spm"],
        "units": {k: lab for k, (lab, _) in U.items()} | {"angle": "deg", "speed": U["speed"][0]},
        "stroke": cv(unit.stroke, "length"),
        "bottom_dead_centre_deg": float(np.rad2deg(bottom)),
        "top_dead_centre_deg": float(np.rad2deg(top)),
        "upstroke_span_deg": float(np.rad2deg(unit.upstroke_span)),
        "downstroke_span_deg": float(np.rad2deg(unit.downstroke_span)),
        "max_torque_factor": cv(tf.max(), "tf"),
        "min_torque_factor": cv(tf.min(), "tf"),
        "peak_upstroke_velocity": cv(v.max(), "speed"),
        "peak_downstroke_velocity": cv(-v.min(), "speed"),
        "peak_acceleration": cv(np.abs(a).max(), "accel"),
        "max_acceleration": cv(a.max(), "accel"),
        "min_acceleration": cv(a.min(), "accel"),
        "min_pressure_angle_deg": float(np.rad2deg(m.pressure_angle.min())),
        "max_pressure_angle_deg": float(np.rad2deg(m.pressure_angle.max())),
        "success": True,
    }
    tc = res = pl = None
    if card is not None:
        scale = INCH if op["load_units"] == "in" else 1.0
        force = POUND if op["load_units"] == "in" else 1.0
        c = DynamometerCard.from_csv(card, position_scale=scale, load_scale=force)
        ratio = c.stroke / float(unit.stroke)
        if not CARD_STROKE_RATIO[0] <= ratio <= CARD_STROKE_RATIO[1]:
            raise MechanismError(
                f"card {card}: its stroke is {ratio:.3g} times the unit's "
                f"({c.stroke:.4g} m against {float(unit.stroke):.4g} m); a card of this unit "
                f"has {CARD_STROKE_RATIO[0]:g} to {CARD_STROKE_RATIO[1]:g} times its stroke "
                "(check the card's units and the file's `units`)"
            )
        dyn = dict(
            speed=omega,
            epsilon=eps,
            beam_inertia=op["beam_inertia"],
            crank_inertia=op["crank_inertia"],
        )
        tc = torque_curve(unit, theta, c, op["structural_unbalance"], **dyn)
        res = optimal_counterbalance(
            theta,
            tc.well + tc.inertia,
            phase=op["phase"],
            free_phase=op["free_phase"],
            cross_check=True,
        )
        cb = res.counterbalance if res.success else None
        if cb is not None:
            tc = torque_curve(unit, theta, c, op["structural_unbalance"], cb, **dyn)
        data["card"] = {
            "file": str(card),
            "card_stroke": cv(c.stroke, "length"),
            "card_to_unit_stroke_ratio": c.stroke / float(unit.stroke),
            "peak_load": cv(c.load.max(), "force"),
            "min_load": cv(c.load.min(), "force"),
            "peak_torque_without_counterbalance": cv(np.abs(tc.well + tc.inertia).max(), "torque"),
            "peak_inertia_torque": cv(np.abs(tc.inertia).max(), "torque"),
            "counterbalance_status": res.status,
            "optimal_counterbalance_moment": cv(res.counterbalance.moment, "torque"),
            "counterbalance_phase_deg": float(np.rad2deg(res.counterbalance.phase)),
            "peak_net_torque": cv(res.peak_torque, "torque"),
            "scan_peak_net_torque": cv(res.scan_peak_torque, "torque")
            if res.scan_peak_torque is not None
            else None,
            "scan_counterbalance_moment": cv(res.scan_counterbalance.moment, "torque")
            if res.scan_counterbalance is not None
            else None,
        }
        if op["rating"] is not None and res.success:
            data["card"]["gearbox_loading_percent"] = 100.0 * res.peak_torque / op["rating"]
            pl = permissible_load(
                unit, theta, op["rating"], res.counterbalance, op["structural_unbalance"]
            )
        data["success"] = bool(res.success)
        step = max(1, int(round(n / 24)))
        data["card"]["torque_curve_15deg"] = [
            {
                "crank_angle_deg": float(np.rad2deg(theta[i])),
                "position": cv(tc.position[i], "length"),
                "torque_factor": cv(tc.torque_factor[i], "tf"),
                "load": cv(tc.load[i], "force"),
                "net_torque": cv(tc.net[i], "torque"),
            }
            for i in range(0, n, step)
        ]
    files = [] if out is None else _write(Path(out), unit, theta, m, tc, pl, U, cv, data)
    return StudyResult("pump-analyze", _summary(data), data, files, [])


def _num(v) -> str:
    return "n/a" if v is None else f"{v:.1f}"


def _summary(d) -> str:
    u = d["units"]
    lines = [
        f"{d['designation'] or 'pumping unit'} ({d['unit_class']}, rotation {d['rotation']}, "
        f"{d['spm']:g} SPM)",
        f"stroke                 {d['stroke']:.4f} {u['length']}",
        f"dead centres           bottom {d['bottom_dead_centre_deg']:.3f} deg, "
        f"top {d['top_dead_centre_deg']:.3f} deg (from 12 o'clock, direction of rotation)",
        f"upstroke / downstroke  {d['upstroke_span_deg']:.3f} / {d['downstroke_span_deg']:.3f} "
        "deg of crank",
        f"torque factor          max {d['max_torque_factor']:.4f}, min "
        f"{d['min_torque_factor']:.4f} {u['tf']}",
        f"peak velocity          up {d['peak_upstroke_velocity']:.4f}, down "
        f"{d['peak_downstroke_velocity']:.4f} {u['speed']}",
        f"acceleration           max {d['max_acceleration']:.4f}, min "
        f"{d['min_acceleration']:.4f} {u['accel']}",
        f"pressure angle         {d['min_pressure_angle_deg']:.2f} .. "
        f"{d['max_pressure_angle_deg']:.2f} deg",
    ]
    c = d.get("card")
    if c:
        lines += [
            f"card                   {c['file']}: stroke {c['card_stroke']:.4f} {u['length']} "
            f"(scaled by {1 / c['card_to_unit_stroke_ratio']:.4f} to the unit), loads "
            f"{c['min_load']:.1f} .. {c['peak_load']:.1f} {u['force']}",
            f"peak torque, no CB     {c['peak_torque_without_counterbalance']:.1f} {u['torque']}",
            f"optimal counterbalance {c['optimal_counterbalance_moment']:.1f} {u['torque']} at "
            f"phase {c['counterbalance_phase_deg']:.2f} deg (LP {c['counterbalance_status']}; "
            f"scan cross-check: peak {_num(c['scan_peak_net_torque'])})",
            f"peak net torque        {c['peak_net_torque']:.1f} {u['torque']}",
        ]
        if c["peak_inertia_torque"] > 0:
            lines.append(
                f"peak inertia torque    {c['peak_inertia_torque']:.1f} {u['torque']} (included)"
            )
        if "gearbox_loading_percent" in c:
            lines.append(f"gearbox loading        {c['gearbox_loading_percent']:.1f} % of rating")
        lines.append(
            f"\n{'angle':>6s} {'position':>10s} {'TF':>9s} {'load':>10s} {'net torque':>12s}   "
            f"(deg, {u['length']}, {u['tf']}, {u['force']}, {u['torque']})"
        )
        for r in c["torque_curve_15deg"]:
            lines.append(
                f"{r['crank_angle_deg']:6.1f} {r['position']:10.3f} {r['torque_factor']:9.3f} "
                f"{r['load']:10.1f} {r['net_torque']:12.1f}"
            )
    return "\n".join(lines)


def _name(data) -> str:
    """The unit's designation for titles (or "pumping unit")."""
    return data.get("designation") or "pumping unit"


def _thousands(unit_scale, *values):
    """``(scale, unit)`` for a figure: the display unit, or a thousand of it (klb, 1000 in-lb)
    when the largest plotted magnitude reaches 10,000 (tick labels keep four digits)."""
    unit, scale = unit_scale
    finite = [np.abs(a[np.isfinite(a)]) for a in (np.asarray(v, dtype=float) for v in values)]
    peak = max((float(a.max()) for a in finite if a.size), default=0.0) * scale
    if not peak >= 1e4:
        return scale, unit
    return scale / 1e3, ("1000 " + unit if "-" in unit or " " in unit else "k" + unit)


def _write(out, unit, theta, m, tc, pl, U, cv, data):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ...jsonutil import dumps
    from ...plotting import PALETTE, crank_axis, style
    from ...plotting import save as save_figure

    out = output_dir(out)
    files = []
    x = np.rad2deg(theta)
    with style():
        fig, axes = plt.subplots(4, 1, sharex=True, figsize=(7, 9), layout="constrained")
        series = (
            (m.polished_rod.position, "length", "position up from the bottom"),
            (m.polished_rod.velocity, "speed", "velocity"),
            (m.polished_rod.acceleration, "accel", "acceleration"),
            (m.torque_factor, "tf", "torque factor"),
        )
        for ax, (y, kind, label) in zip(axes, series):
            ax.plot(x, np.asarray(y) * U[kind][1], color=PALETTE[4])
            ax.set_ylabel(f"{label}, {U[kind][0]}")
        crank_axis(axes[-1], "crank angle θ from 12 o'clock in the direction of rotation")
        axes[0].set_title(f"{_name(data)}: polished rod (exact kinematics)", fontsize=10)
        files.append(save_figure(fig, out / "polished_rod.png", dpi=110))

    rows = torque_factor_table(unit, 15.0)
    with atomic(out / "torque_factor_table.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        header = ["crank_angle_deg", f"torque_factor_{U['tf'][0]}", f"position_{U['length'][0]}"]
        w.writerow([*header, "position_fraction", "beam_angle_deg"])
        for r in rows:
            w.writerow([r["crank_angle_deg"], cv(r["torque_factor"], "tf"),
                        cv(r["position"], "length"), r["position_fraction"],
                        r["beam_angle_deg"]])  # fmt: skip
    files.append(out / "torque_factor_table.csv")

    if tc is not None:
        t_scale, t_unit = _thousands(U["torque"], tc.well, tc.net, tc.counterbalance)
        fig = tc.plot(scale=t_scale, unit=t_unit)
        fig.axes[0].set_title(f"{_name(data)}: gearbox torque", fontsize=10)
        files.append(save_figure(fig, out / "torque.png", dpi=110))
        with atomic(out / "torque_curve.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["crank_angle_deg", f"position_{U['length'][0]}",
                        f"torque_factor_{U['tf'][0]}", f"load_{U['force'][0]}",
                        f"well_torque_{U['torque'][0]}", f"counterbalance_{U['torque'][0]}",
                        f"net_torque_{U['torque'][0]}"])  # fmt: skip
            for i in range(theta.size):
                row = [x[i], cv(tc.position[i], "length"), cv(tc.torque_factor[i], "tf")]
                row += [cv(tc.load[i], "force"), cv(tc.well[i], "torque")]
                row += [cv(tc.counterbalance[i], "torque"), cv(tc.net[i], "torque")]
                w.writerow(row)
        files.append(out / "torque_curve.csv")
    if pl is not None:
        with style():
            fig, ax = plt.subplots(figsize=(7.5, 5), layout="constrained")
            ok = np.isfinite(pl["upper"])
            px = pl["position"] * U["length"][1]
            up = pl["torque_factor"] > 0
            card = () if tc is None else (tc.load,)
            f, f_unit = _thousands(U["force"], pl["upper"], pl["lower"], *card)
            ax.plot(
                px[ok & up],
                pl["upper"][ok & up] * f,
                "^",  # told apart by shape too: a maximum points up, a minimum down
                ms=2,
                color=PALETTE[5],
                label="permissible load, upstroke (maximum)",
            )
            ax.plot(
                px[ok & ~up],
                pl["lower"][ok & ~up] * f,
                "v",
                ms=2,
                color=PALETTE[4],
                label="permissible load, downstroke (minimum)",
            )
            if tc is not None:
                ax.plot(tc.position * U["length"][1], tc.load * f, "k-", lw=1, label="card")
            top = np.nanmax(np.where(ok, tc.load if tc is not None else 0, np.nan)) * f
            ax.set_ylim(0, 2.0 * top if np.isfinite(top) and top > 0 else None)
            ax.set_xlabel(f"polished-rod position, {U['length'][0]}")
            ax.set_ylabel(f"load, {f_unit}")
            ax.set_title(
                f"{_name(data)}: permissible load (gearbox rating, counterbalance as set)",
                fontsize=10,
            )
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, markerscale=4)
            files.append(save_figure(fig, out / "permissible_load.png", dpi=110))
    write_text(out / "pump_analysis.json", dumps(data) + "\n")
    files.append(out / "pump_analysis.json")
    return files

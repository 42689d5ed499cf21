"""Paper 004 (Dzhavadyan): extreme slider velocities of the slider-crank, Table 1 reproduced.

For each rod/crank ratio of Table 1 (centric, crank 1) the crank angle ``phi0`` of the extreme
velocity analog ``S'_v`` and the coefficient ``lambda_s = S'_v phi_u / S_u`` are computed from the
derived polynomial and compared with the published values. A second table checks offset designs:
the derived polynomial's extrema against a bounded numeric search, and the printed polynomial's
roots against the same (they disagree: errata). The derivative ``m0'`` printed in (3) lacks its
minus sign (an erratum of the print only: the polynomial (4) was derived with the right sign).
The reference chart the paper calls for ("reference charts", eqs. 4-7 solved for designers) is
drawn as contours of both extreme velocity analogs and their crank angles over b/a and e/a.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..fileio import atomic
from ..kinematics.extreme_velocity import (
    ERRATA,
    _real_roots,
    extreme_velocity,
    printed_coefficients,
    stroke_crank_angle,
    velocity_analog,
    velocity_analog_derivative,
)
from ..kinematics.slider_crank import SliderCrank
from ..options import takes_options
from ..progress import Stages
from ..units import dms, format_dms
from . import StudyResult

#: Table 1 of paper 004 (e0 = 0, a = 1): lambda = b/a, phi0 (deg, min, s), S'_v, lambda_s.
TABLE_1 = (
    (1.75, (65, 59, 47), 1.1624840, 1.8260135),
    (2.00, (67, 41, 50), 1.1232079, 1.7751467),
    (2.25, (69, 17, 11), 1.0970293, 1.7232689),
    (2.50, (70, 43, 48), 1.0785481, 1.6940459),
    (2.75, (72, 1, 1), 1.0649548, 1.6722682),
    (3.00, (73, 10, 50), 1.0546395, 1.6555548),
    (3.25, (74, 12, 37), 1.0466149, 1.6443281),
    (3.50, (75, 8, 20), 1.0402441, 1.6332362),
    (3.75, (75, 58, 2), 1.0350989, 1.6234271),
    (4.00, (76, 43, 1), 1.0308827, 1.6185005),
    (4.25, (77, 23, 58), 1.0273837, 1.6134233),
    (4.50, (78, 0, 54), 1.0244476, 1.6090079),
    (4.75, (78, 35, 9), 1.0219597, 1.6070124),
    (5.00, (79, 6, 2), 1.0198331, 1.6023044),
    (5.25, (79, 31, 14), 1.0180009, 1.5992682),
    (5.50, (80, 0, 25), 1.0164112, 1.5973291),
    (5.75, (80, 24, 35), 1.0150231, 1.5934570),
    (6.00, (80, 46, 45), 1.0138038, 1.5912461),
)

#: Offset designs (rod/crank, paper's e0 = e/a) for the check of the derived and printed (4).
OFFSET_CASES = ((2.0, 0.3), (3.0, 0.5), (3.0, -0.8), (4.0, 1.0), (5.0, 2.0), (6.0, -0.4))

#: The reference chart's grid: rod/crank and offset/crank (paper's e0 >= 0; e0 < 0 mirrors it).
CHART_RATIOS = (1.2, 6.0)
CHART_OFFSETS = (0.0, 2.0)
#: designs closer than this (per crank length) to the full-turn limit b = a + |e| are left blank:
#: the rod turns through 90 deg to the guide there and the velocity analog grows without bound.
CHART_MARGIN = 0.05

M0_PRIME_ERRATUM = (
    "Paper 004, eq. (3): m0' is printed (e0 + sin phi) cos phi / m0; differentiating (1), "
    "m0^2 = i^2 - (e0 + sin phi)^2, gives m0' = -(e0 + sin phi) cos phi / m0 (the minus sign is "
    "missing). The printed s0' is right with the correct m0', and so is the degree-6 polynomial "
    "(4) built from it (with the printed sign the squared condition is of degree 8)."
)

#: lambda_s published vs computed relative difference above which a row is listed as an erratum.
LAMBDA_TOL = 1e-6
#: Published angle deviation (arc-seconds) above which a row is listed as an erratum.
ANGLE_TOL_ARCSEC = 60.0


def m0(phi, i, e0):
    """Paper 004's (1): ``m0 = sqrt(i^2 - (e0 + sin phi)^2)`` (per crank length)."""
    w = e0 + np.sin(phi)
    return np.sqrt(i * i - w * w)


def m0_derivative(phi, i, e0):
    """``dm0/dphi = -(e0 + sin phi) cos phi / m0``, differentiated from (1)."""
    return -(e0 + np.sin(phi)) * np.cos(phi) / m0(phi, i, e0)


def printed_m0_derivative(phi, i, e0):
    """``m0'`` exactly as printed in (3), ``+(e0 + sin phi) cos phi / m0`` (wrong sign)."""
    return -m0_derivative(phi, i, e0)


def printed_acceleration_analog(phi, i, e0, m0_prime):
    """The printed (3): ``s0' = [m0^2 cos + m0 (1 - 2 sin^2 - e0 sin) - m0' (e0 + sin) cos] /
    m0^2`` with the derivative ``m0_prime`` (an array over ``phi``) supplied."""
    s, c = np.sin(phi), np.cos(phi)
    m = m0(phi, i, e0)
    return (m * m * c + m * (1.0 - 2.0 * s * s - e0 * s) - m0_prime * (e0 + s) * c) / (m * m)


def reference_chart(n_ratio=97, n_offset=81):
    """The reference chart of paper 004: both extremes of the velocity analog over rod/crank
    ``b/a`` and offset/crank ``e/a`` (paper's convention: ``s0`` towards the crank pivot).

    Returns a dict of arrays on the ``(n_offset, n_ratio)`` grid: ``ratio``, ``offset``,
    ``feasible`` (``b/a >= 1 + e/a + CHART_MARGIN``), ``s_max`` and ``phi_max`` (the paper's
    ``S'_v`` per crank length and its crank angle in rad, the working stroke towards the pivot),
    ``s_min`` and ``phi_min`` (the return stroke's extreme, negative), NaN where not feasible.
    Offsets below zero are the mirror image: ``s_max(-e) = -s_min(e)``.
    """
    ratio = np.linspace(*CHART_RATIOS, n_ratio)[None, :]
    offset = np.linspace(*CHART_OFFSETS, n_offset)[:, None]
    feasible = ratio >= 1.0 + offset + CHART_MARGIN
    i = np.where(feasible, ratio, 10.0)
    e0 = np.where(feasible, offset, 0.0)
    ev = extreme_velocity(1.0, i, -e0)  # mechsynth offset = -e
    nan = np.full(feasible.shape, np.nan)
    return {
        "ratio": np.broadcast_to(ratio, feasible.shape),
        "offset": np.broadcast_to(offset, feasible.shape),
        "feasible": feasible,
        "s_max": np.where(feasible, -ev.minimum.value, nan),
        "phi_max": np.where(feasible, ev.minimum.angle, nan),
        "s_min": np.where(feasible, -ev.maximum.value, nan),
        "phi_min": np.where(feasible, ev.maximum.angle, nan),
    }


def table_1():
    """Computed Table 1 rows (dicts) next to the published values, with deviations."""
    ratios = np.array([row[0] for row in TABLE_1])
    ev = extreme_velocity(1.0, ratios, 0.0)
    # Paper's s0 points towards the crank pivot: its maximum is our minimum of dx_B/dphi.
    phi0 = ev.minimum.angle
    s_v = -ev.minimum.value
    phi_u = stroke_crank_angle(1.0, ratios, 0.0)
    lam = s_v * phi_u / ev.stroke
    rows = []
    for k, (ratio, angle, s_pub, lam_pub) in enumerate(TABLE_1):
        phi_pub = dms(*angle)
        rows.append(
            {
                "lambda": ratio,
                "phi0_published": "{}°{:02d}'{:02d}\"".format(*angle),
                "phi0_computed": format_dms(phi0[k]),
                "phi0_deviation_arcsec": float(np.rad2deg(phi0[k] - phi_pub) * 3600.0),
                "S_v_published": s_pub,
                "S_v_computed": float(s_v[k]),
                "S_v_deviation": float(s_v[k] - s_pub),
                "S_v_at_published_phi0": float(velocity_analog(phi_pub, ratio, 0.0)),
                "lambda_s_published": lam_pub,
                "lambda_s_computed": float(lam[k]),
                "lambda_s_relative_deviation": float(lam_pub / lam[k] - 1.0),
            }
        )
    return rows


def _numeric_extremes(i, e0):
    """(phi_max, s0_max, phi_min, s0_min) of the paper's s0 by dense sampling + bounded search."""
    from scipy.optimize import minimize_scalar  # deferred: heavy

    grid = np.linspace(0.0, 2 * np.pi, 2001)
    s = velocity_analog(grid, i, e0)
    out = []
    for sign in (1.0, -1.0):
        k = int(np.argmax(sign * s))
        res = minimize_scalar(
            lambda p, sign=sign: -sign * velocity_analog(p, i, e0),
            bounds=(grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]),
            method="bounded",
            options={"xatol": 1e-12},
        )
        out += [float(np.mod(res.x, 2 * np.pi)), float(velocity_analog(res.x, i, e0))]
    return out


def _printed_root_error(i, e0):
    """Largest |s0'| (per crank length) at the real roots of the printed polynomial in [-1, 1],
    over both crank angles of each root: the printed roots are not extrema when it is large."""
    roots = _real_roots(printed_coefficients(i, e0))
    u = roots.real[np.abs(roots.imag) < 1e-9]
    u = u[np.abs(u) <= 1.0]
    if u.size == 0:
        return None, 0
    best = []
    for root in u:
        phis = np.array([np.arcsin(root), np.pi - np.arcsin(root)])
        best.append(np.min(np.abs(velocity_analog_derivative(phis, i, e0))))
    return float(np.max(best)), int(u.size)


def offset_check():
    """Derived vs numeric extremes and the printed polynomial's residual for offset designs."""
    rows = []
    for i, e0 in OFFSET_CASES:
        ev = extreme_velocity(1.0, i, -e0)  # mechsynth offset = -e (see the module docs)
        pmax, smax, pmin, smin = _numeric_extremes(i, e0)
        printed_err, n_printed = _printed_root_error(i, e0)
        rows.append(
            {
                "lambda": i,
                "e0": e0,
                "s0_max": -float(ev.minimum.value),
                "phi_max_deg": float(np.rad2deg(ev.minimum.angle)),
                "s0_max_numeric": smax,
                "phi_max_numeric_deg": float(np.rad2deg(pmax)),
                "s0_min": -float(ev.maximum.value),
                "phi_min_deg": float(np.rad2deg(ev.maximum.angle)),
                "s0_min_numeric": smin,
                "phi_min_numeric_deg": float(np.rad2deg(pmin)),
                "derived_vs_numeric": max(
                    abs(-ev.minimum.value - smax), abs(-ev.maximum.value - smin)
                ),
                "printed_real_roots": n_printed,
                "printed_max_residual": printed_err,
            }
        )
    return rows


def _chart_rows(chart):
    """The feasible grid points of the reference chart as CSV rows (paper's convention)."""
    ok = chart["feasible"]
    return [
        {
            "b/a": float(r),
            "e/a": float(e),
            "S_v max (towards the pivot)": float(smax),
            "phi at max [deg]": float(np.rad2deg(pmax)),
            "s0 min (return)": float(smin),
            "phi at min [deg]": float(np.rad2deg(pmin)),
        }
        for r, e, smax, pmax, smin, pmin in zip(
            *(chart[k][ok] for k in ("ratio", "offset", "s_max", "phi_max", "s_min", "phi_min"))
        )
    ]


def _chart_summary(chart):
    ok = chart["feasible"]
    return {
        "ratio_range": list(CHART_RATIOS),
        "offset_range": list(CHART_OFFSETS),
        "grid": list(ok.shape),
        "feasible_points": int(ok.sum()),
        "margin": CHART_MARGIN,
        "s_max_range": [float(np.nanmin(chart["s_max"])), float(np.nanmax(chart["s_max"]))],
        "s_min_range": [float(np.nanmin(chart["s_min"])), float(np.nanmax(chart["s_min"]))],
    }


def _fmt(value):
    return "no root" if value is None else f"{value:.3g}"


def _write_csv(path, rows):
    with atomic(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def _figure(path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plotting import LINESTYLES, PALETTE, crank_axis, style
    from ..plotting import save as save_figure

    phi = np.linspace(0.0, 2 * np.pi, 721)
    with style():
        fig, axes = plt.subplots(1, 2, figsize=(12, 5), layout="constrained", sharey=True)
        cases = (
            [(ratio, 0.0, f"b/a = {ratio:g}") for ratio in (1.75, 2.5, 4.0, 6.0)],
            [(3.0, e0, f"b/a = 3, e/a = {e0:g}") for e0 in (0.0, 0.5, 1.0, -1.0)],
        )
        for ax, group in zip(axes, cases):
            for k, (ratio, e0, label) in enumerate(group):
                colour = PALETTE[(4, 5, 3, 6)[k]]
                s = velocity_analog(phi, ratio, e0)
                ax.plot(np.rad2deg(phi), s, color=colour, ls=LINESTYLES[k], label=label)
                ev = extreme_velocity(1.0, ratio, -e0)
                for ext in (ev.minimum, ev.maximum):
                    ax.plot(np.rad2deg(ext.angle), -ext.value, "o", color=colour, mec="k")
            ax.axhline(0.0, color="0.3", lw=0.6)
            crank_axis(ax, "crank angle φ from +x, counter-clockwise")
            ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.16), ncol=2)
        axes[0].set_ylabel("velocity analog s0 = -v_B / (a ω), per crank length")
        axes[0].set_title("Centric slider-crank (paper 004, Table 1): extrema (dots)", fontsize=10)
        axes[1].set_title("Offset designs: extrema from the derived polynomial (dots)", fontsize=10)
        save_figure(fig, path, dpi=130)


def _chart_figure(path, chart):
    """The reference chart: contours of both extremes and their crank angles over b/a, e/a."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plotting import label_contours, prune_labels, style
    from ..plotting import save as save_figure

    x, y = chart["ratio"], chart["offset"]
    panels = (
        (
            "s_max",
            1.0,
            "S'_v = max s0 (working stroke, towards the pivot), per crank length",
            np.array([1.01, 1.02, 1.03, 1.05, 1.07, 1.1, 1.15, 1.2, 1.3, 1.4, 1.6, 2.0]),
        ),
        ("phi_max", 180 / np.pi, "its crank angle φ0, deg", np.arange(40.0, 90.1, 5.0)),
        (
            "s_min",
            -1.0,
            "|min s0| (return stroke), per crank length",
            np.array([1.0, 1.005, 1.01, 1.02, 1.03, 1.05, 1.07, 1.1, 1.15, 1.2, 1.3]),
        ),
        ("phi_min", 180 / np.pi, "its crank angle, deg", np.arange(240.0, 330.1, 5.0)),
    )
    with style():
        fig, axes = plt.subplots(2, 2, figsize=(11, 8.5), layout="constrained")
        for ax, (key, scale, title, levels) in zip(axes.ravel(), panels):
            z = chart[key] * scale
            lo, hi = np.nanmin(z), np.nanmax(z)
            lv = levels[(levels > lo) & (levels < hi)]
            cf = ax.contourf(x, y, z, levels=np.unique(np.r_[lo, lv, hi]), cmap="viridis")
            cs = ax.contour(x, y, z, levels=lv, colors="k", linewidths=0.7)
            label_contours(ax, cs, fmt="%.4g")
            fig.colorbar(cf, ax=ax, shrink=0.9, format="%.4g")
            edge = np.linspace(*CHART_OFFSETS, 50)
            # blank up to the first feasible grid column, hatched where no full turn exists
            step = x[0, 1] - x[0, 0]
            ax.fill_betweenx(
                edge, CHART_RATIOS[0], 1.0 + edge + CHART_MARGIN + step, color="0.93", lw=0.0
            )
            ax.fill_betweenx(
                edge, CHART_RATIOS[0], 1.0 + edge, fc="0.85", hatch="//", ec="0.55", lw=0.4
            )
            ax.plot(1.0 + edge, edge, color="0.3", lw=1.0)
            ax.set_xlim(*CHART_RATIOS)
            ax.set_ylim(*CHART_OFFSETS)
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("rod / crank b/a")
            ax.set_ylabel("offset / crank e/a")
        fig.suptitle(
            "Paper 004's reference chart: extreme slider velocity analogs of the offset "
            "slider-crank\n(hatched: b < a + e, no full turn; light grey: within "
            f"{CHART_MARGIN:g} a of it; for e < 0 read the chart at |e|, max and |min| swapped)",
            fontsize=10,
        )
        prune_labels(fig)
        save_figure(fig, path, dpi=110)


@takes_options(owner="study 'extreme-velocity'")
def run(out=None) -> StudyResult:
    """Run the study; write ``table1.csv``, ``offset_check.csv``, ``velocity_analogs.png`` and an
    animation of the b/a = 2 design into ``out`` when given."""
    names = ["Table 1", "offset designs", "reference chart"]
    names += ["figures and animation", "nomograms"] if out is not None else []
    with Stages("extreme-velocity", names) as stages:
        return _run(out, stages)


def _run(out, stages) -> StudyResult:
    stages.next("Table 1")
    rows = table_1()
    stages.next("offset designs")
    offsets = offset_check()
    stages.next("reference chart")
    chart = reference_chart()
    errata = list(ERRATA) + [M0_PRIME_ERRATUM]
    bad = [r for r in rows if abs(r["lambda_s_relative_deviation"]) > LAMBDA_TOL]
    for r in rows:
        if abs(r["phi0_deviation_arcsec"]) > ANGLE_TOL_ARCSEC:
            errata.append(
                f"Paper 004, Table 1, lambda = {r['lambda']:.2f}: phi0 printed "
                f"{r['phi0_published']}, but the extremum is at {r['phi0_computed']} "
                f"({r['phi0_deviation_arcsec']:+.0f} arc-seconds); at the printed angle s0 = "
                f"{r['S_v_at_published_phi0']:.7f}, not the printed S'_v = "
                f"{r['S_v_published']:.7f} (a misprinted angle)."
            )
    for r in bad:
        errata.append(
            f"Paper 004, Table 1, lambda = {r['lambda']:.2f}: lambda_s printed "
            f"{r['lambda_s_published']:.7f}, but (6) with S'_v = {r['S_v_computed']:.7f}, "
            f"phi_u = pi, S_u = 2 gives {r['lambda_s_computed']:.7f} "
            f"({100 * r['lambda_s_relative_deviation']:+.3f} %)."
        )
    rootless = [o for o in offsets if o["printed_real_roots"] == 0]
    wrong = [o for o in offsets if o["printed_real_roots"] > 0 and o["printed_max_residual"] > 1e-6]
    detail = "; ".join(
        f"b/a = {o['lambda']:g}, e/a = {o['e0']:g}: |s0'| = {o['printed_max_residual']:.3g} at "
        "its roots"
        for o in wrong
    )
    errata.append(
        f"Paper 004, eq. (4) as printed, on {len(offsets)} offset designs: {len(rootless)} have no "
        f"real root sin(phi0) in [-1, 1] at all, {len(wrong)} have roots that are not extrema"
        f"{' (' + detail + ')' if detail else ''}; the derived coefficients give extrema equal "
        "to a bounded numeric search."
    )

    lines = ["Paper 004 - extreme slider velocity analogs, Table 1 (e0 = 0, a = 1)", ""]
    lines.append(
        f"{'b/a':>5} {'phi0 pub':>11} {'phi0 calc':>11} {'dev s':>6} {'S_v pub':>10} "
        f"{'S_v calc':>10} {'dev':>9} {'lam_s pub':>10} {'lam_s calc':>10} {'dev %':>7}"
    )
    for r in rows:
        lines.append(
            f"{r['lambda']:5.2f} {r['phi0_published']:>11} {r['phi0_computed']:>11} "
            f"{r['phi0_deviation_arcsec']:6.1f} {r['S_v_published']:10.7f} "
            f"{r['S_v_computed']:10.7f} {r['S_v_deviation']:9.1e} "
            f"{r['lambda_s_published']:10.7f} {r['lambda_s_computed']:10.7f} "
            f"{100 * r['lambda_s_relative_deviation']:7.3f}"
        )
    summary = _chart_summary(chart)
    lines += [
        "",
        f"Reference chart (the paper's 'reference charts' of (4)-(7)): {summary['grid'][1]} x "
        f"{summary['grid'][0]} designs, b/a {CHART_RATIOS[0]:g}-{CHART_RATIOS[1]:g}, e/a "
        f"{CHART_OFFSETS[0]:g}-{CHART_OFFSETS[1]:g} ({summary['feasible_points']} with a full "
        f"turn and {CHART_MARGIN:g} a to spare); S'_v {summary['s_max_range'][0]:.4f}-"
        f"{summary['s_max_range'][1]:.4f}, return-stroke extreme "
        f"{summary['s_min_range'][0]:.4f} to {summary['s_min_range'][1]:.4f} per crank length",
    ]
    lines += ["", "Offset designs: derived polynomial vs numeric search (paper's s0 convention)"]
    lines.append(
        f"{'b/a':>5} {'e/a':>5} {'s0 max':>10} {'at deg':>8} {'s0 min':>10} {'at deg':>8} "
        f"{'|diff|':>8} {'printed resid':>13}"
    )
    for o in offsets:
        lines.append(
            f"{o['lambda']:5.2f} {o['e0']:5.2f} {o['s0_max']:10.7f} {o['phi_max_deg']:8.3f} "
            f"{o['s0_min']:10.7f} {o['phi_min_deg']:8.3f} {o['derived_vs_numeric']:8.1e} "
            f"{_fmt(o['printed_max_residual']):>13}"
        )

    files = []
    if out is not None:
        stages.next("figures and animation")
        out = Path(out)
        _write_csv(out / "table1.csv", rows)
        _write_csv(out / "offset_check.csv", offsets)
        _figure(out / "velocity_analogs.png")
        _chart_figure(out / "extreme_velocity_chart.png", chart)
        _write_csv(out / "extreme_velocity_chart.csv", _chart_rows(chart))
        design = SliderCrank(crank=1.0, rod=2.0)
        anim = design.animate(frames=36, dpi=60, trace=("B",))
        files = [out / "table1.csv", out / "offset_check.csv", out / "velocity_analogs.png"]
        files += [out / "extreme_velocity_chart.png", out / "extreme_velocity_chart.csv"]
        files.append(anim.save(out / "slider_crank_b_a_2.gif"))
        # the chart the paper says designers need, as an alignment chart: one sheet per extreme
        stages.next("nomograms")
        from ..nomograms import library

        nomograms = {}
        for extreme in ("max", "min"):
            nm = library.build("extreme-velocity", extreme=extreme)
            files.append(nm.save(out / f"nomogram_extreme_velocity_{extreme}.pdf"))
            acc = nm.accuracy
            nomograms[extreme] = {"max_error": acc.max_error, "max_error_mm": acc.max_mm}
            lines.append(
                f"Nomogram of the {extreme}imum velocity analog (alignment chart, A4 at 1:1): "
                f"reads the model to {acc.max_error:.2g} per crank length "
                f"({acc.max_mm:.2g} mm on paper) at worst"
            )

    data = {
        "source": "Dzhavadyan, extreme values of the slider velocity of a slider-crank, Table 1",
        "rows": rows,
        "offset_check": offsets,
        "lambda_s_errata_rows": [r["lambda"] for r in bad],
        "reference_chart": _chart_summary(chart),
    }
    if out is not None:
        data["nomograms"] = nomograms
    result = StudyResult("extreme-velocity", "\n".join(lines), data, files, errata)
    return COVERAGE.attach(result, out)


# ------------------------------------------------------------------------------ coverage
def _coverage():
    from .coverage import Coverage, Item

    t = "tests/test_extreme_velocity.py::"
    c = "tests/test_extreme_velocity_chart.py::"
    k = "kinematics.extreme_velocity."
    return Coverage(
        "Paper 004 (Dzhavadyan): extreme slider velocities of the slider-crank",
        "extreme-velocity",
        (
            Item(
                "Fig. 1",
                "figure",
                "scheme of the offset slider-crank OA = a, AB = b, OC = e",
                "not reproducible",
                "SliderCrank.draw",
                note="the figure is missing from the text; its notation is that of (1)-(2) and "
                "the study draws and animates the b/a = 2 design",
            ),
            Item(
                "eq. (1)",
                "equation",
                "m0 = sqrt(i^2 - (e0 + sin phi)^2)",
                "reproduced",
                "studies.extreme_velocity.m0",
                (c + "test_m0_prime_printed_without_its_minus_sign",),
            ),
            Item(
                "eq. (2)",
                "equation",
                "velocity analog s0 per crank length",
                "reproduced",
                k + "velocity_analog",
                (t + "test_acceleration_analog_formula_matches_finite_differences",),
                "equals -dx_B/dphi / a of SliderCrank to 1e-14 (the paper's s0 points towards "
                "the pivot)",
            ),
            Item(
                "eq. (3) s0'",
                "equation",
                "acceleration analog s0'",
                "reproduced",
                k + "velocity_analog_derivative",
                (
                    c + "test_printed_s0_prime_is_right_with_the_corrected_m0_prime",
                    t + "test_acceleration_analog_formula_matches_finite_differences",
                ),
                "the printed s0' with the corrected m0' equals finite differences to 1e-8",
            ),
            Item(
                "eq. (3) m0'",
                "equation",
                "m0' = dm0/dphi",
                "erratum",
                "studies.extreme_velocity.m0_derivative",
                (
                    c + "test_m0_prime_printed_without_its_minus_sign",
                    c + "test_polynomial_4_was_built_with_the_correct_sign",
                ),
                "printed without its minus sign; (4) was derived with the right one",
            ),
            Item(
                "eq. (4)",
                "equation",
                "degree-6 polynomial in sin(phi0) of s0' = 0",
                "erratum",
                k + "polynomial_coefficients",
                (
                    t + "test_polynomial_vanishes_at_the_numeric_extrema",
                    t + "test_polynomial_is_the_squared_extremum_condition",
                    t + "test_offset_extremes_match_numeric_search",
                ),
                "p6 printed as p0, sign of e0^2 i^2 in p3, p0 wrong: for e0 != 0 the printed "
                "roots are no extrema; derived coefficients used",
            ),
            Item(
                "eq. (4), e0 = 0",
                "equation",
                "the centric cubic in sin^2(phi0)",
                "reproduced",
                k + "polynomial_coefficients",
                (t + "test_centric_polynomial_reduces_to_the_printed_cubic",),
            ),
            Item(
                "eq. (5)",
                "equation",
                "absolute extreme velocity analog S'_v",
                "reproduced",
                k + "extreme_velocity",
                (
                    t + "test_offset_extremes_match_numeric_search",
                    t + "test_batch_equals_single_designs",
                ),
                "any a, b, e: equal to a bounded numeric search to 1e-10",
            ),
            Item(
                "eq. (6)",
                "equation",
                "velocity coefficient lambda_s = S'_v phi_u / S_u",
                "reproduced",
                k + "Extremum.lambda_s",
                (t + "test_table_1_row",),
            ),
            Item(
                "eq. (7)",
                "equation",
                "stroke S_u and its crank angle phi_u",
                "reproduced",
                k + "stroke_crank_angle",
                (t + "test_stroke_crank_angle_formula_7_matches_dead_centres",),
                "the sign lost in the conversion ('lower sign'): phi_u = pi + arccos(...) is the "
                "longer stroke",
            ),
            Item(
                "Table 1, S'_v",
                "table",
                "extreme velocity analog for 18 rod/crank ratios",
                "reproduced",
                "table1.csv",
                (t + "test_table_1_row", c + "test_chart_centric_row_is_table_1"),
                "to 1.02e-7 (one unit of the 7th decimal; 1.011e-7 at b/a = 2.00)",
            ),
            Item(
                "Table 1, phi0",
                "table",
                "crank angle of the extremum",
                "reproduced",
                "table1.csv",
                (t + "test_table_1_row",),
                "to 20 arc-seconds, except b/a = 5.25",
            ),
            Item(
                "Table 1, phi0 at b/a = 5.25",
                "table",
                "printed 79°31'14\"",
                "erratum",
                "table1.csv",
                (t + "test_table_1_row", t + "test_study_rows_and_errata"),
                "the extremum is at 79°34'24\"; the printed angle gives s0 = 1.0180004, not the "
                "printed S'_v",
            ),
            Item(
                "Table 1, lambda_s",
                "table",
                "velocity coefficient column",
                "erratum",
                "table1.csv",
                (t + "test_lambda_s_erratum_two", t + "test_table_1_row"),
                "does not follow from (6) with phi_u = pi, S_u = 2 (up to 0.6 %: 1.7643 for "
                "1.7751 at b/a = 2)",
            ),
            Item(
                "reference charts",
                "finding",
                "eqs. (4)-(7) solved for designers' reference charts",
                "added",
                "extreme_velocity_chart.png",
                (
                    c + "test_chart_centric_row_is_table_1",
                    c + "test_chart_against_dense_sampling_and_mirror",
                    c + "test_chart_figure_is_clean",
                ),
                "contours of both extremes and their angles over b/a 1.2-6, e/a 0-2",
            ),
        ),
    )


COVERAGE = _coverage()

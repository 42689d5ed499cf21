"""Draw the figures of docs/charts.md (run from the repository root):

* docs/figures/slider_crank_chart.png -- the slider-crank design chart at a 100 mm stroke,
  600 rpm, with the 30 deg pressure-angle limit and a 0.2 m rod-length limit;
* docs/figures/slider_crank_pareto.png -- the Pareto front of peak slider acceleration against
  max pressure angle for the same stroke (crank 10-200 mm, rod 50-200 mm, offset +-100 mm);
* docs/figures/convex_shaking_force.png -- the certified minimax shaking force of a slider-crank
  over its counterweight moment and slider mass, with the unbalanced force for comparison.

Prints the numbers quoted in docs/charts.md.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth import objectives as ob  # noqa: E402
from mechsynth.synthesis.charts import slider_crank_chart  # noqa: E402
from mechsynth.synthesis.convex import minimax_cycle  # noqa: E402
from mechsynth.synthesis.pareto import pareto_front  # noqa: E402

OMEGA = ms.rpm(600)
SC = ms.SliderCrank(crank=0.05, rod=0.2, offset=0.02)


def shaking_force(x, phi, m_pin=0.8):
    """Resultant inertia force (N) with a crank-pin mass, slider mass x[1] and a counterweight of
    mass-radius product x[0] (kg m) opposite the crank pin."""
    m = SC.motion(phi, speed=OMEGA)
    a, b = m.points["A"], m.points["B"]
    fx = m_pin * a.ax + x[1] * b.ax + x[0] * OMEGA**2 * np.cos(phi)
    fy = m_pin * a.ay + x[1] * b.ay + x[0] * OMEGA**2 * np.sin(phi)
    return np.stack([fx, fy], axis=-1)


def main(folder=Path(__file__).parent / "figures"):
    folder.mkdir(parents=True, exist_ok=True)

    chart = slider_crank_chart(
        0.1, np.linspace(1.5, 6.0, 121), np.linspace(0.0, 1.6, 121), progress=False
    )
    limits = {"max pressure angle": ("<=", ms.deg(30)), "rod length": ("<=", 0.2)}
    fig = chart.plot(
        measures=["peak slider acceleration", "max pressure angle", "time ratio"],
        limits=limits,
        best="peak slider acceleration",
        title="Slider-crank, stroke 100 mm, 600 rpm: 121 x 121 designs, 360 crank angles",
    )
    fig.savefig(folder / "slider_crank_chart.png", dpi=110)
    plt.close(fig)
    best = chart.argbest("peak slider acceleration", where=limits)
    print(f"chart ({chart.elapsed:.2f} s): best grid design {best}")

    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=OMEGA,
    ).subject_to(ob.stroke("slider") == 0.1)
    fr = pareto_front(
        prob,
        ob.peak_acceleration("slider"),
        ob.max_pressure_angle(),
        eps=ms.deg([50.0, 45.0, 40.0, 35.0, 30.0, 25.0, 20.0]),
    )
    fig = fr.plot(title="Peak slider acceleration vs max pressure angle, stroke 100 mm, 600 rpm")
    fig.savefig(folder / "slider_crank_pareto.png", dpi=110)
    plt.close(fig)
    print(f"Pareto front ({fr.solve_time:.1f} s):")
    for i, r in enumerate(fr.results):
        v = r.variables
        print(
            f"  eps {np.rad2deg(fr.eps[i]):7.3f} deg: a = {fr.first[i]:.7g} m/s^2, pressure "
            f"{np.rad2deg(fr.second[i]):.4f} deg, crank {v['crank'] * 1e3:.3f} mm, rod "
            f"{v['rod'] * 1e3:.3f} mm, offset {v['offset'] * 1e3:.3f} mm ({r.status})"
        )

    bounds = [(0.0, 0.2), (0.5, 2.0)]
    res = minimax_cycle(
        shaking_force, [0.0, 0.5], 72, norm="euclidean", bounds=bounds, names=["u", "m_slider"]
    )
    phi = ms.cycle(720)
    ref = np.linalg.norm(shaking_force(np.array([0.0, 0.5]), phi), axis=-1)
    opt = np.linalg.norm(shaking_force(res.x, phi), axis=-1)
    fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
    deg = np.rad2deg(phi)
    ax.plot(deg, ref, color="0.55", lw=1.3, label=f"no counterweight: peak {ref.max():.4g} N")
    ax.plot(deg, opt, color="C0", lw=1.6, label=f"minimax counterweight: peak {res.value:.4g} N")
    for a in res.active_angles:
        ax.axvline(np.rad2deg(a), color="C3", lw=0.7, ls=":")
    ax.set_xlabel("crank angle, deg")
    ax.set_ylabel("|shaking force|, N")
    ax.set_title(
        f"SOCP: u = {res.x[0] * 1e3:.3f} kg mm, slider mass {res.x[1]:.3g} kg "
        f"({res.status}, {res.extra['rounds']} refinement rounds)",
        fontsize=10,
    )
    ax.grid(True, alpha=0.4)
    ax.legend(fontsize=8)
    fig.savefig(folder / "convex_shaking_force.png", dpi=110)
    plt.close(fig)
    print(res.report())
    print(res.extra)


if __name__ == "__main__":
    main()

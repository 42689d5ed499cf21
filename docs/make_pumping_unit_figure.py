"""Draw docs/figures/pumping_units.png: a conventional unit (C-320D-256-120) and a Mark II
(M-912D-365-168) at their dead centres and at 90 deg, with the torque factor against the crank
angle. Run from the repository root: python docs/make_pumping_unit_figure.py"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mechsynth as ms  # noqa: E402

OUT = Path(__file__).resolve().parent / "figures" / "pumping_units.png"


def main(out=OUT):
    units = {
        "C-320D-256-120, conventional, cw": ms.BeamPumpingUnit.from_api(
            A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in"
        ),
        "M-912D-365-168, Mark II, ccw": ms.BeamPumpingUnit.from_api(
            A=334.0, C=270.0, I=202.56, P=193.5, R=63.56, H=295.13, G=112.13,
            unit_class="mark-ii", rotation="ccw", units="in",
        ),
    }  # fmt: skip
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    theta = ms.cycle(720)
    for col, (name, u) in enumerate(units.items()):
        ax = axes[0, col]
        bottom, top = (float(t) for t in u.dead_centres)
        positions = (
            (bottom, "#0072B2", "bottom", "o"),
            (top, "#D55E00", "top", "s"),
            (np.pi / 2, "0.6", "90", "^"),
        )
        for k, (t, c, lab, mk) in enumerate(positions):
            u.draw(t, ax=ax, color=c, alpha=0.9, labels=k == 0)
            # the pose's crank pin A marked: the poses told apart by shape, not colour alone
            pin = u.motion(np.array([t])).points["A"]
            ax.plot(pin.x, pin.y, mk, color=c, mec="k", ms=7, ls="none", zorder=5,
                    label=f"{lab}: {np.rad2deg(t):.1f} deg")  # fmt: skip
        ax.set_title(name)
        # beside the drawing, not over the crank
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), title="crank at")
        ax = axes[1, col]
        ax.plot(np.rad2deg(theta), ms.to_inch(u.torque_factor(theta)))
        ax.axhline(0, color="k", lw=0.6)
        ax.axvline(np.rad2deg(bottom), color="#0072B2", ls="--", label="bottom dead centre")
        ax.axvline(np.rad2deg(top), color="#D55E00", ls="-.", label="top dead centre")
        ax.legend(fontsize=8, loc="upper right" if col == 0 else "upper left")  # clear of the curve
        ax.set_xlabel("crank angle from 12 o'clock in the direction of rotation, deg")
        ax.set_ylabel("torque factor, in")
        ax.set_title(f"stroke {ms.to_inch(u.stroke):.2f} in, upstroke "
                     f"{np.rad2deg(u.upstroke_span):.1f} deg")  # fmt: skip
        ax.grid(True, alpha=0.4)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100)
    return out


if __name__ == "__main__":
    print(main())

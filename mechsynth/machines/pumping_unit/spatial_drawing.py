"""The spatial double-crank drive drawn in 3-D: an animation of its real geometry over the cycle.

The drive's motion (:meth:`SpatialPumpingUnit.motion`) gives every joint in 3-D: the crankshaft
N with the crank arms' centres O (left) and O1 (right), the crank pins A and A1, the equalizer
B-D-B1, the saddle bearing C and the horsehead point E. :func:`animate_drive` draws them on a
matplotlib 3-D axes with equal scales on its three axes (a metre is as long along the shaft as
up or toward the well), the frame parts still and the links moving, and returns a
:class:`~mechsynth.kinematics.drawing.MechanismAnimation` (``.save("drive.gif")``).

The view keeps the planar unit's frame: x toward the well, y up (drawn vertical), z along the
crankshaft to the unit's right.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ...errors import MechanismError
from ...plotting import PALETTE

__all__ = ["animate_drive"]

#: the links drawn: (label, points, colour, line style, width, marker)
_LINKS = (
    ("left crank arm and pitman (O-A-B)", ("O", "A", "B"), PALETTE[5], "-", 2.4, "o"),
    ("right crank arm and pitman (O1-A1-B1)", ("O1", "A1", "B1"), PALETTE[4], "--", 2.4, "o"),
    ("equalizer (B-D-B1)", ("B", "D", "B1"), PALETTE[0], "-", 4.0, "D"),
    ("beam (D-C-E)", ("D", "C", "E"), PALETTE[0], "-", 1.6, "s"),
)


def animate_drive(
    drive,
    angles=None,
    speed=None,
    *,
    frames: int = 36,
    figsize=(8.0, 5.0),
    dpi: int = 60,
    title: str | None = None,
    view=(22.0, -38.0),
):
    """Animate the spatial drive ``drive`` (a :class:`SpatialPumpingUnit` of one design) in 3-D.

    Parameters
    ----------
    angles : crank angles (rad, the planar unit's convention); default ``frames`` angles over
        one turn in the machine's direction.
    speed : crank speed (rad/s) or None: with a speed the frames show the time and play in real
        time when the turn lasts 1-20 s (else about 3 s per turn, as the planar animations).
    frames : number of frames when ``angles`` is not given (at least 2).
    figsize, dpi : figure size (in) and resolution.
    title : first title line (default: the drive's crank spacing and equalizer width).
    view : (elevation, azimuth) of the camera, deg.

    Returns
    -------
    MechanismAnimation
        ``.save("x.gif")`` writes a GIF (pillow); ``.figure`` is the matplotlib figure.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    from ...kinematics.drawing import MechanismAnimation, _playback

    if angles is None:
        if int(frames) < 2:
            raise MechanismError(f"frames must be at least 2, got {frames!r}")
        angles = drive.sense * np.linspace(0.0, 2.0 * np.pi, int(frames), endpoint=False)
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    if angles.ndim != 1 or angles.size < 2 or not np.all(np.isfinite(angles)):
        raise MechanismError("angles must be at least two finite crank angles (rad)")
    if np.ndim(drive.crank) or np.ndim(drive.pitman):
        raise MechanismError("animate_drive draws one design, not a batch")
    m = drive.motion(angles)
    pos = {k: np.asarray(p.position, dtype=float) for k, p in m.points.items()}
    n = angles.size
    dt, interval, playback = _playback(SimpleNamespace(angles=angles), speed, None)

    fig = Figure(figsize=figsize, dpi=dpi, layout="none")  # by hand: a layout cuts 3-D labels
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.06, 0.1, 0.64, 0.76), projection="3d")
    ax.view_init(elev=view[0], azim=view[1], vertical_axis="y")

    # still: the crankshaft O-O1, the saddle bearing C, the crank pins' circles and the
    # horsehead point's arc
    every = np.concatenate([p.reshape(-1, 3) for p in pos.values()])
    lo, hi = every.min(axis=0), every.max(axis=0)
    grey = "0.55"
    ax.plot(*_columns(pos["O"][0], pos["O1"][0]), color=grey, lw=3.0, label="crankshaft O-O1")
    c = pos["C"][0]
    ax.plot(*_columns(c), color=grey, ls="none", marker="^", ms=7, label="saddle bearing C")
    for k in ("A", "A1", "E"):
        ax.plot(*pos[k].T, color=grey, lw=0.6, ls=":")
    moving = []
    for label, names, colour, ls, lw, marker in _LINKS:
        (line,) = ax.plot([], [], [], color=colour, ls=ls, lw=lw, label=label, marker=marker, ms=3)
        moving.append((line, names))

    # equal scales: the box as long on each axis as the drawing is
    span = np.maximum(hi - lo, 1e-9)
    margin = 0.06 * span.max()
    ax.set_xlim(lo[0] - margin, hi[0] + margin)
    ax.set_ylim(lo[1] - margin, hi[1] + margin)
    ax.set_zlim(lo[2] - margin, hi[2] + margin)
    ax.set_box_aspect(tuple(span + 2.0 * margin), zoom=1.1)
    ax.set_xlabel("x (toward the well), m", fontsize=8, labelpad=2)
    ax.set_ylabel("y (up), m", fontsize=8, labelpad=2)
    ax.set_zlabel("z (shaft), m", fontsize=8, labelpad=2)
    ax.tick_params(labelsize=7, pad=0)
    ax.zaxis.set_major_locator(MaxNLocator(3))  # the shaft is short: three ticks
    fig.legend(loc="center right", fontsize=7, frameon=False)
    head = title or (
        f"Spatial double-crank drive: crank spacing {float(drive.crank_spacing):.3g} m, "
        f"equalizer width {float(drive.equalizer_width):.3g} m"
    )
    fig.suptitle(f"{head}\ncrank angle from 12 o'clock, {playback}", fontsize=9)
    text = ax.text2D(0.02, 0.96, "", transform=ax.transAxes, fontsize=8)

    def update(i):
        for line, names in moving:
            xyz = np.array([pos[k][i] for k in names])
            line.set_data_3d(xyz[:, 0], xyz[:, 1], xyz[:, 2])
        when = "" if dt is None else f",  t = {i * dt:.3g} s"
        shown = np.degrees(np.mod(abs(angles[i]), 2.0 * np.pi))
        text.set_text(f"crank angle {shown:.0f} deg{when}")
        return [line for line, _ in moving] + [text]

    update(0)
    return MechanismAnimation(
        fig, update, n, 1.0 / interval, playback, moving=[line for line, _ in moving] + [text]
    )


def _columns(*points):
    """The x, y and z columns of a polyline through ``points``."""
    return np.asarray(points, dtype=float).T

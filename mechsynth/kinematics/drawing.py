"""Draw and animate any mechanism from its :class:`~mechsynth.kinematics.sketch.Sketch`.

One renderer for every mechanism: links as bars and plates, joints as pins, frame pivots with
hatching, fixed guides hatched over the slider's travel, slots carried by links, extra outlines
(a horsehead, a bridle), the traced paths of chosen points and the point names. Coordinates are
shown in the display length unit (:mod:`mechsynth.display`).

:func:`draw_sketch` draws one frame into an axes; :func:`animate_sketch` returns a
:class:`MechanismAnimation` (a matplotlib ``FuncAnimation``) that saves to GIF with pillow, to
MP4 where ffmpeg is installed, and gives an HTML snippet for notebooks (``to_html()``; a notebook
shows it by itself).

This module imports matplotlib; mechanisms import it only when they draw.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib import animation as manim

from .. import display
from ..errors import MechanismError
from ..plotting import PALETTE, equal_axes
from .sketch import Sketch

__all__ = ["draw_sketch", "animate_sketch", "MechanismAnimation"]

FRAME_COLOUR = "0.15"
LINK_COLOUR = PALETTE[4]
TRACE_COLOURS = (PALETTE[5], PALETTE[3], PALETTE[6], PALETTE[1], PALETTE[2])


#: dash patterns of traced paths (the links are solid)
_TRACE_STYLES = ("--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)))


def _parts(text: str) -> list[str]:
    """``text`` split at ``", "`` outside parentheses (``"a, b (c, d)"``: ``a``, ``b (c, d)``)."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        depth += (ch == "(") - (ch == ")")
        if depth == 0 and text.startswith(", ", i):
            parts.append(text[start:i])
            start = i + 2
    return [*parts, text[start:]]


def _wrapped(text: str, width: int = 64) -> str:
    """``text`` broken into lines at ``", "`` (never inside a value and its unit, nor inside
    parentheses)."""
    lines, line = [], ""
    for part in _parts(text):
        candidate = f"{line}, {part}" if line else part
        if line and len(candidate) > width:
            lines.append(line + ",")
            line = part
        else:
            line = candidate
    return "\n".join([*lines, line])


def _angle_text(sketch: Sketch, frame: int, short: bool = False) -> str:
    """``"crank angle φ = 30.0°"`` (``"φ = 30.0°"`` when short), in [0, 360) deg or rad; a
    length input (a driving slider's displacement) in display length units."""
    name = sketch.angle_symbol if short else sketch.angle_label
    if getattr(sketch, "angle_unit", "rad") == "m":
        return f"{name} = {display.fmt(float(np.asarray(sketch.angles)[frame]), 'm', 4)}"
    value = display.angle_position(float(np.asarray(sketch.angles)[frame]))
    if display.current().angle == "deg":
        return f"{name} = {value:.1f}°"
    return f"{name} = {value:.3f} rad"


def _rectangle(**style):
    """A four-cornered patch whose corners each frame sets (a slider block, a slot)."""
    from matplotlib.patches import Polygon

    return Polygon(np.zeros((4, 2)), closed=True, **style)


class _Scene:
    """The artists of one sketch in one axes, updated frame by frame."""

    def __init__(self, sketch: Sketch, ax, *, trace=(), color=None, alpha=1.0, labels=True):
        from matplotlib.patches import Polygon

        self.sketch, self.ax = sketch, ax
        self.L = display.current().factor("m")
        colour = LINK_COLOUR if color is None else color
        x0, x1, y0, y1 = sketch.extent()
        span = max(x1 - x0, y1 - y0, 1e-12) / self.L
        self.s = 0.03 * span  # symbol size in display units
        kw = dict(color=colour, alpha=alpha)
        pins = (
            sketch.joints
            if sketch.joints is not None
            else [p for bar in sketch.bars for p in bar.points]
        )
        self.moving = list(dict.fromkeys(p for p in pins if p not in sketch.ground))
        self.bars = []
        for bar in sketch.bars:
            if bar.closed:
                patch = Polygon(
                    np.zeros((len(bar.points), 2)),
                    closed=True,
                    facecolor=colour,
                    edgecolor=colour,
                    alpha=0.18 * alpha,
                    lw=1.5,
                    zorder=2,
                )
                ax.add_patch(patch)
                edge = ax.plot([], [], lw=2.2, solid_capstyle="round", zorder=3, **kw)[0]
                self.bars.append((bar, patch, edge))
            else:
                line = ax.plot([], [], lw=2.6, solid_capstyle="round", zorder=3, **kw)[0]
                self.bars.append((bar, None, line))
        self.outlines = []
        for o in sketch.outlines:
            if o.kind == "frame":
                style = dict(color=FRAME_COLOUR, lw=2.0, alpha=alpha, zorder=1)
            elif o.kind == "thin":
                style = dict(color=colour, lw=1.0, alpha=alpha, zorder=2)
            else:
                style = dict(lw=2.2, zorder=3, **kw)
            self.outlines.append((o, ax.plot([], [], **style)[0]))
        self._draw_ground(alpha)
        self.blocks, self.slots = [], []
        for sl in sketch.sliders:
            block = ax.add_patch(
                _rectangle(facecolor="white", edgecolor=colour, lw=1.6, alpha=alpha, zorder=4)
            )
            self.blocks.append((sl, block))
            if sl.through is None:
                self._draw_guide(sl, alpha)
            else:
                slot = ax.add_patch(
                    _rectangle(facecolor="none", edgecolor=colour, lw=1.3, alpha=alpha, zorder=3)
                )
                self.slots.append((sl, slot, self._slot_range(sl)))
        self.joints = ax.plot(
            [],
            [],
            "o",
            ms=5.5,
            mfc="white",
            mec=colour,
            mew=1.4,
            ls="none",
            alpha=alpha,
            zorder=5,
        )[0]
        self.traces = []
        for i, name in enumerate(trace or ()):
            if name not in sketch.points:
                raise MechanismError(
                    f"cannot trace {name!r}: the mechanism's points are {', '.join(sketch.points)}"
                )
            x, y = sketch.points[name]
            c = TRACE_COLOURS[i % len(TRACE_COLOURS)]
            path = ax.plot(
                np.append(x, x[:1]) / self.L,
                np.append(y, y[:1]) / self.L,
                ls=_TRACE_STYLES[i % len(_TRACE_STYLES)],  # told apart by dash, not colour alone
                lw=1.1,
                color=c,
                zorder=1.5,
                label=f"path of {name}",
            )[0]
            self.traces.append(path)
        self.artists = [a for _, patch, line in self.bars for a in (patch, line) if a is not None]
        self.artists += [line for o, line in self.outlines if np.ndim(o.x) == 2]
        self.artists += [b for _, b in self.blocks] + [s for _, s, _ in self.slots]
        self.artists.append(self.joints)
        names = sketch.labels if sketch.labels is not None else self.moving + list(sketch.ground)
        self.labels = []
        if labels:
            for name in names:
                ann = ax.annotate(
                    name,
                    (0.0, 0.0),
                    xytext=(5, 4),
                    textcoords="offset points",
                    fontsize=8,
                    color="0.2",
                    zorder=6,
                )
                self.labels.append((name, ann))
                if name not in sketch.ground:
                    self.artists.append(ann)

    # ------------------------------------------------------------------ static parts
    def _xy(self, name, frame):
        x, y = self.sketch.points[name]
        return float(x[frame]) / self.L, float(y[frame]) / self.L

    def _draw_ground(self, alpha):
        s = self.s
        for g in self.sketch.ground:
            x, y = self._xy(g, 0)
            tri = np.array([[x, y], [x - 0.9 * s, y - 1.5 * s], [x + 0.9 * s, y - 1.5 * s], [x, y]])
            self.ax.plot(tri[:, 0], tri[:, 1], color=FRAME_COLOUR, lw=1.2, alpha=alpha, zorder=1)
            self._hatch((x - 1.6 * s, y - 1.5 * s), (x + 1.6 * s, y - 1.5 * s), alpha)
            self.ax.plot(
                [x], [y], "o", ms=5.5, mfc="white", mec=FRAME_COLOUR, mew=1.4, alpha=alpha, zorder=5
            )

    def _hatch(self, p, q, alpha):
        """A frame line from p to q with short hatch strokes on its right side (seen from p)."""
        p, q = np.asarray(p, float), np.asarray(q, float)
        d = q - p
        length = float(np.hypot(*d))
        if length == 0:
            return
        u = d / length
        n = np.array([u[1], -u[0]])  # right-hand normal
        k = max(int(length / (0.6 * self.s)), 2)
        t = np.linspace(0.0, 1.0, k)
        starts = p[None, :] + t[:, None] * d[None, :]
        ends = starts + 0.7 * self.s * (n - u)[None, :]
        segs = np.full((k * 3, 2), np.nan)
        segs[0::3], segs[1::3] = starts, ends
        self.ax.plot(*zip(p, q), color=FRAME_COLOUR, lw=1.2, alpha=alpha, zorder=1)
        self.ax.plot(segs[:, 0], segs[:, 1], color=FRAME_COLOUR, lw=0.7, alpha=alpha, zorder=1)

    def _draw_guide(self, sl, alpha):
        x, y = self.sketch.points[sl.point]
        p = np.stack([x, y], axis=1) / self.L
        a = self.sketch.slider_angle(sl, 0)
        u, n = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        t = p @ u
        c = float(np.mean(p @ n)) - 0.7 * self.s  # the block's lower face rests on the guide
        lo, hi = float(t.min()) - 2.0 * self.s, float(t.max()) + 2.0 * self.s
        self._hatch(lo * u + c * n, hi * u + c * n, alpha)

    def _slot_range(self, sl):
        x, y = self.sketch.points[sl.point]
        qx, qy = self.sketch.points[sl.through]
        a = np.broadcast_to(np.asarray(sl.angle, dtype=float), x.shape)
        t = ((x - qx) * np.cos(a) + (y - qy) * np.sin(a)) / self.L
        return float(t.min()) - 1.6 * self.s, float(t.max()) + 1.6 * self.s

    # ------------------------------------------------------------------ frames
    def _box(self, centre, a, half_u, half_n):
        """Corners of a rectangle centred at ``centre``, ``2 half_u`` long along ``a``."""
        u, n = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        c = np.asarray(centre)
        return np.array(
            [
                c - half_u * u - half_n * n,
                c + half_u * u - half_n * n,
                c + half_u * u + half_n * n,
                c - half_u * u + half_n * n,
            ]
        )

    def update(self, frame: int):
        sk = self.sketch
        for bar, patch, line in self.bars:
            xy = np.array([self._xy(p, frame) for p in bar.points])
            if patch is not None:
                patch.set_xy(xy)
                xy = np.vstack([xy, xy[:1]])
            line.set_data(xy[:, 0], xy[:, 1])
        for o, line in self.outlines:
            x, y = sk.outline_xy(o, frame)
            line.set_data(np.asarray(x) / self.L, np.asarray(y) / self.L)
        for sl, block in self.blocks:
            a = sk.slider_angle(sl, frame)
            block.set_xy(self._box(self._xy(sl.point, frame), a, 1.2 * self.s, 0.7 * self.s))
        for sl, slot, (lo, hi) in self.slots:
            a = sk.slider_angle(sl, frame)
            q = np.asarray(self._xy(sl.through, frame))
            u = np.array([np.cos(a), np.sin(a)])
            centre = q + 0.5 * (lo + hi) * u
            slot.set_xy(self._box(centre, a, 0.5 * (hi - lo), 0.85 * self.s))
        xy = (
            np.array([self._xy(p, frame) for p in self.moving]) if self.moving else np.zeros((0, 2))
        )
        self.joints.set_data(xy[:, 0], xy[:, 1])
        blocks = {sl.point: sl for sl, _ in self.blocks}
        for name, ann in self.labels:
            x, y = self._xy(name, frame)
            sl = blocks.get(name)
            if sl is not None:  # beyond the corner of its slider block, not on it
                a = sk.slider_angle(sl, frame)
                x += self.s * (1.25 * np.cos(a) - 0.75 * np.sin(a))
                y += self.s * (1.25 * np.sin(a) + 0.75 * np.cos(a))
            ann.xy = (x, y)
        return []

    def limits(self):
        x0, x1, y0, y1 = (v / self.L for v in self.sketch.extent())
        pad = 2.5 * self.s
        return x0 - pad, x1 + pad, y0 - 3.0 * self.s, y1 + pad


def _figsize(sketch: Sketch, width: float) -> tuple[float, float]:
    """A figure size whose axes fit the sketch's aspect ratio (titles and labels added)."""
    x0, x1, y0, y1 = sketch.extent()
    ratio = (y1 - y0 + 1e-12) / (x1 - x0 + 1e-12)
    return width, float(np.clip(0.8 * width * ratio + 1.9, 3.4, 1.2 * width))


def _prepare_axes(ax, scene: _Scene, sketch: Sketch, fresh: bool):
    x0, x1, y0, y1 = scene.limits()
    if fresh:
        equal_axes(ax, "box")  # marked: layout_problems checks the scales stay equal
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
    else:
        equal_axes(ax, "datalim")
        ax.update_datalim([(x0, y0), (x1, y1)])
        ax.autoscale_view()
    unit = display.current().unit("m")
    ax.set_xlabel(f"{sketch.xlabel}, {unit}")
    ax.set_ylabel(f"y, {unit}")
    ax.grid(True, alpha=0.25, ls=":")


def draw_sketch(
    sketch: Sketch,
    frame: int = 0,
    ax=None,
    *,
    trace=(),
    color=None,
    alpha: float = 1.0,
    labels: bool = True,
    title=None,
):
    """Draw frame ``frame`` of ``sketch`` (the other frames give the guides' travel, the traced
    paths and the axis limits). Returns the axes.

    ``title``: None gives a title (design and crank angle) on a new axes and none on a given
    one; a string sets it; False sets none.
    """
    import matplotlib.pyplot as plt

    fresh = ax is None
    if fresh:
        _, ax = plt.subplots(figsize=_figsize(sketch, 7.0), layout="constrained")
    scene = _Scene(sketch, ax, trace=trace, color=color, alpha=alpha, labels=labels)
    scene.update(frame)
    _prepare_axes(ax, scene, sketch, fresh)
    if isinstance(title, str):
        ax.set_title(title, fontsize=10)
    elif title is None and fresh:
        text = f"{_wrapped(sketch.name)}\n{_angle_text(sketch, frame)}"
        ax.set_title(text, fontsize=10)
        extra = text.count("\n") - 1  # the size leaves room for two lines of title
        if extra > 0:  # a long design name: a taller figure, not a title cut at the top
            fig = ax.figure
            fig.set_figheight(fig.get_figheight() + 0.2 * extra)
    if trace:
        ax.legend(loc="best", fontsize=8)
    return ax


# ------------------------------------------------------------------------------ animation
class MechanismAnimation(manim.FuncAnimation):
    """A mechanism moving: a matplotlib ``FuncAnimation`` that knows how to save itself.

    ``save("x.gif")`` writes a GIF with pillow (always available), ``save("x.mp4")`` an MP4
    with ffmpeg (a clear error when ffmpeg is not installed), ``save("x.html")`` a
    stand-alone page; ``to_html()`` gives the HTML snippet a notebook shows (a notebook also
    shows the object by itself).

    Attributes
    ----------
    figure : the matplotlib figure.
    n_frames : number of frames; ``playback_fps`` frames per second of the playback.
    playback : how the playback relates to the machine's time (``"real time"``, ``"slowed
        x 20"``, or ``"3 s per turn"`` without a speed).
    """

    def __init__(self, fig, func, n_frames, playback_fps, playback, moving=()):
        super().__init__(fig, func, frames=n_frames, interval=1e3 / playback_fps, blit=False)
        self.n_frames, self.playback_fps, self.playback = n_frames, playback_fps, playback
        self._moving = list(moving)

    @property
    def figure(self):
        return self._fig

    def save(self, filename, writer=None, fps=None, dpi=None, **kwargs):
        """Write the animation to ``filename``: the writer follows the extension (.gif:
        pillow, .mp4: ffmpeg, .html: embedded frames) unless given. Returns the path."""
        from ..fileio import atomic_path

        path = Path(filename)
        fps = self.playback_fps if fps is None else fps
        if writer is None:
            ext = path.suffix.lower()
            if ext == ".gif":
                with atomic_path(path) as tmp:  # no half-written file, ever
                    self._save_gif(tmp, fps, dpi)
                return path
            if ext in (".mp4", ".m4v", ".mov"):
                if not manim.writers.is_available("ffmpeg"):
                    raise MechanismError(
                        f"cannot write {path.name}: MP4 needs ffmpeg, which is not "
                        "installed; save as .gif (pillow) or .html instead"
                    )
                writer = manim.FFMpegWriter(fps=fps)
            elif ext in (".html", ".htm"):
                writer = manim.HTMLWriter(fps=fps, embed_frames=True)
            else:
                raise MechanismError(
                    f"cannot write {path.name}: give a .gif, .mp4 or .html file name"
                )
        with atomic_path(path) as tmp:
            super().save(str(tmp), writer=writer, dpi=dpi, **kwargs)
        return path

    def frames_rgb(self, dpi=None):
        """Every frame as an RGB array (height, width, 3), drawn by blitting: the still parts
        (axes, ticks, frame pivots, guides, paths) once, the moving links per frame."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        fig = self._fig
        if dpi is not None:
            fig.set_dpi(dpi)
        canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
        for a in self._moving:
            a.set_animated(True)
        self._draw_was_started = True  # rendered (matplotlib warns about unrendered animations)
        try:
            canvas.draw()
            background = canvas.copy_from_bbox(fig.bbox)
            frames = []
            for i in range(self.n_frames):
                self._func(i)
                canvas.restore_region(background)
                for a in self._moving:
                    fig.draw_artist(a)
                frames.append(np.asarray(canvas.buffer_rgba())[..., :3].copy())
        finally:
            for a in self._moving:
                a.set_animated(False)
        return frames

    def _save_gif(self, path, fps, dpi):
        from PIL import Image

        frames = self.frames_rgb(dpi)
        # one palette for all frames (from the first: the colours do not change), no dither
        first = Image.fromarray(frames[0]).quantize(colors=128, method=Image.Quantize.FASTOCTREE)
        images = [first] + [
            Image.fromarray(f).quantize(palette=first, dither=Image.Dither.NONE) for f in frames[1:]
        ]
        images[0].save(
            path,
            format="GIF",
            save_all=True,
            append_images=images[1:],
            duration=int(round(1e3 / fps)),
            loop=0,
            optimize=False,
        )
        return path

    def to_html(self) -> str:
        """An HTML snippet (a JavaScript player with the frames embedded) for notebooks."""
        return self.to_jshtml(fps=self.playback_fps)

    def _repr_html_(self) -> str:
        return self.to_html()


def _playback(sketch: Sketch, speed, duration):
    """(machine seconds per frame or None, playback seconds per frame, playback text)."""
    length = getattr(sketch, "angle_unit", "rad") == "m"
    angles = np.asarray(sketch.angles, dtype=float)
    angles = angles if length else np.unwrap(angles)
    n = angles.size
    step = float(np.median(np.abs(np.diff(angles)))) if n > 1 else 2.0 * np.pi
    step = step if step > 0 else 2.0 * np.pi / max(n, 1)
    # frames per crank turn; a length input (a driving slider) shows one cycle in its frames
    per_turn = float(n) if length else 2.0 * np.pi / step
    if speed is None:
        total = 3.0 * n / per_turn if duration is None else float(duration)
        interval = total / n
        return None, interval, f"{interval * per_turn:.3g} s per {'cycle' if length else 'turn'}"
    dt = step / abs(float(speed))
    real = dt * n
    if duration is None:
        duration = real if 1.0 <= real <= 20.0 else float(np.clip(3.0 * n / per_turn, 0.5, 20.0))
    interval = float(duration) / n
    ratio = interval / dt
    if abs(ratio - 1.0) < 1e-9:
        text = "real time"
    elif ratio > 1.0:
        text = f"slowed x {ratio:.3g}"
    else:
        text = f"sped up x {1.0 / ratio:.3g}"
    return dt, interval, text


def animate_sketch(
    sketch: Sketch,
    *,
    speed=None,
    trace=(),
    duration=None,
    figsize=None,
    dpi: int = 80,
    title: str | None = None,
    color=None,
):
    """Animate every frame of ``sketch``; returns a :class:`MechanismAnimation`.

    Parameters
    ----------
    speed : crank speed (rad/s) of the machine, or None. With a speed the title shows the time
        and the playback runs in real time when all frames last 1-20 s; otherwise it runs at
        about 3 s per turn and the title says how much slower or faster than the machine.
    trace : point names whose paths are drawn.
    duration : playback seconds of all frames (overrides the rule above).
    figsize, dpi : the figure's size (in; default 6.4 in wide, as tall as the mechanism needs)
        and resolution (dots per inch).
    title : first title line (default: the mechanism and its design).
    """
    from matplotlib.figure import Figure

    n = sketch.frames
    dt, interval, playback = _playback(sketch, speed, duration)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = Figure(figsize=figsize or _figsize(sketch, 6.4), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    scene = _Scene(sketch, ax, trace=trace, color=color)
    _prepare_axes(ax, scene, sketch, fresh=True)
    if trace:
        ax.legend(loc="best", fontsize=8)
    head = title or _wrapped(sketch.name)
    # the still title is drawn once; the short line under it changes per frame
    fig.suptitle(f"{head}\n{sketch.angle_label}, {playback}", fontsize=9)
    if figsize is None and head.count("\n"):  # room for a long name's lines, not a cut label
        fig.set_figheight(fig.get_figheight() + 0.18 * head.count("\n"))
    text = ax.set_title("", fontsize=9)

    def update(i):
        scene.update(i)
        when = "" if dt is None else f",  t = {i * dt:.3g} s"
        text.set_text(f"{_angle_text(sketch, i, short=True)}{when}")
        return []

    update(0)
    # lay the figure out once (titles keep their size from frame to frame), then keep it
    fig.canvas.draw()
    fig.set_layout_engine("none")
    return MechanismAnimation(
        fig, update, n, 1.0 / interval, playback, moving=[*scene.artists, text]
    )

"""The page's Synthesis tab: path generation and function generation beside the motion
generation of :mod:`.app`, with a canvas of their own where a click places a target point (path
generation) or a pose (motion generation), and a preview that plays a solution moving over its
targets in the browser.

The path search runs the library's :func:`mechsynth.path_generation` (a four-bar, a
slider-crank or the page's linkage; the crank angles at the targets free, prescribed or the
path's shape only) in a worker process (progress from its starts, Cancel ends it at once, the
page stays live); a function generator (:func:`mechsynth.function_generation`, fast) runs in
the page's worker thread, its certified min-max stage in a worker process. A placed target
point, a pose's position or its angle (the end of its axis) is dragged to move it; the typed
list follows and the move can be undone. Loading a solution makes it the page's mechanism
(:mod:`.synthesis_model` gives its linkage), which then animates, optimizes and exports like
any other.
"""

from __future__ import annotations

import json
import math

import numpy as np

from ..errors import MechanismError
from .model import parse_number
from .synthesis_model import (
    DEFAULT_POINTS,
    FunctionJob,
    PathJob,
    certificate_words,
    even_angles,
    function_preview,
    function_state,
    linkage_variables,
    minmax_worker,
    parse_angles,
    parse_pairs,
    parse_points,
    path_preview,
    path_rows,
    path_state,
    path_worker,
    run_function,
)
from .worker import Worker

__all__ = ["SynthesisTab", "TASKS"]

#: the sub-tabs, in their order on the page
TASKS = ("motion", "path", "function")
#: a press within this fraction of the canvas's view of a placed target grabs it
HIT = 0.03

# the preview's script: draws frame k of the solution sent in 'synth-frames' ('synth-meta'
# gives its links), plays it, and fits the view to 'synth-view' with equal scales
PREVIEW_JS = r"""
const M = meta.data.json.length ? JSON.parse(meta.data.json[0]) : null;
function draw(k) {
  if (!M || !M.n) { links.data = {xs: [], ys: []}; pins.data = {x: [], y: [], name: []}; return; }
  k = ((Math.round(k) % M.n) + M.n) % M.n;
  const F = frames.data, xs = [], ys = [];
  for (const l of M.links) {
    xs.push(l.map(p => F['x:' + p][k])); ys.push(l.map(p => F['y:' + p][k]));
  }
  links.data = {xs: xs, ys: ys};
  pins.data = {x: M.pins.map(p => F['x:' + p][k]), y: M.pins.map(p => F['y:' + p][k]),
               name: M.pins};
}
function fit() {
  const V = view.data;
  if (!V.x0 || !V.x0.length) return;
  let [x0, x1, y0, y1] = [V.x0[0], V.x1[0], V.y0[0], V.y1[0]];
  const w = fig.inner_width || 500, h = fig.inner_height || 300;
  const m = 0.08 * Math.max(x1 - x0, y1 - y0, 1e-12);
  const s = Math.max((x1 - x0 + 2 * m) / w, (y1 - y0 + 2 * m) / h);
  const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  fig.x_range.setv({start: cx - s * w / 2, end: cx + s * w / 2});
  fig.y_range.setv({start: cy - s * h / 2, end: cy + s * h / 2});
}
if (what === 'view' || what === 'resize') fit();
if (what === 'meta') { slider.end = Math.max((M && M.n) ? M.n - 1 : 1, 1); draw(slider.value); }
if (what === 'frame') draw(slider.value);
if (what === 'play') {
  if (window._msPreview) { clearInterval(window._msPreview); window._msPreview = null;
                           play.label = 'Play preview'; }
  else if (M && M.n) {
    play.label = 'Pause preview';
    window._msPreview = setInterval(() => {
      slider.value = (slider.value + 1) % M.n;
    }, 25);
  }
}
"""


# the drag of a placed target in the browser: the mark nearest the press (within HIT of the
# view's size) follows the pointer; 'points', 'poses' and 'view' are the canvas's sources
GRAB_JS = r"""
const V = view.data;
const size = (V.x0 && V.x0.length) ? Math.max(V.x1[0] - V.x0[0], V.y1[0] - V.y0[0]) : 1;
function grab(e) {
  window._msGrab = null;
  let best = HIT * size, g = null;
  const P = points.data, Q = poses.data;
  for (let i = 0; i < P.x.length; i++) {
    const d = Math.hypot(P.x[i] - e.x, P.y[i] - e.y);
    if (d <= best) { best = d; g = ['point', i]; }
  }
  for (let i = 0; i < Q.x.length; i++) {
    const d = Math.hypot(Q.x[i] - e.x, Q.y[i] - e.y);
    if (d <= best) { best = d; g = ['pose', i]; }
    const t = Math.hypot(Q.xs[i][1] - e.x, Q.ys[i][1] - e.y);
    if (t < best) { best = t; g = ['angle', i]; }
  }
  window._msGrab = g;
}
function move(e) {
  const g = window._msGrab;
  if (!g) return;
  const i = g[1];
  if (g[0] === 'point') {
    const d = Object.assign({}, points.data);
    d.x = d.x.slice(); d.y = d.y.slice(); d.x[i] = e.x; d.y[i] = e.y;
    points.data = d;
    return;
  }
  const d = Object.assign({}, poses.data);
  d.x = d.x.slice(); d.y = d.y.slice(); d.xs = d.xs.slice(); d.ys = d.ys.slice();
  const x = d.x[i], y = d.y[i], r = Math.hypot(d.xs[i][1] - x, d.ys[i][1] - y);
  if (g[0] === 'pose') {
    d.x[i] = e.x; d.y[i] = e.y;
    d.xs[i] = [e.x, e.x + d.xs[i][1] - x]; d.ys[i] = [e.y, e.y + d.ys[i][1] - y];
  } else {
    const a = Math.atan2(e.y - y, e.x - x);
    d.xs[i] = [x, x + r * Math.cos(a)]; d.ys[i] = [y, y + r * Math.sin(a)];
  }
  poses.data = d;
}
""".replace("HIT", str(HIT))


class SynthesisTab:
    """Path and function generation in the page of ``app`` (its :class:`~.app.Explorer`)."""

    def __init__(self, app):
        import panel as pn
        from bokeh.events import PanEnd, PanStart, Tap
        from bokeh.models import Button, ColumnDataSource, CustomJS, Range1d, Slider
        from bokeh.plotting import figure

        from .app import _widget

        self.app = app
        self._path_run = Worker()  # the path search
        self._mm_run = Worker()  # the function generator's min-max stage
        self._result = None  # the last path result
        self._tables = None  # the linkage's tables it searched over (None: four-bar, slider)
        self._moved = []  # the target lists (points, poses) before each move, to undo it
        self._linkage_kind = None  # the page's linkage the path options were made for
        self._seen_kind = None  # the page's mechanism when they were last looked at
        self._targets = None  # its targets (m)
        self._function = None  # the running function generation (a future)
        self._fg = None  # the last function generator
        self._fn_job = None  # what made it
        self._function_job = None  # what the running one was asked
        self._fitted = None  # the extent the canvas was last fitted to (display units)

        # the canvas: targets, poses, the previewed solution
        self.fig = figure(
            height=300, min_width=280, sizing_mode="stretch_width",
            tools="pan,wheel_zoom,reset", title="click to place a target point or a pose",
            x_axis_label="x", y_axis_label="y", name="synth-canvas",
            # fixed ranges, set by the fit: a data range would follow a dragged mark
            x_range=Range1d(0, 1), y_range=Range1d(0, 1),
        )  # fmt: skip
        self.fig.toolbar.active_scroll = None
        self.fig.toolbar.active_drag = None  # a click places; pan is a click away
        self.src_curve = ColumnDataSource(dict(x=[], y=[]), name="synth-curve")
        self.src_links = ColumnDataSource(dict(xs=[], ys=[]), name="synth-links")
        self.src_pins = ColumnDataSource(dict(x=[], y=[], name=[]), name="synth-pins")
        self.src_points = ColumnDataSource(dict(x=[], y=[], label=[]), name="synth-points")
        self.src_poses = ColumnDataSource(dict(x=[], y=[], xs=[], ys=[]), name="synth-poses")
        self.src_frames = ColumnDataSource(dict(), name="synth-frames")
        self.src_meta = ColumnDataSource(dict(json=[]), name="synth-meta")
        self.src_view = ColumnDataSource(dict(x0=[], x1=[], y0=[], y1=[]), name="synth-view")
        f = self.fig
        f.line("x", "y", source=self.src_curve, line_color="#009E73", line_width=2,
               line_dash="dashed", name="synth-curve-line")  # fmt: skip
        f.multi_line("xs", "ys", source=self.src_links, line_color="#0072B2", line_width=4,
                     name="synth-link-lines")  # fmt: skip
        f.scatter("x", "y", source=self.src_pins, size=7, fill_color="white",
                  line_color="black", name="synth-pin-marks")  # fmt: skip
        f.multi_line("xs", "ys", source=self.src_poses, line_color="#E69F00", line_width=3,
                     name="synth-pose-axes")  # fmt: skip
        f.scatter("x", "y", source=self.src_poses, marker="square", size=10,
                  fill_color="#E69F00", line_color="black", name="synth-pose-marks")  # fmt: skip
        f.scatter("x", "y", source=self.src_points, marker="circle", size=10,
                  fill_color="#D55E00", line_color="black", name="synth-point-marks")  # fmt: skip
        f.text("x", "y", text="label", source=self.src_points, x_offset=6, y_offset=-6,
               text_font_size="11px", name="synth-point-labels")  # fmt: skip
        f.on_event(Tap, self._on_tap)
        # a drag on the motion generation's canvas: a pose at its start, along the drag
        self._pan_from = None
        f.on_event(PanStart, lambda e: setattr(self, "_pan_from", (float(e.x), float(e.y))))
        f.on_event(PanEnd, self._on_pan_end)
        # while a target is dragged the browser moves its mark (the list follows on release)
        grab_args = dict(points=self.src_points, poses=self.src_poses, view=self.src_view)
        f.js_on_event("panstart", CustomJS(args=grab_args, code=GRAB_JS + "grab(cb_obj);"))
        f.js_on_event("pan", CustomJS(args=grab_args, code=GRAB_JS + "move(cb_obj);"))
        self.frame = Slider(start=0, end=1, value=0, step=1, title="preview frame",
                            show_value=False, sizing_mode="stretch_width", min_width=150,
                            name="synth-frame")  # fmt: skip
        self.play = Button(label="Play preview", width=110, name="synth-play")
        args = dict(meta=self.src_meta, frames=self.src_frames, links=self.src_links,
                    pins=self.src_pins, view=self.src_view, fig=self.fig, slider=self.frame,
                    play=self.play)  # fmt: skip

        def js(what):
            return CustomJS(args=args, code=f"const what = {what!r};\n" + PREVIEW_JS)

        self.src_meta.js_on_change("data", js("meta"))
        self.src_view.js_on_change("data", js("view"))
        self.frame.js_on_change("value", js("frame"))
        self.play.js_on_event("button_click", js("play"))
        self.fig.js_on_change("inner_width", js("resize"))
        self.fig.js_on_change("inner_height", js("resize"))

        # path generation
        self.points_input = _widget(
            pn.widgets.TextAreaInput,
            self._points_label(),
            value=DEFAULT_POINTS,
            height=110,
            min_width=260,
            max_width=600,
            sizing_mode="stretch_width",
            css_classes=["path-points"],
        )
        self.points_input.param.watch(lambda e: self._draw_inputs(), "value")
        self.path_mech = _widget(
            pn.widgets.Select,
            "Mechanism to synthesize",
            options={
                "four-bar: its coupler point": "four-bar",
                "slider-crank: a point on its rod": "slider-crank",
                "the page's linkage: a point of it": "linkage",
            },
            value="four-bar",
            width=240,
        )
        self.path_mech.param.watch(lambda e: app._later(self._path_options), "value")
        self.timing = _widget(
            pn.widgets.Select,
            "Timing",
            options={
                "free: the crank angle at each point is free": "free",
                "prescribed: the crank angle at each point given": "prescribed",
                "shape only: a closed path's shape, placed anywhere": "shape",
            },
            value="free",
            width=300,
        )
        self.timing.param.watch(lambda e: app._later(self._path_options), "value")
        self.path_angles = _widget(
            pn.widgets.TextInput,
            "Crank angle at each point, deg (only their differences count)",
            value="",
            min_width=260,
            max_width=600,
            sizing_mode="stretch_width",
        )
        self.path_even = _widget(pn.widgets.Button, "Evenly spaced angles", width=170,
                                 align="end")  # fmt: skip
        self.path_even.on_click(lambda e: app._later(self.even_angles))
        self.path_trace = _widget(pn.widgets.Select, "Point to follow", options=[], width=150)
        self.path_vary = _widget(
            pn.widgets.MultiChoice, "Dimensions to vary", options=[], value=[], min_width=260,
            max_width=600, sizing_mode="stretch_width",
        )  # fmt: skip
        self.path_spread = _widget(
            pn.widgets.TextInput, "Range of each varied dimension, %", value="30", width=220
        )
        self.path_from_curve = _widget(
            pn.widgets.Button, "Six points of the followed point's path", width=260, align="end"
        )
        self.path_from_curve.on_click(lambda e: app._later(self.points_from_linkage))
        self.path_angles_row = pn.FlexBox(self.path_angles, self.path_even, visible=False,
                                          align_items="flex-end")  # fmt: skip
        self.path_linkage_row = pn.FlexBox(
            self.path_trace, self.path_spread, self.path_vary, self.path_from_curve,
            visible=False, align_items="flex-end",
        )  # fmt: skip
        self.undo_move = _widget(pn.widgets.Button, "Undo the target move", width=180,
                                 disabled=True)  # fmt: skip
        self.undo_move.on_click(lambda e: app._later(self.undo_target_move))
        self.undo_move_poses = _widget(pn.widgets.Button, "Undo the pose move", width=170,
                                       disabled=True, align="end")  # fmt: skip
        self.undo_move_poses.on_click(lambda e: app._later(self.undo_target_move))
        self.path_mu = _widget(
            pn.widgets.TextInput, "Minimum transmission angle, deg", value="30", width=190
        )
        self.path_starts = _widget(
            pn.widgets.IntInput, "Path starts", start=1, end=200, value=6, width=100
        )
        self.path_button = _widget(
            pn.widgets.Button, "Find path generators", button_type="primary", width=170
        )
        self.path_button.on_click(lambda e: app._later(self.start_path))
        self.path_cancel = _widget(
            pn.widgets.Button, "Cancel the search", button_type="warning", width=140,
            disabled=True,
        )  # fmt: skip
        self.path_cancel.on_click(lambda e: app._later(self.cancel_path))
        self.path_progress = pn.indicators.Progress(
            value=0, max=1, width=160, active=False, visible=False, align="center"
        )
        self.path_msg = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["path-msg"])
        self.path_table = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["path-tbl"])
        self.path_pick = _widget(pn.widgets.Select, "Path solution", options=[], width=130)
        self.path_pick.param.watch(lambda e: app._later(self.preview_path), "value")
        self.path_load = _widget(
            pn.widgets.Button, "Load the path generator", width=200, disabled=True
        )
        self.path_load.on_click(lambda e: app._later(self.load_path))

        # function generation
        self.fn_text = _widget(pn.widgets.TextInput, "y = f(x)", value="log10(x)", width=200)
        self.fn_x0 = _widget(pn.widgets.TextInput, "x from", value="1", width=90)
        self.fn_x1 = _widget(pn.widgets.TextInput, "x to", value="10", width=90)
        self.fn_in = _widget(pn.widgets.TextInput, "Input rotation, deg", value="60", width=150)
        self.fn_out = _widget(pn.widgets.TextInput, "Output rotation, deg", value="90", width=150)
        self.fn_pairs = _widget(
            pn.widgets.TextAreaInput,
            "or precision pairs instead of a function, one a line: crank angle, output "
            "angle (deg)",
            value="",
            height=90,
            min_width=260,
            max_width=600,
            sizing_mode="stretch_width",
        )
        self.fn_ground = _widget(
            pn.widgets.TextInput, self._ground_label(), value=self._ground_text(), width=150
        )
        self.fn_mu = _widget(
            pn.widgets.TextInput, "Least transmission angle, deg", value="30", width=190
        )
        self.fn_crank = _widget(pn.widgets.Checkbox, "the crank turns fully", value=True)
        self.fn_button = _widget(
            pn.widgets.Button, "Generate the function", button_type="primary", width=180
        )
        self.fn_button.on_click(lambda e: app._later(self.start_function))
        self.fn_msg = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["fn-msg"])
        self.fn_design = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["fn-design"])
        self.err_fig = figure(
            height=240, min_width=280, sizing_mode="stretch_width", tools="pan,wheel_zoom,reset",
            title="structural error", x_axis_label="x", y_axis_label="output error, deg",
            name="function-error",
        )  # fmt: skip
        self.err_fig.toolbar.active_scroll = None
        self.src_err = ColumnDataSource(dict(x=[], y=[]), name="function-error-curve")
        self.src_prec = ColumnDataSource(dict(x=[], y=[]), name="function-precision")
        self.src_err_before = ColumnDataSource(dict(x=[], y=[]), name="function-error-before")
        self.err_fig.line("x", "y", source=self.src_err_before, line_width=2, color="#999999",
                          line_dash="dashed", legend_label="before the min-max stage")  # fmt: skip
        self.err_fig.line("x", "y", source=self.src_err, line_width=2, color="#D55E00",
                          legend_label="true output - ideal output")  # fmt: skip
        self.err_fig.scatter("x", "y", source=self.src_prec, size=8, color="#0072B2",
                             legend_label="precision points")  # fmt: skip
        self.err_fig.legend.location = "top_center"
        self.err_fig.legend.orientation = "horizontal"
        self.err_fig.y_range.range_padding = 0.4  # room above the curves for the legend
        self.err_fig.legend.label_text_font_size = "10px"
        self.fn_load = _widget(
            pn.widgets.Button, "Load the function generator", width=220, disabled=True
        )
        self.fn_load.on_click(lambda e: app._later(self.load_function))
        self.fn_minmax = _widget(
            pn.widgets.Button, "Minimize the worst error (certified min-max)",
            button_type="primary", width=320, disabled=True,
        )  # fmt: skip
        self.fn_minmax.on_click(lambda e: app._later(self.start_minmax))
        self.fn_mm_cancel = _widget(
            pn.widgets.Button, "Cancel the min-max", button_type="warning", width=150,
            disabled=True,
        )  # fmt: skip
        self.fn_mm_cancel.on_click(lambda e: app._later(self.cancel_minmax))
        self.fn_mm_progress = pn.indicators.Progress(
            value=0, max=1, width=160, active=False, visible=False, align="center"
        )
        self.fn_cert = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["fn-cert"])

        # motion generation: a click places a pose with this angle
        self.pose_angle = _widget(
            pn.widgets.TextInput, "Angle of a clicked pose, deg", value="0", width=200
        )
        app.poses_input.param.watch(lambda e: self._draw_inputs(), "value")
        self._draw_inputs()
        if self._fitted is not None:  # the view before the browser fits it to its canvas
            x0, x1, y0, y1 = self._fitted
            m = 0.08 * _size(self._fitted)
            self.fig.x_range.update(start=x0 - m, end=x1 + m)
            self.fig.y_range.update(start=y0 - m, end=y1 + m)

    # ------------------------------------------------------------------ layout
    def panel(self, motion):
        """The tab: the canvas and its preview player, then path, function and motion
        generation (``motion``: the page's motion-generation widgets) as sub-tabs."""
        import panel as pn

        help_ = pn.pane.HTML(
            "<b>Path generation</b>: a four-bar, a slider-crank or the page's linkage whose "
            "point passes as near as possible to the points (<code>ms.path_generation</code>),"
            " its crank turning fully. A click on the canvas adds a point, a drag moves one; "
            "the list can be typed or pasted.",
            margin=(0, 10),
        )
        path = pn.Column(
            help_,
            self.points_input,
            pn.FlexBox(self.path_mech, self.timing, self.path_mu, self.path_starts),
            self.path_angles_row,
            self.path_linkage_row,
            pn.FlexBox(self.path_button, self.path_cancel, self.undo_move, self.path_progress),
            self.path_msg,
            self.path_table,
            pn.Row(self.path_pick, self.path_load),
            sizing_mode="stretch_width",
        )
        function = pn.Column(
            pn.pane.HTML(
                "<b>Function generation</b>: a four-bar whose rocker turns by y = f(x) as its "
                "crank turns by x (<code>ms.function_generation</code>: three precision points "
                "at Chebyshev spacing, the phases scanned), or through precision pairs."
            ),
            pn.FlexBox(self.fn_text, self.fn_x0, self.fn_x1, self.fn_in, self.fn_out),
            self.fn_pairs,
            pn.FlexBox(self.fn_ground, self.fn_mu, self.fn_crank),
            self.fn_button,
            self.fn_msg,
            self.fn_design,
            pn.Row(self.fn_minmax, self.fn_mm_cancel, self.fn_mm_progress),
            self.fn_cert,
            pn.pane.Bokeh(self.err_fig, sizing_mode="stretch_width"),
            self.fn_load,
            sizing_mode="stretch_width",
        )
        motion = pn.Column(
            pn.pane.HTML(
                "A click on the canvas above adds a pose at the angle given here, a drag a pose "
                "at its start along the drag (or type the poses below). A drag from a pose's "
                "square moves it, from the end of its line turns it."
            ),
            pn.Row(self.pose_angle, self.undo_move_poses),
            motion,
            sizing_mode="stretch_width",
        )
        # motion generation first: it was the tab's content before the other two came
        self.tasks = pn.Tabs(
            ("Motion (poses)", motion),
            ("Path (points)", path),
            ("Function (y = f(x))", function),
            dynamic=True,  # sent to the browser when first shown: the page is ready sooner
            sizing_mode="stretch_width",
        )
        self.tasks.param.watch(lambda e: self.app._later(self.task_changed), "active")
        self._draw_inputs()
        from bokeh.layouts import column, row

        canvas = pn.pane.Bokeh(
            column(self.fig, row(self.play, self.frame, sizing_mode="stretch_width"),
                   sizing_mode="stretch_width"),
            sizing_mode="stretch_width",
        )  # fmt: skip
        return pn.Column(canvas, self.tasks, sizing_mode="stretch_width")

    # ------------------------------------------------------------------ labels
    def _points_label(self) -> str:
        unit = self.app.state.unit_label("m")
        return f"Target points of the coupler point, one a line: x, y ({unit})"

    def _ground_label(self) -> str:
        return f"Ground length, {self.app.state.unit_label('m')}"

    def _ground_text(self) -> str:
        return f"{self.app.state.shown(0.1, 'm'):.6g}"

    # ------------------------------------------------------------------ canvas
    def _task(self) -> str:
        """The sub-tab shown: ``"motion"``, ``"path"`` or ``"function"`` (generation)."""
        task = getattr(self, "tasks", None)
        return TASKS[int(task.active)] if task is not None else "path"

    def task_changed(self):
        """Another sub-tab: the canvas shows its targets and its last solution."""
        self._draw_inputs()
        task = self._task()
        if task == "path":
            self._path_options()
        if task == "path" and self._result is not None and self._result.solutions:
            self.preview_path()
        elif task == "function" and self._fg is not None:
            self.show_function(self._fg)
        else:
            self.clear_preview()

    def _on_tap(self, event):
        self.app._later(self.click, float(event.x), float(event.y))

    def _on_pan_end(self, event):
        start, self._pan_from = self._pan_from, None
        if start is not None:
            self.app._later(self.drag, *start, float(event.x), float(event.y))

    def drag(self, x0: float, y0: float, x1: float, y1: float):
        """A drag on the canvas from ``(x0, y0)`` to ``(x1, y1)`` (display length unit). From
        a placed target (within :data:`HIT` of the view's size; the nearest): a point or a
        pose moves to the drag's end, a pose's axis end turns the pose towards it (to a
        whole degree), and the typed list follows. Elsewhere on the motion generation: a
        pose at the start whose angle is the drag's direction (the angle field follows, to a
        whole degree); elsewhere nothing (the canvas's pan tool is a click away)."""
        if (x1, y1) == (x0, y0):
            return
        grab = self._grabbed(x0, y0)
        if grab is not None:
            self.move_target(*grab, x1, y1)
            return
        if self._task() != "motion":
            return
        # to a whole degree: a drag is not finer than that
        self.pose_angle.value = f"{round(math.degrees(math.atan2(y1 - y0, x1 - x0)))}"
        self.click(x0, y0)

    def _grabbed(self, x: float, y: float):
        """``(what, i)`` of the placed target nearest ``(x, y)`` within reach: ``"point"``,
        ``"pose"`` (its place) or ``"angle"`` (its axis end), ``i`` its row; or None."""
        if self._fitted is None:
            return None
        # from the lists, not the canvas's marks: the browser moves those while dragging
        best, grab = HIT * _size(self._fitted), None
        pts, poses, tips = self._marks()
        for i, (px, py) in enumerate(pts):
            d = math.hypot(px - x, py - y)
            if d <= best:
                best, grab = d, ("point", i)
        for i, (p, tip) in enumerate(zip(poses, tips)):
            d = math.hypot(p[0] - x, p[1] - y)
            if d <= best:
                best, grab = d, ("pose", i)
            t = math.hypot(tip[0] - x, tip[1] - y)
            if t < best:
                best, grab = t, ("angle", i)
        return grab

    def move_target(self, what: str, i: int, x: float, y: float):
        """Move the ``i``-th placed target point (``what`` ``"point"``) or pose (``"pose"``:
        its place) to ``(x, y)``, or turn the pose towards it (``"angle"``); display units.
        The typed list's line changes (others, comments included, stay) and the move can be
        undone (:meth:`undo_target_move`)."""
        x, y = self._snap(x, y)
        widget = self.points_input if what == "point" else self.app.poses_input
        lines = str(widget.value or "").split("\n")
        rows = _row_lines(widget.value, 2 if what == "point" else 3)
        if not 0 <= i < len(rows):
            return
        k, vals = rows[i]
        if what == "point":
            text = f"{x:.6g}, {y:.6g}"
        elif what == "pose":
            text = f"{x:.6g}, {y:.6g}, {vals[2]:.6g}"
        else:
            angle = round(math.degrees(math.atan2(y - vals[1], x - vals[0])))
            text = f"{vals[0]:.6g}, {vals[1]:.6g}, {angle:.6g}"
        comment = lines[k][lines[k].index("#") :] if "#" in lines[k] else ""
        lines[k] = f"{text}  {comment}" if comment else text
        self._moved.append((self.points_input.value, self.app.poses_input.value))
        del self._moved[:-50]
        widget.value = "\n".join(lines)
        self._undo_buttons()

    def undo_target_move(self):
        """The target lists as they were before the last move (moves undone one by one)."""
        if not self._moved:
            return
        self.points_input.value, self.app.poses_input.value = self._moved.pop()
        self._undo_buttons()

    def _undo_buttons(self):
        self.undo_move.disabled = self.undo_move_poses.disabled = not self._moved

    def _snap(self, x: float, y: float) -> tuple[float, float]:
        """``(x, y)`` to a thousandth of the canvas's size (not to a pixel)."""
        if self._fitted is not None:
            x0, x1, y0, y1 = self._fitted
            step = 10.0 ** math.floor(math.log10(max(x1 - x0, y1 - y0, 1e-9) / 1000))
            x, y = round(x / step) * step, round(y / step) * step
        return x, y

    def click(self, x: float, y: float):
        """A click on the canvas at ``(x, y)`` (display length unit): a target point when the
        path generation is shown, a pose (at the angle field's value) when the motion
        generation is; nothing on the function generation."""
        active = self._task()
        x, y = self._snap(x, y)
        if active == "path":
            self.points_input.value = _append(self.points_input.value, f"{x:.6g}, {y:.6g}")
        elif active == "motion":
            try:
                angle = parse_number(self.pose_angle.value, "angle of a clicked pose, deg")
            except MechanismError as exc:
                self.app.synth_msg.object = _bad(exc)
                return
            self.app.poses_input.value = _append(
                self.app.poses_input.value, f"{x:.6g}, {y:.6g}, {angle:.6g}"
            )

    def _marks(self):
        """The targets the canvas shows, from the typed lists (display units): the points
        (path generation), the poses and the ends of their lines (motion generation)."""
        task = self._task()
        pts = _rows(self.points_input.value, 2) if task == "path" else []
        poses = _rows(self.app.poses_input.value, 3) if task == "motion" else []
        ext = _extent(pts + [p[:2] for p in poses])
        r = 0.06 * max(ext[1] - ext[0], ext[3] - ext[2]) if ext else 0.0
        tips = [(p[0] + r * math.cos(math.radians(p[2])), p[1] + r * math.sin(math.radians(p[2])))
                for p in poses]  # fmt: skip
        return pts, poses, tips

    def _draw_inputs(self):
        """The typed or clicked targets and poses on the canvas (lines that do not read are
        left out here; the search names them)."""
        task = self._task()
        pts, poses, tips = self._marks()
        self.fig.title.text = {
            "path": "click to add a target point",
            "function": "the function generator over its input range",
            "motion": "click to add a pose (at the angle set below)",
        }[task]
        self.src_points.data = dict(
            x=[p[0] for p in pts], y=[p[1] for p in pts],
            label=[str(i) for i in range(1, len(pts) + 1)],
        )  # fmt: skip
        ext = _extent(pts + [p[:2] for p in poses])
        self.src_poses.data = dict(
            x=[p[0] for p in poses], y=[p[1] for p in poses],
            xs=[[p[0], t[0]] for p, t in zip(poses, tips)],
            ys=[[p[1], t[1]] for p, t in zip(poses, tips)],
        )  # fmt: skip
        unit = self.app.state.unit_label("m")
        self.fig.xaxis.axis_label = f"x, {unit}"
        self.fig.yaxis.axis_label = f"y, {unit}"
        if ext and not _inside(ext, self._fitted):
            fitted = self._fitted
            if fitted is not None and _size(ext) < 0.2 * _size(fitted) and _meets(ext, fitted):
                # a point clicked or typed just outside: the view grows, it does not jump
                ext = (min(ext[0], fitted[0]), max(ext[1], fitted[1]),
                       min(ext[2], fitted[2]), max(ext[3], fitted[3]))  # fmt: skip
            self._fit(ext)

    def _fit(self, ext):
        x0, x1, y0, y1 = ext
        if x1 - x0 < 1e-12 and y1 - y0 < 1e-12:
            x0, x1, y0, y1 = x0 - 1, x1 + 1, y0 - 1, y1 + 1
        self._fitted = (x0, x1, y0, y1)
        self.src_view.data = dict(x0=[x0], x1=[x1], y0=[y0], y1=[y1])

    def _show_preview(self, cols: dict, links, pins, curve=None, extra=()):
        """Send a solution's cycle (``cols``: point -> (n, 2) in m) to the browser."""
        f = self.app.state.display.factor("m")
        data, n = {}, 0
        for p, xy in cols.items():
            xy = np.asarray(xy, float) / f
            data[f"x:{p}"], data[f"y:{p}"] = xy[:, 0].tolist(), xy[:, 1].tolist()
            n = len(xy)
        self.src_frames.data = data
        self.src_meta.data = dict(json=[json.dumps(dict(n=n, links=links, pins=pins))])
        if curve is not None:
            c = np.asarray(curve, float) / f
            self.src_curve.data = dict(x=c[:, 0].tolist() + [float(c[0, 0])],
                                       y=c[:, 1].tolist() + [float(c[0, 1])])  # fmt: skip
        else:
            self.src_curve.data = dict(x=[], y=[])
        allp = np.concatenate([np.asarray(v, float) for v in cols.values()]) / f
        ext = _extent([tuple(r) for r in allp] + list(extra))
        self._fit(ext)

    def clear_preview(self):
        self.src_frames.data = {}
        self.src_meta.data = dict(json=[json.dumps(dict(n=0, links=[], pins=[]))])
        self.src_curve.data = dict(x=[], y=[])

    # ------------------------------------------------------------------ path generation
    def _page_linkage(self):
        """The page's linkage kind (one with a linkage file's tables), or None."""
        kind = self.app.state.kind
        return kind if kind.file_data else None

    def _path_options(self):
        """The fields the mechanism and timing chosen ask for: the crank angles with
        prescribed timing; the point to follow and the dimensions to vary (the page's
        linkage's, made again when the page shows another)."""
        self.path_angles_row.visible = self.timing.value == "prescribed"
        linkage = self.path_mech.value == "linkage"
        self.path_linkage_row.visible = linkage
        if not linkage:
            return
        self._seen_kind = self.app.state.kind
        kind = self._page_linkage()
        if kind is None:
            self.path_trace.options, self.path_vary.options = [], []
            self.path_msg.object = _bad(
                f"the page shows the {self.app.state.kind.title}, not a linkage: pick "
                "'Linkage' in the Mechanism menu, open a linkage file, build one or load a "
                "synthesized one first",
                "path-state",
            )
            self._linkage_kind = None
            return
        if kind is self._linkage_kind:
            return
        self._linkage_kind = kind
        lk = kind.build(dict(self.app.state.values))
        ground = set(lk.topology().ground)
        moving = [p for p in lk.points if p not in ground]
        self.path_trace.options = moving
        self.path_trace.value = next((p for p in kind.trace if p in moving), moving[-1])
        names = [d.name for d in kind.dims]
        self.path_vary.options = names
        # the crank's phase only shifts the crank angles: free timing has them free already
        self.path_vary.value = [n for n in names if n != "phase"]
        if "path-state" in str(self.path_msg.object) and "not a linkage" in str(
            self.path_msg.object
        ):
            self.path_msg.object = ""

    def even_angles(self):
        """Crank angles evenly spaced over a turn, one per target point, in the field."""
        n = len(_rows(self.points_input.value, 2))
        self.path_angles.value = ", ".join(f"{math.degrees(a):.6g}" for a in even_angles(n))

    def points_from_linkage(self, n: int = 6):
        """``n`` points of the followed point's path at the page's design (crank angles
        evenly spaced over a turn) as the targets, to move or edit from there."""
        kind = self._page_linkage()
        if kind is None or not self.path_trace.value:
            self._path_options()
            return
        st = self.app.state
        lk = kind.build(dict(st.values))
        p = lk.motion(even_angles(n)).points[self.path_trace.value]
        f = st.display.factor("m")
        xy = np.column_stack(np.broadcast_arrays(p.x, p.y)) / f
        self.points_input.value = "\n".join(f"{x:.6g}, {y:.6g}" for x, y in xy)

    def path_job(self) -> PathJob:
        """The search the fields ask for (MechanismError names a bad field)."""
        st = self.app.state
        targets = parse_points(self.points_input.value, st)
        mu_text = (self.path_mu.value or "").strip()
        mu = None
        if mu_text:
            mu = math.radians(parse_number(mu_text, "minimum transmission angle, deg"))
        timing, mech = self.timing.value, self.path_mech.value
        kw = {}
        if timing == "prescribed":
            kw["angles"] = parse_angles(self.path_angles.value, len(targets))
        if mech == "linkage":
            kind = self._page_linkage()
            if kind is None:
                raise MechanismError(
                    f"the page shows the {st.kind.title}, not a linkage: pick 'Linkage' in the "
                    "Mechanism menu or open a linkage file first"
                )
            spread = parse_number(self.path_spread.value, "range of each varied dimension, %")
            if not kind.build(dict(st.values)).periodic:
                raise MechanismError(
                    f"the {kind.title} is driven by a slider: path generation turns a crank "
                    "(a linkage driven by a crank, or the four-bar or the slider-crank)"
                )
            kw.update(
                tables=kind.file_data,
                values=dict(st.values),
                trace=self.path_trace.value,
                variables=linkage_variables(st, list(self.path_vary.value), spread / 100.0),
            )
        return PathJob(targets, timing, mu, int(self.path_starts.value or 1), mechanism=mech,
                       **kw)  # fmt: skip

    def start_path(self):
        if self._path_run.running:
            return
        try:
            job = self.path_job()
        except MechanismError as exc:
            self.path_msg.object = _bad(exc, "path-state")
            return
        self._path_run.start(path_worker, job)
        self._path_run.stage = "starting the search"
        self.path_button.disabled = True
        self.path_cancel.disabled = False
        self.path_progress.param.update(visible=True, active=True, value=-1)
        self.path_msg.object = "<span id='path-state'>searching: starting the search...</span>"

    def cancel_path(self):
        if not self._path_run.running:
            return
        self._end_path(kill=True)
        self.path_msg.object = "<span id='path-state'>cancelled</span>"

    def close(self):
        """Stop a running search or min-max (the session ended)."""
        if self._path_run.running:
            self._end_path(kill=True)
        if self._mm_run.running:
            self._end_minmax(kill=True)

    def _end_path(self, kill=False):
        self._path_run.end(kill)
        self.path_button.disabled = False
        self.path_cancel.disabled = True
        self.path_progress.param.update(active=False, visible=False)

    def poll(self):
        """Collect the workers' messages and the function generator (periodic callback)."""
        self._poll_function()
        self._poll_minmax()
        if self.path_mech.value == "linkage" and self.app.state.kind is not self._seen_kind:
            self._path_options()  # the page shows another mechanism
        run = self._path_run
        if not run.running:
            return
        for msg in run.messages():
            if msg[0] == "progress":
                _, desc, k, total = msg
                if total:
                    self.path_progress.param.update(max=total, value=min(k, total))
                run.stage = f"start {k} of {total or '?'}"
            elif msg[0] == "done":
                job = run.job
                self._end_path()
                self.show_path(msg[1], job.targets, job.tables)
                return
            elif msg[0] == "error":
                self._end_path()
                self.path_msg.object = _bad(f"the search failed: {msg[1]}", "path-state")
                return
        self.path_msg.object = (
            f"<span id='path-state'>searching: {run.stage} ({run.elapsed:.0f} s)</span>"
        )

    def show_path(self, res, targets, tables=None):
        """A finished search: its ranked solutions in the table, the best previewed
        (``tables``: the linkage's when the search was over the page's linkage)."""
        self._result, self._targets = res, np.asarray(targets, float)
        self._tables = tables
        rows = path_rows(res)
        if not rows:
            self.path_msg.object = _bad(
                f"nothing found ({res.status}{': ' + res.message if res.message else ''}"
                "): try more starts, a smaller minimum transmission angle or other points",
                "path-state",
            )
            self.path_table.object = ""
            self.path_pick.options = []
            self.path_load.disabled = True
            self.clear_preview()
            return
        st = self.app.state
        unit = st.unit_label("m")
        f = st.display.factor("m")

        def head(name, u):
            return f"<th>{name}, {unit if u == 'm' else 'deg'}</th>"

        def cell(v, u):
            return f"<td>{v / f if u == 'm' else math.degrees(v):.6g}</td>"

        html = [
            "<table id='path-table' style='font-size:13px'><tr><th>rank</th>"
            f"<th>largest distance, {unit}</th><th>sum of squared distances, {unit}^2</th>"
            "<th>min transmission angle, deg</th>"
            + "".join(head(n, u) for n, _, u in rows[0]["dims"])
            + "<th>note</th></tr>"
        ]
        for r in rows:
            html.append(
                f"<tr><td>{r['rank']}</td><td>{r['max_distance'] / f:.4g}</td>"
                f"<td>{r['error'] / f**2:.4g}</td>"
                f"<td>{math.degrees(r['transmission']):.1f}</td>"
                + "".join(cell(v, u) for _, v, u in r["dims"])
                + f"<td>{r['note'] or ''}</td></tr>"
            )
        html.append("</table>")
        self.path_table.object = "".join(html)
        what = {"four-bar": "four-bar", "slider-crank": "slider-crank"}.get(
            _mechanism_of(res.solutions[0]), "design"
        )
        timing = {"free": "", "shape": ", by the path's shape",
                  "prescribed": ", at the crank angles given"}[res.timing]  # fmt: skip
        self.path_msg.object = (
            f"<span id='path-state'>{len(rows)} {what}{'s' if len(rows) != 1 else ''} "
            f"through the {len(targets)} points{timing} "
            f"({res.status}, {res.seconds:.1f} s, {res.starts} starts), best first: pick one to "
            "preview it over the points, load it to edit, optimize or export it</span>"
        )
        options = [str(r["rank"]) for r in rows]
        if list(self.path_pick.options) == options and self.path_pick.value == "1":
            self.preview_path()
        self.path_pick.options = options
        self.path_pick.value = "1"
        self.path_load.disabled = False

    def _solution(self):
        if self._result is None or not self._result.solutions:
            return None, 0
        rank = int(self.path_pick.value or 1)
        return self._result.solutions[rank - 1], rank

    def preview_path(self):
        sol, _ = self._solution()
        if sol is None:
            return
        pv = path_preview(sol)
        t = self._targets / self.app.state.display.factor("m")
        self._show_preview(
            pv["points"], links=pv["links"], pins=pv["pins"], curve=pv["points"][pv["trace"]],
            extra=[tuple(r) for r in t],
        )  # fmt: skip

    def load_path(self):
        sol, rank = self._solution()
        app = self.app
        if sol is None or app._busy("load a solution"):
            return
        try:
            st = path_state(sol, rank, app.units_select.value, self._tables)
        except MechanismError as exc:
            self.path_msg.object = _bad(exc, "path-state")
            return
        app._load_state(st, None)
        # the targets on the drawing (points: no angle)
        app._targets = np.column_stack([self._targets, np.full(len(self._targets), np.nan)])
        app._draw_targets()
        if hasattr(app, "tabs"):
            app.tabs.active = 0

    # ------------------------------------------------------------------ function generation
    def function_job(self) -> FunctionJob:
        """The generator the fields ask for (MechanismError names a bad field)."""
        st = self.app.state
        ground = st.si(parse_number(self.fn_ground.value, self._ground_label()), "m")
        mu_text = (self.fn_mu.value or "").strip()
        mu = math.radians(parse_number(mu_text, "least transmission angle, deg")) if (
            mu_text) else None  # fmt: skip
        common = dict(ground=ground, min_transmission=mu, require_crank=bool(self.fn_crank.value))
        if (self.fn_pairs.value or "").strip():
            return FunctionJob(pairs=parse_pairs(self.fn_pairs.value), **common)
        x0 = parse_number(self.fn_x0.value, "x from")
        x1 = parse_number(self.fn_x1.value, "x to")
        rin = math.radians(parse_number(self.fn_in.value, "input rotation, deg"))
        rout = math.radians(parse_number(self.fn_out.value, "output rotation, deg"))
        return FunctionJob(self.fn_text.value, (x0, x1), rin, rout, **common)

    def start_function(self):
        from .app import _POOL

        if self._function is not None:
            return
        try:
            job = self.function_job()
        except MechanismError as exc:
            self.fn_msg.object = _bad(exc, "function-state")
            return
        self.fn_button.disabled = True
        self.fn_minmax.disabled = True
        self.fn_msg.object = "<span id='function-state'>generating...</span>"
        self._function = _POOL.submit(run_function, job)
        self._function_job = job

    def _poll_function(self):
        if self._function is None or not self._function.done():
            return
        fut, self._function = self._function, None
        self.fn_button.disabled = False
        try:
            fg = fut.result()
        except (ValueError, TypeError, MechanismError) as exc:
            self.fn_msg.object = _bad(exc, "function-state")
            self.fn_minmax.disabled = not self._can_minmax()
            return
        self._fn_job = self._function_job
        self.show_function(fg)

    def _can_minmax(self) -> bool:
        fg, job = self._fg, self._fn_job
        return (fg is not None and fg.solve is None and job is not None and job.pairs is None
                and not self._mm_run.running)  # fmt: skip

    def start_minmax(self):
        """The certified min-max stage from the precision-point design, in a worker process
        (the function generator of the fields, made again there, then its worst structural
        error minimized; Cancel ends it)."""
        if self._mm_run.running or self._fg is None:
            return
        job = self._fn_job  # the generator shown, not the fields as edited since
        if job is None or job.pairs is not None:
            self.fn_cert.object = _bad(
                "the min-max stage needs a function y = f(x): precision pairs alone do not "
                "define the error over the whole range", "function-certificate",
            )  # fmt: skip
            return
        self._mm_run.start(minmax_worker, job)
        self._mm_run.stage = "starting the solve"
        self.fn_minmax.disabled = self.fn_button.disabled = True
        self.fn_mm_cancel.disabled = False
        self.fn_mm_progress.param.update(visible=True, active=True, value=-1)
        self.fn_cert.object = "<span id='function-certificate'>min-max: starting...</span>"

    def cancel_minmax(self):
        if not self._mm_run.running:
            return
        self._end_minmax(kill=True)
        self.fn_cert.object = "<span id='function-certificate'>min-max cancelled</span>"

    def _end_minmax(self, kill=False):
        self._mm_run.end(kill)
        self.fn_button.disabled = False
        self.fn_minmax.disabled = not self._can_minmax()
        self.fn_mm_cancel.disabled = True
        self.fn_mm_progress.param.update(active=False, visible=False)

    def _poll_minmax(self):
        run = self._mm_run
        if not run.running:
            return
        for msg in run.messages():
            if msg[0] == "progress":
                _, desc, k, total = msg
                if total:
                    self.fn_mm_progress.param.update(max=total, value=min(k, total))
                run.stage = f"start {k} of {total or '?'}" + (
                    ", certifying the worst error" if total and k >= total else "")  # fmt: skip
            elif msg[0] == "done":
                self._end_minmax()
                self.show_function(msg[1])
                return
            elif msg[0] == "error":
                self._end_minmax()
                self.fn_cert.object = _bad(f"the min-max failed: {msg[1]}",
                                           "function-certificate")  # fmt: skip
                return
        self.fn_cert.object = (
            f"<span id='function-certificate'>min-max: {run.stage} ({run.elapsed:.0f} s)</span>"
        )

    def show_function(self, fg):
        """A function generator: its structural error curve, its design, its preview."""
        self._fg = fg
        fmt = self.app._fmt
        d = fg.design
        err = np.degrees(np.asarray(fg.error, float))
        if fg.precision_x is not None:
            x, xlabel = np.asarray(fg.x, float), "x"
            px = np.asarray(fg.precision_x, float)
        else:
            x, xlabel = np.degrees(np.asarray(fg.x, float)), "crank angle, deg"
            px = np.degrees(np.asarray(fg.precision_points, float)[:, 0])
        self.src_err.data = dict(x=x.tolist(), y=err.tolist())
        before = [] if fg.start_error is None else np.degrees(fg.start_error).tolist()
        self.src_err_before.data = dict(x=x.tolist() if before else [], y=before)
        # where the (start) design meets f exactly: on the zero of the precision-point
        # design's curve (the dashed one after the min-max stage)
        self.src_prec.data = dict(x=px.tolist(), y=[0.0] * len(px))
        self.err_fig.xaxis.axis_label = xlabel
        self.err_fig.title.text = (
            f"structural error ({fg.method}): largest {math.degrees(fg.max_error):.4g} deg"
        )
        turns = "turns fully" if d.full_turn else "does not turn fully"
        self.fn_design.object = (
            "<div id='function-design'>"
            f"crank <b>{fmt(d.crank, 'm')}</b>, coupler <b>{fmt(d.coupler, 'm')}</b>, rocker "
            f"<b>{fmt(d.rocker, 'm')}</b>, ground <b>{fmt(d.ground, 'm')}</b> ({d.branch} "
            f"branch; the crank {turns}); phases: crank {math.degrees(fg.phases[0]):.2f} deg, "
            f"rocker {math.degrees(fg.phases[1]):.2f} deg; largest structural error "
            f"<span id='function-max-error'>{math.degrees(fg.max_error):.4g}</span> deg"
            + (f" ({fg.max_error_y:.4g} in y)" if fg.max_error_y is not None else "")
            + f"; least transmission angle {math.degrees(fg.min_transmission_angle):.1f} deg"
            "</div>"
        )
        self.fn_msg.object = (
            f"<span id='function-state'>a {fg.method} four-bar "
            + (f"for y = {_esc(fg.function)}" if fg.function else "through the pairs")
            + ": its motion over the input range is on the canvas above</span>"
        )
        self.fn_load.disabled = not d.full_turn
        self.fn_minmax.disabled = not self._can_minmax()
        if fg.solve is not None:
            self.fn_cert.object = (
                "<span id='function-certificate'>" + _esc(certificate_words(fg)) + "</span>"
            )
        elif not self._mm_run.running:
            self.fn_cert.object = ""
        pv = function_preview(fg)
        self._show_preview(pv, links=[["O1", "A"], ["A", "B"], ["B", "O2"]],
                           pins=["O1", "A", "B", "O2"])  # fmt: skip

    def load_function(self):
        app = self.app
        if self._fg is None or app._busy("load a solution"):
            return
        try:
            st = function_state(self._fg, app.units_select.value)
        except MechanismError as exc:
            self.fn_msg.object = _bad(exc, "function-state")
            return
        app._load_state(st, None)
        if hasattr(app, "tabs"):
            app.tabs.active = 0

    # ------------------------------------------------------------------ units
    def units_changed(self):
        """The page's units changed: the labels say the new length unit."""
        from .app import _set_label

        _set_label(self.points_input, self._points_label())
        _set_label(self.fn_ground, self._ground_label())
        # the results in the new units (the typed lists are read in them from now on)
        if self._result is not None:
            rank = self.path_pick.value
            self.show_path(self._result, self._targets, self._tables)
            self.path_pick.value = rank
        if self._fg is not None:
            self.show_function(self._fg)
        self.task_changed()


# ------------------------------------------------------------------------------ helpers
def _append(text: str | None, line: str) -> str:
    text = (text or "").rstrip("\n")
    return f"{text}\n{line}" if text else line


def _rows(text, k: int) -> list[tuple[float, ...]]:
    """The lines of ``text`` that are ``k`` finite numbers (as typed)."""
    return [vals for _, vals in _row_lines(text, k)]


def _row_lines(text, k: int) -> list[tuple[int, tuple[float, ...]]]:
    """``(line index, numbers)`` of the lines of ``text`` that are ``k`` finite numbers."""
    import re

    out = []
    for n, line in enumerate(str(text or "").split("\n")):
        parts = [p for p in re.split(r"[,\s;]+", line.split("#")[0].strip()) if p]
        if len(parts) != k:
            continue
        try:
            vals = tuple(float(p) for p in parts)
        except ValueError:
            continue
        if all(math.isfinite(v) for v in vals):
            out.append((n, vals))
    return out


def _extent(points) -> tuple[float, float, float, float] | None:
    if not points:
        return None
    a = np.asarray(points, float)[:, :2]
    return (float(a[:, 0].min()), float(a[:, 0].max()), float(a[:, 1].min()),
            float(a[:, 1].max()))  # fmt: skip


def _size(ext) -> float:
    return max(ext[1] - ext[0], ext[3] - ext[2])


def _inside(ext, fitted) -> bool:
    if fitted is None:
        return False
    x0, x1, y0, y1 = fitted
    m = 0.08 * max(x1 - x0, y1 - y0)
    return ext[0] >= x0 - m and ext[1] <= x1 + m and ext[2] >= y0 - m and ext[3] <= y1 + m


def _mechanism_of(sol) -> str:
    if sol.fourbar is not None:
        return "four-bar"
    return "slider-crank" if sol.linkage.name == "slider-crank path generator" else "linkage"


def _meets(ext, fitted) -> bool:
    """The extents overlap (or touch)."""
    return not (ext[1] < fitted[0] or ext[0] > fitted[1] or ext[3] < fitted[2]
                or ext[2] > fitted[3])  # fmt: skip


def _esc(text) -> str:
    import html

    return html.escape(str(text), quote=False)


def _bad(text, ident="synth-state") -> str:
    return f"<span id='{ident}' style='color:#b00'>{_esc(text)}</span>"

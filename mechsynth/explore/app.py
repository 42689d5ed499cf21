"""The explorer page (Panel and Bokeh) and its server.

One :class:`Explorer` per browser session: it turns widgets into a
:class:`~mechsynth.explore.model.State` and the model's answers into Bokeh glyphs. The
certified solve runs in a worker process (cancellable, reporting its starts), chart sweeps in a
worker thread; a periodic callback collects their results, so no computation blocks the page.
"""

from __future__ import annotations

import io
import json
import math
import multiprocessing
import queue
import socket
import sys
import time
import webbrowser
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource, HoverTool, LinearColorMapper, Span, TapTool
from bokeh.plotting import figure

from ..errors import MechanismError
from .model import (
    State,
    checks,
    curves,
    kind_names,
    load_file,
    solve_worker,
    sweep_chart,
)

__all__ = ["Explorer", "serve", "free_port"]

FRAMES = 72  # frames of the animation per turn
FIGURE = (560, 460)  # drawing size, px
FRAME = (FIGURE[0] - 75, FIGURE[1] - 85)  # about its inner frame (axes and title taken off)
COLORS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442"]
_POOL = ThreadPoolExecutor(max_workers=2, thread_name_prefix="mechsynth-explore")


class Explorer:
    """The page of one browser session.

    Parameters
    ----------
    state : the state to start from (a mechanism with its problem).
    out : folder where exports are also written (None: downloads only).
    """

    def __init__(self, state: State, out: Path | None = None):
        self.state = state
        self.out = Path(out) if out else None
        self.loaded = {}
        self.last_result = None
        self.design = None
        self.sketch = None
        self.curve_data = None
        self._proc = None
        self._queue = None
        self._t0 = 0.0
        self._sweep = None
        self._stage = ""
        self._chart = None
        self._building = False
        self._design_msgs = {}
        self._build_widgets()
        self._rebuild_dims()
        self._refresh(None)

    # ------------------------------------------------------------------ widgets
    def _build_widgets(self):
        titles = kind_names()
        options = {v: k for k, v in titles.items()}
        self._file_key = None
        if self.state.kind.title not in titles.values():
            self._file_key = self.state.kind.title
            options = {self.state.kind.title: "__file__", **options}
            self.loaded["__file__"] = self.state
        self.kind_select = _widget(
            pn.widgets.Select,
            "Mechanism",
            options=options,
            width=340,
            value="__file__" if self._file_key else self.state.kind.key,
        )
        self.kind_select.param.watch(self._on_kind, "value")
        self.file_input = _widget(
            pn.widgets.TextInput,
            "Load a TOML file (problem, design or linkage file) on this computer",
            placeholder="path/to/file.toml",
            width=270,
        )
        self.file_button = _widget(pn.widgets.Button, "Load", width=60, align="end")
        self.file_button.on_click(self._on_load)
        self.file_msg = pn.pane.Alert("", alert_type="danger", visible=False, width=340)
        self.units_select = _widget(
            pn.widgets.Select,
            "Display units",
            options=["si", "mm-deg", "oilfield"],
            value=self.state.units,
            width=160,
        )
        self.units_select.param.watch(self._on_units, "value")
        self.speed_input = _widget(
            pn.widgets.FloatInput,
            "Crank speed, rpm",
            value=0.0,
            start=0.0,
            width=150,
            description="0: velocities and accelerations as analogs per radian of crank angle",
        )
        self.speed_input.param.watch(self._on_speed, "value")
        self.dims_col = pn.Column(width=360)
        self.design_msg = pn.pane.Alert(
            "", alert_type="danger", visible=False, width=340, css_classes=["design-message"]
        )

        # drawing
        self.fig = figure(
            width=FIGURE[0],
            height=FIGURE[1],
            tools="pan,wheel_zoom,reset,save",
            title="",
            x_axis_label="x",
            y_axis_label="y",
        )
        self.src_bars = ColumnDataSource(dict(xs=[], ys=[], color=[]))
        self.src_plates = ColumnDataSource(dict(xs=[], ys=[], color=[]))
        self.src_paths = ColumnDataSource(dict(xs=[], ys=[], color=[]))
        self.src_guides = ColumnDataSource(dict(xs=[], ys=[]))
        self.src_outlines = ColumnDataSource(dict(xs=[], ys=[]))
        self.src_joints = ColumnDataSource(dict(x=[], y=[], name=[]))
        self.src_ground = ColumnDataSource(dict(x=[], y=[], name=[]))
        self.src_blocks = ColumnDataSource(dict(x=[], y=[], angle=[], w=[], h=[]))
        self.fig.multi_line(
            "xs",
            "ys",
            source=self.src_paths,
            line_color="color",
            line_dash="dashed",
            line_width=1.2,
            name="paths",
        )
        self.fig.multi_line(
            "xs", "ys", source=self.src_guides, line_color="#444444", line_width=2, name="guides"
        )
        self.fig.multi_line(
            "xs",
            "ys",
            source=self.src_outlines,
            line_color="#555555",
            line_width=2,
            name="outlines",
        )
        self.fig.patches(
            "xs",
            "ys",
            source=self.src_plates,
            fill_color="color",
            fill_alpha=0.35,
            line_color="color",
            line_width=3,
            name="plates",
        )
        self.fig.multi_line(
            "xs", "ys", source=self.src_bars, line_color="color", line_width=5, name="bars"
        )
        self.fig.rect(
            "x",
            "y",
            width="w",
            height="h",
            angle="angle",
            source=self.src_blocks,
            fill_color="#bbbbbb",
            line_color="#333333",
            name="blocks",
        )
        self.fig.scatter(
            "x",
            "y",
            source=self.src_ground,
            marker="triangle",
            size=16,
            fill_color="#888888",
            line_color="black",
            name="ground",
        )
        self.fig.scatter(
            "x",
            "y",
            source=self.src_joints,
            size=9,
            fill_color="white",
            line_color="black",
            line_width=2,
            name="joints",
        )
        self.fig.text(
            "x",
            "y",
            text="name",
            source=self.src_joints,
            x_offset=6,
            y_offset=-6,
            text_font_size="11px",
            name="labels",
        )

        self.player = _widget(
            pn.widgets.Player,
            "Crank angle",
            start=0,
            end=FRAMES - 1,
            value=0,
            interval=60,
            loop_policy="loop",
            width=420,
            show_value=False,
            visible_loop_options=[],
        )
        self.player.param.watch(self._on_frame, "value")
        self.fps = _widget(
            pn.widgets.IntSlider,
            "Animation, frames per second",
            start=2,
            end=40,
            value=16,
            width=200,
        )
        self.fps.param.watch(lambda e: setattr(self.player, "interval", int(1000 / e.new)), "value")
        self.stats = pn.pane.HTML("", width=330, css_classes=["stats"])
        self.checks_pane = pn.pane.HTML("", width=330, css_classes=["checks"])

        # curves
        self.curve_figs, self.curve_srcs, self.spans = [], [], []
        for title in ("position", "velocity", "acceleration", "angles"):
            f = figure(
                width=290,
                height=230,
                title=title,
                tools="pan,wheel_zoom,reset,save",
                x_axis_label="crank angle, deg",
            )
            f.x_range.start, f.x_range.end = 0, 360
            src = ColumnDataSource(dict(x=[], y=[], y2=[]))
            f.line(
                "x",
                "y",
                source=src,
                line_width=2,
                color=COLORS[0],
                legend_label="pressure" if title == "angles" else title,
            )
            if title == "angles":
                f.line(
                    "x",
                    "y2",
                    source=src,
                    line_width=2,
                    color=COLORS[1],
                    legend_label="transmission",
                )
                f.legend.location = "top_left"
                f.legend.label_text_font_size = "9px"
            else:
                f.legend.visible = False
            span = Span(location=0, dimension="height", line_color="#D55E00", line_width=1.5)
            f.add_layout(span)
            self.curve_figs.append(f)
            self.curve_srcs.append(src)
            self.spans.append(span)

        # problem and optimization
        self.objective = _widget(pn.widgets.TextInput, "Objective measure", width=300)
        self.sense = _widget(pn.widgets.Select, "", options=["minimize", "maximize"], width=110)
        self.constraints = _widget(
            pn.widgets.TextAreaInput,
            "Constraints (one a line: measure <= value unit)",
            height=110,
            width=420,
        )
        self.method = _widget(
            pn.widgets.Select, "Method", options=["ipopt", "slsqp", "de"], width=100
        )
        self.starts = _widget(
            pn.widgets.IntInput, "Starts", start=1, end=1000, width=80, css_classes=["opt-starts"]
        )
        for w in (self.objective, self.sense, self.constraints, self.method, self.starts):
            w.param.watch(self._on_problem, "value")
        self.problem_msg = pn.pane.Alert(
            "", alert_type="danger", visible=False, width=420, css_classes=["problem-message"]
        )
        self.opt_button = _widget(pn.widgets.Button, "Optimize", button_type="primary", width=110)
        self.opt_button.on_click(self._on_optimize)
        self.cancel_button = _widget(
            pn.widgets.Button, "Cancel", button_type="warning", width=90, disabled=True
        )
        self.cancel_button.on_click(self._on_cancel)
        self.progress = pn.indicators.Progress(
            value=0, max=1, width=200, active=False, visible=False
        )
        self.opt_status = pn.pane.HTML("", width=340, css_classes=["opt-status"])
        self.report = pn.pane.HTML("", width=600, css_classes=["opt-report"])

        # chart
        self.chart_x = _widget(pn.widgets.Select, "x axis", width=140)
        self.chart_y = _widget(pn.widgets.Select, "y axis", width=140)
        self.chart_measure = _widget(pn.widgets.Select, "colour: measure", width=220)
        self.chart_n = _widget(
            pn.widgets.IntSlider, "points per axis", start=5, end=80, value=30, width=200
        )
        self.chart_button = _widget(pn.widgets.Button, "Sweep", button_type="primary", width=90)
        self.chart_button.on_click(self._on_sweep)
        self.chart_measure.param.watch(lambda e: self._draw_chart(), "value")
        self.chart_msg = pn.pane.HTML("", width=600, css_classes=["chart-message"])
        self.chart_fig = figure(
            width=620,
            height=500,
            tools="tap,pan,wheel_zoom,reset,save",
            title="click a cell to load that design",
        )
        self.chart_src = ColumnDataSource(
            dict(x=[], y=[], v=[], raw=[], ok=[], i=[], j=[], w=[], h=[])
        )
        self.mapper = LinearColorMapper(palette="Viridis256", nan_color="#eeeeee")
        cells = self.chart_fig.rect(
            "x",
            "y",
            width="w",
            height="h",
            source=self.chart_src,
            fill_color={"field": "v", "transform": self.mapper},
            line_color=None,
            fill_alpha="ok",
            name="cells",
            nonselection_fill_alpha="ok",
            selection_line_color="black",
        )
        self.chart_fig.add_tools(
            HoverTool(tooltips=[("x", "@x"), ("y", "@y"), ("value", "@raw")], renderers=[cells])
        )
        self.chart_marker = ColumnDataSource(dict(x=[], y=[]))
        self.chart_fig.scatter(
            "x",
            "y",
            source=self.chart_marker,
            marker="cross",
            size=18,
            line_color="red",
            line_width=3,
        )
        self.chart_fig.select_one(TapTool).mode = "replace"
        self.chart_src.selected.on_change("indices", self._on_cell)

        # exports
        self.dl_toml = pn.widgets.FileDownload(
            callback=self._export_toml,
            filename="problem.toml",
            label="Problem file (TOML)",
            width=220,
        )
        self.dl_draw = pn.widgets.FileDownload(
            callback=self._export_drawing,
            filename="mechanism.png",
            label="Drawing (PNG)",
            width=220,
        )
        self.dl_curves = pn.widgets.FileDownload(
            callback=self._export_curves,
            filename="curves.png",
            label="Motion curves (PNG)",
            width=220,
        )
        self.dl_chart = pn.widgets.FileDownload(
            callback=self._export_chart, filename="chart.png", label="Chart (PNG)", width=220
        )
        self.export_msg = pn.pane.HTML("", width=600, css_classes=["export-message"])

    def _rebuild_dims(self):
        """Sliders, number fields, bounds and messages for the kind's dimensions."""
        st = self.state
        self._building = True
        try:
            self.dim_widgets = {}
            rows = []
            for d in st.kind.dims:
                unit = st.unit_label(d.unit)
                label = f"{d.name}, {unit}" if unit else d.name
                lo, hi = _r(st.shown(d.lo, d.unit)), _r(st.shown(d.hi, d.unit))
                value = st.shown(st.values[d.name], d.unit)
                lo, hi = min(lo, value), max(hi, value)
                step = _nice_step((hi - lo) / 400)
                slider = _widget(
                    pn.widgets.EditableFloatSlider,
                    label,
                    start=lo,
                    end=hi,
                    value=value,
                    step=step,
                    width=330,
                    format="0[.]0000",
                    css_classes=[f"dim-{d.name}"],
                )
                slider.param.watch(lambda e, n=d.name: self._on_dim(n, e.new), "value")
                vlo, vhi = st.vary.get(d.name, (d.lo, d.hi))
                vary = _widget(
                    pn.widgets.Checkbox,
                    "vary",
                    value=d.name in st.vary,
                    width=60,
                    disabled=not d.varies,
                )
                lo_in = _widget(
                    pn.widgets.FloatInput,
                    "",
                    value=_r(st.shown(vlo, d.unit)),
                    width=110,
                    css_classes=[f"lo-{d.name}"],
                )
                hi_in = _widget(
                    pn.widgets.FloatInput,
                    "",
                    value=_r(st.shown(vhi, d.unit)),
                    width=110,
                    css_classes=[f"hi-{d.name}"],
                )
                for w in (vary, lo_in, hi_in):
                    w.param.watch(lambda e, n=d.name: self._on_bounds(n), "value")
                msg = pn.pane.Alert(
                    "",
                    alert_type="danger",
                    visible=False,
                    width=330,
                    css_classes=[f"msg-{d.name}"],
                    margin=(0, 5),
                )
                self.dim_widgets[d.name] = (slider, vary, lo_in, hi_in, msg)
                rows.append(
                    pn.Column(
                        slider,
                        pn.Row(
                            vary,
                            pn.pane.HTML("bounds", margin=(8, 2)),
                            lo_in,
                            hi_in,
                            margin=(-8, 5, 0, 5),
                        ),
                        msg,
                        margin=(0, 0, 6, 0),
                        styles={"border-bottom": "1px solid #ddd"},
                    )
                )
                slider.description = d.label
            self.dims_col.objects = rows
            self.speed_input.value = (
                0.0 if st.speed is None else round(st.speed * 60 / (2 * math.pi), 6)
            )
            self.objective.value = st.objective
            self.sense.value = st.sense
            self.constraints.value = "\n".join(st.constraints)
            self.method.value = st.method
            self.starts.value = st.starts
            names = [d.name for d in st.kind.dims]
            self.chart_x.options = names
            self.chart_y.options = names
            self.chart_x.value = names[0]
            self.chart_y.value = names[1]
            self._chart = None
            self.chart_src.data = dict(x=[], y=[], v=[], raw=[], ok=[], i=[], j=[], w=[], h=[])
        finally:
            self._building = False

    def _sync_values(self):
        """Move the sliders to the state's values (after a solve or a chart click)."""
        st = self.state
        self._building = True
        try:
            for d in st.kind.dims:
                slider = self.dim_widgets[d.name][0]
                value = st.shown(st.values[d.name], d.unit)
                slider.param.update(
                    start=min(slider.start, value), end=max(slider.end, value), value=value
                )
        finally:
            self._building = False

    # ------------------------------------------------------------------ events
    def _on_kind(self, event):
        if self._busy("change the mechanism"):
            return
        if event.new == "__file__":
            self.state = self.loaded["__file__"]
            self.state.units = self.units_select.value
        else:
            self.state = State.default(event.new, self.units_select.value)
        self.opt_status.object = ""
        self.report.object = ""
        self._rebuild_dims()
        self._refresh(None)

    def _on_load(self, event=None):
        path = self.file_input.value.strip()
        try:
            st = load_file(path, self.units_select.value)
        except (OSError, ValueError) as exc:
            self.file_msg.object = str(exc)
            self.file_msg.visible = True
            return
        self.file_msg.visible = False
        self.loaded["__file__"] = st
        options = {k: v for k, v in self.kind_select.options.items() if v != "__file__"}
        self.kind_select.options = {st.kind.title: "__file__", **options}
        if self.kind_select.value == "__file__":
            self._on_kind(type("E", (), {"new": "__file__"}))
        else:
            self.kind_select.value = "__file__"

    def _on_units(self, event):
        self.state.units = event.new
        self._rebuild_dims()
        self._refresh(None)

    def _on_speed(self, event):
        if self._building:
            return
        v = event.new
        self.state.speed = None if not v else float(v) * 2 * math.pi / 60
        self._refresh(None)

    def _on_dim(self, name, value):
        if self._building:
            return
        d = self.state.kind.dim(name)
        self.state.values[name] = self.state.si(value, d.unit) if value is not None else np.nan
        self._refresh(name)

    def _on_bounds(self, name):
        if self._building:
            return
        st = self.state
        d = st.kind.dim(name)
        _, vary, lo_in, hi_in, msg = self.dim_widgets[name]
        if vary.value:
            lo = np.nan if lo_in.value is None else st.si(lo_in.value, d.unit)
            hi = np.nan if hi_in.value is None else st.si(hi_in.value, d.unit)
            st.vary[name] = (lo, hi)
        else:
            st.vary.pop(name, None)
        self._show_bound_messages()

    def _show_bound_messages(self) -> bool:
        bad = self.state.bound_messages()
        for n, (_, _, _, _, msg) in self.dim_widgets.items():
            text = bad.get(n) or self._design_msgs.get(n, "")
            msg.object = text
            msg.visible = bool(text)
        return not bad

    def _on_problem(self, event):
        if self._building:
            return
        st = self.state
        st.objective = self.objective.value or ""
        st.sense = self.sense.value
        st.constraints = [c for c in (self.constraints.value or "").splitlines() if c.strip()]
        st.method = self.method.value
        st.starts = int(self.starts.value or 1)
        self._show_checks()

    def _on_frame(self, event):
        self._draw_frame(int(event.new))

    # ------------------------------------------------------------------ refresh
    def _refresh(self, changed):
        """Rebuild the design from the state; on failure show the message next to the field
        that was changed (the drawing keeps the last valid design)."""
        design, message = self.state.check_design()
        self._design_msgs = {}
        if message is not None:
            where = changed if changed in self.dim_widgets else None
            if where is None:
                self.design_msg.object = f"The design cannot be built: {message}"
                self.design_msg.visible = True
            else:
                self._design_msgs[where] = message
                self.design_msg.object = f"{where}: the design cannot be built (see the field)"
                self.design_msg.visible = True
            self._show_bound_messages()
            self.stats.object = (
                "<div id='stats' style='color:#b00'>invalid design: "
                "showing the last valid one</div>"
            )
            return
        self.design_msg.visible = False
        self._show_bound_messages()
        self.design = design
        try:
            self.sketch = design.sketch(design.turn_sign * _frames_phi())
            self.curve_data = curves(self.state, design)
        except (MechanismError, ValueError) as exc:  # pragma: no cover - checked above
            self.design_msg.object = str(exc)
            self.design_msg.visible = True
            return
        self._draw_static()
        self._draw_frame(int(self.player.value))
        self._draw_curves()
        self._show_stats()
        self._show_checks()

    def _length(self, v):
        return np.asarray(v, dtype=float) / self.state.display.factor("m")

    def _draw_static(self):
        sk, st = self.sketch, self.state
        x0, x1, y0, y1 = (float(self._length(v)) for v in sk.extent())
        # equal scales on both axes: the ranges in the proportions of the plot's frame
        pad = 0.1 * max(x1 - x0, y1 - y0, 1e-9)
        w_px, h_px = FRAME
        scale = max((x1 - x0 + 2 * pad) / w_px, (y1 - y0 + 2 * pad) / h_px)
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        self.fig.x_range.start, self.fig.x_range.end = cx - scale * w_px / 2, cx + scale * w_px / 2
        self.fig.y_range.start, self.fig.y_range.end = cy - scale * h_px / 2, cy + scale * h_px / 2
        unit = st.unit_label("m")
        self.fig.xaxis.axis_label = f"x, {unit}"
        self.fig.yaxis.axis_label = f"y, {unit}"
        self.fig.title.text = sk.name or st.kind.title
        trace = [p for p in st.kind.trace if p in sk.points]
        self.src_paths.data = dict(
            xs=[self._length(sk.points[p][0]).tolist() for p in trace],
            ys=[self._length(sk.points[p][1]).tolist() for p in trace],
            color=[COLORS[(i + 2) % len(COLORS)] for i in range(len(trace))],
        )
        self.src_ground.data = dict(
            x=[float(self._length(sk.points[g][0][0])) for g in sk.ground],
            y=[float(self._length(sk.points[g][1][0])) for g in sk.ground],
            name=list(sk.ground),
        )
        fixed = [o for o in sk.outlines if np.ndim(o.x) == 1]
        self._fixed_outlines = (
            [self._length(o.x).tolist() for o in fixed],
            [self._length(o.y).tolist() for o in fixed],
        )
        # fixed guides over the block's travel
        xs, ys = [], []
        size = max(x1 - x0, y1 - y0, 1e-9)
        for s in sk.sliders:
            if s.through is not None:
                continue
            px, py = self._length(sk.points[s.point][0]), self._length(sk.points[s.point][1])
            a = np.asarray(s.angle, dtype=float)
            a0 = float(a) if a.ndim == 0 else float(a.ravel()[0])
            u = np.array([math.cos(a0), math.sin(a0)])
            t = px * u[0] + py * u[1]
            ext = 0.08 * size
            t0, t1 = float(t.min()) - ext, float(t.max()) + ext
            bx, by = float(px[0] - t[0] * u[0]), float(py[0] - t[0] * u[1])
            xs.append([bx + t0 * u[0], bx + t1 * u[0]])
            ys.append([by + t0 * u[1], by + t1 * u[1]])
        self._guides = (xs, ys)
        self._block = 0.06 * size

    def _draw_frame(self, k):
        sk = self.sketch
        if sk is None:
            return
        k = k % sk.frames
        pts = {
            n: (float(self._length(x[k])), float(self._length(y[k])))
            for n, (x, y) in sk.points.items()
        }
        bars_x, bars_y, bars_c, pl_x, pl_y, pl_c = [], [], [], [], [], []
        for i, b in enumerate(sk.bars):
            xs = [pts[p][0] for p in b.points]
            ys = [pts[p][1] for p in b.points]
            c = COLORS[i % len(COLORS)]
            if len(b.points) >= 3:
                pl_x.append(xs)
                pl_y.append(ys)
                pl_c.append(c)
            else:
                bars_x.append(xs)
                bars_y.append(ys)
                bars_c.append(c)
        self.src_bars.data = dict(xs=bars_x, ys=bars_y, color=bars_c)
        self.src_plates.data = dict(xs=pl_x, ys=pl_y, color=pl_c)
        joints = (
            sk.joints
            if sk.joints is not None
            else tuple(dict.fromkeys(p for b in sk.bars for p in b.points))
        )
        moving = [p for p in joints if p not in sk.ground]
        self.src_joints.data = dict(
            x=[pts[p][0] for p in moving], y=[pts[p][1] for p in moving], name=list(moving)
        )
        bx, by, ba = [], [], []
        gx, gy = list(self._guides[0]), list(self._guides[1])
        for s in sk.sliders:
            a = sk.slider_angle(s, k)
            bx.append(pts[s.point][0])
            by.append(pts[s.point][1])
            ba.append(a)
            if s.through is not None:
                ux, uy = math.cos(a), math.sin(a)
                tx, ty = pts[s.through]
                r = 2.5 * self._block
                gx.append([tx - r * ux, tx + r * ux])
                gy.append([ty - r * uy, ty + r * uy])
        w = self._block
        self.src_blocks.data = dict(x=bx, y=by, angle=ba, w=[1.6 * w] * len(bx), h=[w] * len(bx))
        self.src_guides.data = dict(xs=gx, ys=gy)
        ox, oy = list(self._fixed_outlines[0]), list(self._fixed_outlines[1])
        for o in sk.outlines:
            if np.ndim(o.x) == 2:
                x, y = sk.outline_xy(o, k)
                ox.append(self._length(x).tolist())
                oy.append(self._length(y).tolist())
        self.src_outlines.data = dict(xs=ox, ys=oy)
        angle = 360.0 * k / FRAMES
        for span in self.spans:
            span.location = angle
        _set_label(self.player, f"Crank angle {angle:.0f} deg")

    def _draw_curves(self):
        c, st = self.curve_data, self.state
        lin = c["unit"] == "m"
        analog = c["speed"] is None
        pos_u = "m" if lin else "rad"
        vel_u = ("m/rad" if analog else "m/s") if lin else ("1" if analog else "rad/s")
        acc_u = ("m/rad^2" if analog else "m/s^2") if lin else ("1" if analog else "rad/s^2")
        labels = []
        for key, unit in (("position", pos_u), ("velocity", vel_u), ("acceleration", acc_u)):
            y = np.asarray(c[key], dtype=float)
            if lin:
                y = y / st.display.factor(unit)
                shown = st.display.unit(unit)
            elif unit == "rad":
                y, shown = np.degrees(y), "deg"
            else:
                shown = unit if unit != "1" else "rad/rad"
            labels.append((key, y, shown))
        for (key, y, shown), f, src in zip(labels, self.curve_figs, self.curve_srcs):
            src.data = dict(x=c["angle"].tolist(), y=y.tolist(), y2=[0.0] * y.size)
            f.title.text = f"{c['output']} {key}"
            f.yaxis.axis_label = f"{key}, {shown}"
        p = c["pressure"]
        t = c["transmission"]
        n = c["angle"].size
        self.curve_srcs[3].data = dict(
            x=c["angle"].tolist(),
            y=(np.degrees(p).tolist() if p is not None else [np.nan] * n),
            y2=(np.degrees(t).tolist() if t is not None else [np.nan] * n),
        )
        self.curve_figs[3].yaxis.axis_label = "pressure, transmission angle, deg"

    def _fmt(self, value, unit):
        v, shown = self.state.display.convert(float(value), unit)
        if unit == "rad":
            v, shown = math.degrees(value), "deg"
        return f"{v:.6g} {shown}".rstrip()

    def _show_stats(self):
        c = self.curve_data
        unit = "m" if c["unit"] == "m" else "rad"
        what = "stroke" if unit == "m" else "swing"
        value = self._fmt(c["stroke"], unit)
        self.stats.object = (
            f"<div id='stats'><b>{what}</b> of {c['output']}: "
            f"<span id='stroke' data-si='{c['stroke']!r}'>{value}</span></div>"
        )

    def _show_checks(self):
        if self.design is None:
            return
        try:
            rows = checks(self.state, self.design)
        except (ValueError, TypeError, MechanismError) as exc:
            self.checks_pane.object = ""
            self.problem_msg.object = str(exc)
            self.problem_msg.visible = True
            return
        self.problem_msg.visible = False
        html = ["<table id='checks' style='font-size:13px;border-collapse:collapse'>"]
        for r in rows:
            val = self._fmt(r.value, r.unit)
            if r.objective:
                html.append(
                    f"<tr><td>{r.op}</td><td><b>{r.name}</b></td><td>{val}</td><td></td></tr>"
                )
            else:
                colour = "#1a7f37" if r.ok else "#cf222e"
                mark = "OK" if r.ok else "violated"
                html.append(
                    f"<tr style='color:{colour}' class='{'ok' if r.ok else 'bad'}'>"
                    f"<td>{mark}</td><td>{r.name} {r.op} {self._fmt(r.bound, r.unit)}</td>"
                    f"<td>{val}</td><td></td></tr>"
                )
        html.append("</table>")
        self.checks_pane.object = "".join(html)

    # ------------------------------------------------------------------ optimize
    def _busy(self, what) -> bool:
        if self._proc is not None:
            self.opt_status.object = f"<span style='color:#b00'>cancel the solve to {what}</span>"
            return True
        return False

    def _on_optimize(self, event=None):
        if self._proc is not None:
            return
        self._on_problem(None)
        if not self._show_bound_messages():
            self.opt_status.object = (
                "<span id='opt-state' style='color:#b00'>fix the bounds "
                "shown next to the fields</span>"
            )
            return
        try:
            data = self.state.problem_data()
            self.state.problem()  # its errors name the measure or the bound
        except (ValueError, TypeError, MechanismError) as exc:
            self.opt_status.object = f"<span id='opt-state' style='color:#b00'>{exc}</span>"
            return
        ctx = multiprocessing.get_context("spawn")
        self._queue = ctx.Queue()
        self._proc = ctx.Process(target=solve_worker, args=(data, self._queue), daemon=True)
        self._proc.start()
        self._t0 = time.perf_counter()
        self._stage = "starting the solver"
        self.opt_button.disabled = True
        self.cancel_button.disabled = False
        self.progress.visible = True
        self.progress.active = True
        self.progress.value = -1
        self.opt_status.object = "<span id='opt-state'>solving: starting the solver...</span>"

    def _on_cancel(self, event=None):
        if self._proc is None:
            return
        self._proc.terminate()
        self._proc.join(timeout=5)
        self._end_solve()
        self.opt_status.object = "<span id='opt-state'>cancelled</span>"

    def close(self):
        """Stop a running solve (the session ended)."""
        if self._proc is not None:
            self._proc.terminate()
            self._end_solve()

    def _end_solve(self):
        self._proc = None
        self._queue = None
        self.opt_button.disabled = False
        self.cancel_button.disabled = True
        self.progress.active = False
        self.progress.visible = False

    def poll(self):
        """Collect the worker's messages and the chart sweep (periodic callback)."""
        if self._queue is not None:
            elapsed = time.perf_counter() - self._t0
            while True:
                try:
                    msg = self._queue.get_nowait()
                except (queue.Empty, OSError, ValueError):
                    break
                if msg[0] == "progress":
                    _, desc, k, total = msg
                    if total:
                        self.progress.max = total
                        self.progress.value = min(k, total)
                    self._stage = f"{desc} {k}/{total or '?'}"
                    if total and k >= total:
                        self._stage += ", certifying the peaks"
                elif msg[0] == "done":
                    self._end_solve()
                    self._apply_result(msg[1])
                    break
                elif msg[0] == "error":
                    self._end_solve()
                    self.opt_status.object = (
                        f"<span id='opt-state' style='color:#b00'>solve failed: {msg[1]}</span>"
                    )
                    break
            if self._proc is not None:  # the elapsed time moves even between messages
                self.opt_status.object = (
                    f"<span id='opt-state'>solving: {self._stage} ({elapsed:.0f} s)</span>"
                )
            if (
                self._proc is not None
                and not self._proc.is_alive()
                and self._queue is not None
                and self._queue.empty()
            ):
                self._end_solve()
                self.opt_status.object = (
                    "<span id='opt-state' style='color:#b00'>the solver "
                    "process ended without a result</span>"
                )
        if self._sweep is not None and self._sweep.done():
            fut, self._sweep = self._sweep, None
            self.chart_button.disabled = False
            try:
                self._chart = fut.result()
            except (ValueError, MechanismError) as exc:
                self.chart_msg.object = f"<span style='color:#b00'>{exc}</span>"
                return
            self._draw_chart()

    def _apply_result(self, res):
        st = self.state
        ok = res.get("success")
        status = res.get("status")
        colour = "#1a7f37" if ok else "#cf222e"
        value = res.get("value")
        text = f"{status}: {res.get('objective')} = {value:.6g}" if value is not None else status
        self.opt_status.object = (
            f"<span id='opt-state' style='color:{colour}'>{text} "
            f"({res.get('solve_time', 0):.1f} s)</span>"
        )
        self.report.object = "<pre id='opt-report'>" + _escape(res.get("report", "")) + "</pre>"
        if res.get("variables"):
            st.values = st.values_of(res["variables"])
            self._sync_values()
            self._refresh(None)
        self.last_result = res

    # ------------------------------------------------------------------ chart
    def _on_sweep(self, event=None):
        if self._sweep is not None:
            return
        x, y = self.chart_x.value, self.chart_y.value
        st = self.state
        try:
            if x == y:
                raise ValueError("choose two different dimensions for the chart")
            _ = [st.kind.dim(x), st.kind.dim(y)]
        except ValueError as exc:
            self.chart_msg.object = f"<span style='color:#b00'>{exc}</span>"
            return
        snapshot = State(
            st.kind,
            dict(st.values),
            dict(st.vary),
            st.objective,
            st.sense,
            list(st.constraints),
            st.speed,
            st.units,
        )
        self.chart_button.disabled = True
        self.chart_msg.object = "sweeping..."
        n = int(self.chart_n.value)
        self._chart_state = snapshot
        self._sweep = _POOL.submit(sweep_chart, snapshot, x, y, n)

    def _draw_chart(self):
        ch = self._chart
        if ch is None:
            return
        st = self._chart_state
        labels = list(ch.values)
        if self.chart_measure.options != labels:
            self.chart_measure.options = labels
        label = self.chart_measure.value if self.chart_measure.value in labels else labels[0]
        (xn, xv), (yn, yv) = list(ch.grid.items())
        dx, dy = st.kind.dim(xn), st.kind.dim(yn)
        X, Y = np.meshgrid(xv, yv, indexing="ij")
        vals = ch.values[label]
        unit = ch.units.get(label, "")
        data = np.asarray(vals.filled(np.nan), dtype=float)
        if unit == "rad":
            data, shown = np.degrees(data), "deg"
        else:
            data = data / st.display.factor(unit) if unit else data
            shown = st.display.unit(unit) if unit else ""
        ok = ch.satisfied(None)
        good = np.ones_like(ok)
        for text in st.constraints:
            from ..synthesis.problem_file import parse_constraint

            c = parse_constraint(text)
            if c.measure.name in ch.values and c.op in ("<=", ">="):
                good &= ch.satisfied({c.measure.name: (c.op, c.bound)})
        alpha = np.where(ok, np.where(good, 1.0, 0.45), 0.0)
        wx = (xv[1] - xv[0]) / st.display.factor(dx.unit or "1") if xv.size > 1 else 1
        wy = (yv[1] - yv[0]) / st.display.factor(dy.unit or "1") if yv.size > 1 else 1
        raw = data.copy()
        scale_note = ""
        finite = data[np.isfinite(data) & ok]
        if finite.size:
            lo, hi = float(finite.min()), float(finite.max())
            # a measure over decades (peaks over a wide box): colour its logarithm
            log = lo > 0 and hi / lo > 30
            if log:
                data = np.log10(np.where(data > 0, data, np.nan))
                lo, hi = math.log10(lo), math.log10(hi)
                scale_note = " (colour on a log scale)"
            self.mapper.low, self.mapper.high = lo, hi
        self.chart_src.selected.indices = []
        self.chart_src.data = dict(
            raw=np.where(np.isfinite(raw), raw, np.nan).ravel().tolist(),
            x=(X / st.display.factor(dx.unit or "1")).ravel().tolist(),
            y=(Y / st.display.factor(dy.unit or "1")).ravel().tolist(),
            v=np.where(np.isfinite(data), data, np.nan).ravel().tolist(),
            ok=alpha.ravel().tolist(),
            i=np.indices(X.shape)[0].ravel().tolist(),
            j=np.indices(X.shape)[1].ravel().tolist(),
            w=[abs(wx)] * X.size,
            h=[abs(wy)] * X.size,
        )
        ux, uy = st.unit_label(dx.unit), st.unit_label(dy.unit)
        self.chart_fig.xaxis.axis_label = f"{xn}, {ux}" if ux else xn
        self.chart_fig.yaxis.axis_label = f"{yn}, {uy}" if uy else yn
        self.chart_fig.title.text = (
            f"{label}"
            + (f", {shown}" if shown else "")
            + scale_note
            + ": click a cell to load that design"
        )
        self.chart_msg.object = (
            f"{ch.size} designs in {ch.elapsed:.2f} s; {int(ch.feasible.sum())} can be built; "
            "faded cells break a constraint, blank cells cannot be built"
            + (f" ({_escape(ch.reason)})" if ch.reason else "")
        )
        self._colour_bar_range = (self.mapper.low, self.mapper.high)

    def _on_cell(self, attr, old, new):
        if not new or self._chart is None:
            return
        k = new[0]
        i, j = self.chart_src.data["i"][k], self.chart_src.data["j"][k]
        self.load_cell(i, j)

    def load_cell(self, i: int, j: int):
        """Load the chart's design (i, j) into the sliders."""
        ch = self._chart
        (xn, xv), (yn, yv) = list(ch.grid.items())
        if not ch.feasible[i, j]:
            self.chart_msg.object = "<span style='color:#b00'>that design cannot be built</span>"
            return
        self.state.values[xn] = float(xv[i])
        self.state.values[yn] = float(yv[j])
        self._sync_values()
        self._refresh(None)
        st = self.state
        self.chart_marker.data = dict(
            x=[xv[i] / st.display.factor(st.kind.dim(xn).unit or "1")],
            y=[yv[j] / st.display.factor(st.kind.dim(yn).unit or "1")],
        )

    # ------------------------------------------------------------------ exports
    def _save(self, name, data: bytes) -> io.BytesIO:
        if self.out is not None:
            self.out.mkdir(parents=True, exist_ok=True)
            path = self.out / name
            tmp = path.with_suffix(path.suffix + ".part")
            tmp.write_bytes(data)
            tmp.replace(path)
            self.export_msg.object = f"written: <span class='written'>{_escape(str(path))}</span>"
        return io.BytesIO(data)

    def _export_toml(self):
        try:
            text = self.state.problem_toml()
        except (ValueError, MechanismError) as exc:
            self.export_msg.object = f"<span style='color:#b00'>{_escape(str(exc))}</span>"
            return io.BytesIO(f"# cannot write the problem: {exc}\n".encode())
        return self._save("problem.toml", text.encode())

    def _export_drawing(self):
        from matplotlib.figure import Figure

        from ..display import display_units

        fig = Figure(figsize=(6, 5))
        ax = fig.subplots()
        k = int(self.player.value)
        with display_units(self.state.units):
            self.design.draw(
                self.design.turn_sign * 2 * math.pi * k / FRAMES, ax=ax, trace=self.state.kind.trace
            )
        fig.tight_layout()
        return self._save("mechanism.png", _png(fig))

    def _export_curves(self):
        from matplotlib.figure import Figure

        fig = Figure(figsize=(9, 6))
        axes = fig.subplots(2, 2).ravel()
        for f, src, ax in zip(self.curve_figs, self.curve_srcs, axes):
            d = src.data
            ax.plot(d["x"], d["y"], label="pressure" if f is self.curve_figs[3] else None)
            if f is self.curve_figs[3]:
                ax.plot(d["x"], d["y2"], label="transmission")
                ax.legend(fontsize=8)
            ax.axvline(360.0 * int(self.player.value) / FRAMES, color="#D55E00", lw=1)
            ax.set_title(f.title.text, fontsize=10)
            ax.set_xlabel("crank angle, deg")
            ax.set_ylabel(f.yaxis[0].axis_label, fontsize=9)
            ax.set_xlim(0, 360)
        fig.tight_layout()
        return self._save("curves.png", _png(fig))

    def _export_chart(self):
        if self._chart is None:
            self.export_msg.object = "sweep a chart first (Chart tab)"
            return io.BytesIO(b"")
        from ..display import display_units

        label = self.chart_measure.value or None
        with display_units(self.state.units):
            fig = self._chart.plot(measures=[label] if label else None)
        data = _png(fig)
        import matplotlib.pyplot as plt

        plt.close(fig)
        return self._save("chart.png", data)

    # ------------------------------------------------------------------ layout
    def view(self):
        sidebar = pn.Column(
            pn.pane.HTML("<h2 style='margin:4px 0'>mechsynth explore</h2>"),
            self.kind_select,
            pn.Row(self.file_input, self.file_button),
            self.file_msg,
            pn.Row(self.units_select, self.speed_input),
            pn.Row(self.opt_button, self.cancel_button, self.progress),
            self.opt_status,
            self.design_msg,
            self.dims_col,
            width=380,
            scroll=True,
            height=980,
        )
        design_tab = pn.Column(
            pn.Row(
                pn.pane.Bokeh(self.fig),
                pn.Column(
                    pn.Row(self.player),
                    self.fps,
                    self.stats,
                    pn.pane.HTML("<b>Problem measures</b> (green: holds, red: violated)"),
                    self.checks_pane,
                ),
            ),
            pn.Row(*[pn.pane.Bokeh(f) for f in self.curve_figs]),
        )
        problem_tab = pn.Column(
            pn.Row(self.sense, self.objective),
            self.constraints,
            pn.Row(self.method, self.starts),
            self.problem_msg,
            pn.pane.HTML(
                "Tick <b>vary</b> beside a dimension to make it a variable within "
                "its bounds; <b>Optimize</b> runs the certified solve in a separate "
                "process (the page stays live; <b>Cancel</b> stops it)."
            ),
            self.report,
        )
        chart_tab = pn.Column(
            pn.Row(self.chart_x, self.chart_y, self.chart_n, self.chart_button),
            self.chart_measure,
            self.chart_msg,
            pn.pane.Bokeh(self.chart_fig),
        )
        export_tab = pn.Column(
            pn.pane.HTML(
                "The problem file runs with <code>mechsynth optimize FILE</code>."
                + (
                    f" Exports are also written to <code>{_escape(str(self.out))}</code>."
                    if self.out
                    else ""
                )
            ),
            self.dl_toml,
            self.dl_draw,
            self.dl_curves,
            self.dl_chart,
            self.export_msg,
        )
        self.tabs = pn.Tabs(
            ("Design", design_tab),
            ("Problem", problem_tab),
            ("Chart", chart_tab),
            ("Export", export_tab),
            dynamic=False,
        )
        return pn.Row(sidebar, self.tabs)


# ------------------------------------------------------------------------------ helpers
def _widget(cls, label, **kwargs):
    """A widget titled ``label`` (``label`` in recent Panel, ``name`` before)."""
    key = "label" if "label" in cls.param else "name"
    if "button_type" in kwargs and "color" in cls.param:
        kwargs["color"] = kwargs.pop("button_type")
    return cls(**{key: label}, **kwargs)


def _r(x: float) -> float:
    """``x`` to 6 significant digits (what number fields show)."""
    return float(f"{x:.6g}")


def _set_label(widget, label):
    setattr(widget, "label" if "label" in widget.param else "name", label)


def label_of(widget) -> str:
    """The title of a widget (``label`` in recent Panel, ``name`` before)."""
    return widget.label if "label" in widget.param else widget.name


def _frames_phi():
    return np.arange(FRAMES) * (2 * np.pi / FRAMES)


def _nice_step(x):
    if not x > 0 or not np.isfinite(x):
        return 1e-3
    e = 10.0 ** math.floor(math.log10(x))
    return e


def _escape(text):
    import html

    return html.escape(str(text))


def _png(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    return buf.getvalue()


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free on ``host`` now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def serve(
    file=None,
    *,
    host="127.0.0.1",
    port=0,
    browser=True,
    out=None,
    json_out=False,
    units="si",
    kind=None,
    threaded=False,
):
    """Serve the explorer on ``http://host:port/`` (``port`` 0: a free port).

    ``file``: a TOML problem, design or linkage file to start from; ``kind``: a mechanism key
    otherwise (default slider-crank). Prints the address (as JSON with ``json_out``) once
    serving, opens the browser unless ``browser`` is False and serves until interrupted
    (``threaded``: returns the server's thread at once, for tests).
    """
    start = load_file(file, units) if file else State.default(kind or "slider-crank", units)
    port = int(port) or free_port(host)
    out = Path(out) if out else None

    def page():
        state = load_file(file, units) if file else State.default(kind or "slider-crank", units)
        app = Explorer(state, out)
        poll = pn.state.add_periodic_callback(app.poll, period=150)

        def closed(context):
            poll.stop()
            app.close()

        pn.state.on_session_destroyed(closed)
        return app.view()

    del start  # read once above so that a bad file fails before the server starts
    origins = [f"{host}:{port}", f"localhost:{port}", f"127.0.0.1:{port}"]
    if host not in ("127.0.0.1", "localhost", "::1"):
        # served on a network address (--host): pages reach it by names the server cannot list
        origins.append("*")
    server = pn.serve(
        {"/": page},
        port=port,
        address=host,
        websocket_origin=origins,
        show=False,
        start=False,
        title="mechsynth explore",
        verbose=False,
        threaded=threaded,
    )
    url = f"http://{host}:{port}/"
    info = {"url": url, "host": host, "port": port, "out": str(out) if out else None}
    if threaded:
        server.start()
        return server, info
    server.start()
    if json_out:
        print(json.dumps(info), flush=True)
    else:
        print(f"mechsynth explore: serving on {url} (Ctrl+C stops)", flush=True)
    if browser:
        webbrowser.open(url)
    try:
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
        sys.stdout.flush()
    return 0

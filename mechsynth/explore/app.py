"""The explorer page (Panel and Bokeh) and its server.

One :class:`Explorer` per browser session: it turns widgets into a
:class:`~mechsynth.explore.model.State` and the model's answers into Bokeh glyphs. A design's
whole cycle is sent to the browser once (:mod:`.animation`) and played there at the display's
frame rate. The certified solve runs in a worker process (cancellable, reporting its starts),
chart sweeps in a worker thread (reporting their chunks); a periodic callback collects their
results, so no computation blocks the page.
"""

from __future__ import annotations

import io
import json
import math
import socket
import sys
import tempfile
import threading
import time
import webbrowser
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import panel as pn
from bokeh.layouts import column, row
from bokeh.models import (
    Button,
    CheckboxGroup,
    ColorBar,
    ColumnDataSource,
    CustomJS,
    Div,
    HoverTool,
    Label,
    LinearColorMapper,
    PointDrawTool,
    Range1d,
    Slider,
    Span,
    TapTool,
)
from bokeh.plotting import figure

from ..errors import MechanismError
from .animation import A11Y_JS, COLORS, FRAMES, PLAYER_JS, fit_ranges, frame_glyphs, frames
from .editor_page import Editing, url_state
from .model import (
    State,
    candidate_state,
    checks,
    curves,
    kind_names,
    load_file,
    motion_candidates,
    parse_number,
    solve_worker,
    sweep_chart,
)
from .synthesis_tab import SynthesisTab
from .worker import Worker

__all__ = ["Explorer", "serve", "free_port", "label_of"]

_POOL = ThreadPoolExecutor(max_workers=2, thread_name_prefix="mechsynth-explore")
_WARM: dict[str, object] = {}  # kind key -> the future of its warm-up sweep (one per process)
_WARM_LOCK = threading.Lock()
CHART_ANGLES = 180  # crank angles per design in a chart sweep
# dimension rows made with the page beyond its mechanism's (rows are added when a mechanism
# needs more; every row made costs the page's start some 10 models)
MIN_ROWS = 0


def warm(state: State):
    """Start (once per mechanism and process) a tiny sweep in the background so that the
    first chart of the page finds its compiled kernels loaded; returns its future."""
    key = state.kind.key
    with _WARM_LOCK:
        fut = _WARM.get(key)
        if fut is None:
            dims = [d.name for d in state.kind.dims]
            snap = _snapshot(state)
            fut = _POOL.submit(_quiet_sweep, snap, dims[0], dims[1], 3)
            _WARM[key] = fut
    return fut


def _quiet_sweep(state, x, y, n):
    try:
        return sweep_chart(state, x, y, n, angles=CHART_ANGLES)
    except (ValueError, MechanismError):
        return None


def _snapshot(st: State) -> State:
    return State(
        st.kind,
        dict(st.values),
        dict(st.vary),
        st.objective,
        st.sense,
        list(st.constraints),
        st.speed,
        st.units,
        st.method,
        st.starts,
        st.seed,
    )


class Explorer:
    """The page of one browser session.

    Parameters
    ----------
    state : the state to start from (a mechanism with its problem).
    out : folder where exports are also written (None: downloads only).
    source : the name of the file ``state`` was read from (shown in the mechanism menu).
    """

    def __init__(self, state: State, out: Path | None = None, source: str | None = None):
        self.state = state
        self.out = Path(out) if out else None
        self.loaded = {}
        self.last_result = None
        self.design = None
        self.sketch = None
        self.curve_data = None
        self.frame_cols, self.frame_meta = None, None
        self._solve = Worker()  # the Optimize tab's solve
        self._sweep = None
        self._sweep_t0 = 0.0
        self._sweep_progress = [None]
        self._chart = None
        self._chart_state = None
        self._building = False
        self._design_msgs = {}
        self._field_msgs = {}
        self._kind_value = None
        self._fit_next = True
        self._rows, self._row_dims = [], []
        self._busy_note = ("", 0.0)
        self._targets = None  # target poses (SI rows x, y, angle) shown on the drawing
        self._synth = None  # the running motion-generation search (a future)
        self._candidates = []
        self._synthesis = None  # the Synthesis tab's object, made when first needed
        self._tab_pending = {}  # tab index -> (its placeholder, what makes its content)
        self._build_widgets(source)
        self.editing = Editing(self)  # joints dragged, linkages built, undo, the URL
        self._rebuild_dims()
        self._refresh(None)

    @property
    def synthesis(self) -> SynthesisTab:
        """Path and function generation, clicked targets (made when first opened or used:
        its canvas and widgets are not part of the page's start)."""
        if self._synthesis is None:
            self._synthesis = SynthesisTab(self)
        return self._synthesis

    @property
    def chart_fig(self):
        """The chart's figure (made when first needed: the Chart tab opened, or a chart)."""
        if self._chart_fig is None:
            tap = TapTool(mode="replace")
            fig = figure(
                height=500, min_width=300, max_width=760, sizing_mode="stretch_width",
                tools=[tap, "pan", "wheel_zoom", "reset", "save"],
                title="click a cell to load that design",
            )  # fmt: skip
            fig.toolbar.active_scroll = None
            cells = fig.rect(
                "x", "y", width="w", height="h", source=self.chart_src,
                fill_color={"field": "v", "transform": self.mapper}, line_color=None,
                fill_alpha="ok", name="cells", nonselection_fill_alpha="ok",
                selection_line_color="black",
            )  # fmt: skip
            fig.add_layout(self.colour_bar, "right")
            fig.add_tools(
                HoverTool(
                    tooltips=[("x", "@x"), ("y", "@y"), ("value", "@raw")], renderers=[cells]
                )
            )
            fig.scatter(
                "x", "y", source=self.chart_marker, marker="cross", size=18, line_color="red",
                line_width=3,
            )  # fmt: skip
            self._chart_fig = fig
        return self._chart_fig

    # ------------------------------------------------------------------ widgets
    def _build_widgets(self, source):
        options = {v: k for k, v in kind_names().items()}
        value = self.state.kind.key
        if source is not None or self.state.kind.key not in kind_names():
            label = _file_label(self.state, source)
            options = {label: "__file__", **options}
            self.loaded["__file__"] = self.state
            value = "__file__"
        self._kind_value = value
        self.kind_select = _widget(
            pn.widgets.Select, "Mechanism", options=options, value=value, width=330
        )
        self._watch(self.kind_select, self._on_kind)
        self.upload = _widget(
            pn.widgets.FileInput,
            "Open a TOML file (problem, design or linkage file)",
            accept=".toml",
            multiple=False,
            width=330,
            css_classes=["upload"],
        )
        self._watch(self.upload, self._on_upload)
        self.file_input = _widget(
            pn.widgets.TextInput,
            "or a file's path on the server's computer",
            placeholder="path/to/file.toml",
            width=250,
        )
        self.file_button = _widget(pn.widgets.Button, "Load", width=70, align="end")
        self.file_button.on_click(lambda e: self._later(self._on_load, e))
        self.file_msg = pn.pane.Alert(
            "", alert_type="danger", visible=False, width=330, css_classes=["file-message"]
        )
        self.units_select = _widget(
            pn.widgets.Select,
            "Display units",
            options=["si", "mm-deg", "oilfield"],
            value=self.state.units,
            width=130,
        )
        self._watch(self.units_select, self._on_units)
        self.speed_input = _widget(
            pn.widgets.TextInput,
            "Crank speed, rpm",
            value="0",
            width=190,
            css_classes=["speed"],
            description="0: velocities and accelerations as analogs per unit of the input",
        )
        self._watch(self.speed_input, self._on_speed)
        self.speed_msg = pn.pane.Alert(
            "", alert_type="danger", visible=False, width=330, css_classes=["speed-message"]
        )
        self.dims_col = pn.Column(width=340)
        self.design_msg = pn.pane.Alert(
            "", alert_type="danger", visible=False, width=330, css_classes=["design-message"]
        )

        # drawing: all frames of the cycle go to the browser, which plays them
        x0, x1, y0, y1 = fit_ranges((-1, 1, -1, 1), 600, 380)
        self.fig = figure(
            height=440,
            min_width=300,
            sizing_mode="stretch_width",
            tools="pan,wheel_zoom,reset,save",
            x_range=Range1d(x0, x1),
            y_range=Range1d(y0, y1),
            title="",
            x_axis_label="x",
            y_axis_label="y",
            name="drawing",
        )
        self.fig.toolbar.active_scroll = None
        self.src_bars = ColumnDataSource(dict(xs=[], ys=[], color=[]))
        self.src_plates = ColumnDataSource(dict(xs=[], ys=[], color=[]))
        self.src_paths = ColumnDataSource(dict(xs=[], ys=[], color=[]))
        self.src_guides = ColumnDataSource(dict(xs=[], ys=[]))
        self.src_outlines = ColumnDataSource(dict(xs=[], ys=[]))
        self.src_joints = ColumnDataSource(dict(x=[], y=[], name=[]))
        self.src_ground = ColumnDataSource(dict(x=[], y=[], name=[]))
        self.src_blocks = ColumnDataSource(dict(x=[], y=[], angle=[], w=[], h=[]))
        self.src_vel = ColumnDataSource(dict(xs=[], ys=[]))
        self.src_acc = ColumnDataSource(dict(xs=[], ys=[]))
        self.src_frames = ColumnDataSource(dict(input=[]), name="frames")
        self.src_meta = ColumnDataSource(dict(json=[], force=[]), name="meta")
        f = self.fig
        f.multi_line(
            "xs", "ys", source=self.src_paths, line_color="color", line_dash="dashed",
            line_width=1.2, name="paths",
        )  # fmt: skip
        f.multi_line(
            "xs", "ys", source=self.src_guides, line_color="#444444", line_width=2, name="guides"
        )
        f.multi_line(
            "xs", "ys", source=self.src_outlines, line_color="#555555", line_width=2,
            name="outlines",
        )  # fmt: skip
        f.patches(
            "xs", "ys", source=self.src_plates, fill_color="color", fill_alpha=0.35,
            line_color="color", line_width=3, name="plates",
        )  # fmt: skip
        f.multi_line(
            "xs", "ys", source=self.src_bars, line_color="color", line_width=5, name="bars"
        )
        f.rect(
            "x", "y", width="w", height="h", angle="angle", source=self.src_blocks,
            fill_color="#bbbbbb", line_color="#333333", name="blocks",
        )  # fmt: skip
        ground = f.scatter(
            "x", "y", source=self.src_ground, marker="triangle", size=16, fill_color="#888888",
            line_color="black", name="ground",
        )  # fmt: skip
        # a fixed pivot is dragged to move it (the dimensions that place it follow)
        self.drag_tool = PointDrawTool(
            renderers=[ground], add=False, drag=True, description="Drag a fixed pivot"
        )
        f.add_tools(self.drag_tool)
        f.toolbar.active_drag = self.drag_tool  # pan is a click away in the toolbar
        self.src_ground.on_change("data", self._on_ground_moved)
        self._ground_shown = None
        f.multi_line("xs", "ys", source=self.src_vel, line_color="#009E73", line_width=2.5,
                     name="velocity")  # fmt: skip
        f.multi_line("xs", "ys", source=self.src_acc, line_color="#CC79A7", line_width=2.5,
                     name="acceleration")  # fmt: skip
        self.joints_renderer = f.scatter(
            "x", "y", source=self.src_joints, size=9, fill_color="white", line_color="black",
            line_width=2, name="joints",
        )  # fmt: skip
        f.text(
            "x", "y", text="name", source=self.src_joints, x_offset=6, y_offset=-6,
            text_font_size="11px", name="labels",
        )  # fmt: skip

        # the player (in the browser)
        self.frame = Slider(
            start=0, end=FRAMES - 1, value=0, step=1, title="frame of the cycle",
            show_value=False, sizing_mode="stretch_width", min_width=160, name="frame",
        )  # fmt: skip
        self.play = Button(label="Play", width=60, name="play", button_type="primary")
        self.back = Button(label="Step back", width=80, name="back")
        self.fwd = Button(label="Step forward", width=95, name="fwd")
        self.reverse = Button(label="Reverse", width=70, name="reverse")
        self.period = Slider(
            start=0.5, end=20, value=3, step=0.5, title="seconds per cycle", width=150,
            name="period",
        )  # fmt: skip
        self.vectors = CheckboxGroup(
            labels=["velocity vectors", "acceleration vectors"], active=[], inline=True,
            name="vectors",
        )  # fmt: skip
        self.input_label = Div(text="", name="input-label", width=150)
        self.overlay = Label(
            x=8, y=8, x_units="screen", y_units="screen", text="", text_font_size="12px",
            text_color="#333333", name="input-overlay",
        )  # fmt: skip
        self.fig.add_layout(self.overlay)
        # the curves' figures are made after the page's first document (_make_curve_figs);
        # their data, markers and labels are kept here until then
        self.curve_figs = []
        self.curve_srcs = [ColumnDataSource(dict(x=[], y=[], y2=[])) for _ in range(4)]
        self.spans = [
            Span(location=0, dimension="height", line_color="#D55E00", line_width=1.5)
            for _ in range(4)
        ]
        self._curve_labels = [
            dict(title=t, x="crank angle, deg", y="", xr=(0, 360))
            for t in ("position", "velocity", "acceleration", "angles")
        ]
        args = dict(
            sources=dict(
                meta=self.src_meta, frames=self.src_frames, bars=self.src_bars,
                plates=self.src_plates, joints=self.src_joints, blocks=self.src_blocks,
                guides=self.src_guides, outlines=self.src_outlines, vel=self.src_vel,
                acc=self.src_acc,
            ),
            fig=self.fig, frame=self.frame, play=self.play, period_s=self.period,
            vectors=self.vectors, spans=self.spans, label=self.input_label, overlay=self.overlay,
            back=self.back, fwd=self.fwd, reverse=self.reverse,
        )  # fmt: skip
        # one script for every trigger (the page sends its code once), told which called it by
        # the model (an event's origin); the accessible names are given where the page's
        # widgets may have changed
        player = CustomJS(args=args, code=_WHAT_JS + PLAYER_JS + _A11Y_WHEN + A11Y_JS + "}\n")
        self.src_meta.js_on_change("data", player)
        self.frame.js_on_change("value", player)
        for button in (self.play, self.back, self.fwd, self.reverse):
            button.js_on_event("button_click", player)
        self.vectors.js_on_change("active", player)
        self.fig.js_on_change("inner_width", player)
        self.fig.js_on_change("inner_height", player)
        self.frame.on_change("value", lambda attr, old, new: self._on_frame(new))
        self.trace_select = _widget(
            pn.widgets.MultiChoice, "Trace the path of", options=[], value=[], width=300
        )
        self._watch(self.trace_select, lambda e: self._draw_paths())
        self.stats = pn.pane.HTML("", width=330, css_classes=["stats"])
        self.checks_pane = pn.pane.HTML("", width=330, css_classes=["checks"])

        # problem and optimization
        self.objective = _widget(pn.widgets.TextInput, "Objective measure", width=260)
        self.sense = _widget(
            pn.widgets.Select, "Sense", options=["minimize", "maximize"], width=110
        )
        self.constraints = _widget(
            pn.widgets.TextAreaInput,
            "Constraints (one a line: measure <= value unit)",
            height=110,
            min_width=280,
            max_width=600,
            sizing_mode="stretch_width",
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
            "", alert_type="danger", visible=False, min_width=280, max_width=600,
            sizing_mode="stretch_width", css_classes=["problem-message"],
        )
        self.opt_button = _widget(pn.widgets.Button, "Optimize", button_type="primary", width=100)
        self.opt_button.on_click(self._on_optimize)
        self.cancel_button = _widget(
            pn.widgets.Button, "Cancel", button_type="warning", width=80, disabled=True
        )
        self.cancel_button.on_click(self._on_cancel)
        self.progress = pn.indicators.Progress(
            value=0, max=1, width=130, active=False, visible=False, align="center"
        )
        self.opt_status = pn.pane.HTML(
            "", width=330, css_classes=["opt-status"], styles={"overflow-wrap": "anywhere"}
        )
        self.report = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["opt-report"])

        # chart
        self.chart_x = _widget(pn.widgets.Select, "x axis", width=140)
        self.chart_y = _widget(pn.widgets.Select, "y axis", width=140)
        self.chart_measure = _widget(pn.widgets.Select, "colour: measure", width=220)
        self.chart_n = _widget(
            pn.widgets.IntSlider, "points per axis", start=5, end=80, value=30, width=200
        )
        self.chart_button = _widget(pn.widgets.Button, "Sweep", button_type="primary", width=90)
        self.chart_button.on_click(self._on_sweep)
        self._watch(self.chart_measure, lambda e: self._draw_chart())
        self.chart_msg = pn.pane.HTML(
            "", sizing_mode="stretch_width", css_classes=["chart-message"]
        )
        self.chart_progress = pn.indicators.Progress(
            value=0, max=1, width=200, active=False, visible=False
        )
        self.chart_src = ColumnDataSource(
            dict(x=[], y=[], v=[], raw=[], ok=[], i=[], j=[], w=[], h=[])
        )
        self.mapper = LinearColorMapper(palette="Viridis256", nan_color="#eeeeee")
        self.colour_bar = ColorBar(color_mapper=self.mapper, title="", width=12)
        self.chart_marker = ColumnDataSource(dict(x=[], y=[]))
        self.chart_src.selected.on_change("indices", self._on_cell)
        self._chart_fig = None  # made with the Chart tab (see chart_fig)

        # synthesis: motion generation through target poses
        self.src_targets = ColumnDataSource(dict(x=[], y=[], xs=[], ys=[]))
        self.fig.multi_line(
            "xs", "ys", source=self.src_targets, line_color="#E69F00", line_width=3,
            name="target-axes",
        )  # fmt: skip
        self.fig.scatter(
            "x", "y", source=self.src_targets, marker="square", size=10, fill_color="#E69F00",
            line_color="black", name="targets",
        )  # fmt: skip
        self.poses_input = _widget(
            pn.widgets.TextAreaInput,
            "Target poses of the coupler, one a line: x, y (length unit), angle (deg)",
            value=_DEFAULT_POSES,
            height=130,
            min_width=280,
            max_width=600,
            sizing_mode="stretch_width",
            css_classes=["poses"],
        )
        self.synth_button = _widget(
            pn.widgets.Button, "Find linkages", button_type="primary", width=130
        )
        self.synth_button.on_click(lambda e: self._later(self._on_synthesize))
        self.synth_msg = pn.pane.HTML(
            "", sizing_mode="stretch_width", css_classes=["synth-message"]
        )
        self.synth_table = pn.pane.HTML(
            "", sizing_mode="stretch_width", css_classes=["synth-table"]
        )
        self.synth_pick = _widget(pn.widgets.Select, "Solution", options=[], width=120)
        self.synth_load = _widget(
            pn.widgets.Button, "Load into the editor", width=170, disabled=True
        )
        self.synth_load.on_click(lambda e: self._later(self._on_load_candidate))

        # exports
        def download(cb, filename, label, **kw):
            return pn.widgets.FileDownload(
                callback=cb, filename=filename, label=label, width=260, **kw
            )

        self.dl_toml = download(self._export_toml, "problem.toml", "Problem file (TOML)")
        self.dl_design = download(self._export_design, "design.toml", "Design file (TOML)")
        self.dl_draw = download(self._export_drawing, "mechanism.png", "Drawing (PNG)")
        self.dl_curves = download(self._export_curves, "curves.png", "Motion curves (PNG)")
        self.dl_chart = download(
            self._export_chart, "chart.png", "Chart (PNG): sweep a chart first", disabled=True
        )
        self.export_msg = pn.pane.HTML(
            "", sizing_mode="stretch_width", css_classes=["export-message"]
        )

    def _dim_row(self, i):
        """Row ``i`` of the dimension widgets (made once; a mechanism's dimensions are shown
        by updating rows in place, which the browser always follows)."""
        slider = _widget(
            pn.widgets.FloatSlider, "dimension", start=0.0, end=1.0, value=0.5, step=0.01,
            show_value=False, width=320, margin=(0, 10),
        )  # fmt: skip
        field = _widget(pn.widgets.TextInput, "dimension", value="", width=120, margin=(0, 10))
        self._watch(slider, lambda e: self._on_slider(self._row_dims[i], e.new))
        self._watch(field, lambda e: self._on_field(self._row_dims[i], e.new))
        vary = _widget(pn.widgets.Checkbox, "vary", value=False, width=90, align="end")
        lo_in = _widget(pn.widgets.TextInput, "lower bound", value="", width=100)
        hi_in = _widget(pn.widgets.TextInput, "upper bound", value="", width=100)
        for w in (vary, lo_in, hi_in):
            w.param.watch(lambda e: self._on_bounds(self._row_dims[i]), "value")
        msg = pn.pane.Alert(
            "", alert_type="danger", visible=False, width=320, margin=(0, 5),
        )  # fmt: skip
        # rows are reused across mechanisms, and Panel does not pass a change of css classes on
        # to the page: a row's parts are found by their labels (and a message by its markup)
        head = pn.Column(field, slider, margin=0)
        # the widgets are shown and hidden one by one: Panel does not pass a change of a
        # served layout's own visibility on to the page
        layout = pn.Column(
            head, pn.Row(vary, lo_in, hi_in, margin=(-4, 5, 6, 5)), msg, margin=0
        )
        return dict(
            slider=slider, field=field, vary=vary, lo=lo_in, hi=hi_in, msg=msg, head=head,
            layout=layout,
        )  # fmt: skip

    def _rebuild_dims(self):
        """Sliders, number fields, bounds and messages for the kind's dimensions."""
        st = self.state
        self._building = True
        try:
            dims = st.kind.dims
            while len(self._rows) < max(len(dims), MIN_ROWS):
                self._rows.append(self._dim_row(len(self._rows)))
            # the mechanism's rows only, as one change of the column's children (rows hidden
            # widget by widget made the browser lay the page out again for each widget)
            shown = [r["layout"] for r in self._rows[: len(dims)]]
            if list(self.dims_col.objects) != shown:
                self.dims_col.objects = shown
            self.dim_widgets, self.dim_fields = {}, {}
            self._field_msgs = {}
            self._row_dims = [d.name for d in dims] + [None] * (len(self._rows) - len(dims))
            for row_, d in zip(self._rows, dims):
                unit = st.unit_label(d.unit)
                label = f"{d.name}, {unit}" if unit else d.name
                lo, hi = _r(st.shown(d.lo, d.unit)), _r(st.shown(d.hi, d.unit))
                value = st.shown(st.values[d.name], d.unit)
                lo, hi = min(lo, value), max(hi, value)
                slider, field = row_["slider"], row_["field"]
                _set_label(slider, f"{label} ({d.label})" if d.label else label)
                slider.param.update(
                    start=lo, end=hi, value=value, step=_nice_step((hi - lo) / 400)
                )
                _set_label(field, label)
                field.value = _text(value)
                vlo, vhi = st.vary.get(d.name, (d.lo, d.hi))
                vary, lo_in, hi_in, msg = row_["vary"], row_["lo"], row_["hi"], row_["msg"]
                _set_label(vary, f"vary {d.name}")
                vary.param.update(value=d.name in st.vary, disabled=not d.varies)
                _set_label(lo_in, f"{d.name} lower bound")
                lo_in.value = _text(st.shown(vlo, d.unit))
                _set_label(hi_in, f"{d.name} upper bound")
                hi_in.value = _text(st.shown(vhi, d.unit))
                msg.param.update(object="", visible=False)
                self.dim_widgets[d.name] = (slider, vary, lo_in, hi_in, msg)
                self.dim_fields[d.name] = field
            label, speed = st.speed_field()
            _set_label(self.speed_input, label)
            _set_label(
                self.poses_input,
                f"Target poses of the coupler, one a line: x, y ({st.unit_label('m')}), "
                "angle (deg)",
            )
            self.speed_input.value = _text(speed)
            self.speed_msg.visible = False
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
            self.dl_chart.disabled = True
            self.dl_chart.label = "Chart (PNG): sweep a chart first"
            self.chart_src.data = dict(x=[], y=[], v=[], raw=[], ok=[], i=[], j=[], w=[], h=[])
            self.chart_marker.data = dict(x=[], y=[])
            self.chart_msg.object = ""
            self._fit_next = True
        finally:
            self._building = False

    def _sync_values(self):
        """Move the sliders and fields to the state's values (after a solve or a chart
        click)."""
        st = self.state
        self._building = True
        try:
            for d in st.kind.dims:
                slider = self.dim_widgets[d.name][0]
                value = st.shown(st.values[d.name], d.unit)
                slider.param.update(
                    start=min(slider.start, value), end=max(slider.end, value), value=value
                )
                self.dim_fields[d.name].value = _text(value)
                self._field_msgs.pop(d.name, None)
        finally:
            self._building = False

    # ------------------------------------------------------------------ events
    def _later(self, fn, *args):
        """Run ``fn(*args)`` where it may change the Bokeh models of the page: in a served
        page on the document's next tick, with its lock held (a widget's callback may run
        without it, and a Bokeh model changed there raises in the server); at once
        elsewhere (tests drive the page object from Python)."""
        if not _served():
            return fn(*args)
        pn.state.curdoc.add_next_tick_callback(lambda: fn(*args))
        return None

    def _watch(self, widget, fn):
        """Call ``fn(event)`` when ``widget``'s value changes, except while the page itself
        sets the widgets (``_building``, checked when the change happens)."""

        def changed(event):
            if not self._building:
                self._later(fn, event)

        widget.param.watch(changed, "value")

    def _on_kind(self, event):
        if self._building:
            return
        if self._busy("change the mechanism"):
            self._building = True
            try:
                self.kind_select.value = self._kind_value  # the menu keeps what is shown
            finally:
                self._building = False
            return
        self._kind_value = event.new
        self._targets = None
        if event.new == "__file__":
            self.state = self.loaded["__file__"]
            self.state.units = self.units_select.value
        else:
            self.state = State.default(event.new, self.units_select.value)
        self.opt_status.object = ""
        self.report.object = ""
        self.last_result = None
        self._rebuild_dims()
        self._refresh(None)

    def _load_state(self, st: State, source: str):
        """Show a state read from a file (the menu names it by the file)."""
        self.file_msg.visible = False
        self.loaded["__file__"] = st
        options = {k: v for k, v in self.kind_select.options.items() if v != "__file__"}
        label = _file_label(st, source)
        self._building = True
        try:
            self.kind_select.options = {label: "__file__", **options}
            self.kind_select.value = "__file__"
        finally:
            self._building = False
        self._on_kind(_Event("__file__"))

    def _file_error(self, exc):
        self.file_msg.object = str(exc)
        self.file_msg.visible = True

    def _on_load(self, event=None):
        if self._busy("load a file"):
            return
        path = (self.file_input.value or "").strip()
        if not path:
            self._file_error("type a file's path first (or open one with the button above)")
            return
        try:
            st = load_file(path, self.units_select.value)
        except (OSError, ValueError) as exc:
            self._file_error(exc)
            return
        self._load_state(st, Path(path).name)

    def _on_upload(self, event):
        if event.new is None:
            return
        if self._busy("load a file"):
            return
        name = Path(self.upload.filename or "uploaded.toml").name
        with tempfile.TemporaryDirectory(prefix="mechsynth-explore-") as tmp:
            path = Path(tmp) / name
            path.write_bytes(event.new)
            try:
                st = load_file(path, self.units_select.value)
            except (OSError, ValueError) as exc:
                self._file_error(f"{name}: {exc}".replace(f"{path}", name))
                return
        self._load_state(st, name)

    def _on_units(self, event):
        self.state.units = event.new
        self._rebuild_dims()
        self._refresh(None)
        if self._synthesis is not None:
            self._synthesis.units_changed()

    def _on_speed(self, event):
        if self._building:
            return
        try:
            self.state.set_speed(event.new)
        except MechanismError as exc:
            self.speed_msg.object = str(exc)
            self.speed_msg.visible = True
            return
        self.speed_msg.visible = False
        self._refresh(None)

    def _on_slider(self, name, value):
        if self._building:
            return
        self._field_msgs.pop(name, None)
        self._set_dim(name, value)  # the drawing first (see _refresh), then the field's text
        self._building = True
        try:
            self.dim_fields[name].value = _text(value)
        finally:
            self._building = False

    def _on_field(self, name, text):
        if self._building:
            return
        d = self.state.kind.dim(name)
        unit = self.state.unit_label(d.unit)
        try:
            value = parse_number(text, f"{name}{', ' + unit if unit else ''}")
        except MechanismError as exc:
            self._field_msgs[name] = str(exc)
            self._show_bound_messages()
            return
        self._field_msgs.pop(name, None)
        slider = self.dim_widgets[name][0]
        self._building = True
        try:
            slider.param.update(
                start=min(slider.start, value), end=max(slider.end, value), value=value
            )
        finally:
            self._building = False
        self._set_dim(name, value)

    def _set_dim(self, name, value):
        d = self.state.kind.dim(name)
        self.state.values[name] = self.state.si(value, d.unit)
        self._refresh(name, first=True)

    # kept for callers of the previous page (tests drive sliders by value)
    _on_dim = _set_dim

    def _on_bounds(self, name):
        if self._building:
            return
        st = self.state
        d = st.kind.dim(name)
        _, vary, lo_in, hi_in, msg = self.dim_widgets[name]
        if vary.value:
            unit = st.unit_label(d.unit)
            try:
                lo = st.si(parse_number(lo_in.value, f"{name}: lower bound, {unit}"), d.unit)
                hi = st.si(parse_number(hi_in.value, f"{name}: upper bound, {unit}"), d.unit)
            except MechanismError as exc:
                st.vary[name] = (np.nan, np.nan)
                self._field_msgs[f"bound:{name}"] = str(exc)
                self._show_bound_messages()
                return
            self._field_msgs.pop(f"bound:{name}", None)
            st.vary[name] = (lo, hi)
        else:
            self._field_msgs.pop(f"bound:{name}", None)
            st.vary.pop(name, None)
        self._show_bound_messages()
        self.editing.show_url()

    def _show_bound_messages(self) -> bool:
        bad = self.state.bound_messages()
        for n, (_, _, _, _, msg) in self.dim_widgets.items():
            text = (
                self._field_msgs.get(n)
                or self._field_msgs.get(f"bound:{n}")
                or bad.get(n)
                or self._design_msgs.get(n, "")
            )
            # the dimension's name in the message's markup (rows are reused across mechanisms)
            msg.object = f"<div class='msg-{n}'>{_escape(text, quote=False)}</div>" if text else ""
            msg.visible = bool(text)
        return not bad and not any(k.startswith("bound:") for k in self._field_msgs)

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
        self.editing.show_url()

    def _on_frame(self, k):
        self._draw_frame(int(k))

    # ------------------------------------------------------------------ refresh
    def _refresh(self, changed, first=False):
        """Rebuild the design from the state; on failure show the message next to the field
        that was changed (the drawing keeps the last valid design). ``first``: draw the
        mechanism on a tick of its own before the rest (a dimension's slider or field)."""
        design, message = self.state.check_design()
        self._design_msgs = {}
        if message is not None:
            where = changed if changed in self.dim_widgets else None
            if where is None:
                self.design_msg.object = f"The design cannot be built: {message}"
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
        try:
            cols, meta = frames(self.state, design, trace=self.state.kind.trace)
            self.curve_data = curves(self.state, design)
        except (MechanismError, ValueError) as exc:
            self.design_msg.object = f"The design cannot be drawn: {exc}"
            self.design_msg.visible = True
            return
        self.design_msg.visible = False
        self._show_bound_messages()
        self.design = design
        self.sketch = None
        self.frame_cols, self.frame_meta = cols, meta
        if self._fit_next or not first:
            self._refresh_rest(changed)
            return
        # the mechanism first, on a tick of its own: every Bokeh property set is sent at once,
        # so the browser redraws the joints before the cycle, the curves and the checks
        # (setting those takes the server 20-40 ms; the model's work is 1-2 ms)
        self._draw_frame(int(self.frame.value))
        self._later(self._refresh_rest, changed, False)

    def _refresh_rest(self, changed, draw=True):
        """The rest of a new design's page: the cycle, the curves, the stats and checks."""
        if self.frame_cols is None:
            return
        self._send_frames(draw)
        self._draw_curves()
        self._show_stats()
        self._show_checks()
        self.editing.after_refresh(changed)

    def _send_frames(self, draw=True):
        """The cycle to the browser (which plays it), the current frame drawn here too (unless
        ``draw`` is False: it was just drawn)."""
        st, meta = self.state, self.frame_meta
        unit = st.unit_label("m")
        self.fig.xaxis.axis_label = f"x, {unit}"
        self.fig.yaxis.axis_label = f"y, {unit}"
        self.fig.title.text = getattr(self.design, "name", "") or st.kind.title
        if self._fit_next:  # a new mechanism or new units: the view fits it (here and there)
            x0, x1, y0, y1 = fit_ranges(meta["extent"], 600, 380)
            self.fig.x_range.update(start=x0, end=x1, reset_start=x0, reset_end=x1)
            self.fig.y_range.update(start=y0, end=y1, reset_start=y0, reset_end=y1)
        cols = self.frame_cols
        self._show_ground()
        points = list(meta["points"])
        self._building = True
        try:
            if list(self.trace_select.options) != points:
                self.trace_select.options = points
                self.trace_select.value = [p for p in meta["trace"] if p in points]
        finally:
            self._building = False
        self._draw_paths()
        self._draw_targets()
        if draw:
            self._draw_frame(int(self.frame.value))
        self.src_frames.data = cols
        self.src_meta.data = dict(json=[json.dumps(meta)], force=[bool(self._fit_next)])
        self._fit_next = False

    def _show_ground(self):
        cols, meta = self.frame_cols, self.frame_meta
        data = dict(
            x=[cols[f"x:{g}"][0] for g in meta["ground"]],
            y=[cols[f"y:{g}"][0] for g in meta["ground"]],
            name=list(meta["ground"]),
        )
        self._ground_shown = data
        self.src_ground.data = dict(data)

    def _on_ground_moved(self, attr, old, new):
        """A fixed pivot dragged on the drawing: the dimensions that place it follow when the
        linkage still assembles over its cycle; otherwise it snaps back, saying why."""
        shown = self._ground_shown
        if shown is None or new is shown or self.frame_meta is None:
            return
        moved = [
            i
            for i, (x, y) in enumerate(zip(new.get("x", []), new.get("y", [])))
            if i < len(shown["x"]) and (x, y) != (shown["x"][i], shown["y"][i])
        ]
        if not moved or len(new.get("x", [])) != len(shown["x"]):
            return
        if self.editing.draft_drawn():
            # the draft's points are drawn over this mechanism: a drag moves them, not the
            # pivot under them (the drawing's tool takes every point under the pointer)
            self._later(self._show_ground)
            return
        i = moved[0]
        name = shown["name"][i]
        st = self.state
        f = st.display.factor("m")
        x, y = float(new["x"][i]) * f, float(new["y"][i]) * f
        dims = {d.name for d in st.kind.dims}
        before = dict(st.values)
        if {f"{name}_x", f"{name}_y"} <= dims:
            st.values[f"{name}_x"], st.values[f"{name}_y"] = x, y
        elif st.kind.key == "four-bar" and name == "O2":
            x1, y1 = shown["x"][0] * f, shown["y"][0] * f
            st.values["ground"] = math.hypot(x - x1, y - y1)
        elif st.kind.key == "beam-pump" and name == "O2":
            # the centre bearing: I its horizontal distance from the crankshaft O1, H its
            # height above the base (the crankshaft G above it)
            x1, y1 = shown["x"][0] * f, shown["y"][0] * f
            st.values["I"] = x - x1
            st.values["H"] = y - y1 + st.values["G"]
        else:
            self._snap_back(f"{name} is the frame's origin of the {st.kind.title}: it stays")
            return
        design, message = st.check_design()
        if message is None and st.kind.key == "beam-pump":
            # a unit whose geometry I and H do not give so (a file's Mark II): not moved
            px, py = design.sketch(np.array([0.0])).points[name]
            miss = math.hypot(float(np.ravel(px)[0]) - x, float(np.ravel(py)[0]) - y)
            if miss > 1e-9 * max(abs(x), abs(y), 1.0):
                message = f"I and H do not place {name} of this unit there: edit their fields"
        if message is not None:
            st.values = before
            self._snap_back(f"cannot move {name} there: {message}")
            return
        self._sync_values()
        self._refresh(None)

    def _snap_back(self, why):
        self.design_msg.object = why
        self.design_msg.visible = True
        self._show_ground()

    def _draw_paths(self):
        cols = self.frame_cols
        if cols is None:
            return
        trace = [p for p in self.trace_select.value if f"x:{p}" in cols]
        self.src_paths.data = dict(
            xs=[cols[f"x:{p}"] + cols[f"x:{p}"][:1] for p in trace],
            ys=[cols[f"y:{p}"] + cols[f"y:{p}"][:1] for p in trace],
            color=[COLORS[(i + 2) % len(COLORS)] for i in range(len(trace))],
        )

    def _draw_frame(self, k):
        if self.frame_cols is None:
            return
        g = frame_glyphs(self.frame_cols, self.frame_meta, k)
        self.src_bars.data = g["bars"]
        self.src_plates.data = g["plates"]
        self.src_joints.data = g["joints"]
        self.src_blocks.data = g["blocks"]
        self.src_guides.data = g["guides"]
        self.src_outlines.data = g["outlines"]
        meta = self.frame_meta
        inp = self.frame_cols["input"][int(k) % meta["n"]]
        for span in self.spans:
            span.location = 360.0 * (int(k) % meta["n"]) / meta["n"] if meta["periodic"] else inp
        digits = 0 if meta["periodic"] else 1
        text = f"{meta['input_label']} {inp:.{digits}f} {meta['input_unit']}"
        self.input_label.text = f"<span id='input-shown'>{text}</span>"
        self.overlay.text = text

    def _input_phi(self, k: int) -> float:
        """The design's input at frame ``k`` (rad or m)."""
        n = self.frame_meta["n"]
        return float(np.asarray(self.design.turn(n))[int(k) % n])

    def _draw_curves(self):
        c, st = self.curve_data, self.state
        lin = c["unit"] == "m"
        analog = c["speed"] is None
        slider_in = c.get("input_unit") == "m"
        per = "m" if slider_in else "rad"
        pos_u = "m" if lin else "rad"
        if lin:
            vel_u = f"m/{per}" if analog else "m/s"
            acc_u = f"m/{per}^2" if analog else "m/s^2"
        else:
            vel_u = (f"rad/{per}" if slider_in else "1") if analog else "rad/s"
            acc_u = (f"rad/{per}^2" if slider_in else "1") if analog else "rad/s^2"
        if slider_in:
            x = (np.asarray(c["angle"], float) / st.display.factor("m")).tolist()
            xlabel = f"input displacement, {st.unit_label('m')}"
        else:
            x = np.asarray(c["angle"], float).tolist()
            xlabel = "crank angle, deg"
        xr = (x[0], x[-1]) if slider_in else (0, 360)
        for key, unit, lab, src in zip(
            ("position", "velocity", "acceleration"),
            (pos_u, vel_u, acc_u),
            self._curve_labels,
            self.curve_srcs,
        ):
            y = np.asarray(c[key], dtype=float)
            if unit == "rad":
                y, shown = np.degrees(y), "deg"
            elif unit in ("1",):
                shown = "rad/rad"
            else:
                try:
                    y = y / st.display.factor(unit)
                    shown = st.display.unit(unit)
                except (KeyError, ValueError, MechanismError):
                    shown = unit
            src.data = dict(x=x, y=y.tolist(), y2=[0.0] * y.size)
            lab.update(title=f"{c['output']} {key}", y=f"{key}, {shown}", x=xlabel, xr=xr)
        p, t = c["pressure"], c["transmission"]
        n = len(x)
        self.curve_srcs[3].data = dict(
            x=x,
            y=(np.degrees(p).tolist() if p is not None else [np.nan] * n),
            y2=(np.degrees(t).tolist() if t is not None else [np.nan] * n),
        )
        self._curve_labels[3].update(y="pressure, transmission angle, deg", x=xlabel, xr=xr)
        self._label_curves()

    def _make_curve_figs(self) -> list:
        """The four curves' figures (made once)."""
        if not self.curve_figs:
            for i, (src, span) in enumerate(zip(self.curve_srcs, self.spans)):
                cf = figure(
                    width=300, height=220, tools="pan,wheel_zoom,reset,save",
                    x_range=Range1d(0, 360),
                )  # fmt: skip
                cf.toolbar.active_scroll = None
                angles = i == 3
                cf.line(
                    "x", "y", source=src, line_width=2, color=COLORS[0],
                    legend_label="pressure" if angles else "curve",
                )  # fmt: skip
                if angles:
                    cf.line("x", "y2", source=src, line_width=2, color=COLORS[1],
                            legend_label="transmission")  # fmt: skip
                    cf.legend.location = "top_left"
                    cf.legend.label_text_font_size = "9px"
                else:
                    cf.legend.visible = False
                cf.add_layout(span)
                self.curve_figs.append(cf)
            self._label_curves()
        return self.curve_figs

    def _label_curves(self):
        for cf, lab in zip(self.curve_figs, self._curve_labels):
            cf.title.text = lab["title"]
            cf.xaxis.axis_label = lab["x"]
            cf.yaxis.axis_label = lab["y"]
            cf.x_range.update(start=lab["xr"][0], end=lab["xr"][1])

    def _fmt(self, value, unit):
        if unit == "rad":
            return f"{math.degrees(value):.6g} deg"
        try:
            v, shown = self.state.display.convert(float(value), unit)
        except (KeyError, ValueError, MechanismError):
            v, shown = float(value), unit
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
        if self._solve.running:
            self._busy_note = (f"cancel the solve to {what}", time.perf_counter())
            self.opt_status.object = (
                f"<span id='opt-state' style='color:#b00'>solving: cancel the solve to "
                f"{what}</span>"
            )
            return True
        return False

    def _on_optimize(self, event=None):
        if self._solve.running:
            return
        self._on_problem(None)
        if self._field_msgs or not self._show_bound_messages():
            self.opt_status.object = (
                "<span id='opt-state' style='color:#b00'>fix the fields "
                "shown with a message first</span>"
            )
            return
        try:
            data = self.state.problem_data()
            self.state.problem()  # its errors name the measure or the bound
        except (ValueError, TypeError, MechanismError) as exc:
            self.opt_status.object = f"<span id='opt-state' style='color:#b00'>{exc}</span>"
            return
        self._solve.start(solve_worker, data, "starting the solver")
        self.opt_button.disabled = True
        self.cancel_button.disabled = False
        self.progress.visible = True
        self.progress.active = True
        self.progress.value = -1
        self.opt_status.object = "<span id='opt-state'>solving: starting the solver...</span>"

    def _on_cancel(self, event=None):
        if not self._solve.running:
            return
        self._end_solve(kill=True)
        self.opt_status.object = "<span id='opt-state'>cancelled</span>"

    def close(self):
        """Stop a running solve (the session ended)."""
        if self._solve.running:
            self._end_solve(kill=True)
        if self._synthesis is not None:
            self._synthesis.close()

    def _end_solve(self, kill: bool = False):
        self._solve.end(kill)  # reaped: no zombie process stays behind
        self.opt_button.disabled = False
        self.cancel_button.disabled = True
        self.progress.active = False
        self.progress.visible = False

    def poll(self):
        """Collect the worker's messages and the chart sweep (periodic callback)."""
        run = self._solve
        if run.running:
            for msg in run.messages():
                if msg[0] == "progress":
                    _, desc, k, total = msg
                    if total:
                        self.progress.max = total
                        self.progress.value = min(k, total)
                    run.stage = f"{desc} {k}/{total or '?'}"
                    if total and k >= total:
                        run.stage += ", certifying the peaks"
                elif msg[0] == "done":
                    self._end_solve()
                    self._apply_result(msg[1])
                    break
                elif msg[0] == "error":
                    self._end_solve()
                    text = msg[1]
                    if text == "the process ended without a result":
                        text = "the solver process ended without a result"
                    else:
                        text = f"solve failed: {_escape(text)}"
                    self.opt_status.object = (
                        f"<span id='opt-state' style='color:#b00'>{text}</span>"
                    )
                    break
            if run.running:  # the elapsed time moves even between messages
                note, since = self._busy_note
                note = note if time.perf_counter() - since < 10 else ""
                self.opt_status.object = (
                    f"<span id='opt-state'>solving: {run.stage} ({run.elapsed:.0f} s)"
                    + (f"<br><span style='color:#b00'>{note}</span>" if note else "")
                    + "</span>"
                )
        self._poll_sweep()
        self._poll_synthesis()
        if self._synthesis is not None:
            self._synthesis.poll()

    def _objective_unit(self) -> str:
        from ..synthesis.problem_file import parse_measure

        try:
            return parse_measure(self.state.objective).bind(type(self.design)).unit
        except (ValueError, TypeError, MechanismError, AttributeError):
            return ""

    def _apply_result(self, res):
        st = self.state
        ok = res.get("success")
        status = res.get("status")
        colour = "#1a7f37" if ok else "#cf222e"
        value = res.get("value")
        if res.get("variables"):
            st.values = st.values_of(res["variables"])
            self._sync_values()
            self._refresh(None)
        if value is not None:
            shown = self._fmt(value, self._objective_unit())
            text = f"{status}: {res.get('objective')} = {shown}"
        else:
            text = str(status)
        self.opt_status.object = (
            f"<span id='opt-state' style='color:{colour}'>{_escape(text)} "
            f"({res.get('solve_time', 0):.1f} s)</span>"
        )
        self.report.object = "<pre id='opt-report'>" + _escape(res.get("report", "")) + "</pre>"
        self.last_result = res

    # ------------------------------------------------------------------ synthesis
    def _on_synthesize(self, event=None):
        if self._synth is not None:
            return
        snapshot = _snapshot(self.state)
        text = self.poses_input.value or ""
        self.synth_button.disabled = True
        self.synth_msg.object = "<span id='synth-state'>searching...</span>"
        self._synth = _POOL.submit(motion_candidates, text, snapshot)

    def _poll_synthesis(self):
        if self._synth is None or not self._synth.done():
            return
        fut, self._synth = self._synth, None
        self.synth_button.disabled = False
        try:
            poses, cands = fut.result()
        except (ValueError, MechanismError) as exc:
            self.synth_msg.object = (
                f"<span id='synth-state' style='color:#b00'>{_escape(exc)}</span>"
            )
            return
        self._candidates, self._candidate_poses = cands, poses
        st = self.state
        rows = []
        for i, c in enumerate(cands, start=1):
            p = c.linkage.parameters
            rows.append(
                f"<tr><td>{i}</td><td>{c.kind}</td><td>{' '.join(c.defects) or 'none'}</td>"
                f"<td>{c.grashof}</td><td>{math.degrees(c.min_transmission):.1f}</td>"
                f"<td>{self._fmt(float(p['OA']), 'm')}</td>"
                f"<td>{self._fmt(float(p['AB']), 'm')}</td></tr>"
            )
        # the message first: when the table shows, the message says what it holds
        self.synth_msg.object = (
            f"<span id='synth-state'>{len(cands)} linkages through the {len(poses)} poses, "
            "best first (defect-free first, then by their transmission angle): pick one and "
            "load it to see it move over the targets</span>"
        )
        self.synth_table.object = (
            "<table id='synth-table' style='font-size:13px'><tr><th>rank</th><th>kind</th>"
            "<th>defects</th><th>Grashof</th><th>min transmission angle, deg</th><th>crank</th>"
            "<th>coupler</th></tr>" + "".join(rows) + "</table>"
        )
        self.synth_pick.options = [str(i) for i in range(1, len(cands) + 1)]
        self.synth_pick.value = "1"
        self.synth_load.disabled = False
        del st

    def _on_load_candidate(self, event=None):
        if not self._candidates or self._busy("load a solution"):
            return
        rank = int(self.synth_pick.value or 1)
        st = candidate_state(self._candidates[rank - 1], rank, self.units_select.value)
        targets = self._candidate_poses
        self._load_state(st, None)
        self._targets = targets
        self._draw_targets()
        if hasattr(self, "tabs"):
            self.tabs.active = 0  # the drawing, where the solution moves over its targets

    def _draw_targets(self):
        t = self._targets
        if t is None or self.frame_meta is None:
            self.src_targets.data = dict(x=[], y=[], xs=[], ys=[])
            return
        f = self.state.display.factor("m")
        x0, x1, y0, y1 = self.frame_meta["extent"]
        r = 0.08 * max(x1 - x0, y1 - y0)
        x, y = t[:, 0] / f, t[:, 1] / f
        self.src_targets.data = dict(
            x=x.tolist(),
            y=y.tolist(),
            # a target point (path generation) has no angle: no line
            xs=[[a, a + r * math.cos(g)] if g == g else [a, a] for a, g in zip(x, t[:, 2])],
            ys=[[b, b + r * math.sin(g)] if g == g else [b, b] for b, g in zip(y, t[:, 2])],
        )

    # ------------------------------------------------------------------ chart
    def _on_sweep(self, event=None):
        if self._sweep is not None:
            return
        x, y = self.chart_x.value, self.chart_y.value
        st = self.state
        try:
            if x == y:
                raise MechanismError("choose two different dimensions for the chart")
            _ = [st.kind.dim(x), st.kind.dim(y)]
        except ValueError as exc:
            self.chart_msg.object = f"<span style='color:#b00'>{_escape(exc)}</span>"
            return
        snapshot = _snapshot(st)
        self.chart_button.disabled = True
        n = int(self.chart_n.value)
        self._chart_state = snapshot
        progress = self._sweep_progress = [None]
        warm_up = warm(snapshot)

        def run():
            from .. import progress as prog

            me = threading.get_ident()
            if not warm_up.done():
                progress[0] = ("warming", 0, 0)
                warm_up.result()

            def seen(desc, k, total):
                if threading.get_ident() == me:
                    progress[0] = ("sweeping", k, total)

            with prog.observe(seen):
                return sweep_chart(snapshot, x, y, n, angles=CHART_ANGLES)

        self._sweep_t0 = time.perf_counter()
        self._sweep = _POOL.submit(run)
        self.chart_progress.visible = True
        self.chart_progress.active = True
        self.chart_progress.value = -1
        self._show_sweep_progress()

    def _show_sweep_progress(self):
        p = self._sweep_progress[0]
        t = time.perf_counter() - self._sweep_t0
        if p is not None and p[0] == "warming":
            text = (
                f"preparing the compiled kernels of this mechanism (the first chart only; "
                f"later sweeps take well under a second) ... {t:.0f} s"
            )
        elif p is not None and p[2]:
            self.chart_progress.max = int(p[2])
            self.chart_progress.value = min(int(p[1]), int(p[2]))
            text = f"sweeping: {p[1]}/{p[2]} parts of the grid ({t:.1f} s)"
        else:
            text = f"sweeping {self.chart_n.value} x {self.chart_n.value} designs ({t:.1f} s)"
        self.chart_msg.object = f"<span id='chart-progress'>{text}</span>"

    def _poll_sweep(self):
        if self._sweep is None:
            return
        if not self._sweep.done():
            self._show_sweep_progress()
            return
        fut, self._sweep = self._sweep, None
        self.chart_button.disabled = False
        self.chart_progress.active = False
        self.chart_progress.visible = False
        try:
            self._chart = fut.result()
        except (ValueError, MechanismError) as exc:
            self.chart_msg.object = f"<span style='color:#b00'>{_escape(exc)}</span>"
            return
        self._draw_chart()

    def _draw_chart(self):
        ch = self._chart
        if ch is None:
            return
        from ..synthesis.problem_file import parse_constraint

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
            c = parse_constraint(text)
            if c.measure.name in ch.values and c.op in ("<=", ">="):
                good &= ch.satisfied({c.measure.name: (c.op, c.bound)})
        alpha = np.where(ok, np.where(good, 1.0, 0.45), 0.0)
        fx, fy = st.display.factor(dx.unit or "1"), st.display.factor(dy.unit or "1")
        wx = (xv[1] - xv[0]) / fx if xv.size > 1 else 1
        wy = (yv[1] - yv[0]) / fy if yv.size > 1 else 1
        raw = data.copy()
        scale_note = ""
        finite = data[np.isfinite(data) & ok]
        if finite.size:
            lo, hi = float(finite.min()), float(finite.max())
            # a measure over decades (peaks over a wide box): colour its logarithm
            if lo > 0 and hi / lo > 30:
                data = np.log10(np.where(data > 0, data, np.nan))
                lo, hi = math.log10(lo), math.log10(hi)
                scale_note = " (colour on a log scale)"
            self.mapper.low, self.mapper.high = lo, hi
        self.colour_bar.title = (
            (f"log10 of {label}" if scale_note else label) + (f", {shown}" if shown else "")
        )
        self.chart_src.selected.indices = []
        self.chart_src.data = dict(
            raw=np.where(np.isfinite(raw), raw, np.nan).ravel().tolist(),
            x=(X / fx).ravel().tolist(),
            y=(Y / fy).ravel().tolist(),
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
            f"{label}" + (f", {shown}" if shown else "") + scale_note + ": click a cell to load it"
        )
        self.chart_msg.object = (
            f"<span id='chart-done'>{ch.size} designs in {ch.elapsed:.2f} s; "
            f"{int(ch.feasible.sum())} can be built; faded cells break a constraint, blank "
            "cells cannot be built"
            + (f" ({_escape(ch.reason)})" if ch.reason else "")
            + "</span>"
        )
        self.dl_chart.disabled = False
        self.dl_chart.label = "Chart (PNG)"
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
            from ..fileio import write_bytes

            self.out.mkdir(parents=True, exist_ok=True)
            path = self.out / name
            write_bytes(path, data)
            self.export_msg.object = f"written: <span class='written'>{_escape(str(path))}</span>"
        return io.BytesIO(data)

    def _export_text(self, make, name, what):
        try:
            text = make()
        except (ValueError, MechanismError) as exc:
            self.export_msg.object = (
                f"<span style='color:#b00'>cannot write the {what}: {_escape(exc)}</span>"
            )
            return io.BytesIO(f"# cannot write the {what}: {exc}\n".encode())
        return self._save(name, text.encode())

    def _export_toml(self):
        return self._export_text(self.state.problem_toml, "problem.toml", "problem file")

    def _export_design(self):
        return self._export_text(self.state.design_toml, "design.toml", "design file")

    def _message_png(self, text) -> io.BytesIO:
        """A PNG that says why there is nothing to draw (never an empty download)."""
        from matplotlib.figure import Figure

        fig = Figure(figsize=(6, 2))
        fig.text(0.5, 0.5, text, ha="center", va="center", wrap=True, fontsize=11)
        self.export_msg.object = f"<span style='color:#b00'>{_escape(text)}</span>"
        return io.BytesIO(_png(fig))

    def _export_drawing(self):
        from matplotlib.figure import Figure

        from ..display import display_units

        if self.design is None:
            return self._message_png(
                "No valid design to draw: " + (self.design_msg.object or "fix the dimensions")
            )
        fig = Figure(figsize=(6, 5))
        ax = fig.subplots()
        meta = self.frame_meta
        phi = self._input_phi(int(self.frame.value))
        with display_units(self.state.units):
            self.design.draw(phi, ax=ax, trace=tuple(self.trace_select.value))
        del meta
        fig.tight_layout()
        return self._save("mechanism.png", _png(fig))

    def _export_curves(self):
        from matplotlib.figure import Figure

        if self.design is None:
            return self._message_png("No valid design: no motion curves to draw")
        fig = Figure(figsize=(9, 6))
        axes = fig.subplots(2, 2).ravel()
        meta = self.frame_meta
        k = int(self.frame.value) % meta["n"]
        at = 360.0 * k / meta["n"] if meta["periodic"] else self.frame_cols["input"][k]
        for i, (lab, src, ax) in enumerate(zip(self._curve_labels, self.curve_srcs, axes)):
            d = src.data
            ax.plot(d["x"], d["y"], label="pressure" if i == 3 else None)
            if i == 3:
                ax.plot(d["x"], d["y2"], label="transmission")
                ax.legend(fontsize=8)
            ax.axvline(at, color="#D55E00", lw=1)
            ax.set_title(lab["title"], fontsize=10)
            ax.set_xlabel(lab["x"])
            ax.set_ylabel(lab["y"], fontsize=9)
            ax.set_xlim(d["x"][0], d["x"][-1])
        fig.tight_layout()
        return self._save("curves.png", _png(fig))

    def _export_chart(self):
        if self._chart is None:
            return self._message_png("No chart yet: press Sweep on the Chart tab first")
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
            pn.pane.HTML("<h1 style='margin:4px 0;font-size:1.4em'>mechsynth explore</h1>"),
            self.kind_select,
            self.upload,
            pn.Row(self.file_input, self.file_button),
            self.file_msg,
            pn.Row(self.units_select, self.speed_input),
            self.speed_msg,
            pn.Row(self.opt_button, self.cancel_button, self.progress),
            self.opt_status,
            self.design_msg,
            self.dims_col,
            width=350,
            css_classes=["sidebar"],
            styles={"max-height": "calc(100vh - 16px)", "overflow-y": "auto"},
        )
        # the drawing and its player in one pane: Panel walks each pane's models (their
        # scripts reference each other, so two panes walked the drawing twice)
        drawing = pn.pane.Bokeh(
            column(
                self.fig,
                row(self.play, self.back, self.fwd, self.reverse, sizing_mode="stretch_width"),
                row(self.frame, sizing_mode="stretch_width"),
                row(self.input_label, self.period, sizing_mode="stretch_width"),
                row(self.vectors, sizing_mode="stretch_width"),
                sizing_mode="stretch_width",
            ),
            sizing_mode="stretch_width",
        )
        # the editing controls and the curves follow the page's first document (sent once the
        # browser has drawn the mechanism): the page is ready sooner
        editing = pn.Column(sizing_mode="stretch_width")
        curves = pn.Column(sizing_mode="stretch_width")
        design_tab = pn.Column(
            drawing,
            editing,
            pn.FlexBox(
                self.trace_select,
                pn.Column(
                    self.stats,
                    pn.pane.HTML("<b>Problem measures</b> (green: holds, red: violated)"),
                    self.checks_pane,
                ),
            ),
            curves,
            sizing_mode="stretch_width",
        )

        def fill():
            editing.objects = [self.editing.panel()]
            # one under the other: a row of them would widen the page past a phone's screen,
            # and a wrapping box draws them with no room inside their frames
            curves.objects = [
                pn.Column(
                    *[pn.pane.Bokeh(cf) for cf in self._make_curve_figs()],
                    css_classes=["curves"],
                )
            ]

        if _served():
            pn.state.onload(lambda: self._later(fill))
        else:
            fill()
        # the other tabs are made and sent to the browser when first opened: the page's
        # start sends the Design tab only (its models are most of the first document)
        makers = [self._problem_tab, self._chart_tab, self._synthesis_tab, self._export_tab]
        names = ["Problem", "Chart", "Synthesis", "Export"]
        tabs = [("Design", design_tab)]
        self._tab_pending = {}
        for k, (name, make) in enumerate(zip(names, makers), start=1):
            holder = pn.Column(sizing_mode="stretch_width")
            self._tab_pending[k] = (holder, make)
            tabs.append((name, holder))
        self.tabs = pn.Tabs(*tabs, dynamic=False, sizing_mode="stretch_width")
        self.tabs.param.watch(lambda e: self._later(self._open_tab, e.new), "active")
        if self._synthesis is not None:  # already in use (from Python): its panel now
            self._open_tab(names.index("Synthesis") + 1)
        main = pn.Column(
            self.tabs, sizing_mode="stretch_width", min_width=300, css_classes=["main"]
        )
        return pn.FlexBox(
            sidebar, main, flex_wrap="wrap", sizing_mode="stretch_width",
            stylesheets=[_LAYOUT_CSS], css_classes=["explorer"],
        )  # fmt: skip

    def _open_tab(self, k):
        """Tab ``k`` shown: its content made and sent to the browser the first time."""
        pending = self._tab_pending.pop(int(k), None)
        if pending is not None:
            holder, make = pending
            holder.objects = [make()]

    def _problem_tab(self):
        return pn.Column(
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
            sizing_mode="stretch_width",
        )

    def _chart_tab(self):
        return pn.Column(
            pn.FlexBox(self.chart_x, self.chart_y, self.chart_n, self.chart_button),
            self.chart_measure,
            pn.Row(self.chart_progress),
            self.chart_msg,
            pn.pane.Bokeh(self.chart_fig, sizing_mode="stretch_width"),
            sizing_mode="stretch_width",
        )

    def _synthesis_tab(self):
        motion = pn.Column(
            pn.pane.HTML(
                "<b>Motion generation</b>: four-bars and slider-cranks whose coupler passes "
                "through 2 to 5 poses (<code>ms.motion_generation</code>; 3 poses leave the "
                "fixed pivots free, so give 4 or 5 here)."
            ),
            self.poses_input,
            self.synth_button,
            self.synth_msg,
            self.synth_table,
            pn.Row(self.synth_pick, self.synth_load),
            sizing_mode="stretch_width",
        )
        return self.synthesis.panel(motion)

    def _export_tab(self):
        return pn.Column(
            pn.pane.HTML(
                "The problem file runs with <code>mechsynth optimize FILE</code>; the design "
                "file with <code>mechsynth animate FILE</code> (and opens here again)."
                + (
                    f" Exports are also written to <code>{_escape(str(self.out))}</code>."
                    if self.out
                    else ""
                )
            ),
            self.dl_toml,
            self.dl_design,
            self.dl_draw,
            self.dl_curves,
            self.dl_chart,
            self.export_msg,
            sizing_mode="stretch_width",
        )


# which of the player's triggers called it (see PLAYER_JS)
_WHAT_JS = """const origin = cb_obj && cb_obj.origin ? cb_obj.origin : cb_obj;
const what = origin === sources.meta ? 'meta' : origin === frame ? 'frame'
  : origin === play ? 'play' : origin === back ? 'back' : origin === fwd ? 'fwd'
  : origin === reverse ? 'reverse' : origin === vectors ? 'vectors'
  : origin === fig ? 'resize' : '';
"""
_A11Y_WHEN = "if (what === 'meta' || what === 'resize') {\n"


# five poses of a crank-rocker's coupler (examples/motion_poses.csv), in mm and deg
_DEFAULT_POSES = """117.06, 162.96, 74.08
108.33, 234.82, 57.49
16.41, 242.76, 49.78
-71.55, 155.10, 54.48
-72.26, 50.12, 71.67"""


# the controls beside the drawing on a wide screen; on a narrow one the drawing first
_LAYOUT_CSS = """
.sidebar { flex: 0 0 350px; }
.main { flex: 1 1 320px; width: auto !important; min-width: 0 !important; }
@media (max-width: 720px) {
  .main { order: 1; flex-basis: 100%; }
  .sidebar { order: 2; flex: 1 1 100%; max-height: none !important; }
}
"""


# ------------------------------------------------------------------------------ helpers
class _Event:
    def __init__(self, new):
        self.new = new


def _file_label(state: State, source: str | None) -> str:
    """The menu's entry for a state read from a file: never the title of a built-in (whose
    entry would be chosen instead, showing the built-in's values)."""
    title = state.kind.title
    if source and source not in title:
        return f"{title} from {source}"
    return title if title not in kind_names().values() else f"{title} (from a file)"


def _served() -> bool:
    """Whether the page is being served (else driven from Python, as tests do)."""
    doc = pn.state.curdoc
    return doc is not None and getattr(doc, "session_context", None) is not None


def _widget(cls, label, **kwargs):
    """A widget titled ``label`` (``label`` in recent Panel, ``name`` before)."""
    key = "label" if "label" in cls.param else "name"
    if "button_type" in kwargs and "color" in cls.param:
        kwargs["color"] = kwargs.pop("button_type")
    return cls(**{key: label}, **kwargs)


def _r(x: float) -> float:
    """``x`` to 6 significant digits (what number fields show)."""
    return float(f"{x:.6g}")


def _text(x: float) -> str:
    """A number as a field shows it (6 significant digits)."""
    return f"{float(x):.6g}"


def _set_label(widget, label):
    setattr(widget, "label" if "label" in widget.param else "name", label)


def label_of(widget) -> str:
    """The title of a widget (``label`` in recent Panel, ``name`` before)."""
    return widget.label if "label" in widget.param else widget.name


def _nice_step(x):
    if not x > 0 or not np.isfinite(x):
        return 1e-3
    return 10.0 ** math.floor(math.log10(x))


def _escape(text, quote=True):
    import html

    return html.escape(str(text), quote=quote)


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
    from bokeh.settings import settings

    start = load_file(file, units) if file else State.default(kind or "slider-crank", units)
    port = int(port) or free_port(host)
    # Bokeh checks every new page's models for a developer's mistakes (some 0.1 s a page);
    # the page's models are fixed and tested
    settings.perform_document_validation.set_value(False)
    out = Path(out) if out else None
    source = Path(file).name if file else None
    warm(start)  # the first chart's kernels load while the page is being opened

    def page():
        state = load_file(file, units) if file else State.default(kind or "slider-crank", units)
        state, from_url, url_msg = url_state(state, units)  # a shared link's design
        app = Explorer(state, out, source=None if from_url else source)
        if url_msg:
            app.design_msg.param.update(object=url_msg, visible=True)
        poll = pn.state.add_periodic_callback(app.poll, period=150)

        def closed(context):
            poll.stop()
            app.close()

        pn.state.on_session_destroyed(closed)
        return app.view()

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
        start=bool(threaded),  # a thread of its own runs its loop; else the loop below
        title="mechsynth explore",
        verbose=False,
        threaded=threaded,
    )
    url = f"http://{host}:{port}/"
    info = {"url": url, "host": host, "port": port, "out": str(out) if out else None}
    if threaded:  # serving in Panel's thread already
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

"""The explorer page's editing (Panel and Bokeh): moving joints dragged on the drawing, a
linkage built by clicks ("New linkage"), undo and redo (buttons, Ctrl+Z and Ctrl+Y) and the
design's state in the page's URL.

One :class:`Editing` per :class:`~mechsynth.explore.app.Explorer`; the logic is in
:mod:`.editor` and :mod:`.history` (tested without a browser). Panel and Bokeh are imported
inside the functions (``import mechsynth.explore`` stays light).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import MechanismError
from .editor import STEP_TYPES, Draft, drag_joint, state_from_query, to_query
from .history import History
from .model import State, parse_number

__all__ = ["Editing", "url_state"]

# Ctrl+Z / Ctrl+Y (Cmd on a Mac; Ctrl+Shift+Z redoes) outside text fields, whose own undo
# stays theirs; the key goes to the server through the ``keys`` source. The page's address
# follows the design (``history.replaceState``: no reload, no new history entry).
KEYS_JS = r"""
if (!window.mx_keys) {
  window.mx_keys = true;
  document.addEventListener('keydown', (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.altKey) return;
    const k = (e.key || '').toLowerCase();
    let what = null;
    if (k === 'z' && !e.shiftKey) what = 'undo';
    else if (k === 'y' || (k === 'z' && e.shiftKey)) what = 'redo';
    if (!what) return;
    const t = e.composedPath ? e.composedPath()[0] : e.target;
    const tag = t && t.tagName ? t.tagName.toUpperCase() : '';
    const typing = tag === 'TEXTAREA' || (tag === 'INPUT' &&
      !['range', 'checkbox', 'radio', 'button'].includes((t.type || '').toLowerCase()));
    if (typing) return;
    e.preventDefault();
    keys.data = {n: [(keys.data.n[0] || 0) + 1], what: [what]};
  });
}
const q = url.data.q && url.data.q[0];
if (q && location.search !== '?' + q) history.replaceState(null, '', location.pathname + '?' + q);
"""


@dataclass(frozen=True)
class _Snap:
    """One step of the history: the page's state (its values copied) and the draft."""

    state: State
    draft: Draft | None

    def same(self, state: State, draft) -> bool:
        return (
            self.state.kind is state.kind
            and self.state.values == state.values
            and self.state.speed == state.speed
            and self.draft is draft
        )


def _copy(st: State) -> State:
    from .app import _snapshot

    return _snapshot(st)


def url_state(fallback: State, units: str):
    """The page's start: ``(state, from_url, message)``: the state the page's URL query
    carries (``from_url`` True), else ``fallback``; ``message`` says why a URL's state was not
    valid (None when it was, or there was none)."""
    import panel as pn

    args = dict(pn.state.session_args or {})
    try:
        st = state_from_query(args, units)
    except (MechanismError, ValueError) as exc:
        return fallback, False, f"The address's design was not loaded: {exc}"
    if st is None:
        return fallback, False, None
    design, message = st.check_design()
    if message is not None:
        return fallback, False, f"The address's design cannot be built: {message}"
    return st, True, None


class Editing:
    """The editing parts of one page (``app``: its :class:`Explorer`)."""

    def __init__(self, app):
        import panel as pn
        from bokeh.events import Tap
        from bokeh.models import ColumnDataSource, CustomJS

        from .app import _widget

        self.app = app
        self.history = History()
        self.draft: Draft | None = None
        self.building = False
        self._draft_kind = None
        self._restoring = False

        # moving joints drag with the fixed pivots' tool
        joints = app.joints_renderer
        app.drag_tool.renderers = [*app.drag_tool.renderers, joints]
        app.drag_tool.description = "Drag a pivot or a joint"
        app.src_joints.on_change("data", self._on_joint_moved)
        # the tool sends every source it edits (the joints' too when a pivot is dragged): a
        # joint was dragged when the tool grabbed it (its selection reaches the server first)
        self._grabbed = None
        app.src_joints.selected.on_change("indices", self._on_grab)
        app.fig.on_event(Tap, self._on_tap)

        # the draft's points and links while it does not assemble
        self.src_draft = ColumnDataSource(dict(x=[], y=[], name=[]), name="draft-points")
        self.src_draft_links = ColumnDataSource(dict(xs=[], ys=[]), name="draft-links")
        app.fig.multi_line(
            "xs", "ys", source=self.src_draft_links, line_color="#999999", line_width=3,
            line_dash="dotted", name="draft-link-lines",
        )  # fmt: skip
        draft = app.fig.scatter(
            "x", "y", source=self.src_draft, marker="circle", size=10, fill_color="#F0E442",
            line_color="black", name="draft",
        )  # fmt: skip
        # a draft's point dragged moves that element (Draft.move)
        app.drag_tool.renderers = [*app.drag_tool.renderers, draft]
        self._draft_shown = None
        self.src_draft.on_change("data", self._on_draft_dragged)
        app.fig.text(
            "x", "y", text="name", source=self.src_draft, x_offset=7, y_offset=-7,
            text_font_size="11px", name="draft-labels",
        )  # fmt: skip

        # keys and the address
        self.keys = ColumnDataSource(dict(n=[0], what=[""]), name="keys")
        self.keys.on_change("data", self._on_key)
        self.url = ColumnDataSource(dict(q=[""]), name="url-state")
        code = CustomJS(args=dict(keys=self.keys, url=self.url), code=KEYS_JS)
        app.src_meta.js_on_change("data", code)
        app.fig.js_on_change("inner_width", code)  # the page's first layout: keys and address
        self.url.js_on_change("data", code)

        # widgets
        self.undo_button = _widget(pn.widgets.Button, "Undo", width=70, disabled=True)
        self.redo_button = _widget(pn.widgets.Button, "Redo", width=70, disabled=True)
        self.undo_button.on_click(lambda e: app._later(self.undo))
        self.redo_button.on_click(lambda e: app._later(self.redo))
        self.new_button = _widget(pn.widgets.Button, "New linkage", width=110)
        self.new_button.on_click(lambda e: app._later(self.new_linkage))
        self.edit_button = _widget(pn.widgets.Button, "Edit this linkage", width=140)
        self.edit_button.on_click(lambda e: app._later(self.edit_linkage))
        self.stop_button = _widget(pn.widgets.Button, "Stop building", width=120, visible=False)
        self.stop_button.on_click(lambda e: app._later(self.stop))
        self.step = _widget(
            pn.widgets.Select, "A click on the drawing adds",
            options={**{v: k for k, v in STEP_TYPES.items()}, **_CLICK_EDITS}, value="ground",
            width=250, visible=False,
        )  # fmt: skip
        self.p1 = _widget(pn.widgets.Select, "about / first point", options=[], width=150)
        self.p2 = _widget(pn.widgets.Select, "second point", options=[], width=150)
        self.angle = _widget(pn.widgets.TextInput, "guide angle, deg", value="0", width=120)
        self.travel = _widget(pn.widgets.TextInput, "travel", value="", width=120)
        self.delete_button = _widget(pn.widgets.Button, "Delete the last element", width=190)
        self.delete_button.on_click(lambda e: app._later(self.delete_last))
        self.download = pn.widgets.FileDownload(
            callback=self._export, filename="linkage.toml", label="Linkage file (TOML)",
            width=190,
        )  # fmt: skip
        # any element of the draft: chosen here (or by a click, "select"), moved by the next
        # click ("move"), its dimensions typed, deleted with what depends on it
        self.element = _widget(pn.widgets.Select, "Element", options=[], width=110)
        self.element_dims = _widget(
            pn.widgets.TextInput, "its dimensions", value="", width=330,
            css_classes=["element-dims"],
        )  # fmt: skip
        self.delete_element_button = _widget(
            pn.widgets.Button, "Delete it (and what depends on it)", width=250
        )
        self.delete_element_button.on_click(lambda e: app._later(self.delete_element))
        app._watch(self.element, lambda e: self._show_element())
        app._watch(self.element_dims, lambda e: self.set_element_dims(e.new))
        self.message = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["editor-message"])
        self.toml = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["editor-toml"])
        for w in (
            self.p1, self.p2, self.angle, self.travel, self.delete_button, self.download,
            self.element, self.element_dims, self.delete_element_button,
        ):  # fmt: skip
            w.visible = False
        app._watch(self.step, lambda e: self._show_draft())

    # ------------------------------------------------------------------ layout
    def panel(self):
        """The editing controls (under the player)."""
        import panel as pn

        return pn.Column(
            pn.FlexBox(
                self.undo_button,
                self.redo_button,
                self.new_button,
                self.edit_button,
                self.stop_button,
            ),
            pn.FlexBox(self.step, self.p1, self.p2, self.angle, self.travel),
            pn.FlexBox(self.delete_button, self.download),
            pn.FlexBox(self.element, self.element_dims, self.delete_element_button),
            self.message,
            self.toml,
            sizing_mode="stretch_width",
        )

    # ------------------------------------------------------------------ history
    def after_refresh(self, changed=None):
        """A design was drawn: record it (a run of one dimension's changes is one step),
        keep the draft's file in step with the fields, and put the design in the URL."""
        app = self.app
        st = app.state
        if self.draft is not None and st.kind is self._draft_kind:
            self.draft = self.draft.with_values(st.values)
            self._show_draft()
        cur = self.history.current
        if not self._restoring and (cur is None or not cur.same(st, self.draft)):
            self.history.record(_Snap(_copy(st), self.draft), key=changed)
        self._buttons()
        self._show_edit()
        self.show_url()

    def show_url(self):
        """The page's state (the design and the problem) in its address."""
        try:
            q = to_query(self.app.state)
        except MechanismError:
            return
        if self.url.data.get("q") != [q]:
            self.url.data = dict(q=[q])

    def _show_edit(self):
        st = self.app.state
        editing = self.building and self.draft is not None and st.kind is self._draft_kind
        _set(self.edit_button, visible=st.kind.file_data is not None and not editing)

    def _record_draft(self):
        self.history.record(_Snap(_copy(self.app.state), self.draft))
        self._buttons()

    def _buttons(self):
        _set(self.undo_button, disabled=not self.history.can_undo)
        _set(self.redo_button, disabled=not self.history.can_redo)

    def undo(self):
        self._go(self.history.undo)

    def redo(self):
        self._go(self.history.redo)

    def _go(self, step):
        app = self.app
        if app._busy("undo or redo"):
            return
        snap = step()
        if snap is None:
            return
        self._restoring = True
        try:
            self._apply(snap)
        finally:
            self._restoring = False
        self._buttons()

    def _apply(self, snap: _Snap):
        from .app import _text
        from .model import kind_names

        app = self.app
        st = _copy(snap.state)
        st.units = app.units_select.value
        self.draft = snap.draft
        self._show_draft()
        if st.kind is app.state.kind:
            app.state.values = dict(st.values)
            app.state.speed = st.speed
            app._sync_values()
            app._building = True
            try:
                app.speed_input.value = _text(app.state.speed_field()[1])
            finally:
                app._building = False
            app._refresh(None)
        elif st.kind.key in kind_names() and (st.kind.file_data is None or _builtin_title(st.kind)):
            app._building = True
            try:
                app.kind_select.value = st.kind.key
            finally:
                app._building = False
            app._kind_value = st.kind.key
            app.state = st
            app._targets = None
            app._rebuild_dims()
            app._refresh(None)
        else:
            app._load_state(st, "")
        self._show_draft()

    # ------------------------------------------------------------------ keys
    def _on_key(self, attr, old, new):
        what = (new.get("what") or [""])[0]
        if what == "undo":
            self.app._later(self.undo)
        elif what == "redo":
            self.app._later(self.redo)

    # ------------------------------------------------------------------ dragging
    def _on_grab(self, attr, old, new):
        if new:
            self._grabbed = int(new[0])

    def _on_joint_moved(self, attr, old, new):
        """A moving joint dragged on the drawing: the dimensions it defines follow when the
        linkage still assembles over its cycle; otherwise it snaps back, saying why."""
        from .animation import frame_glyphs

        app = self.app
        if app.frame_cols is None or app.design is None or self.building:
            return
        meta = app.frame_meta
        k = int(app.frame.value) % meta["n"]
        shown = frame_glyphs(app.frame_cols, meta, k)["joints"]
        names = list(new.get("name", []))
        xs, ys = list(new.get("x", [])), list(new.get("y", []))
        if names != list(shown["name"]) or len(xs) != len(names) or len(ys) != len(names):
            if len(xs) != len(shown["name"]):
                app._later(app._draw_frame, k)  # a point deleted on the drawing comes back
            return
        i, self._grabbed = self._grabbed, None
        if i is None or i >= len(names):
            return
        x0, x1, y0, y1 = meta["extent"]
        size = max(x1 - x0, y1 - y0, 1e-12)
        if not math.hypot(xs[i] - shown["x"][i], ys[i] - shown["y"][i]) > 1e-9 * size:
            return
        name = names[i]
        st = app.state
        f = st.display.factor("m")
        phi = app._input_phi(k)
        try:
            values = drag_joint(st, name, (float(xs[i]) * f, float(ys[i]) * f), phi)
        except (MechanismError, ValueError) as exc:
            self._snap_back(k, str(exc))
            return
        before = st.values
        st.values = values
        design, message = st.check_design()
        if message is not None:
            st.values = before
            self._snap_back(k, f"cannot move {name} there: {message}")
            return
        app._sync_values()
        app._refresh(None)

    def _snap_back(self, k, why):
        app = self.app
        app.design_msg.object = why
        app.design_msg.visible = True
        app._draw_frame(k)

    # ------------------------------------------------------------------ building
    def new_linkage(self):
        """Start a new linkage: clicks on the drawing add its elements."""
        self.draft = Draft()
        self._draft_kind = None
        self.building = True
        self.step.value = "ground"
        self._show_draft()
        self._record_draft()

    def edit_linkage(self):
        """Go on building the page's linkage (a file's, the six-link, one found by synthesis):
        clicks add to its groups."""
        st = self.app.state
        if st.kind.file_data is None:
            self._say(f"{st.kind.title} is not a linkage: start a new one", bad=True)
            return
        self.draft = Draft.from_tables(st.kind.file_data).with_values(st.values)
        self._draft_kind = st.kind
        self.building = True
        self._show_draft("clicks add to this linkage")
        self._record_draft()

    def stop(self):
        """Clicks on the drawing no longer add elements (the draft stays)."""
        self.building = False
        self._show_draft()

    def delete_last(self):
        if self.draft is None or not self.draft.steps:
            self._say("nothing to delete")
            return
        self._set_draft(self.draft.delete_last())

    def _on_tap(self, event):
        if not self.building or self.draft is None:
            return
        self.app._later(self.click, float(event.x), float(event.y))

    def click(self, x: float, y: float):
        """A click on the drawing at (x, y) in the display's length unit: adds the chosen
        element there."""
        app = self.app
        st = app.state
        # snapped to a grid of about a thousandth of the view (0 is 0, not 1e-8)
        grid = _grid(app.fig.x_range.end - app.fig.x_range.start)
        f = st.display.factor("m")
        x, y = round(x / grid) * grid * f, round(y / grid) * grid * f
        d, step = self.draft, self.step.value
        if step in ("select", "move"):
            self._click_edit(step, x, y)
            return
        try:
            if step == "ground":
                d = d.ground(x, y)
            elif step == "crank":
                d = d.crank(self.p1.value, x, y)
            elif step == "slider":
                unit = st.unit_label("m")
                travel = st.si(parse_number(self.travel.value, f"travel, {unit}"), "m")
                d = d.slider(x, y, self._angle(), travel)
            elif step == "rrr":
                d = d.rrr(self.p1.value, self.p2.value, x, y)
            elif step == "rrp":
                d = d.rrp(self.p1.value, x, y, self._angle())
            elif step == "rpr":
                d = d.rpr(self.p1.value, self.p2.value)
            elif step == "attach":
                d = d.attach(self.p1.value, self.p2.value, x, y)
        except MechanismError as exc:
            self._say(str(exc), bad=True)
            return
        self._set_draft(d)

    # ------------------------------------------------------------------ any element
    def _click_edit(self, step, x, y):
        """A click in "select" (the nearest point becomes the element edited) or "move" (the
        element edited goes there) mode; (x, y) in m."""
        d = self.draft
        if step == "select":
            places = d.places()
            if not places:
                self._say("no element to select yet", bad=True)
                return
            name = min(places, key=lambda p: math.hypot(*(places[p] - (x, y))))
            self.element.value = name
            self._show_element()
            self._say(f"{name} selected: the next click moves it (\"move the selected\")")
            self.step.value = "move"
            return
        name = self.element.value
        if not name:
            self._say("select an element first (in the list, or a click in select mode)", bad=True)
            return
        try:
            new = d.move(name, x, y)
        except MechanismError as exc:
            self._say(str(exc), bad=True)
            return
        self._set_draft(new, f"{name} moved")

    def draft_drawn(self) -> bool:
        """Whether a draft's points are drawn over the page's mechanism (being built)."""
        shown = self._draft_shown
        return self.building and self.draft is not None and bool(shown and shown["name"])

    def _on_draft_dragged(self, attr, old, new):
        """A point of the draft (drawn while it does not assemble) dragged: that element moves
        there (its dimensions from the drop), or the point goes back, saying why."""
        shown, app = self._draft_shown, self.app
        if shown is None or self.draft is None or new is shown:
            return
        names = list(new.get("name", []))
        xs, ys = list(new.get("x", [])), list(new.get("y", []))
        if names != shown["name"] or len(xs) != len(names) or len(ys) != len(names):
            if len(xs) != len(shown["name"]):
                app._later(self._show_draft)  # a point deleted on the drawing comes back
            return
        moved = [i for i in range(len(names)) if (xs[i], ys[i]) != (shown["x"][i], shown["y"][i])]
        if len(moved) != 1:
            return
        i = moved[0]
        f = app.state.display.factor("m")
        app._later(self._drop_draft_point, names[i], float(xs[i]) * f, float(ys[i]) * f)

    def _drop_draft_point(self, name, x, y):
        try:
            new = self.draft.move(name, x, y)
        except MechanismError as exc:
            self._show_draft()
            self._say(f"cannot move {name}: {exc}", bad=True)
            return
        self.element.value = name
        self._set_draft(new, f"{name} moved")

    def delete_element(self, name: str | None = None):
        """Delete the element chosen (and the elements placed from it), saying which."""
        name = name or self.element.value
        if self.draft is None or not name:
            self._say("nothing to delete")
            return
        try:
            new, deps = self.draft.delete(name)
        except MechanismError as exc:
            self._say(str(exc), bad=True)
            return
        said = f"deleted {name}" + (
            f" and what depends on it: {', '.join(deps)}" if deps else " (nothing depends on it)"
        )
        self._set_draft(new, said)

    def _element_text(self, name) -> str:
        st = self.app.state
        parts = []
        for key, (v, unit) in self.draft.dims_of(name).items():
            parts.append(f"{key} = {st.shown(v, unit):.6g}")
        return ", ".join(parts)

    def _show_element(self):
        """The chosen element's dimensions in its field (display units: lengths, deg)."""
        d, name = self.draft, self.element.value
        text = self._element_text(name) if d is not None and name in d.elements else ""
        app = self.app
        app._building = True
        try:
            self.element_dims.value = text
        finally:
            app._building = False
        from .app import _set_label

        unit = app.state.unit_label("m")
        _set_label(self.element_dims, f"its dimensions ({unit}, angles in deg)")

    def set_element_dims(self, text: str):
        """The chosen element's dimensions typed as ``name = value, ...`` (display units)."""
        d, name = self.draft, self.element.value
        if d is None or name not in d.elements:
            return
        st = self.app.state
        known = d.dims_of(name)
        values = {}
        for part in [t for t in (text or "").replace(";", ",").split(",") if t.strip()]:
            key, eq, number = part.partition("=")
            key = key.strip()
            if not eq or key not in known:
                self._say(
                    f"{name}'s dimensions are {', '.join(known) or 'none'} (name = value, ...), "
                    f"got {part.strip()!r}",
                    bad=True,
                )
                return
            unit = known[key][1]
            try:
                shown = parse_number(number, f"{key}, {st.unit_label(unit) or 'deg'}")
            except MechanismError as exc:
                self._say(str(exc), bad=True)
                return
            values[key] = st.si(shown, unit)
        if all(known[k][0] == v for k, v in values.items()):
            return
        self._set_draft(d.with_values(values), f"{name}'s dimensions changed")

    def _angle(self) -> float:
        return math.radians(parse_number(self.angle.value, "guide angle, deg"))

    def _set_draft(self, d: Draft, did: str | None = None):
        app = self.app
        if d == self.draft:  # e.g. a drag's first report, within the file's 6 digits: no step
            self._show_draft()
            return
        self.draft = d
        lk, message = d.check()
        if lk is None:
            # the page keeps the last mechanism; the draft's points are drawn over it, and
            # the fields no longer write into the draft
            self._draft_kind = None
            self._show_draft(f"{did}; {message}" if did else message)
            self._record_draft()
            return
        st = State.of(d.kind(), app.units_select.value)
        if not st.slider_driven and not app.state.slider_driven:
            st.speed = app.state.speed
        self._draft_kind = st.kind
        done = "the linkage assembles: drawn and animated, its dimensions in the fields"
        self._show_draft(f"{did}; {done}" if did else done)
        app._load_state(st, "")

    def _say(self, text, bad=False):
        from .app import _escape

        colour = "#b00" if bad else "#333"
        self.message.object = (
            f"<div id='editor-message' style='color:{colour}'>{_escape(text, quote=False)}</div>"
        )

    def _show_controls(self):
        step = self.step.value
        on = self.building
        two = step in ("rrr", "rpr", "attach")
        one = two or step in ("crank", "rrp")
        self.p1.visible = on and one
        self.p2.visible = on and two
        self.angle.visible = on and step in ("slider", "rrp")
        self.travel.visible = on and step == "slider"
        labels = {
            "crank": ("about (a ground point)", ""),
            "rrr": ("first point", "second point"),
            "rrp": ("rod from", ""),
            "rpr": ("link about", "through (the block's pin)"),
            "attach": ("on the link from", "towards"),
        }
        from .app import _set_label

        a, b = labels.get(step, ("about / first point", "second point"))
        _set_label(self.p1, a)
        if b:
            _set_label(self.p2, b)
        if not self.travel.value:
            st = self.app.state
            self.travel.value = f"{st.shown(0.1, 'm'):.6g}"
        _set_label(self.travel, f"travel, {self.app.state.unit_label('m')}")

    def _show_draft(self, message=None):
        """The draft's file, its points (while it does not assemble) and the controls."""
        from .app import _escape

        app = self.app
        d = self.draft
        on = self.building and d is not None
        self.step.visible = on
        self._show_edit()
        self.stop_button.visible = on
        self.delete_button.visible = d is not None
        self.download.visible = d is not None
        for w in (self.element, self.element_dims, self.delete_element_button):
            w.visible = d is not None and bool(d.steps)
        self._show_controls()
        if d is None:
            self.toml.object = ""
            self._draft_shown = dict(x=[], y=[], name=[])
            self.src_draft.data = dict(self._draft_shown)
            self.src_draft_links.data = dict(xs=[], ys=[])
            return
        points = list(d.points)
        ground = list(d.ground_points)
        p1_opts = ground if self.step.value == "crank" else points
        self.p1.options = p1_opts
        if self.p1.value not in p1_opts and p1_opts:
            self.p1.value = p1_opts[-1] if self.step.value != "crank" else p1_opts[0]
        self.p2.options = points
        if self.p2.value not in points and points:
            self.p2.value = ground[-1] if ground else points[-1]
        elements = list(d.elements)
        if list(self.element.options) != elements:
            self.element.options = elements
        if self.element.value not in elements and elements:
            self.element.value = elements[-1]
        self._show_element()
        self.toml.object = (
            "<b>The linkage file</b> (<code>mechsynth optimize</code>, "
            "<code>mechsynth animate</code> and this page read it):"
            f"<pre id='editor-toml' style='font-size:12px'>{_escape(d.toml(), quote=False)}</pre>"
        )
        if message is not None:
            good = message.startswith("the linkage assembles")
            self._say(message, bad=not good)
        assembled = self._draft_kind is not None and app.state.kind is self._draft_kind
        f = app.state.display.factor("m")
        places = {} if assembled else d.places()
        self._draft_shown = dict(
            x=[float(v[0]) / f for v in places.values()],
            y=[float(v[1]) / f for v in places.values()],
            name=list(places),
        )
        self.src_draft.data = dict(self._draft_shown)
        xs, ys = [], []
        for s in d.steps:
            ends = _links(s)
            for a, b in ends:
                if a in places and b in places:
                    xs.append([places[a][0] / f, places[b][0] / f])
                    ys.append([places[a][1] / f, places[b][1] / f])
        self.src_draft_links.data = dict(xs=xs, ys=ys)

    def _export(self):
        import io

        if self.draft is None:
            return io.BytesIO(b"")
        return self.app._save("linkage.toml", self.draft.toml().encode())


# what a click on the drawing does besides adding an element
_CLICK_EDITS = {
    "select an element (the nearest point)": "select",
    "move the selected element here": "move",
}


def _set(widget, **values):
    """Set a widget's parameters that change (a set, even to the same value, costs a message)."""
    changed = {k: v for k, v in values.items() if getattr(widget, k) != v}
    if changed:
        widget.param.update(**changed)


def _grid(span: float) -> float:
    """A round step of about a thousandth of ``span`` (1, 2 or 5 times a power of ten)."""
    if not span > 0 or not math.isfinite(span):
        return 1e-6
    step = span / 1000
    p = 10.0 ** math.floor(math.log10(step))
    return next(m * p for m in (1, 2, 5, 10) if m * p >= step)


def _links(step) -> list[tuple[str, str]]:
    t, p = step["type"], step.get("point")
    if t == "crank":
        return [(step["about"], p)]
    if t == "rrr":
        return [(step["first"][0], p), (step["second"][0], p)]
    if t == "rrp":
        return [(step["rod"][0], p)]
    if t == "attach":
        return [(step["on"][0], p), (step["on"][1], p)]
    if t == "rpr":
        return [(step["about"], step["through"])]
    return []


def _builtin_title(kind) -> bool:
    from .model import KINDS

    return kind.title == KINDS[kind.key].title

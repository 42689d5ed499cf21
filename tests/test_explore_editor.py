"""The explorer's editing: moving joints dragged to new places, a linkage built by clicks, undo
and redo, the design's state in the URL; the logic without a browser, the page object driven
from Python, and (marked ``browser`` and ``slow``) what a user sees in headless Chromium."""

import math
import tomllib

import numpy as np
import pytest

from mechsynth.errors import MechanismError
from mechsynth.explore.editor import (
    Draft,
    drag_joint,
    joint_dims,
    state_from_query,
    to_query,
)
from mechsynth.explore.history import History
from mechsynth.explore.model import State


def _at(state, values, point, phi):
    """``point``'s place (m) at the input ``phi`` of the design of ``values``."""
    st = State.of(state.kind)
    st.values = dict(values)
    x, y = st.design().sketch(np.array([phi])).points[point]
    return np.array([float(np.ravel(x)[0]), float(np.ravel(y)[0])])


# ------------------------------------------------------------------------------ dragging
@pytest.mark.parametrize(
    "key, point, dims",
    [
        ("impact", "A", ("OA", "phase")),
        ("impact", "B", ("AB", "DB")),
        ("impact", "K", ("K_along", "K_left")),
        ("linkage", "B", ("AB", "DB")),
        ("four-bar", "B", ("coupler", "rocker")),
        ("slider-crank", "B", ("rod", "offset")),
        ("beam-pump", "B", ("P", "C")),
        ("dwell", "C", ("k", "gamma")),
    ],
)
def test_a_dragged_joint_lands_where_it_is_dropped_changing_only_its_dimensions(key, point, dims):
    st = State.default(key)
    phi = float(st.design().turn(180)[25])
    here = _at(st, st.values, point, phi)
    size = max(abs(v) for d, v in st.values.items() if st.kind.dim(d).unit == "m")
    target = here + 0.01 * size * np.array([1.0, 0.6])
    assert joint_dims(st, point) == dims
    new = drag_joint(st, point, target, phi)
    assert {k for k in new if new[k] != st.values[k]} <= set(dims)
    # the design of the new values puts the joint there (the whole design solved again)
    assert np.hypot(*(_at(st, new, point, phi) - target)) < 1e-9 * size


def test_drag_values_are_the_closed_forms():
    """A crank pin's place gives the crank's length (the distance to its pivot) and its phase
    (the pin's angle minus the crank angle); an RRR joint's its two links' lengths; an
    attached point's its offsets along and to the left of its link's axis."""
    st = State.default("linkage")  # the six-link of paper 001
    phi = 0.7
    target = np.array([0.01, 0.035])  # m
    new = drag_joint(st, "A", target, phi)
    assert new["OA"] == pytest.approx(math.hypot(*target), rel=1e-9)
    assert new["phase"] == pytest.approx(math.atan2(target[1], target[0]) - phi, abs=1e-9)
    a, d = _at(st, new, "A", phi), np.array([0.12, 0.05])
    b = _at(st, new, "B", phi) + np.array([0.004, -0.002])
    new2 = drag_joint(State.of(st.kind) if False else _with(st, new), "B", b, phi)
    assert new2["AB"] == pytest.approx(np.hypot(*(b - a)), rel=1e-9)
    assert new2["DB"] == pytest.approx(np.hypot(*(b - d)), rel=1e-9)
    st2 = _with(st, new2)
    bb = _at(st2, st2.values, "B", phi)
    u = (bb - d) / np.hypot(*(bb - d))
    k = d + 0.03 * u + 0.01 * np.array([-u[1], u[0]])
    new3 = drag_joint(st2, "K", k, phi)
    assert new3["K_along"] == pytest.approx(0.03, abs=1e-9)
    assert new3["K_left"] == pytest.approx(0.01, abs=1e-9)


def _with(st, values):
    out = State.of(st.kind)
    out.values = dict(values)
    return out


def test_a_slider_goes_to_the_nearest_place_on_its_guide():
    st = State.default("impact")  # N on a guide at 90 deg through O, 130 mm to its left
    phi = 1.0
    here = _at(st, st.values, "N", phi)
    new = drag_joint(st, "N", here + np.array([0.02, 0.01]), phi)
    there = _at(st, new, "N", phi)
    assert there[0] == pytest.approx(here[0], abs=1e-12)  # still on its vertical guide
    assert there[1] == pytest.approx(here[1] + 0.01, abs=1e-9)
    assert set(k for k in new if new[k] != st.values[k]) == {"KN"}


def test_a_joint_of_one_dimension_goes_to_the_nearest_place_it_can_reach():
    # the beam pump's horsehead H: on the beam's line through O2, at A from it
    st = State.default("beam-pump")
    phi = 0.9
    o2, h = _at(st, st.values, "O2", phi), _at(st, st.values, "H", phi)
    u = (h - o2) / np.hypot(*(h - o2))
    target = h + 0.2 * u + 0.05 * np.array([-u[1], u[0]])  # m: 0.2 further, 0.05 aside
    new = drag_joint(st, "H", target, phi)
    assert new["A"] == pytest.approx(st.values["A"] + 0.2, rel=1e-9)
    assert {k for k in new if new[k] != st.values[k]} == {"A"}
    assert _at(st, new, "H", phi) == pytest.approx(h + 0.2 * u, abs=1e-9)
    with pytest.raises(MechanismError, match="cannot move H there: A would have to be zero or"):
        drag_joint(st, "H", o2 - 0.5 * u, phi)  # behind the centre bearing
    # the dwell linkage's slider B: the rod scales the linkage (paper 003's ratios), so B
    # goes to the drop's x on its line
    st = State.default("dwell")
    b = _at(st, st.values, "B", phi)
    new = drag_joint(st, "B", b + np.array([0.05, 0.02]), phi)
    assert _at(st, new, "B", phi) == pytest.approx(b + np.array([0.05, 0.0]), abs=1e-9)
    assert new["rod"] == pytest.approx(st.values["rod"] * (b[0] + 0.05) / b[0], rel=1e-9)
    # link 5's stem end G: its slot's angle xi, to the place nearest the drop
    g = _at(st, st.values, "G", phi)
    target = g + np.array([0.02, 0.012])
    new = drag_joint(st, "G", target, phi)
    assert {k for k in new if new[k] != st.values[k]} == {"xi"}

    def miss(xi):
        return np.hypot(*(_at(st, dict(new, xi=xi), "G", phi) - target))

    assert miss(new["xi"]) < np.hypot(*(g - target))
    assert miss(new["xi"]) <= min(miss(new["xi"] - 1e-4), miss(new["xi"] + 1e-4)) + 1e-12
    assert State.of(st.kind).check_design()[1] is None


def test_a_drag_that_cannot_be_reached_or_a_fixed_pivot_says_why():
    st = State.default("linkage")
    phi = 0.3
    a, d, b = (_at(st, st.values, p, phi) for p in ("A", "D", "B"))
    u = (d - a) / np.hypot(*(d - a))
    mirror = a + 2 * ((b - a) @ u) * u - (b - a)  # B reflected across the line A-D
    with pytest.raises(MechanismError, match="cannot move B there: .*other assembly branch"):
        drag_joint(st, "B", mirror, phi)
    with pytest.raises(MechanismError, match="O is a fixed pivot"):
        joint_dims(st, "O")
    with pytest.raises(MechanismError, match="F of the Dwell linkage .* is not a joint"):
        joint_dims(State.default("dwell"), "F")  # the stem's end in the slot: not a joint
    with pytest.raises(MechanismError, match="must be numbers"):
        drag_joint(st, "A", (float("nan"), 0.0), phi)


# ------------------------------------------------------------------------------ the draft
def _four_bar_draft():
    return (
        Draft()
        .ground(0.0, 0.0)
        .ground(0.1, 0.0)
        .crank("O1", 0.0, 0.03)
        .rrr("A", "O2", 0.06, 0.08)
        .attach("A", "B", 0.02, 0.09)
    )


def test_a_draft_built_by_clicks_puts_every_point_where_it_was_clicked():
    d = _four_bar_draft()
    lk, message = d.check()
    assert message is None
    assert lk.parameters["O1A"] == pytest.approx(0.03)
    assert lk.parameters["phase"] == pytest.approx(math.pi / 2, abs=1e-5)  # 6 digits kept
    assert lk.parameters["AB"] == pytest.approx(math.hypot(0.06, 0.05), rel=5e-6)  # 6 digits
    assert lk.parameters["O2B"] == pytest.approx(math.hypot(0.04, 0.08), rel=5e-6)
    sk = lk.sketch(np.array([0.0]))
    for p, xy in {"A": (0, 0.03), "B": (0.06, 0.08), "C": (0.02, 0.09)}.items():
        assert np.ravel(sk.points[p][0])[0] == pytest.approx(xy[0], abs=1e-6)
        assert np.ravel(sk.points[p][1])[0] == pytest.approx(xy[1], abs=1e-6)
    # the other side of A -> O2 is the other assembly branch
    other = d.delete_last().delete_last().rrr("A", "O2", 0.06, -0.02)
    from mechsynth.synthesis.linkage_file import linkage_from_data

    lk2 = linkage_from_data(other.tables())
    assert other.steps[-1]["branch"] == -1
    assert np.ravel(lk2.sketch(np.array([0.0])).points["B"][1])[0] == pytest.approx(-0.02, abs=1e-6)


def test_every_step_type_and_the_file_it_writes(tmp_path):
    from mechsynth.synthesis.linkage_file import load_linkage

    d = (
        Draft()
        .ground(0.0, 0.0)
        .ground(0.3, 0.0)
        .slider(0.0, 0.05, 0.0, 0.1)  # A, driven along +x over 100 mm
        .rrr("A", "O2", 0.15, 0.15)  # B
        .rrp("B", 0.3, 0.25, 0.0)  # C on a guide along x through (0.3, 0.25)
        .rpr("O1", "B")
    )
    lk, message = d.check()
    assert message is None, message
    assert lk.driver == "slider" and lk.input_range == (0.0, 0.1)
    sk = lk.sketch(np.array([0.0]))
    for p, xy in {"A": (0, 0.05), "B": (0.15, 0.15), "C": (0.3, 0.25)}.items():
        assert np.ravel(sk.points[p][0])[0] == pytest.approx(xy[0], abs=1e-6)
        assert np.ravel(sk.points[p][1])[0] == pytest.approx(xy[1], abs=1e-6)
    path = tmp_path / "built.toml"
    path.write_text(d.toml())
    again = load_linkage(path)
    assert again.parameters == pytest.approx(lk.parameters)
    assert tomllib.loads(d.toml())["group"][0]["type"] == "slider"


def test_the_draft_follows_the_dimensions_changed_on_the_page():
    d = (
        Draft()
        .ground(0.0, 0.0)
        .ground(0.3, 0.0)
        .crank("O1", 0.02, 0.0)
        .rrr("A", "O2", 0.15, 0.15)
        .rrp("B", 0.3, 0.25, 0.0)
        .attach("A", "B", 0.05, 0.05)
        .rpr("O1", "C")
    )
    lk, message = d.check()
    assert message is None, message
    changed = {k: v * 1.01 if v else 0.001 for k, v in lk.parameters.items()}
    again = d.with_values(changed)
    from mechsynth.synthesis.linkage_file import linkage_from_data

    got = linkage_from_data(again.tables()).parameters
    assert set(got) == set(changed)  # every dimension is found in the file by its name
    for k, v in changed.items():
        assert got[k] == pytest.approx(v, rel=1e-5)


@pytest.mark.parametrize("key", ["linkage", "impact"])
def test_a_linkages_tables_go_on_as_a_draft_with_the_pages_values(key):
    st = State.default(key)  # the six-link (a guide through coordinates), the impact machine
    d = Draft.from_tables(st.kind.file_data)  # (a guide through O, with its offset)
    changed = {k: v * 1.01 if v else 0.001 for k, v in st.values.items()}
    from mechsynth.synthesis.linkage_file import linkage_from_data

    got = linkage_from_data(d.with_values(changed).tables()).parameters
    for k, v in changed.items():
        assert got[k] == pytest.approx(v, rel=1e-5), k
    more = d.attach("B", "K", 0.05, 0.05)  # a point on the link DB (K is on it too)
    lk, message = more.check()
    assert message is None and more.steps[-1]["point"] == "C"
    assert lk.default_output == "N"  # the file's output kept
    sk = lk.sketch(np.array([0.0]))
    assert np.ravel(sk.points["C"][0])[0] == pytest.approx(0.05, abs=1e-6)


def test_a_draft_says_what_is_missing_or_why_it_does_not_assemble():
    d = Draft()
    assert d.check() == (None, "click on the drawing to add a ground point")
    d = d.ground(0.0, 0.0).ground(0.1, 0.0)
    with pytest.raises(MechanismError, match="add the driver first"):
        d.rrr("O1", "O2", 0.05, 0.05)
    with pytest.raises(MechanismError, match="turns about a ground point .*got 'B'"):
        d.crank("B", 0.0, 0.02)
    d = d.crank("O1", 0.05, 0.0)
    assert "add a group" in d.check()[1]
    with pytest.raises(MechanismError, match="driver already"):
        d.crank("O1", 0.0, 0.02)
    # links too short to reach over the whole turn: the library's message
    bad = d.rrr("A", "O2", 0.075, 0.0)
    lk, message = bad.check()
    assert lk is None and "RRR" in message and "cannot be assembled" in message
    assert bad.delete_last() == d and Draft().delete_last() == Draft()


def test_any_element_of_a_draft_moves_changes_or_goes_with_its_dependents():
    d = _four_bar_draft()  # O1, O2, A (crank), B (RRR of A and O2), C (on AB)
    assert d.elements == ("O1", "O2", "A", "B", "C")
    assert d.dependents("A") == ("B", "C") and d.dependents("O1") == ("A", "B", "C")
    assert d.dependents("C") == ()
    # an earlier group moved: it lands where clicked, the later ones keep their dimensions
    moved = d.move("B", 0.07, 0.085)
    lk, message = moved.check()
    assert message is None, message
    sk = lk.sketch(np.array([0.0]))
    assert np.ravel(sk.points["B"][0])[0] == pytest.approx(0.07, abs=1e-6)
    assert np.ravel(sk.points["B"][1])[0] == pytest.approx(0.085, abs=1e-6)
    assert lk.parameters["AB"] == pytest.approx(math.hypot(0.07, 0.055), rel=5e-6)
    assert moved.dims_of("C") == d.dims_of("C")  # C rides on AB with its offsets
    # the crank pin moved: its length and phase from O1, the RRR keeps its lengths
    lk, message = d.move("A", 0.025, 0.0).check()
    assert message is None, message
    assert lk.parameters["O1A"] == pytest.approx(0.025) and lk.parameters["phase"] == 0.0
    assert lk.parameters["AB"] == d.dims_of("B")["AB"][0]
    # a ground point moved
    assert d.move("O2", 0.11, 0.0).dims_of("O2") == {"O2_x": (0.11, "m"), "O2_y": (0.0, "m")}
    # its dimensions changed by name, the file follows
    d2 = d.with_values({"AB": 0.07})
    assert d2.dims_of("B")["AB"] == (0.07, "m") and d2.dims_of("A") == d.dims_of("A")
    # deleted with what depends on it; what does not depend on it stays
    gone, deps = d.delete("B")
    assert deps == ("C",) and gone.elements == ("O1", "O2", "A")
    gone, deps = d.delete("C")
    assert deps == () and gone == d.delete_last()
    six = Draft.from_tables(State.default("linkage").kind.file_data)
    gone, deps = six.delete("D")  # the six-link's second ground point: B, K, N use it
    assert deps == ("B", "K", "N") and gone.elements == ("O", "A")
    with pytest.raises(MechanismError, match="'Z' is not an element.*O1, O2, A, B, C"):
        d.move("Z", 0.0, 0.0)
    with pytest.raises(MechanismError, match="RPR group.* has no place of its own"):
        Draft().ground(0, 0).ground(0.1, 0).crank("O1", 0.02, 0).rpr("O2", "A").move("O2A", 0, 0)


# ------------------------------------------------------------------------------ history
def test_history_merges_a_run_of_one_dimension_and_undoes_and_redoes():
    h = History(limit=3)
    assert h.undo() is None and h.redo() is None
    h.record("start")
    h.record("rod 1", key="rod", now=10.0)
    h.record("rod 2", key="rod", now=10.5)  # the same drag: merged
    h.record("rod 3", key="rod", now=12.0)  # later: a step of its own
    assert h.undo() == "rod 2" and h.undo() == "start" and h.undo() is None
    assert h.redo() == "rod 2" and h.redo() == "rod 3" and h.redo() is None
    h.undo()
    h.record("crank", key="crank", now=20.0)  # a new change: no redo left
    assert not h.can_redo
    for i in range(5):
        h.record(i)
    assert len(h._past) == 3  # the limit


# ------------------------------------------------------------------------------ the URL
def test_the_url_carries_a_built_in_mechanism_and_a_linkage():
    st = State.default("four-bar", units="mm-deg")
    st.values.update(crank=0.25, rocker=0.9)
    st.speed = 12.5
    back = state_from_query(_args(to_query(st)))
    assert back.kind.key == "four-bar" and back.units == "mm-deg"
    assert back.values == st.values and back.speed == 12.5
    lk_state = State.of(_four_bar_draft().kind(), "si")
    lk_state.values["O1A"] = 0.025
    q = to_query(lk_state)
    assert "mechanism=file" in q and len(q) < 1200
    back = state_from_query(_args(q))
    assert back.kind.title == lk_state.kind.title and back.values == lk_state.values
    assert back.kind.file_data == lk_state.kind.file_data
    impact = State.default("impact")
    assert "mechanism=impact" in to_query(impact) and "linkage=" not in to_query(impact)
    assert state_from_query({}) is None


def test_the_url_carries_the_problem_the_page_shows():
    from mechsynth.explore.model import load_file

    st = load_file("examples/optimize_centric_slider_crank.toml", "mm-deg")  # the reference
    st.constraints = [*st.constraints, "min_transmission_angle >= 40 deg"]
    st.vary["offset"] = (-0.01, 0.02)
    st.sense, st.method, st.starts = "maximize", "slsqp", 7
    back = state_from_query(_args(to_query(st)))
    assert back.objective == st.objective == "peak_acceleration(slider)"
    assert back.constraints == st.constraints and len(back.constraints) == 3
    assert back.vary == st.vary and back.vary["rod"] == (0.08, 0.2)
    assert (back.sense, back.method, back.starts) == ("maximize", "slsqp", 7)
    assert back.problem_data() == st.problem_data()  # the same problem file
    # none: no constraints and no variables come back as none (not the mechanism's defaults)
    st.constraints, st.vary = [], {}
    back = state_from_query(_args(to_query(st)))
    assert back.constraints == [] and back.vary == {}
    # a bound typed that is not a number yet is left out
    st.vary = {"crank": (float("nan"), 0.1), "rod": (0.1, 0.2)}
    assert "vary=crank" not in to_query(st) and "vary=rod" in to_query(st)
    # an address without the problem keeps the mechanism's own
    back = state_from_query(_args("mechanism=four-bar&crank=0.3"))
    assert back.constraints == State.default("four-bar").constraints


def _args(query):
    from urllib.parse import parse_qs

    return {k: [v.encode() for v in vs] for k, vs in parse_qs(query).items()}


@pytest.mark.parametrize(
    "query, message",
    [
        ("mechanism=pendulum", "mechanism must be one of"),
        ("mechanism=four-bar&crank=abc", "crank must be a number, got 'abc'"),
        ("mechanism=four-bar&crank=-1", "crank must be positive"),
        ("mechanism=four-bar&speed=-3", "speed must not be negative"),
        ("mechanism=four-bar&units=furlongs", "units must be one of"),
        ("mechanism=file&linkage=@@@", "not a packed linkage"),
        ("mechanism=slider-crank&rod=inf", "rod must be a finite number"),
        ("mechanism=four-bar&problem=1&objective=bogus", "objective: unknown measure 'bogus'"),
        ("mechanism=four-bar&problem=1&sense=most", "sense must be minimize or maximize"),
        ("mechanism=four-bar&problem=1&constraint=time_ratio+%3D+1", "constraint: cannot read"),
        ("mechanism=four-bar&problem=1&vary=crank:0.1", "vary must be name:lower:upper"),
        ("mechanism=four-bar&problem=1&vary=width:0:1", "name of crank, coupler, rocker"),
        ("mechanism=four-bar&problem=1&vary=crank:x:1", "crank lower bound must be a number"),
        ("mechanism=four-bar&problem=1&vary=crank:0.2:0.1", "bounds: crank: lower bound 0.2 m"),
        ("mechanism=four-bar&problem=1&method=newton", "method must be one of ipopt"),
        ("mechanism=four-bar&problem=1&starts=two", "starts must be a whole number"),
        ("mechanism=four-bar&problem=1&starts=0", "starts must be 1 to 1000, got 0"),
    ],
)
def test_a_bad_url_says_which_parameter(query, message):
    with pytest.raises(MechanismError, match=message):
        state_from_query(_args(query))


# ------------------------------------------------------------------------------ the page object
@pytest.fixture
def page():
    pytest.importorskip("panel")
    from mechsynth.explore.app import Explorer

    return Explorer(State.default("slider-crank", units="mm-deg"))


def test_page_builds_a_linkage_by_clicks_and_undoes_each_step(page):
    ed = page.editing
    ed.new_linkage()
    ed.click(0.0, 0.0)  # mm
    ed.click(100.0, 0.0)
    assert "O2 = [0.1, 0.0]" in ed.toml.object
    ed.step.value = "crank"
    ed._show_draft()
    ed.p1.value = "O1"
    ed.click(0.0, 30.0)
    assert page.state.kind.key == "slider-crank"  # no linkage yet: the last one is drawn
    ed.step.value = "rrr"
    ed._show_draft()
    ed.p1.value, ed.p2.value = "A", "O2"
    ed.click(60.0, 80.0)
    assert page.state.kind.title == "Linkage built in the page"
    assert page.dim_fields["O2B"].value == "89.4427"  # mm: the clicked distance to O2
    assert "the linkage assembles" in ed.message.object
    assert page.kind_select.value == "__file__"
    # a dimension changed on the page is in the file
    page._on_field("O1A", "35")
    assert "length = 0.035" in ed.toml.object
    ed.undo()
    assert page.dim_fields["O1A"].value == "30" and "length = 0.03\n" in ed.toml.object
    ed.undo()  # the RRR group: the slider-crank is drawn again, the draft has 3 steps
    assert page.state.kind.key == "slider-crank" and len(ed.draft.steps) == 3
    assert page.kind_select.value != "__file__"
    ed.redo()
    assert page.state.kind.title == "Linkage built in the page"
    ed.delete_last()
    assert "add a group" in ed.message.object


def test_page_edits_an_earlier_element_selected_in_the_list_or_by_a_click(page):
    ed = page.editing
    ed.new_linkage()
    ed.click(0.0, 0.0)
    ed.click(100.0, 0.0)
    ed.step.value = "crank"
    ed.p1.value = "O1"
    ed.click(0.0, 30.0)
    ed.step.value = "rrr"
    ed._show_draft()
    ed.p1.value, ed.p2.value = "A", "O2"
    ed.click(60.0, 80.0)
    ed.step.value = "attach"
    ed._show_draft()
    ed.p1.value, ed.p2.value = "A", "B"
    ed.click(20.0, 90.0)
    assert page.state.kind.title == "Linkage built in the page" and "C_along" in page.dim_fields
    # B chosen by a click near it, then moved by the next click
    ed.step.value = "select"
    ed.click(58.0, 79.0)
    assert ed.element.value == "B" and ed.step.value == "move"
    assert ed.element_dims.value == "AB = 78.1026, O2B = 89.4427"  # 6 digits of m kept
    ed.click(70.0, 85.0)
    assert "B moved" in ed.message.object
    # hypot(70, 55) and hypot(30, 85) mm (A is at (0, 30) to the 6 digits of its phase)
    assert float(page.dim_fields["AB"].value) == pytest.approx(89.0225, abs=2e-4)
    assert float(page.dim_fields["O2B"].value) == pytest.approx(90.1388, abs=2e-4)
    x, y = page.frame_cols["x:B"][0], page.frame_cols["y:B"][0]
    assert (x, y) == pytest.approx((70.0, 85.0), abs=1e-4)  # drawn where clicked (6 digits)
    # its dimensions typed
    ed.element_dims.value = "AB = 95"
    assert page.dim_fields["AB"].value == "95" and "B's dimensions changed" in ed.message.object
    ed.element_dims.value = "AB = 95, XY = 3"
    assert "B's dimensions are AB, O2B (name = value, ...), got 'XY = 3'" in ed.message.object
    # the crank (an earlier element) deleted: its dependents go with it, said in the message
    ed.element.value = "A"
    ed.delete_element()
    assert "deleted A and what depends on it: B, C" in ed.message.object
    assert ed.draft.elements == ("O1", "O2")
    # the draft no longer assembles: the last linkage stays drawn, the draft's points over it
    assert "add the driver" in ed.message.object and ed.src_draft.data["name"] == ["O1", "O2"]
    ed.undo()  # each edit is a step of undo
    assert ed.draft.elements == ("O1", "O2", "A", "B", "C")
    assert page.dim_fields["AB"].value == "95"
    ed.undo()
    assert float(page.dim_fields["AB"].value) == pytest.approx(89.0225, abs=2e-4)
    ed.redo()
    assert page.dim_fields["AB"].value == "95"


def test_page_a_draft_point_dragged_moves_its_element(page):
    ed = page.editing
    page.kind_select.value = "four-bar"  # its O2 is a pivot that drags
    ground_length = page.state.values["ground"]
    ed.new_linkage()
    ed.click(0.0, 0.0)
    ed.click(100.0, 0.0)
    ed.step.value = "crank"
    ed.p1.value = "O1"
    ed.click(0.0, 30.0)
    assert ed.src_draft.data["name"] == ["O1", "O2", "A"]  # no group yet: drawn as a draft

    def drag(name, x, y):
        data = {k: list(v) for k, v in ed.src_draft.data.items()}
        i = data["name"].index(name)
        data["x"][i], data["y"][i] = x, y
        ed.src_draft.data = data

    drag("A", 40.0, 0.0)  # mm: the crank 40 mm long at phase 0
    assert ed.draft.dims_of("A") == {"O1A": (0.04, "m"), "phase": (0.0, "rad")}
    assert "A moved" in ed.message.object and ed.element.value == "A"
    assert ed.src_draft.data["x"][2] == pytest.approx(40.0) and ed.src_draft.data["y"][2] == 0.0
    # the tool drags every point under the pointer: while the draft is drawn over the page's
    # mechanism, its pivots stay (the four-bar's O2 dragged with a draft's point over it)
    ground = {k: list(v) for k, v in page.src_ground.data.items()}
    assert ground["name"] == ["O1", "O2"]
    ground["x"][1] += 5.0
    page.src_ground.data = ground
    assert page.state.values["ground"] == ground_length
    assert page.src_ground.data["x"][1] == ground["x"][1] - 5.0
    drag("O1", 100.0, 0.0)  # onto O2: the crank's pin stays, O1 goes
    assert ed.draft.dims_of("O1") == {"O1_x": (0.1, "m"), "O1_y": (0.0, "m")}
    ed.undo()
    assert ed.draft.dims_of("O1") == {"O1_x": (0.0, "m"), "O1_y": (0.0, "m")}
    # a point dropped where its element cannot go: back, saying why
    drag("A", 0.0, 0.0)  # onto its pivot: a crank of length 0
    assert "cannot move A: crank: click away from O1" in ed.message.object
    assert ed.src_draft.data["x"][2] == pytest.approx(40.0)


def test_page_drags_a_crank_pin_and_snaps_back_with_the_reason(page):
    ed = page.editing

    def drag(name, dx, dy=0.0):
        from mechsynth.explore.animation import frame_glyphs

        k = int(page.frame.value)
        data = {k_: list(v) for k_, v in frame_glyphs(page.frame_cols, page.frame_meta, k)[
            "joints"].items()}  # fmt: skip
        i = data["name"].index(name)
        data["x"][i] += dx
        data["y"][i] += dy
        page.src_joints.selected.indices = [i]  # the drawing's tool grabs it
        page.src_joints.data = data
        page.src_joints.selected.indices = []

    # the drawing's tool sends the joints as the browser shows them when a pivot is dragged
    # (the player may stand between two frames): no joint was grabbed, nothing changes
    data = {k_: list(v) for k_, v in page.src_joints.data.items()}
    data["x"] = [x + 0.5 for x in data["x"]]
    page.src_joints.data = data
    assert page.state.values["crank"] == 0.07 and not page.design_msg.visible
    drag("A", 5.0)  # mm, at crank angle 0: the crank from 70 to 75 mm
    assert page.state.values["crank"] == pytest.approx(0.075)
    assert page.dim_fields["crank"].value == "75" and not page.design_msg.visible
    drag("A", 200.0)  # a crank longer than the rod: back, with the library's reason
    assert page.state.values["crank"] == pytest.approx(0.075)
    assert page.design_msg.visible
    assert "cannot move A there: " in page.design_msg.object
    ed.undo()
    assert page.dim_fields["crank"].value == "70"


def test_page_drags_the_dwell_linkages_joints_and_the_beam_pumps_pivot_and_horsehead():
    pytest.importorskip("panel")
    from mechsynth.explore.animation import frame_glyphs
    from mechsynth.explore.app import Explorer

    page = Explorer(State.default("dwell", units="mm-deg"))

    def drag(name, dx, dy=0.0, source="joints"):
        k = int(page.frame.value)
        if source == "joints":
            glyphs = frame_glyphs(page.frame_cols, page.frame_meta, k)["joints"]
            src = page.src_joints
        else:
            glyphs, src = page.src_ground.data, page.src_ground
        data = {k_: list(v) for k_, v in glyphs.items()}
        i = data["name"].index(name)
        data["x"][i] += dx
        data["y"][i] += dy
        if source == "joints":
            src.selected.indices = [i]  # the drawing's tool grabs it
        src.data = data
        src.selected.indices = []
        return data["x"][i], data["y"][i]

    x, y = drag("C", 20.0, 10.0)  # mm: the coupler point C (k, gamma)
    assert not page.design_msg.visible
    assert page.frame_cols["x:C"][0] == pytest.approx(x, abs=1e-6)
    assert page.frame_cols["y:C"][0] == pytest.approx(y, abs=1e-6)
    assert page.dim_fields["k"].value != "1.2109"
    rod = page.state.values["rod"]
    drag("B", 4000.0)  # B far out: the rod follows; the linkage still turns
    assert page.state.values["rod"] > 2 * rod and not page.design_msg.visible
    drag("G", 30.0, 10.0)  # the stem end: the slot's angle
    assert page.dim_fields["xi"].value != "17.75"
    page.editing.undo()
    page.editing.undo()
    assert page.state.values["rod"] == rod
    # the beam pump: the horsehead H (its A), the centre bearing O2 (I and H)
    page.units_select.value = "si"
    page.state = State.default("beam-pump", units="si")
    page._rebuild_dims()
    page._refresh(None)
    a = page.state.values["A"]
    drag("H", 0.0, 0.3)  # m, at crank angle 0: mostly across the beam
    assert page.state.values["A"] != a and not page.design_msg.visible
    o2 = np.array([page.frame_cols["x:O2"][0], page.frame_cols["y:O2"][0]])
    h = np.array([page.frame_cols["x:H"][0], page.frame_cols["y:H"][0]])
    assert np.hypot(*(h - o2)) == pytest.approx(page.state.values["A"], rel=1e-9)
    x, y = drag("O2", 0.1, 0.05, source="ground")
    assert page.state.values["I"] == pytest.approx(x, abs=1e-12)
    assert page.dim_fields["I"].value == f"{x:.6g}" and not page.design_msg.visible
    assert (page.frame_cols["x:O2"][0], page.frame_cols["y:O2"][0]) == pytest.approx((x, y))
    drag("O2", 0.0, 30.0, source="ground")  # far above: the pitman cannot reach the beam
    assert "cannot move O2 there: " in page.design_msg.object
    assert page.state.values["I"] == pytest.approx(x, abs=1e-12)


# ------------------------------------------------------------------------------ in the browser
# the server and browser of the visible-page tests (one server for the module)
from test_explore_visible import _open, _select, _shown_fits, browser, server  # noqa: E402, F401

# a joint's place on the screen and in the drawing's units
JOINT = """(name) => { const d = Bokeh.documents[0], f = d.get_model_by_name('drawing');
  const v = Bokeh.index.find_one(f), G = d.get_model_by_name('joints').data_source.data;
  const i = G.name.indexOf(name), r = v.canvas_view.el.getBoundingClientRect();
  return [r.left + v.frame.x_scale.compute(G.x[i]), r.top + v.frame.y_scale.compute(G.y[i]),
          G.x[i], G.y[i]]; }"""
# a place of the drawing (its units) on the screen
SCREEN_AT = """([x, y]) => { const d = Bokeh.documents[0], f = d.get_model_by_name('drawing');
  const v = Bokeh.index.find_one(f), r = v.canvas_view.el.getBoundingClientRect();
  return [r.left + v.frame.x_scale.compute(x), r.top + v.frame.y_scale.compute(y)]; }"""


# the drawing's place on the screen and its ranges: a press lands where it is aimed only once
# the page has stopped moving (a served change may re-lay it out after a position is read)
PLACE = """() => { const f = Bokeh.documents[0].get_model_by_name('drawing');
  const r = Bokeh.index.find_one(f).canvas_view.el.getBoundingClientRect();
  return [r.left, r.top, f.x_range.start, f.x_range.end, f.y_range.start, f.y_range.end]; }"""


def _still(page):
    last = None
    for _ in range(60):
        now = page.evaluate(PLACE)
        if now == last:
            return
        last = now
        page.wait_for_timeout(400)


def _drag_joint(page, name, dx, dy=0.0):
    _still(page)
    x, y, _, _ = page.evaluate(JOINT, name)
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + dx / 2, y + dy / 2, steps=4)
    page.mouse.move(x + dx, y + dy, steps=4)
    page.mouse.up()


def _value(page, label):
    return float(page.get_by_label(label, exact=True).input_value())


@pytest.mark.browser
@pytest.mark.slow
def test_browser_a_dragged_crank_pin_moves_the_fields_or_snaps_back_saying_why(page_b):
    from playwright.sync_api import expect

    page = page_b
    _select(page, "Mechanism", "Linkage (six-link of paper 001, or a TOML file)")
    expect(page.get_by_label("OA, mm", exact=True)).to_have_value("30", timeout=60_000)
    page.wait_for_timeout(1000)
    _drag_joint(page, "A", 12, -8)  # pixels, at crank angle 0
    expect(page.get_by_label("OA, mm", exact=True)).not_to_have_value("30", timeout=60_000)
    page.wait_for_timeout(800)
    _, _, ax, ay = page.evaluate(JOINT, "A")  # where the page draws A now (mm)
    assert _value(page, "OA, mm") == pytest.approx(math.hypot(ax, ay), rel=1e-4)
    assert _value(page, "phase, deg") == pytest.approx(math.degrees(math.atan2(ay, ax)), abs=0.01)
    assert ay > 0.5  # dragged up: the phase is the pin's angle at crank angle 0
    # the coupler joint B far away: its links cannot assemble; back, with the reason
    before = page.evaluate(JOINT, "B")[2:]
    _drag_joint(page, "B", 400, 0)
    page.locator(".design-message").get_by_text("cannot move B there").wait_for(timeout=60_000)
    page.wait_for_timeout(600)
    assert page.evaluate(JOINT, "B")[2:] == pytest.approx(before, abs=1e-6)
    assert _value(page, "AB, mm") == 120 and _value(page, "DB, mm") == 80
    _shown_fits(page)


@pytest.mark.browser
@pytest.mark.slow
def test_browser_the_dwell_linkages_joints_and_the_beam_pumps_horsehead_drag(page_b):
    from playwright.sync_api import expect

    page = page_b
    _select(page, "Mechanism", "Dwell linkage (paper 003)")
    expect(page.get_by_label("k", exact=True)).to_have_value("1.2109", timeout=60_000)
    page.wait_for_function(  # the coupler point C and the stem's end G are handles
        "() => Bokeh.documents[0].get_model_by_name('joints').data_source.data.name.join()"
        " === 'A,B,C,G'", timeout=60_000,
    )  # fmt: skip
    _drag_joint(page, "C", 10, -6)  # pixels, at crank angle 0: k and gamma follow
    expect(page.get_by_label("k", exact=True)).not_to_have_value("1.2109", timeout=60_000)
    page.wait_for_timeout(800)
    k, gamma = _value(page, "k"), _value(page, "gamma, deg")
    assert gamma != -20.39 and not page.locator(".design-message").is_visible()
    # where the page draws C is where the API puts it for the fields' values
    from mechsynth.explore.model import State

    st = State.default("dwell", units="mm-deg")
    st.values.update(k=k, gamma=math.radians(gamma))
    sk = st.design().sketch(np.array([0.0]))
    _, _, cx, cy = page.evaluate(JOINT, "C")
    assert cx == pytest.approx(float(np.ravel(sk.points["C"][0])[0]) * 1e3, abs=0.01)  # mm
    assert cy == pytest.approx(float(np.ravel(sk.points["C"][1])[0]) * 1e3, abs=0.01)
    _drag_joint(page, "G", 0, -12)  # the slot's angle
    expect(page.get_by_label("xi, deg", exact=True)).not_to_have_value("17.75", timeout=60_000)
    _shown_fits(page)
    # the beam pump's horsehead: along the beam, its A follows
    _select(page, "Mechanism", "Beam pumping unit (API 11E dimensions)")
    expect(page.get_by_label("A, mm", exact=True)).to_have_value("3937", timeout=60_000)
    page.wait_for_function(
        "() => Bokeh.documents[0].get_model_by_name('joints').data_source.data.name"
        ".includes('H')", timeout=60_000,
    )  # fmt: skip
    _drag_joint(page, "H", 15, 0)
    expect(page.get_by_label("A, mm", exact=True)).not_to_have_value("3937", timeout=60_000)
    page.wait_for_timeout(800)
    a = _value(page, "A, mm")
    hx, hy = page.evaluate(JOINT, "H")[2:]
    g = page.evaluate(
        "() => { const G = Bokeh.documents[0].get_model_by_name('ground').data_source.data;"
        " const i = G.name.indexOf('O2'); return [G.x[i], G.y[i]]; }"
    )
    assert math.hypot(hx - g[0], hy - g[1]) == pytest.approx(a, rel=1e-5)
    # a horsehead pulled back past the centre bearing: back, with the reason
    _drag_joint(page, "H", -2000, 0)
    page.locator(".design-message").get_by_text("cannot move H there").wait_for(timeout=60_000)
    assert _value(page, "A, mm") == a


@pytest.fixture
def page_b(browser, server):  # noqa: F811
    pg = _open(browser, server)
    yield pg
    pg.close()


def _click_at(page, x, y):
    _still(page)
    sx, sy = page.evaluate(SCREEN_AT, [x, y])
    page.mouse.click(sx, sy)
    page.wait_for_timeout(600)


@pytest.mark.browser
@pytest.mark.slow
def test_browser_a_linkage_built_by_clicks_is_drawn_its_file_downloaded_and_undone(page_b):
    from playwright.sync_api import expect

    from mechsynth.synthesis.linkage_file import load_linkage

    page = page_b
    menu = page.get_by_label("Mechanism", exact=True)
    page.get_by_role("button", name="New linkage").click()
    adds = page.get_by_label("A click on the drawing adds", exact=True)
    adds.wait_for(timeout=60_000)
    _click_at(page, 0, 0)  # mm
    _click_at(page, 100, 0)
    toml = page.locator("#editor-toml")
    expect(toml).to_contain_text("O2 = [0.1, 0.0]", timeout=60_000)
    adds.select_option(label="crank (on a ground point)")
    expect(page.get_by_label("about (a ground point)", exact=True)).to_be_visible()
    _click_at(page, 0, 30)
    expect(page.locator("#editor-message")).to_contain_text("add a group", timeout=60_000)
    adds.select_option(label="RRR group (two links)")
    expect(page.get_by_label("first point", exact=True)).to_be_visible()
    page.get_by_label("first point", exact=True).select_option("A")
    page.get_by_label("second point", exact=True).select_option("O2")
    _click_at(page, 60, 80)
    expect(page.locator("#editor-message")).to_contain_text("the linkage assembles", timeout=60_000)
    expect(page.get_by_label("O2B, mm", exact=True)).to_have_value("89.4427", timeout=60_000)
    assert menu.evaluate("e => e.options[e.selectedIndex].text") == "Linkage built in the page"
    page.wait_for_timeout(800)
    _, _, bx, by = page.evaluate(JOINT, "B")  # at crank angle 0: where it was clicked
    assert (bx, by) == (pytest.approx(60, abs=1e-3), pytest.approx(80, abs=1e-3))
    _shown_fits(page)
    with page.expect_download() as dl:
        page.get_by_role("button", name="Linkage file (TOML)").click()
    path = dl.value.path()
    lk = load_linkage(path)
    assert lk.parameters["O1A"] == pytest.approx(0.03) and lk.parameters["O2_x"] == 0.1
    assert "[[group]]" in toml.inner_text()
    # Ctrl+Z (outside a text field) takes the RRR group back: the slider-crank is drawn again
    page.locator("#editor-toml").click()
    page.keyboard.press("Control+z")
    expect(page.get_by_label("crank, mm", exact=True)).to_have_value("50", timeout=60_000)
    assert "Slider-crank" in menu.evaluate("e => e.options[e.selectedIndex].text")
    page.get_by_role("button", name="Redo").click()
    expect(page.get_by_label("O2B, mm", exact=True)).to_have_value("89.4427", timeout=60_000)
    page.get_by_role("button", name="Delete the last element").click()
    expect(page.locator("#editor-message")).to_contain_text("add a group", timeout=60_000)


@pytest.mark.browser
@pytest.mark.slow
def test_browser_an_earlier_group_selected_moved_retyped_and_deleted(page_b):
    from playwright.sync_api import expect

    page = page_b
    page.get_by_role("button", name="New linkage").click()
    adds = page.get_by_label("A click on the drawing adds", exact=True)
    adds.wait_for(timeout=60_000)
    message = page.locator("#editor-message")
    _click_at(page, 0, 0)  # mm
    _click_at(page, 100, 0)
    adds.select_option(label="crank (on a ground point)")
    expect(page.get_by_label("about (a ground point)", exact=True)).to_be_visible()
    _click_at(page, 0, 30)
    adds.select_option(label="RRR group (two links)")
    page.get_by_label("first point", exact=True).select_option("A")
    page.get_by_label("second point", exact=True).select_option("O2")
    _click_at(page, 60, 80)
    expect(message).to_contain_text("the linkage assembles", timeout=60_000)
    adds.select_option(label="attached point")
    page.get_by_label("on the link from", exact=True).select_option("A")
    page.get_by_label("towards", exact=True).select_option("B")
    _click_at(page, 20, 90)
    expect(page.get_by_label("C_along, mm", exact=True)).to_be_visible(timeout=60_000)
    # the RRR group (an earlier step than C) chosen by a click near B, then moved
    adds.select_option(label="select an element (the nearest point)")
    _click_at(page, 58, 79)
    expect(page.get_by_label("Element", exact=True)).to_have_value("B", timeout=60_000)
    dims = page.get_by_label("its dimensions (mm, angles in deg)", exact=True)
    expect(dims).to_have_value("AB = 78.1026, O2B = 89.4427", timeout=60_000)
    assert adds.evaluate("e => e.options[e.selectedIndex].text") == "move the selected element here"
    _click_at(page, 70, 85)
    expect(message).to_contain_text("B moved", timeout=60_000)
    expect(page.get_by_label("O2B, mm", exact=True)).to_have_value("90.1388", timeout=60_000)
    assert _value(page, "AB, mm") == pytest.approx(89.0225, abs=2e-4)  # hypot(70, 55)
    page.wait_for_timeout(800)
    _, _, bx, by = page.evaluate(JOINT, "B")  # drawn where clicked, at crank angle 0
    assert (bx, by) == (pytest.approx(70, abs=1e-3), pytest.approx(85, abs=1e-3))
    _, _, cx, cy = page.evaluate(JOINT, "C")  # C rides on AB with its offsets
    assert (cx, cy) != (pytest.approx(20, abs=0.5), pytest.approx(90, abs=0.5))
    _shown_fits(page)
    # its dimensions typed
    dims.fill("AB = 95, O2B = 90.1388")
    dims.press("Enter")
    expect(page.get_by_label("AB, mm", exact=True)).to_have_value("95", timeout=60_000)
    expect(message).to_contain_text("B's dimensions changed")
    # the crank deleted with what depends on it, said; the draft drawn over the last linkage
    page.get_by_label("Element", exact=True).select_option("A")
    page.get_by_role("button", name="Delete it (and what depends on it)").click()
    expect(message).to_contain_text("deleted A and what depends on it: B, C", timeout=60_000)
    expect(page.locator("#editor-toml")).not_to_contain_text('point = "B"')
    page.wait_for_function(
        "() => Bokeh.documents[0].get_model_by_name('draft').data_source.data.name.join()"
        " === 'O1,O2'", timeout=60_000,
    )  # fmt: skip
    # a point of the draft dragged: that element moves there
    _still(page)
    x, y = page.evaluate(
        "() => { const d = Bokeh.documents[0], f = d.get_model_by_name('drawing');"
        " const v = Bokeh.index.find_one(f), r = v.canvas_view.el.getBoundingClientRect();"
        " const D = d.get_model_by_name('draft').data_source.data, i = D.name.indexOf('O2');"
        " return [r.left + v.frame.x_scale.compute(D.x[i]),"
        " r.top + v.frame.y_scale.compute(D.y[i])]; }"
    )
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x, y - 10, steps=4)
    page.mouse.move(x, y - 20, steps=4)
    page.mouse.up()
    expect(message).to_contain_text("O2 moved", timeout=60_000)
    o2 = tomllib.loads(page.locator("#editor-toml").inner_text())["ground"]["O2"]
    assert o2[0] == pytest.approx(0.1, abs=2e-3) and o2[1] > 0.001  # m: moved up
    page.get_by_role("button", name="Undo").click()
    expect(page.locator("#editor-toml")).to_contain_text("O2 = [0.1, 0.0]", timeout=60_000)
    # undone: the five elements again, B where it was typed
    page.get_by_role("button", name="Undo").click()
    expect(page.locator("#editor-toml")).to_contain_text('point = "C"', timeout=60_000)
    expect(page.get_by_label("AB, mm", exact=True)).to_have_value("95", timeout=60_000)


@pytest.mark.browser
@pytest.mark.slow
def test_browser_the_address_carries_the_design_and_a_reload_restores_it(browser, server):  # noqa: F811
    from playwright.sync_api import expect

    pg = browser.new_page(viewport={"width": 1280, "height": 800})
    try:
        pg.goto(
            server["url"] + "?mechanism=four-bar&units=mm-deg&speed=0&crank=0.25&coupler=1.1"
            "&rocker=0.9&ground=1"
        )
        pg.wait_for_selector("#stroke", timeout=60_000)
        assert pg.get_by_label("crank, mm", exact=True).input_value() == "250"
        assert pg.get_by_label("coupler, mm", exact=True).input_value() == "1100"
        assert (
            pg.get_by_label("Mechanism", exact=True).evaluate(
                "e => e.options[e.selectedIndex].text"
            )
            == "Four-bar"
        )
        assert pg.get_by_label("Crank speed, rpm", exact=True).input_value() == "0"
        box = pg.get_by_label("rocker, mm", exact=True)
        box.fill("950")
        box.press("Enter")
        pg.wait_for_function("() => location.search.includes('rocker=0.95')", timeout=60_000)
        pg.reload()
        pg.wait_for_selector("#stroke", timeout=60_000)
        assert pg.get_by_label("rocker, mm", exact=True).input_value() == "950"
        assert pg.get_by_label("crank, mm", exact=True).input_value() == "250"
        _shown_fits(pg)
        # a bad address: the file's design, and the reason
        pg.goto(server["url"] + "?mechanism=four-bar&crank=abc")
        pg.wait_for_selector("#stroke", timeout=60_000)
        expect(pg.locator(".design-message")).to_contain_text("crank must be a number")
    finally:
        pg.close()


@pytest.mark.browser
@pytest.mark.slow
def test_browser_the_address_carries_the_problem_and_a_reload_restores_it(browser, server):  # noqa: F811
    from playwright.sync_api import expect

    pg = browser.new_page(viewport={"width": 1280, "height": 800})
    try:
        pg.goto(server["url"])  # the reference problem's file: its problem in the address
        pg.wait_for_function("() => location.search.includes('vary=rod')", timeout=60_000)
        assert "constraint=stroke%28slider%29+%3D%3D+100+mm" in pg.evaluate("location.search")
        pg.get_by_text("Problem", exact=True).first.click()
        box = pg.get_by_label("Constraints (one a line: measure <= value unit)", exact=True)
        box.wait_for(timeout=60_000)
        box.fill("stroke(slider) == 100 mm\nmin_transmission_angle >= 40 deg")
        box.blur()
        pg.get_by_label("Starts", exact=True).fill("5")
        pg.get_by_label("Starts", exact=True).press("Enter")
        pg.get_by_label("vary offset", exact=True).check()
        pg.wait_for_function(
            "() => location.search.includes('vary=offset') && location.search.includes("
            "'min_transmission_angle') && location.search.includes('starts=5')",
            timeout=60_000,
        )  # fmt: skip
        pg.reload()
        pg.wait_for_selector("#stroke", timeout=60_000)
        pg.get_by_text("Problem", exact=True).first.click()
        box = pg.get_by_label("Constraints (one a line: measure <= value unit)", exact=True)
        expect(box).to_have_value(
            "stroke(slider) == 100 mm\nmin_transmission_angle >= 40 deg", timeout=60_000
        )
        expect(pg.get_by_label("Starts", exact=True)).to_have_value("5")
        expect(pg.get_by_label("Objective measure", exact=True)).to_have_value(
            "peak_acceleration(slider)"
        )
        assert pg.get_by_label("vary offset", exact=True).is_checked()
        assert pg.get_by_label("vary rod", exact=True).is_checked()
        assert pg.get_by_label("rod upper bound", exact=True).input_value() == "200"
        # a bad value in the address: the page's start, and which parameter
        pg.goto(server["url"] + "?mechanism=four-bar&problem=1&sense=most")
        pg.wait_for_selector("#stroke", timeout=60_000)
        expect(pg.locator(".design-message")).to_contain_text(
            "sense must be minimize or maximize, got 'most'"
        )
    finally:
        pg.close()


def test_page_goes_on_building_the_six_link():
    pytest.importorskip("panel")
    from mechsynth.explore.app import Explorer

    page = Explorer(State.default("linkage", units="mm-deg"))
    ed = page.editing
    assert ed.edit_button.visible
    page._on_field("OA", "32")
    ed.edit_linkage()
    assert not ed.edit_button.visible and ed.building
    ed.step.value = "attach"
    ed._show_draft()
    ed.p1.value, ed.p2.value = "B", "K"
    ed.click(50.0, 50.0)
    assert page.state.kind.title == "Linkage six-link, edited in the page"
    assert page.dim_fields["C_left"].visible and page.dim_fields["OA"].value == "32"
    assert 'point = "C"' in ed.toml.object and "length = 0.032" in ed.toml.object
    ed.undo()
    assert page.state.kind.title == "Linkage: six-link of paper 001"

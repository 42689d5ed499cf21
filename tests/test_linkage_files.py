"""Linkages in TOML files: the format, its errors (naming the table and the key), problem files
with ``mechanism = "linkage"`` and the ``linkage`` chart kind."""

import json
from pathlib import Path

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.synthesis import load_linkage
from mechsynth.synthesis.linkage_file import linkage_from_data
from mechsynth.synthesis.problem_file import load_problem

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def six_link():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}, name="six-link")
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
        .with_output("N")
    )


def test_example_file_is_the_python_linkage():
    lk = load_linkage(EXAMPLES / "six_link.toml")
    ref = six_link()
    assert lk.name == "six-link" and list(lk.parameters) == list(ref.parameters)
    for k, v in ref.parameters.items():
        assert lk.parameters[k] == pytest.approx(v, abs=1e-15)
    phi = ms.cycle(90)
    np.testing.assert_array_equal(
        lk.motion(phi, kernel=False).points["N"].x, ref.motion(phi, kernel=False).points["N"].x
    )


def _data(**groups):
    base = {"ground": {"O": [0, 0], "D": ["120 mm", "50 mm"]}}
    base["group"] = [
        {"type": "crank", "point": "A", "about": "O", "length": "30 mm"},
        *groups.get("extra", []),
    ]
    return base


def test_every_group_type_and_named_dimensions():
    data = _data(
        extra=[
            {
                "type": "rrr",
                "point": "B",
                "first": ["A", {"name": "coupler", "value": "120 mm"}],
                "second": ["D", 0.08],
                "branch": -1,
                "links": ["cpl", "rck"],
            },
            {"type": "attach", "point": "K", "on": "rck", "along": "-50 mm", "left": "5 mm"},
            {
                "type": "rrp",
                "point": "N",
                "rod": ["K", "100 mm"],
                "guide": {"through": "D", "angle": "100 deg", "offset": "20 mm"},
            },
            {"type": "rpr", "link": "lever", "about": "D", "through": "A", "offset": "2 mm"},
            {
                "type": "follower",
                "point": "F",
                "on": ["O", "A"],
                "profile": {"type": "circle", "radius": "50 mm", "center": ["30 mm", 0]},
                "guide": {"through": [0, 0], "angle": "-90 deg"},
                "roller": "5 mm",
            },
        ]
    )
    lk = linkage_from_data(data)
    assert lk.parameters["coupler"] == pytest.approx(0.12)
    assert lk.parameters["N_guide_offset"] == pytest.approx(0.02)
    assert lk.parameters["F_profile_radius"] == pytest.approx(0.05)
    assert lk.links == ("OA", "cpl", "rck", "N", "KN", "lever", "A", "F")
    m = lk.motion(ms.cycle(72))
    assert set(m.sliders) == {"F", "N", "A"}


@pytest.mark.parametrize(
    "change, message",
    [
        ({"ground": {"O": [0]}}, r"\[ground\] O: expected \[x, y\]"),
        ({"ground": {"O": ["3 furlong", 0]}}, r"\[ground\] O: unknown unit 'furlong'"),
        ({"group": []}, r"\[\[group\]\]: give the driver"),
        ({"group": [{"type": "gear"}]}, r"\[\[group\]\] 1: type must be one of crank, rrr"),
        (
            {"group": [{"type": "crank", "point": "A", "about": "O", "lenght": 0.1}]},
            r"\[\[group\]\] 1: unknown key\(s\) lenght; missing key\(s\) length",
        ),
        (
            {"group": [{"type": "crank", "point": "A", "about": "Q", "length": 0.1}]},
            r"\[\[group\]\] 1 \(crank A\): crank A: unknown point 'Q'",
        ),
        (
            {"group": [{"type": "crank", "point": "A", "about": "O", "length": -0.1}]},
            r"\[\[group\]\] 1 \(crank A\): OA must be positive",
        ),
        ({"linkage": {"nmae": "x"}}, r"\[linkage\]: unknown key\(s\) nmae"),
        # a quantity's unit is checked against its dimension (was 0.524 m and 0.057 rad)
        (
            {"group": [{"type": "crank", "point": "A", "about": "O", "length": "30 deg"}]},
            r"^f.toml: \[\[group\]\] 1 \(crank A\): length: '30 deg' is an angle, "
            r"expected a length",
        ),
        (
            {
                "group": [
                    {"type": "crank", "point": "A", "about": "O", "length": 0.03,
                     "phase": "57 mm"}
                ]
            },
            r"phase: '57 mm' is a length, expected an angle",
        ),
        ({"ground": {"O": ["1 deg", 0]}}, r"\[ground\] O: '1 deg' is an angle, expected a length"),
        ({"linkage": {"output": "Z"}}, r"\[linkage\] output: output: unknown point 'Z'"),
    ],
)
def test_schema_errors_name_table_and_key(change, message):
    data = _data()
    data.update(change)
    with pytest.raises(ValueError, match=message):
        linkage_from_data(data, "f.toml")


def test_group_key_errors():
    bad = _data(extra=[{"type": "rrp", "point": "N", "rod": ["A", 0.1], "guide": 0.3}])
    with pytest.raises(ValueError, match=r"\[\[group\]\] 2 \(rrp N\): guide: expected"):
        linkage_from_data(bad)
    bad = _data(extra=[{"type": "rrr", "point": "B", "first": ["A"], "second": ["D", 0.08]}])
    with pytest.raises(ValueError, match=r"\(rrr B\): first: expected \[point, length\]"):
        linkage_from_data(bad)
    bad = _data(
        extra=[
            {
                "type": "follower",
                "point": "F",
                "on": "OA",
                "profile": {"type": "spline"},
                "guide": {"through": [0, 0], "angle": 0},
            }
        ]
    )
    with pytest.raises(ValueError, match=r"profile: expected a table with type = 'circle'"):
        linkage_from_data(bad)


def test_problem_file_inline_and_by_reference(tmp_path):
    ref = load_problem(EXAMPLES / "optimize_six_link.toml")
    assert isinstance(ref.problem.mechanism, ms.Linkage)
    assert ref.problem.variables["KN"] == pytest.approx((0.06, 0.2))
    names = [c.name for c in ref.problem.constraints]
    assert names[:2] == ["assembly_margin(B) >= 0.001", "assembly_margin(N) >= 0.001"]
    inline = (EXAMPLES / "six_link.toml").read_text()
    head = 'mechanism = "linkage"\nminimize = "peak_acceleration(N)"\n'
    (tmp_path / "p.toml").write_text(head + inline + "\n[variables]\nDB = [0.06, 0.1]\n")
    spec = load_problem(tmp_path / "p.toml")
    assert spec.problem.mechanism.parameters == load_linkage(EXAMPLES / "six_link.toml").parameters
    both = head + 'linkage = "six_link.toml"\n' + inline[inline.index("[ground]") :]
    (tmp_path / "q.toml").write_text(both)
    with pytest.raises(ValueError, match="inline .* or as linkage = 'file', not both"):
        load_problem(tmp_path / "q.toml")


def test_chart_linkage_cli(tmp_path, capsys):
    rc = main(
        [
            "chart",
            "linkage",
            "--set",
            f"file={EXAMPLES / 'chart_six_link.toml'}",
            "--set",
            "n=8",
            "--out",
            str(tmp_path),
            "--json",
        ]
    )
    data = json.loads(capsys.readouterr().out)
    assert rc == 0 and data["feasible"] == 64 and data["n"] == 8
    assert (tmp_path / "chart_six_link_chart.png").stat().st_size > 10_000
    best = data["best_on_grid"]
    # the best grid design's stroke is the linkage's own value there
    lk = load_linkage(EXAMPLES / "six_link.toml")
    design = lk(KN=best["params"]["KN"], N_guide_angle=best["params"]["N_guide_angle"])
    assert best["grid"]["N_guide_angle"] == pytest.approx(
        np.rad2deg(design.parameters["N_guide_angle"])
    )
    stroke = np.ptp(design.motion(ms.cycle(180)).sliders["N"].position)
    assert best["values"]["stroke(N)"] == pytest.approx(stroke, rel=1e-12)


@pytest.mark.parametrize(
    "options, message",
    [
        ([], "option file is required"),
        (["file=nowhere.toml"], "chart file nowhere.toml not found"),
        (["file={ex}/six_link.toml"], r"missing the \[chart\] table"),
        (["file={ex}/chart_six_link.toml", "x=XY:0:1"], "has no parameter 'XY'"),
        (["file={ex}/chart_six_link.toml", "n=many"], "option n must be an integer, got 'many'"),
        # both axes on one parameter said "40 x 40 designs" and evaluated 40
        (["file={ex}/chart_six_link.toml", "x=KN:0.06:0.2", "y=KN:0.06:0.2"], "both 'KN'"),
        (
            ["file={ex}/chart_six_link.toml", "colour=red"],
            "unknown option colour; options: file, n",
        ),
    ],
)
def test_chart_linkage_errors(options, message, capsys):
    args = ["chart", "linkage"]
    for o in options:
        args += ["--set", o.format(ex=EXAMPLES)]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert message.replace("\\", "") in err.replace("\\", "") or pytest.fail(err)
    assert err.count("\n") == 1

"""The coverage tables of the studies: valid declarations, every named test exists, the docs page
is generated from them, and each study reports its table."""

from pathlib import Path

import pytest

from mechsynth.errors import MechanismError
from mechsynth.studies.coverage import (
    STATUSES,
    Coverage,
    Item,
    declared,
    markdown_page,
    missing_tests,
)

ROOT = Path(__file__).resolve().parents[1]
COVERED = {"extreme-velocity", "nail-header", "beam-pump", "impact", "spatial-pump", "dwell"}


def test_the_studies_declare_their_coverage():
    cov = declared()
    assert COVERED <= set(cov)
    for name, c in cov.items():
        assert c.study == name
        assert len(c.items) >= 10
        assert sum(c.counts().values()) == len(c.items)


@pytest.mark.parametrize("name", sorted(COVERED))
def test_every_declared_test_exists(name):
    assert missing_tests(declared()[name], ROOT) == []


def test_missing_tests_are_found(tmp_path):
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_a.py").write_text("def test_there():\n    pass\n")
    cov = Coverage(
        "paper",
        "study",
        (
            Item("eq. (1)", "equation", "x", "reproduced", tests=("tests/test_a.py::test_there",)),
            Item("eq. (2)", "equation", "y", "erratum", tests=("tests/test_a.py::test_gone",)),
            Item("eq. (3)", "equation", "z", "reproduced", tests=("tests/test_b.py::test_x",)),
        ),
    )
    assert missing_tests(cov, tmp_path) == [
        "eq. (2): tests/test_a.py::test_gone",
        "eq. (3): tests/test_b.py::test_x",
    ]


def test_docs_page_is_generated_from_the_declarations():
    # regenerate with: python -m mechsynth.studies.coverage > docs/coverage.md
    assert (ROOT / "docs" / "coverage.md").read_text(encoding="utf-8") == markdown_page()


def test_declarations_are_checked():
    with pytest.raises(MechanismError, match="status 'fine'"):
        Item("eq. (1)", "equation", "x", "fine", tests=("t::t",))
    with pytest.raises(MechanismError, match="kind 'poem'"):
        Item("eq. (1)", "poem", "x", "reproduced", tests=("t::t",))
    with pytest.raises(MechanismError, match="names the tests"):
        Item("eq. (1)", "equation", "x", "reproduced")
    Item("Fig. 1", "figure", "missing", "not reproducible", note="the figure is missing")
    item = Item("eq. (1)", "equation", "x", "reproduced", tests=("t::t",))
    with pytest.raises(MechanismError, match="declared twice"):
        Coverage("p", "s", (item, item))
    assert set(STATUSES) >= {"reproduced", "erratum", "not reproducible"}


def test_views_of_one_declaration(tmp_path):
    c = declared()["extreme-velocity"]
    text = c.text()
    assert text.startswith("coverage of Paper 004") and "eq. (3) m0'" in text
    d = c.to_dict()
    assert d["counts"]["erratum"] >= 4 and d["items"][0]["ref"] == "Fig. 1"
    csv_text = c.to_csv()
    assert csv_text.splitlines()[0] == "ref,kind,what,status,where,tests,note"
    assert len(csv_text.strip().splitlines()) == len(c.items) + 1
    path = c.to_csv(tmp_path / c.csv_name)
    with open(path, newline="") as fh:
        assert fh.read() == csv_text
    assert "| eq. (3) m0' |" in c.markdown()


def test_attach_puts_the_table_into_a_study_result(tmp_path):
    from mechsynth.report import StudyResult

    c = declared()["nail-header"]
    r = c.attach(StudyResult("nail-header", "summary", {"x": 1}, [], []), tmp_path)
    assert r.summary.startswith("summary\n\ncoverage of Paper 003")
    assert r.data["coverage"]["study"] == "nail-header" and r.data["x"] == 1
    assert r.files == [tmp_path / "nail_header_coverage.csv"] and r.files[0].is_file()
    assert c.attach(StudyResult("n", "s", {}, [], [])).files == []


def test_extreme_velocity_study_reports_its_coverage():
    from mechsynth.studies import run_study

    r = run_study("extreme-velocity")
    assert r.data["coverage"]["study"] == "extreme-velocity"
    assert "coverage of Paper 004" in r.summary

"""What of each source paper the studies reproduce: one declaration per study, many views.

A study declares ``COVERAGE = Coverage(...)`` in its module: every numbered equation, table,
figure, finding and recommendation of its paper as an :class:`Item` with where it is reproduced,
the tests that check it and its status. The study prints the table in its summary, puts it in its
JSON data and writes it as CSV; ``docs/coverage.md`` is generated from the same declarations
(``python -m mechsynth.studies.coverage > docs/coverage.md``), and the tests check that every
named test exists and that the page is up to date, so the table stays true.

Statuses
--------
``reproduced``: computed here and agreeing with the paper (to the stated tolerance).
``erratum``: the paper's item is wrong; the correct one is computed and the error recorded.
``refuted``: a finding that does not hold when computed.
``not reproducible``: cannot be computed from what the paper gives (the note says why).
``added``: what the paper asks for or leaves open, done here (e.g. a chart it calls for).
"""

from __future__ import annotations

import ast
import csv
import importlib
import io
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import MechanismError

__all__ = [
    "STATUSES",
    "KINDS",
    "Item",
    "Coverage",
    "declared",
    "missing_tests",
    "markdown_page",
]

STATUSES = ("reproduced", "erratum", "refuted", "not reproducible", "added")
KINDS = ("equation", "table", "figure", "finding", "recommendation", "data")


@dataclass(frozen=True)
class Item:
    """One numbered element of a paper.

    Attributes
    ----------
    ref : the paper's label: ``"eq. (3)"``, ``"Table 1"``, ``"Fig. 2"``, ``"finding 1"``.
    kind : one of :data:`KINDS`.
    what : what it is, one line.
    status : one of :data:`STATUSES`.
    where : where it is reproduced (module and function, or the study's output file).
    tests : ``"tests/test_file.py::test_name"`` of every test that checks it.
    note : the tolerance, the erratum or why it is not reproducible.
    """

    ref: str
    kind: str
    what: str
    status: str
    where: str = ""
    tests: tuple[str, ...] = ()
    note: str = ""

    def __post_init__(self):
        if self.kind not in KINDS:
            raise MechanismError(f"{self.ref}: kind {self.kind!r} is not one of {KINDS}")
        if self.status not in STATUSES:
            raise MechanismError(f"{self.ref}: status {self.status!r} is not one of {STATUSES}")
        object.__setattr__(self, "tests", tuple(self.tests))
        if self.status != "not reproducible" and not self.tests:
            raise MechanismError(f"{self.ref}: a {self.status} item names the tests that check it")


@dataclass(frozen=True)
class Coverage:
    """The items of one paper covered by one study."""

    paper: str
    study: str
    items: tuple[Item, ...] = field(default_factory=tuple)

    def __post_init__(self):
        object.__setattr__(self, "items", tuple(self.items))
        refs = [i.ref for i in self.items]
        dup = sorted({r for r in refs if refs.count(r) > 1})
        if dup:
            raise MechanismError(f"coverage of {self.study}: items declared twice: {dup}")

    @property
    def csv_name(self) -> str:
        """The file name a study writes its table to: ``<study>_coverage.csv``."""
        return f"{self.study.replace('-', '_')}_coverage.csv"

    def attach(self, result, out=None):
        """Put the table into a study's ``result`` (a StudyResult): its summary, its data
        (``coverage``) and, with ``out``, the CSV file. Returns ``result``."""
        result.summary = f"{result.summary}\n\n{self.text()}"
        result.data["coverage"] = self.to_dict()
        if out is not None:
            result.files.append(self.to_csv(Path(out) / self.csv_name))
        return result

    def counts(self) -> dict[str, int]:
        """Items per status."""
        return {s: sum(i.status == s for i in self.items) for s in STATUSES}

    def to_dict(self) -> dict:
        """JSON-ready: the paper, the study, the counts and the items."""
        return {
            "paper": self.paper,
            "study": self.study,
            "counts": self.counts(),
            "items": [
                {
                    "ref": i.ref,
                    "kind": i.kind,
                    "what": i.what,
                    "status": i.status,
                    "where": i.where,
                    "tests": list(i.tests),
                    "note": i.note,
                }
                for i in self.items
            ],
        }

    def text(self) -> str:
        """The table for a study's summary: reference, status, what; notes indented below."""
        width = max(len(i.ref) for i in self.items)
        counts = ", ".join(f"{n} {s}" for s, n in self.counts().items() if n)
        lines = [f"coverage of {self.paper} ({len(self.items)} items: {counts}):"]
        for i in self.items:
            lines.append(f"  {i.ref:<{width}}  {i.status:<16}  {i.what}")
            if i.note:
                lines.append(f"  {'':<{width}}  {'':<16}  ({i.note})")
        return "\n".join(lines)

    def to_csv(self, path=None):
        """The items as CSV (tests joined by spaces): written to ``path`` or returned."""
        from ..fileio import atomic

        cols = ("ref", "kind", "what", "status", "where", "tests", "note")

        def write(fh):
            w = csv.writer(fh)
            w.writerow(cols)
            for i in self.items:
                w.writerow([i.ref, i.kind, i.what, i.status, i.where, " ".join(i.tests), i.note])

        if path is None:
            buf = io.StringIO()
            write(buf)
            return buf.getvalue()
        with atomic(path, "w", newline="") as fh:
            write(fh)
        return Path(path)

    def markdown(self) -> str:
        """A markdown section: the table with the tests named."""

        def cell(text):
            return text.replace("|", "\\|")

        lines = [
            f"## {self.paper} — `mechsynth study run {self.study}`",
            "",
            "| item | what | status | where | tests | note |",
            "|---|---|---|---|---|---|",
        ]
        for i in self.items:
            tests = "<br>".join(f"`{t.split('::')[-1]}`" for t in i.tests)
            files = sorted({t.split("::")[0].rsplit("/", 1)[-1] for t in i.tests})
            where = f"`{i.where}`" if i.where else ""
            lines.append(
                f"| {cell(i.ref)} | {cell(i.what)} | {i.status} | {cell(where)} | "
                f"{tests}{' (' + ', '.join(files) + ')' if files else ''} | {cell(i.note)} |"
            )
        return "\n".join(lines)


def declared() -> dict[str, Coverage]:
    """``{study name: Coverage}`` of every registered study that declares one."""
    from . import STUDIES

    out = {}
    for name, (module, _) in STUDIES.items():
        cov = getattr(importlib.import_module(module), "COVERAGE", None)
        if cov is not None:
            out[name] = cov
    return out


def _test_names(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}


def missing_tests(coverage: Coverage, root) -> list[str]:
    """The tests ``coverage`` names that do not exist under the project ``root``."""
    root = Path(root)
    cache: dict[str, set[str]] = {}
    missing = []
    for item in coverage.items:
        for t in item.tests:
            file, _, name = t.partition("::")
            path = root / file
            if file not in cache:
                cache[file] = _test_names(path) if path.is_file() else set()
            if name not in cache[file]:
                missing.append(f"{item.ref}: {t}")
    return missing


PAGE_HEAD = """# What the studies reproduce

Generated from the studies' declarations (`COVERAGE` in each study module, see
`mechsynth/studies/coverage.py`) by `python -m mechsynth.studies.coverage > docs/coverage.md`; a
test checks that this page is up to date and that every test it names exists. Every numbered
equation, table, figure, finding and recommendation of each paper has a row: where it is
reproduced, the tests that check it, and its status -- *reproduced*, *erratum* (the paper's item is
wrong; the correct one is computed and the error recorded), *refuted* (a finding that does not
hold), *not reproducible* (the note says why) or *added* (what the paper asks for or leaves open,
done here). Each study prints the same table in its summary, its JSON (`coverage`) and
`<study>_coverage.csv`.

Studies without a declaration yet: {missing}.
"""


def markdown_page() -> str:
    """The whole of ``docs/coverage.md``."""
    from . import STUDIES

    cov = declared()
    missing = ", ".join(f"`{n}`" for n in STUDIES if n not in cov) or "none"
    parts = [PAGE_HEAD.format(missing=missing)]
    parts += [c.markdown() + "\n" for c in cov.values()]
    return "\n".join(parts)


if __name__ == "__main__":  # pragma: no cover - a generator script
    print(markdown_page(), end="")

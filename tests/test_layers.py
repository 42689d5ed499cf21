"""The layers depend only leftwards: kinematics <- dynamics <- objectives <- synthesis <-
machines <- nomograms <- studies <- explore <- cli (docs/architecture.md). Checked on the source,
including imports inside functions."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "mechsynth"
ORDER = [
    "kinematics",
    "dynamics",
    "objectives",
    "synthesis",
    "machines",
    "nomograms",
    "studies",
    "explore",
]


def _imported_layers(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    rel = path.relative_to(PACKAGE).parts
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against the module's package
                base = list(rel[:-1])[: len(rel) - node.level]
                target = base + (node.module.split(".") if node.module else [])
            elif node.module and node.module.startswith("mechsynth"):
                target = node.module.split(".")[1:]
            else:
                continue
            names = [a.name for a in node.names]
            if not target:  # "from .. import studies"
                yield from (n for n in names if n in ORDER + ["cli"])
            else:
                yield target[0]
        elif isinstance(node, ast.Import):
            for a in node.names:
                parts = a.name.split(".")
                if parts[0] == "mechsynth" and len(parts) > 1:
                    yield parts[1]


@pytest.mark.parametrize("layer", ORDER)
def test_layer_imports_only_leftwards(layer):
    allowed = set(ORDER[: ORDER.index(layer) + 1])
    forbidden = (set(ORDER) | {"cli"}) - allowed
    bad = []
    for path in sorted((PACKAGE / layer).rglob("*.py")):
        for target in _imported_layers(path):
            if target in forbidden:
                bad.append(f"{path.relative_to(PACKAGE)} imports {target}")
    assert not bad, "; ".join(bad)

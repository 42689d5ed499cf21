"""Results of studies and charts: a summary for people, JSON data for programs, files written and
errata found in the sources. Shared by every layer that reports (studies, charts, the CLI)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ["StudyResult"]


@dataclass
class StudyResult:
    """What a study produced.

    Attributes
    ----------
    name : the study's registry name.
    summary : human-readable report (tables with published vs computed values, deviations).
    data : JSON-serializable results (what ``--json`` prints).
    files : figures and tables written to ``out``.
    errata : errors found in the source, one sentence each.
    """

    name: str
    summary: str
    data: dict[str, Any]
    files: list[Path] = field(default_factory=list)
    errata: list[str] = field(default_factory=list)

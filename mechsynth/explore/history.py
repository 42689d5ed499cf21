"""Undo and redo of the explorer's design changes, without Panel.

A :class:`History` holds snapshots (any objects: the page keeps its state and its linkage
draft); :meth:`History.record` adds one after each change, merging a run of changes with the
same ``key`` made within ``merge_s`` seconds (a slider dragged through 40 values is one step).

>>> h = History()
>>> h.record("a"); h.record("b", key="rod", now=0.0); h.record("c", key="rod", now=0.2)
>>> h.undo(), h.redo(), h.can_redo
('a', 'c', False)
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

__all__ = ["History"]


@dataclass
class History:
    """Snapshots of the design, the newest last; ``limit`` the most kept."""

    limit: int = 200
    merge_s: float = 1.0
    _past: list = field(default_factory=list)  # the current snapshot is the last
    _future: list = field(default_factory=list)
    _last_key: Any = None
    _last_t: float = -1e300

    @property
    def current(self):
        return self._past[-1] if self._past else None

    @property
    def can_undo(self) -> bool:
        return len(self._past) > 1

    @property
    def can_redo(self) -> bool:
        return bool(self._future)

    def record(self, snapshot, key=None, now: float | None = None) -> None:
        """``snapshot`` as the current design; it replaces the current one when ``key`` is
        not None, equals the previous record's key and comes within ``merge_s`` of it. Clears
        what could be redone."""
        now = time.monotonic() if now is None else now
        merge = (
            key is not None
            and key == self._last_key
            and now - self._last_t <= self.merge_s
            and len(self._past) > 1
        )
        if merge:
            self._past[-1] = snapshot
        else:
            self._past.append(snapshot)
            del self._past[: max(len(self._past) - self.limit, 0)]
        self._future.clear()
        self._last_key, self._last_t = key, now

    def undo(self):
        """The snapshot before the current one (which becomes redoable), or None."""
        if not self.can_undo:
            return None
        self._future.append(self._past.pop())
        self._last_key = None
        return self._past[-1]

    def redo(self):
        """The snapshot last undone, or None."""
        if not self._future:
            return None
        self._past.append(self._future.pop())
        self._last_key = None
        return self._past[-1]

"""Progress bars for long work (tqdm): on a terminal only, off everywhere with :func:`quiet`.

Every run that may take more than a couple of seconds (multi-start solves, sweeps, Pareto
fronts, studies) shows a bar on standard error when it runs on a terminal; nothing is printed
when the output is a file or a pipe, or inside ``with quiet():`` (the command line's
``--quiet``). Studies name their stages (:class:`Stages`).
"""

from __future__ import annotations

__all__ = ["bar", "quiet", "is_quiet", "Stages"]

_quiet = [False]


class _Quiet:
    def __init__(self, previous: bool):
        self._previous = previous

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        _quiet[0] = self._previous


def quiet(flag: bool = True) -> _Quiet:
    """Turn every progress bar off (``flag=True``) or back to automatic; in a ``with`` block
    the previous setting returns on exit."""
    previous = _quiet[0]
    _quiet[0] = bool(flag)
    return _Quiet(previous)


def is_quiet() -> bool:
    """True when progress bars are off."""
    return _quiet[0]


def bar(iterable=None, *, total=None, desc=None, enabled=None, leave=False, unit="it"):
    """A tqdm bar: shown when ``enabled`` is True, or when it is None and standard error is a
    terminal; never when :func:`quiet` is on."""
    from tqdm.auto import tqdm

    if _quiet[0] or enabled is False:
        disable = True
    else:
        disable = None if enabled is None else False
    return tqdm(iterable, total=total, desc=desc, disable=disable, leave=leave, unit=unit)


class Stages:
    """Named stages of a study as one bar: ``with Stages("nail-header", [...]) as st:
    st.next("Table 1")``; each ``next`` completes the previous stage and shows the new name."""

    def __init__(self, name: str, stages, enabled=None):
        self.name, self.stages = name, list(stages)
        self._bar = bar(total=len(self.stages), desc=name, enabled=enabled, unit="stage")
        self._started = False

    def next(self, stage: str) -> None:
        if self._started:
            self._bar.update()
        self._started = True
        self._bar.set_description_str(f"{self.name}: {stage}")

    def __enter__(self) -> Stages:
        return self

    def __exit__(self, *exc) -> None:
        if self._started:
            self._bar.update()
        self._bar.close()

"""Progress bars for long work (tqdm): on a terminal only, off everywhere with :func:`quiet`.

Every run that may take more than a couple of seconds (multi-start solves, sweeps, Pareto
fronts, studies) shows a bar on standard error when it runs on a terminal; nothing is printed
when the output is a file or a pipe, or inside ``with quiet():`` (the command line's
``--quiet``). Studies name their stages (:class:`Stages`).
"""

from __future__ import annotations

__all__ = ["bar", "quiet", "is_quiet", "observe", "Stages"]

_quiet = [False]
_observers: list = []


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


class _Observing:
    def __init__(self, callback):
        self._callback = callback

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        _observers.remove(self._callback)


def observe(callback) -> _Observing:
    """Report every bar's progress to ``callback(desc, done, total)`` (after each step), shown
    on a terminal or not: how a program other than a terminal (a web page) follows a long run.
    In a ``with`` block the callback is removed on exit.

    >>> seen = []
    >>> with observe(lambda desc, k, n: seen.append((desc, k, n))):
    ...     for _ in bar(range(2), desc="starts", enabled=False):
    ...         pass
    >>> seen
    [('starts', 0, 2), ('starts', 1, 2), ('starts', 2, 2)]
    """
    _observers.append(callback)
    return _Observing(callback)


class _Observed:
    """A tqdm bar that also tells the observers of each step."""

    def __init__(self, inner, iterable, total, desc):
        self._inner, self._iterable, self._desc = inner, iterable, desc
        self._total = total if total is not None else _length(iterable)
        self._done = 0
        self._tell()

    def _tell(self):
        for cb in list(_observers):
            cb(self._desc, self._done, self._total)

    def __iter__(self):
        for item in self._inner:
            yield item
            self._done += 1
            self._tell()

    def update(self, n=1):
        self._inner.update(n)
        self._done += n
        self._tell()

    def set_description_str(self, desc, *args, **kwargs):
        self._desc = desc
        self._inner.set_description_str(desc, *args, **kwargs)

    def __getattr__(self, name):
        return getattr(self._inner, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._inner.close()


def _length(iterable):
    try:
        return len(iterable)
    except TypeError:
        return None


class _Silent:
    """What a bar that shows nothing needs: iteration, a count, ``update`` and ``close`` (no
    tqdm import, which costs more than a small solve)."""

    disable = True

    def __init__(self, iterable, total, desc):
        self.iterable, self.total, self.desc, self.n = iterable, total, desc, 0

    def __iter__(self):
        for item in self.iterable:
            yield item
            self.n += 1

    def update(self, n=1):
        self.n += n

    def set_description_str(self, desc=None, refresh=True):
        self.desc = desc

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def bar(iterable=None, *, total=None, desc=None, enabled=None, leave=False, unit="it"):
    """A tqdm bar: shown when ``enabled`` is True, or when it is None and standard error is a
    terminal; never when :func:`quiet` is on."""
    if _quiet[0] or enabled is False:
        inner = _Silent(iterable, total, desc)
    else:
        from tqdm.auto import tqdm

        disable = None if enabled is None else False
        inner = tqdm(iterable, total=total, desc=desc, disable=disable, leave=leave, unit=unit)
    if _observers:
        return _Observed(inner, iterable, total, desc)
    return inner


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

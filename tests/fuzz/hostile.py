"""Shared pieces of the fuzz suite: hostile values and the rule every input must follow.

Every input ends in success or in a clear refusal: a :class:`mechsynth.MechanismError` (a
``ValueError``) through the API, exit code 1 with one line on stderr through the CLI. Anything
else -- another exception type, a traceback, a silent NaN in a returned result -- is a failure
of the suite. ``FUZZ_EXAMPLES`` sets how many generated cases each property draws: a quick
number in the normal run, the full number in the run marked ``slow``.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechsynth as ms

QUICK = 20
FULL = 300

#: outcome counts of every case run, by target (the README quotes the full run's totals)
COUNTS: Counter = Counter()

_numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.floats(min_value=-1e3, max_value=1e3),
    st.floats(min_value=1e-12, max_value=1e12),
    st.integers(min_value=-(10**20), max_value=10**20),
    st.sampled_from([0.0, -0.0, 1e-320, 1e300, -1e300, 1e16, 1e-16, 0.75, 1.0, 3.0]),
)

#: anything a careless or hostile caller may pass where a number is expected
hostile = st.one_of(
    _numbers,
    st.booleans(),
    st.none(),
    st.text(max_size=8),
    st.binary(max_size=4),
    st.complex_numbers(allow_nan=True, allow_infinity=True),
    st.lists(_numbers, max_size=4),
    st.lists(st.lists(_numbers, max_size=3), max_size=3),
    st.builds(np.array, st.lists(_numbers, min_size=0, max_size=4)),
    st.builds(lambda v: np.full((2, 3), v), _numbers),
    st.builds(lambda v: np.full((4, 1), v), _numbers),
    st.dictionaries(st.text(max_size=3), _numbers, max_size=2),
)

#: a number, mostly of sensible size, sometimes not
lengthish = st.one_of(
    st.floats(min_value=1e-3, max_value=10.0),
    st.floats(min_value=1e-12, max_value=1e16),
    hostile,
)


def check(target: str, fn):
    """Run ``fn``; its result must be finite where numeric, or it must raise MechanismError.
    Returns ``"ok"`` or ``"refused"``; raises AssertionError for anything else."""
    try:
        out = fn()
    except ms.MechanismError:
        COUNTS[(target, "refused")] += 1
        return "refused"
    except BaseException as exc:  # pragma: no cover - the failure the suite exists to catch
        raise AssertionError(
            f"{target}: {type(exc).__name__} instead of a MechanismError: {exc}"
        ) from exc
    _assert_finite(target, out)
    COUNTS[(target, "ok")] += 1
    return "ok"


def _assert_finite(target, out):
    if out is None:
        return
    if isinstance(out, (float, int, np.floating)):
        assert math.isfinite(float(out)), f"{target}: returned {out}"
        return
    if isinstance(out, np.ndarray) and out.dtype.kind == "f":
        assert np.all(np.isfinite(out)), f"{target}: returned non-finite values"
        return
    if isinstance(out, tuple):
        for v in out:
            _assert_finite(target, v)


def run(n, strategy, body):
    """Draw ``n`` cases of ``strategy`` (deterministically) and call ``body(*case)`` on each."""

    @settings(
        max_examples=n,
        deadline=None,
        database=None,
        derandomize=True,
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def prop(args):
        body(*args)

    prop()

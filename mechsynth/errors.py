"""Exceptions raised by mechsynth.

Both subclass the built-in :class:`ValueError`, so ``except ValueError`` keeps working in
user code that does not know about mechsynth.
"""


class MechanismError(ValueError):
    """A design that cannot be assembled or cannot move as asked.

    The message names the violated condition with its numbers, e.g.
    ``"rod (0.05 m) shorter than crank + |offset| (0.07 m): the crank cannot make a full turn"``.
    """


class SolverError(RuntimeError):
    """A solver could not be run at all (missing plugin, malformed problem).

    A solver that runs and fails or ends infeasible does *not* raise: it says so in its result.
    """

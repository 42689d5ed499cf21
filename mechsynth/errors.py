"""Exceptions raised by mechsynth.

Both subclass the built-in :class:`ValueError`, so ``except ValueError`` keeps working in
user code that does not know about mechsynth.
"""


class MechanismError(ValueError):
    """Bad input, or a design that cannot be assembled or cannot move as asked.

    Every check of mechsynth's public functions raises this (a ``ValueError``): a parameter
    that is not a finite real number, a negative length, shapes that do not broadcast, an
    unknown option, a file that does not follow its schema, a request too large for memory.

    The message names the violated condition with its numbers, e.g.
    ``"rod (0.05 m) shorter than crank + |offset| (0.07 m): the crank cannot make a full turn"``.
    """


class UsageError(MechanismError, TypeError):
    """A request that no design can answer: an output, joint or measure the model does not
    have (``peak_acceleration("slider")`` of a four-bar, ``forces.magnitude("R99")``). Unlike
    an assembly failure it does not depend on the design's dimensions, so problems report it
    when they are built rather than treat it as an infeasible point. Also a ``TypeError``, for
    code that catches the wrong kind of argument that way."""


class UnknownNameError(UsageError, KeyError):
    """A point, link or slider a motion does not have (``motion.links["nope"]``): a
    :class:`MechanismError` naming the known ones, and a ``KeyError``, so ``except KeyError``
    and ``dict.get`` keep working."""

    __str__ = BaseException.__str__  # KeyError's would quote the whole message


class SolverError(RuntimeError):
    """A solver could not be run at all (missing plugin, malformed problem).

    A solver that runs and fails or ends infeasible does *not* raise: it says so in its result.
    """

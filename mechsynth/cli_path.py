"""The ``mechsynth synthesize path`` command (registered by :mod:`mechsynth.cli`)."""

from __future__ import annotations


def add_parser(sub) -> None:
    """Add the ``path`` subcommand to the subparsers ``sub``."""

"""The ``mechsynth synthesize function`` command (registered by :mod:`mechsynth.cli`)."""

from __future__ import annotations


def add_parser(sub) -> None:
    """Add the ``function`` subcommand to the subparsers ``sub``."""

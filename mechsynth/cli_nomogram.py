"""The ``mechsynth nomogram`` command (registered by :mod:`mechsynth.cli`)."""

from __future__ import annotations


def add_parser(sub) -> None:
    """Add the ``nomogram`` subcommand to the subparsers ``sub``."""

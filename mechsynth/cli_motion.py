"""The ``mechsynth synthesize motion`` command (registered by :mod:`mechsynth.cli`)."""

from __future__ import annotations


def add_parser(sub) -> None:
    """Add the ``motion`` subcommand to the subparsers ``sub``."""

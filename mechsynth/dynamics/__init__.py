"""Forces: mass properties, loads, kinetostatics, reduced dynamics and motors."""

from .inertia import LinkInertia, com_track, kinetic_energy, reduced_inertia

__all__ = ["LinkInertia", "com_track", "kinetic_energy", "reduced_inertia"]

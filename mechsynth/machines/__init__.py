"""Named machines built from the generic layers: one home per machine.

A machine here is a domain model (its geometry, motion, forces and the analyses its engineers
ask for) composed from ``kinematics``, ``dynamics``, ``objectives`` and ``synthesis``. Studies and
the command line use machines; the generic layers never import them.
"""

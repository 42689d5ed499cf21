"""Induction motor by Kloss's formula, referred to the crank through a gear ratio.

At the motor shaft ``M = 2 M_k s s_k / (s^2 + s_k^2)`` with slip ``s = 1 - omega_m / omega_sync``.
At the crank (gear ratio ``U = omega_m / omega_crank``, efficiency ``eta``):
``M_crank(omega) = eta U M(U omega)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError

__all__ = ["InductionMotor", "LinearDrive"]


def _positive(name, value):
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise MechanismError(f"{name} must be a positive finite number, got {value}")
    return v


@dataclass(frozen=True)
class InductionMotor:
    """Induction motor on Kloss's formula, driving the crank through a gear.

    Parameters
    ----------
    breakdown_torque : M_k, breakdown (maximum) torque at the motor shaft (N m), > 0.
    critical_slip : s_k, slip at breakdown torque, 0 < s_k < 1.
    sync_speed : omega_sync, synchronous angular speed of the motor (rad/s), > 0.
    gear_ratio : U_red = omega_motor / omega_crank, > 0.
    efficiency : gear efficiency, 0 < eta <= 1.
    """

    breakdown_torque: float
    critical_slip: float
    sync_speed: float
    gear_ratio: float = 1.0
    efficiency: float = 1.0

    def __post_init__(self):
        _positive("breakdown_torque", self.breakdown_torque)
        sk = float(self.critical_slip)
        if not math.isfinite(sk) or not 0.0 < sk < 1.0:
            raise MechanismError(f"critical_slip must lie in (0, 1), got {self.critical_slip}")
        _positive("sync_speed", self.sync_speed)
        _positive("gear_ratio", self.gear_ratio)
        eta = float(self.efficiency)
        if not math.isfinite(eta) or not 0.0 < eta <= 1.0:
            raise MechanismError(f"efficiency must lie in (0, 1], got {self.efficiency}")

    @classmethod
    def from_catalogue(
        cls,
        rated_power,
        rated_speed,
        sync_speed,
        overload_ratio,
        gear_ratio=1.0,
        efficiency=1.0,
    ):
        """Build from catalogue data.

        Parameters
        ----------
        rated_power : rated shaft power P_n (W).
        rated_speed, sync_speed : rated and synchronous speeds (rad/s); rated < sync.
        overload_ratio : lambda = M_k / M_n, > 1.

        The critical slip follows from Kloss's formula at the rated point:
        ``s_k = s_n (lambda + sqrt(lambda^2 - 1))``; it must stay below 1.
        """
        p = _positive("rated_power", rated_power)
        wn = _positive("rated_speed", rated_speed)
        ws = _positive("sync_speed", sync_speed)
        lam = float(overload_ratio)
        if not math.isfinite(lam) or lam <= 1.0:
            raise MechanismError(f"overload_ratio must exceed 1, got {overload_ratio}")
        if wn >= ws:
            raise MechanismError(f"rated_speed {wn} must be below sync_speed {ws}")
        sn = 1.0 - wn / ws
        sk = sn * (lam + math.sqrt(lam * lam - 1.0))
        if sk >= 1.0:
            raise MechanismError(
                f"critical slip {sk:.4g} from rated slip {sn:.4g} and overload_ratio {lam} "
                "is not below 1"
            )
        mn = p / wn
        return cls(lam * mn, sk, ws, gear_ratio, efficiency)

    def slip(self, omega_crank):
        """Slip at crank speed ``omega_crank`` (rad/s)."""
        return 1.0 - self.gear_ratio * np.asarray(omega_crank, dtype=float) / self.sync_speed

    def shaft_torque(self, omega_motor):
        """Kloss torque at the motor shaft (N m) at motor speed ``omega_motor`` (rad/s)."""
        s = 1.0 - np.asarray(omega_motor, dtype=float) / self.sync_speed
        sk = self.critical_slip
        return 2.0 * self.breakdown_torque * s * sk / (s * s + sk * sk)

    def torque(self, omega_crank):
        """Driving torque referred to the crank (N m) at crank speed ``omega_crank`` (rad/s)."""
        return (
            self.efficiency
            * self.gear_ratio
            * self.shaft_torque(self.gear_ratio * np.asarray(omega_crank, dtype=float))
        )

    @property
    def crank_sync_speed(self):
        """Synchronous speed seen at the crank (rad/s)."""
        return self.sync_speed / self.gear_ratio


@dataclass(frozen=True)
class LinearDrive:
    """Linear drive characteristic at the crank, ``M = a - b omega`` (N m; a > 0, b > 0)."""

    a: float
    b: float

    def __post_init__(self):
        _positive("a", self.a)
        _positive("b", self.b)

    def torque(self, omega_crank):
        return self.a - self.b * np.asarray(omega_crank, dtype=float)

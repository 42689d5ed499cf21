"""The slider mass of the AB4115 nail header chosen for several nail sizes at once (paper 003,
first part: "choose, or make adjustable, the slider mass").

The paper gives the upsetting law for one nail (d = 3 mm). Other sizes are taken geometrically
similar (an assumption of this module, not the paper's): the upsetting travel ``h``, the blank
length ``l_blank`` scale with ``d`` and ``c1`` with ``d^-2``, so the yield part ``F_e0`` and the
force at the end of the blow ``F_e0 + c1 (1e3 h)^4`` both scale with ``d^2``. Each size is a load
case; the reactions are affine in the slider mass for every case, so the mass minimizing the
worst peak over all cases is one SOCP over the cases' rows stacked.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...errors import MechanismError
from ...objectives.forces import reaction_affine_map
from ...synthesis.convex import minimax_affine
from .model import NailHeader

__all__ = ["NAIL_DIAMETERS", "nail_case", "robust_slider_mass"]

#: nail diameters (mm) of the load cases; 3 mm is the paper's
NAIL_DIAMETERS = (2.0, 2.5, 3.0)
REFERENCE_D = 3.0


def nail_case(d: float, base: NailHeader | None = None) -> NailHeader:
    """The header loaded by a nail of diameter ``d`` (mm), geometrically similar to the paper's
    3 mm nail (see the module notes)."""
    base = NailHeader() if base is None else base
    if not (np.isfinite(d) and d > 0):
        raise MechanismError(f"nail diameter d must be positive and finite, got {d} mm")
    k = d / REFERENCE_D
    return replace(base, d=float(d), h=base.h * k, l_blank=base.l_blank * k, c1=base.c1 / k**2)


def _map(case: NailHeader, joints, phi):
    def design(x):
        return replace(case, m3=float(x[0]))

    return reaction_affine_map(design, joints, [float(case.m3)], phi)


def _peak(A, b, m):
    return float(np.max(np.linalg.norm(A @ np.atleast_1d(m) + b, axis=-1)))


def _checked(A, b, rows, bounds):
    """The SOCP optimum of the peak of ``A m + b`` over ``m`` in ``bounds``, its 1-D check (a
    bounded scalar search on the exact, convex peak) and whether the two agree (to 1e-4 kg and
    1e-6 of the peak): the certificate, also when the conic solver calls its answer
    inaccurate."""
    from scipy.optimize import minimize_scalar  # deferred: heavy

    res = minimax_affine(A, b, angles=rows, norm="euclidean", bounds=[bounds], names=["m3"])
    chk = minimize_scalar(
        lambda m: _peak(A, b, m), bounds=bounds, method="bounded", options={"xatol": 1e-9}
    )
    agree = (
        res.x is not None
        and abs(float(res.x[0]) - float(chk.x)) <= 1e-4
        and abs(res.value - float(chk.fun)) <= 1e-6 * abs(float(chk.fun))
    )
    return res, float(chk.x), float(chk.fun), bool(agree)


def robust_slider_mass(
    diameters=NAIL_DIAMETERS,
    joints=("R10", "R21", "R32"),
    phi=None,
    bounds=(1.0, 200.0),
    scan=None,
):
    """The slider mass minimizing the worst peak reaction at ``joints`` over every nail size in
    ``diameters`` (mm), and each size's own optimum (what an adjustable slider would take).

    Returns a dict: ``robust`` and ``compromise`` (dicts: ``mass``, ``value``, ``status`` of the
    conic solver, the scalar check ``check_mass``, ``check_value`` and ``certified``: both
    agree; ``value`` is the worst peak in N for ``robust``, the worst ratio to the cases' own
    optima for ``compromise``), ``cases`` (one dict per size: ``d_mm``,
    ``peak_upsetting_force``, ``own_mass``, ``own_peak``, ``status``, ``check_mass``,
    ``certified``, ``peak_at_15kg``, ``peak_at_robust``, ``peak_at_compromise`` and, with
    ``scan`` (slider masses, kg), ``scan_peaks``: the peak at each of them)."""
    from ...units import cycle

    phi = -cycle(1440) if phi is None else phi
    if len(diameters) == 0:
        raise MechanismError("diameters: give at least one nail size")
    maps, cases = [], []
    for d in diameters:
        case = nail_case(d)
        A, b, rows = _map(case, joints, phi)
        maps.append((A, b, rows))
        own, check_mass, _, certified = _checked(A, b, rows, bounds)
        cases.append(
            {
                "d_mm": float(d),
                "peak_upsetting_force": float(
                    case.upsetting(case.motion(np.array([0.0]), speed=case.omega))[0]
                ),
                "own_mass": None if own.x is None else float(own.x[0]),
                "own_peak": float(own.value),
                "status": own.status,
                "check_mass": check_mass,
                "certified": certified,
                "peak_at_15kg": _peak(A, b, 15.0),
            }
        )
        if scan is not None:
            y = A[None, :, :, 0] * np.asarray(scan, dtype=float)[:, None, None] + b[None]
            cases[-1]["scan_peaks"] = np.max(np.linalg.norm(y, axis=-1), axis=1)
    out = {"cases": cases, "joints": list(joints), "diameters_mm": [float(d) for d in diameters]}
    own = [c["own_peak"] for c in cases]
    for key, weights in (("robust", [1.0] * len(maps)), ("compromise", own)):
        A = np.concatenate([m[0] / w for m, w in zip(maps, weights)])
        b = np.concatenate([m[1] / w for m, w in zip(maps, weights)])
        rows = np.concatenate([m[2] for m in maps])
        res, check_mass, check_value, certified = _checked(A, b, rows, bounds)
        out[key] = {
            "mass": None if res.x is None else float(res.x[0]),
            "value": float(res.value),
            "status": res.status,
            "check_mass": check_mass,
            "check_value": check_value,
            "certified": certified,
        }
        mass = check_mass if res.x is None else float(res.x[0])
        for c, (Ac, bc, _) in zip(cases, maps):
            c[f"peak_at_{key}"] = _peak(Ac, bc, mass)
    return out

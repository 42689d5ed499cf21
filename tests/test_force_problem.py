"""Force measures in the Problem API: the slider mass of the nail header minimizing the peak R32
by certified IPOPT (CasADi kinetostatics) equals the exact cvxpy minimax of the study."""

import pytest

import mechsynth as ms
from mechsynth.machines.nail_header import NailHeader
from mechsynth.objectives.forces import peak_reaction
from mechsynth.studies.nail_header import _minimax


def test_ipopt_slider_mass_matches_the_convex_minimax():
    prob = ms.Problem(NailHeader, variables={"m3": (1.0, 200.0)}, speed=-ms.rpm(600), angles=48)
    prob.minimize(peak_reaction("R32"))
    res = prob.solve(starts=2)
    assert res.success, res.message
    # the study's convex minimax over 1440 angles (its "optimal slider mass" stage alone)
    study = _minimax(("R32",), ms.cycle(1440), with_cw=False)
    assert study.status == "optimal"
    assert res.design.m3 == pytest.approx(study.x[0], rel=2e-3)
    assert res.value == pytest.approx(study.value, rel=1e-5)

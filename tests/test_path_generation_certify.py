"""Measure constraints of path generation certified by the library's certifier
(path_measures.certify_constraints / certified)."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.synthesis.path_cases import exact_case
from mechsynth.synthesis.path_generation import evaluated
from mechsynth.synthesis.path_measures import certified, certify_constraints


def _design():
    t, d, ang = exact_case()
    return evaluated(d, "open", ang, t)


def test_certificate_is_the_true_peak_over_the_continuous_angle():
    sol = _design()
    lk = sol.linkage
    dense = ob.max_pressure_angle().evaluate(lk, ms.cycle(100_000))
    acc = ob.peak_acceleration("P").evaluate(lk, ms.cycle(100_000), speed=10.0)
    cons = [ob.max_pressure_angle() <= dense * 1.01, ob.peak_acceleration("P") <= 0.99 * acc]
    pa, pk = certify_constraints(cons, lk, 10.0)
    # the certifier's peak is at least every grid value and within round-off of the densest
    assert pa.value >= dense - 1e-12 and pa.value == pytest.approx(dense, rel=1e-9)
    assert pk.value >= acc - 1e-9 and pk.value == pytest.approx(acc, rel=1e-8)
    assert pa.holds and not pk.holds
    # at the angle it names, the measure's samples reach the value
    a = np.array(pk.angles)
    samples = ob.peak_acceleration("P").bind(lk).samples(lk, lk.motion(a, speed=10.0))
    assert np.max(samples) == pytest.approx(pk.value, rel=1e-12)
    assert "BROKEN" in str(pk) and "holds" in str(pa)
    assert pk.as_dict()["holds"] is False


def test_a_design_the_certifier_rejects_is_dropped_with_the_reason():
    sol = _design()
    acc = ob.peak_acceleration("P").evaluate(sol.linkage, ms.cycle(3600), speed=10.0)
    kept, why = certified([sol], [ob.peak_acceleration("P") <= 0.99 * acc], 10.0)
    assert kept == [] and why.startswith("certifier: peak_acceleration(P)")
    kept, why = certified([sol], [ob.peak_acceleration("P") <= 1.01 * acc], 10.0)
    assert why == "" and kept[0].certificate[0].holds and kept[0].error == sol.error
    assert certified([sol], (), None) == ([sol], "")


@pytest.mark.slow
def test_general_linkage_solutions_are_certified():
    six = (
        ms.Linkage(ground={"O": (0, 0), "D": (1.0, 0.1), "E": (0.2, 1.2)})
        .crank("A", about="O", length=0.25)
        .rrr("B", ("A", 0.9), ("D", 0.7))
        .attach("C", on=("A", "B"), along=0.4, left=0.3)
        .rrr("F", ("C", 0.8), ("E", 0.7))
        .attach("P", on=("C", "F"), along=0.5, left=-0.2)
        .with_output("P")
    )
    phi = np.array([0.2, 0.9, 1.6, 2.4, 3.1, 3.9, 4.6, 5.3, 5.9])
    q = six.motion(phi).points["P"]
    targets = np.column_stack([q.x, q.y])
    cap = ob.peak_acceleration("P").evaluate(six, ms.cycle(3600))
    res = ms.path_generation(targets, mechanism=six, trace="P", starts=1, timing="prescribed",
                             angles=phi, variables={"CF": (0.5, 1.1), "EF": (0.4, 1.0)},
                             constraints=[ob.peak_acceleration("P") <= 1.05 * cap])  # fmt: skip
    assert res.success
    (cert,) = res.best.certificate
    assert cert.holds and cert.value <= 1.05 * cap * (1 + 1e-6)

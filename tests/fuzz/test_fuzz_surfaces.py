"""Fuzz the surfaces added after the first fuzz suite: the Linkage builder and its TOML files,
the impact machine, the spatial drive. Same rule as ``test_fuzz_api``: each call succeeds with
finite numbers or refuses with a MechanismError -- never another exception, never a NaN."""

import numpy as np
import pytest
from hostile import FULL, QUICK, check, hostile, lengthish
from hostile import run as _run
from hypothesis import strategies as st

import mechsynth as ms
from mechsynth.machines.impact.impact import Tool, newton_impact
from mechsynth.synthesis.linkage_file import linkage_from_data

SIZES = [pytest.param(QUICK, id="quick"), pytest.param(FULL, id="full", marks=pytest.mark.slow)]

names = st.one_of(st.sampled_from(["A", "B", "O", "D", "K", "AB", ""]), hostile)
branches = st.one_of(st.sampled_from([1, -1]), hostile)




@pytest.mark.parametrize("n", SIZES)
def test_linkage_builder(n):
    def body(ground, crank, l1, l2, point, branch, links, on):
        def build():
            lk = ms.Linkage(ground=ground).crank("A", about="O", length=crank)
            lk = lk.rrr(point, ("A", l1), ("D", l2), branch=branch, links=links)
            lk = lk.attach("K", on=on, along=0.01)
            m = lk.motion(ms.cycle(16))
            return m.points["K"].x

        check("Linkage builder", build)

    _run(
        n,
        st.tuples(
            st.one_of(*[st.just({"O": (0, 0), "D": (0.1, 0)})] * 3, hostile),
            st.one_of(st.just(0.02), st.just(0.02), lengthish),
            st.one_of(st.just(0.1), st.just(0.1), lengthish),
            st.one_of(st.just(0.09), st.just(0.09), lengthish),
            st.one_of(st.just("B"), st.just("B"), names),
            branches,
            st.one_of(st.none(), st.just(("AB1", "DB1")), hostile),
            st.one_of(st.just(("D", "B")), st.just(("A", "A")), names),
        ),
        body,
    )


_quantities = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-10, 10),
    st.booleans(),
    st.sampled_from(["30 mm", "30 deg", "0.1 m", "1 rpm", "x", "", "1e400 mm", "-5 mm"]),
    st.lists(st.floats(-1, 1), max_size=3),
)


@pytest.mark.parametrize("n", SIZES)
def test_linkage_tables(n):
    def body(d_x, length, phase, l1, branch):
        data = {
            "linkage": {"name": "fuzz"},
            "ground": {"O": [0, 0], "D": [d_x, 0]},
            "group": [
                {"type": "crank", "point": "A", "about": "O", "length": length, "phase": phase},
                {"type": "rrr", "point": "B", "first": ["A", l1], "second": ["D", "80 mm"],
                 "branch": branch},  # fmt: skip
            ],
        }
        def build():
            return linkage_from_data(data, "f.toml").motion(ms.cycle(8)).points["B"].y

        check("linkage tables", build)

    def q(sensible):  # mostly a buildable design, the rest hostile
        return st.one_of(st.just(sensible), st.just(sensible), _quantities)

    _run(
        n,
        st.tuples(q("100 mm"), q("20 mm"), q("10 deg"), q("100 mm"), st.one_of(branches, q(1))),
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_impact_machine_and_blow(n):
    lk = ms.six_link()

    def body(speed, gear, flywheel, mass, e, v):
        def build():
            tool = Tool(mass=mass, restitution=e)
            r = newton_impact(2.0, v, tool)
            m = ms.ImpactMachine(lk, tool=tool, speed_rpm=speed, gear_ratio=gear, flywheel=flywheel)
            return (m.drive_inertia(), m.omega, *(np.ravel(x) for x in r.values()))

        check("impact machine", build)

    _run(
        n,
        st.tuples(
            st.one_of(st.floats(100, 3000), hostile),
            st.one_of(st.none(), st.floats(1, 50), hostile),
            st.one_of(st.floats(0, 1), hostile),
            st.one_of(st.floats(0.5, 5), hostile),
            st.one_of(st.floats(0, 1), hostile),
            st.one_of(st.floats(0, 10), hostile),
        ),
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_spatial_drive(n):
    unit = ms.BeamPumpingUnit.from_api(
        A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in"
    )
    phi = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)

    def body(spacing, width, name, value):
        def build():
            s = ms.SpatialPumpingUnit.from_planar(unit, spacing, width, **{name: value})
            return s.motion(phi).polished_rod.position

        check("spatial drive", build)

    _run(
        n,
        st.tuples(
            st.one_of(st.floats(0.8, 1.5), hostile),
            st.one_of(st.none(), st.floats(0.8, 1.5), hostile),
            st.sampled_from(["phase_mismatch", "crank_difference", "pitman_difference",
                             "shaft_tilt", "beam_skew", "equalizer_offset"]),  # fmt: skip
            st.one_of(st.floats(-0.05, 0.05), st.floats(-3, 3), hostile),
        ),
        body,
    )

"""Fuzz the API: constructors, motion arguments, batch kernels, Problem and solve options,
sweeps, loads and problem files with generated hostile values. Each must succeed with finite
numbers or refuse with a MechanismError -- never another exception, never a silent NaN.

The quick run draws ``QUICK`` cases per property; ``pytest -m slow tests/fuzz`` draws ``FULL``.
"""

import numpy as np
import pytest
from hostile import FULL, QUICK, check, hostile, lengthish
from hostile import run as _run
from hypothesis import strategies as st

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.dynamics.loads import Gravity, TabulatedLoad, TorsionSpring
from mechsynth.kinematics.compiled import four_bar_batch, slider_crank_batch
from mechsynth.synthesis.charts import sweep
from mechsynth.synthesis.problem_file import load_problem

SIZES = [pytest.param(QUICK, id="quick"), pytest.param(FULL, id="full", marks=pytest.mark.slow)]




@pytest.mark.parametrize("n", SIZES)
def test_slider_crank_constructor_and_properties(n):
    def body(a, b, e):
        def build():
            sc = ms.SliderCrank(crank=a, rod=b, offset=e)
            if np.ndim(sc.crank) or np.ndim(sc.rod) or np.ndim(sc.offset):
                return None
            return (sc.stroke, sc.time_ratio, *sc.dead_centres, *sc.dead_centre_positions)

        check("SliderCrank", build)

    _run(n, st.tuples(lengthish, lengthish, st.one_of(st.floats(-1, 1), hostile)), body)


@pytest.mark.parametrize("n", SIZES)
def test_four_bar_constructor_and_properties(n):
    def body(a, b, c, d, branch, full_turn):
        def build():
            fb = ms.FourBar(crank=a, coupler=b, rocker=c, ground=d, branch=branch,
                            full_turn=full_turn)  # fmt: skip
            return fb.grashof_margin

        check("FourBar", build)

    _run(
        n,
        st.tuples(
            lengthish,
            lengthish,
            lengthish,
            lengthish,
            st.one_of(st.sampled_from(["open", "crossed"]), hostile),
            st.one_of(st.booleans(), hostile),
        ),  # fmt: skip
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_motion_arguments(n):
    sc = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01)
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)

    def body(phi, speed, eps):
        for mech in (sc, fb):

            def move(mech=mech):
                m = mech.motion(phi, speed=speed, epsilon=eps)
                return np.asarray(m.links["crank"].omega, dtype=float)

            check(f"{type(mech).__name__}.motion", move)

    _run(
        n,
        st.tuples(
            st.one_of(st.builds(ms.cycle, st.integers(2, 50)), hostile),
            st.one_of(st.none(), st.floats(-100, 100), hostile),
            st.one_of(st.just(0.0), hostile),
        ),
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_batch_kernels(n):
    def body(a, phi, speed):
        check(
            "slider_crank_batch",
            lambda: slider_crank_batch(a, 0.3, 0.0, phi, speed=speed).acceleration,
        )
        check(
            "four_bar_batch",
            lambda: four_bar_batch(a, 4.3, 3.0, 5.2, phi, speed=speed).rocker_omega,
        )

    _run(
        n,
        st.tuples(
            st.one_of(st.floats(0.01, 0.1), hostile),
            st.one_of(st.builds(ms.cycle, st.integers(2, 30)), hostile),
            st.one_of(st.none(), st.floats(-10, 10), hostile),
        ),
        body,
    )


def _problem_args():
    bound = st.one_of(st.floats(-1, 1), hostile)
    return st.fixed_dictionaries(
        {},
        optional={
            "variables": st.one_of(
                st.fixed_dictionaries({"crank": st.tuples(bound, bound)}),
                hostile,
            ),
            "speed": st.one_of(st.floats(-100, 100), hostile),
            "angles": st.one_of(st.integers(-5, 100), hostile),
            "tol": st.one_of(st.floats(-1, 1), hostile),
            "feasibility_margin": hostile,
            "fixed": st.one_of(st.fixed_dictionaries({"rod": lengthish}), hostile),
        },
    )


@pytest.mark.parametrize("n", SIZES)
def test_problem_construction(n):
    def body(kwargs):
        args = {"variables": {"crank": (0.01, 0.1)}, "fixed": {"rod": 0.3}}
        args.update(kwargs)
        check("Problem", lambda: ms.Problem(ms.SliderCrank, **args) and None)

    _run(n, st.tuples(_problem_args()), body)


@pytest.mark.parametrize("n", SIZES)
def test_solve_options_are_refused_before_any_work(n):
    prob = ms.Problem(ms.SliderCrank, variables={"crank": (0.02, 0.1)}, fixed={"rod": 0.3})
    prob.minimize(ob.peak_acceleration("slider"))

    def body(kwargs):
        def solve():
            # only bad options reach the solver here: valid ones would solve (slow)
            try:
                from mechsynth.synthesis.solvers import _check_options

                _check_options(prob, kwargs.get("method", "ipopt"), kwargs.get("starts", 1),
                               kwargs.get("seed", 0), kwargs.get("rtol", 1e-9),
                               kwargs.get("max_rounds", 12), kwargs.get("n_dense", 2048),
                               kwargs.get("options"), kwargs.get("x0"), None)  # fmt: skip
            except ms.MechanismError:
                raise
            return None

        check("Problem.solve options", solve)

    _run(
        n,
        st.tuples(
            st.fixed_dictionaries(
                {},
                optional={
                    "starts": hostile,
                    "seed": hostile,
                    "rtol": hostile,
                    "max_rounds": hostile,
                    "n_dense": hostile,
                    "x0": st.one_of(hostile, st.fixed_dictionaries({"crank": hostile})),
                    "options": st.one_of(
                        st.none(),
                        st.dictionaries(
                            st.sampled_from(["max_iter", "tol", "foo", "mu_strategy"]),
                            st.one_of(st.integers(-5, 50), st.text(max_size=4), hostile),
                            max_size=2,
                        ),
                    ),
                },
            )
        ),
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_sweep(n):
    def body(axis, angles, chunk):
        check(
            "sweep",
            lambda: (
                sweep(
                    ms.SliderCrank,
                    {"crank": axis},
                    {"stroke": ob.stroke("slider")},
                    fixed={"rod": 0.3},
                    angles=angles,
                    chunk=chunk,
                    progress=False,
                )
                .values["stroke"]
                .compressed()
            ),
        )

    _run(
        n,
        st.tuples(
            st.one_of(st.lists(st.floats(0.01, 0.2), min_size=1, max_size=4), hostile),
            st.one_of(st.integers(2, 40), hostile),
            st.one_of(st.none(), st.integers(1, 10), hostile),
        ),
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_loads(n):
    def body(g, tilt, x, y, preload):
        check("Gravity", lambda: Gravity(g, tilt) and None)
        check("TabulatedLoad", lambda: TabulatedLoad(x, y, period=2 * np.pi) and None)
        check("TorsionSpring", lambda: TorsionSpring("rod", "rod", preload, 1.0, 0.0) and None)

    _run(
        n,
        st.tuples(
            st.one_of(st.floats(0, 20), hostile),
            hostile,
            st.one_of(st.just([0.0, 1.0, 2.0]), hostile),
            st.one_of(st.just([1.0, 2.0, 3.0]), hostile),
            hostile,
        ),
        body,
    )


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        if v != v:
            return "nan"
        if v in (float("inf"), float("-inf")):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return '"?"'


_file_values = st.one_of(
    st.integers(-10, 10**10),
    st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(),
    st.text(max_size=10).filter(lambda t: all(c.isprintable() for c in t)),
    st.sampled_from(["600 rpm", "600 m", "5 deg", "0.1 mm", "1e400", "slider-crank", "x"]),
    st.lists(st.one_of(st.floats(-1, 1), st.text(max_size=3)), max_size=3),
)


@pytest.mark.parametrize("n", SIZES)
def test_problem_files(tmp_path, n):
    keys = ["mechanism", "minimize", "maximize", "constraints", "speed", "method", "starts",
            "seed", "angles", "title", "bogus"]  # fmt: skip

    def body(top, variables):
        lines = [f"{k} = {_toml_value(v)}" for k, v in top.items()]
        lines.append("[variables]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in variables.items()]
        path = tmp_path / "p.toml"
        path.write_text("\n".join(lines) + "\n")
        check("problem file", lambda: load_problem(path) and None)

    _run(
        n,
        st.tuples(
            st.dictionaries(st.sampled_from(keys), _file_values, max_size=6).map(
                lambda d: {"mechanism": "slider-crank", "minimize": "stroke(slider)", **d}
            ),
            st.dictionaries(
                st.sampled_from(["crank", "rod", "offset", "x"]), _file_values, max_size=3
            ),  # fmt: skip
        ),
        body,
    )


@pytest.mark.parametrize("n", SIZES)
def test_path_generation_arguments(n):
    def body(a, b, c):
        check(
            "path_generation",
            lambda: ms.path_generation(
                [(0, 0), (1, 0.2), (2, 0), (1, -0.6)],
                starts=1,
                min_transmission=a,
                time_limit=b,
                feasibility_margin=c,
            ).error,
        )

    _run(n, st.tuples(hostile, hostile, hostile), body)


@pytest.mark.parametrize("n", SIZES)
def test_path_bound_arguments(n):
    def body(a, b, c, d):
        check(
            "path_bound",
            lambda: ms.path_bound(
                [(0, 0), (1, 0.2), (2, 0), (1, -0.6)],
                [0.0, 1.0, 2.0, a],
                max_boxes=b,
                time_limit=0.5,
                rtol=c,
                best=d,
            ).lower,
        )

    angle = st.one_of(st.floats(2.5, 6.0), hostile)
    boxes = st.one_of(st.integers(1, 300), hostile)
    rtol = st.one_of(st.floats(1e-4, 0.5), hostile)
    best = st.one_of(st.none(), st.floats(0.0, 2.0), hostile)
    _run(n, st.tuples(angle, boxes, rtol, best), body)

"""Fuzz the precision-synthesis surfaces added last: RP dyads (``Burmester.rp_point``,
``rp_dyads``, their pairing) and the function-generator problem files. Same rule as
``test_fuzz_api``: success with finite numbers or a MechanismError, nothing else."""

import numpy as np
import pytest
from hostile import FULL, QUICK, check, hostile
from hostile import run as _run
from hypothesis import strategies as st

import mechsynth as ms
import mechsynth.synthesis.function_problem  # noqa: F401  (registers the file mechanism)
from mechsynth.synthesis.motion_generation import pair
from mechsynth.synthesis.problem_file import load_problem

SIZES = [pytest.param(QUICK, id="quick"), pytest.param(FULL, id="full", marks=pytest.mark.slow)]

_pose = st.tuples(
    st.floats(-5, 5), st.floats(-5, 5), st.floats(-3.2, 3.2)
)  # fmt: skip
_valid = st.lists(_pose, min_size=3, max_size=5, unique_by=lambda p: (p[0], p[1]))
_poses = st.one_of(_valid, _valid, _valid, hostile)


@pytest.mark.parametrize("n", SIZES)
def test_rp_dyads(n):
    def body(poses, angle):
        def rp():
            bm = ms.burmester(poses)
            if bm.n == 3:
                d = bm.rp_point(angle)
                return [*d.centre, d.line_angle, d.residual]
            out = []
            for d in bm.rp_dyads():
                out += [*d.centre, d.line_angle]
                for c in bm.points if bm.n == 5 else ():
                    if c.kind == "RR":
                        out.append(pair(bm.poses, c, d).min_transmission)
            return out

        check("RP dyads", rp)

    _run(n, st.tuples(_poses, st.one_of(st.floats(-7, 7), hostile)), body)


_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-10, 10),
    st.booleans(),
    st.sampled_from(["30 deg", "0.1 m", "x**2", "log10(x)", "", "six-bar", "crossed", "1e400"]),
    st.lists(st.floats(-2, 2), max_size=3),
)


def _toml(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    if isinstance(v, float) and not np.isfinite(v):
        return "nan" if np.isnan(v) else ("inf" if v > 0 else "-inf")
    return repr(v)


@pytest.mark.parametrize("n", SIZES)
def test_function_generator_files(tmp_path, n):
    base = {"y": "x**2", "x": [0, 1], "input_range": "90 deg", "output_range": "90 deg"}
    keys = ["y", "x", "input_range", "output_range", "mechanism", "branch", "bogus"]

    def body(function, crank):
        lines = ['mechanism = "function-generator"', 'minimize = "structural_error"',
                 "[function]"]  # fmt: skip
        lines += [f"{k} = {_toml(v)}" for k, v in {**base, **function}.items()]
        lines += ["[variables]", f"crank = {_toml(crank)}", "[fixed]", "coupler = 2.0"]
        lines += ["rocker = 1.0", "ground = 2.0", 'phi0 = "140 deg"', 'psi0 = "245 deg"']
        path = tmp_path / "f.toml"
        path.write_text("\n".join(lines) + "\n")
        check("function-generator file", lambda: load_problem(path) and None)

    _run(
        n,
        st.tuples(
            st.dictionaries(st.sampled_from(keys), _values, max_size=2),
            st.one_of(st.just([0.1, 1.0]), _values),
        ),
        body,
    )

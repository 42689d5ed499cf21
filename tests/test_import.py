"""``import mechsynth`` is light: the heavy libraries load on first use, never at import.

Each check runs in a fresh interpreter (``sys.modules`` of this test process already holds
everything), from the checkout's root.
"""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ["scipy", "cvxpy", "casadi", "numba", "matplotlib", "tqdm", "sympy"]


def _loaded(code: str) -> list[str]:
    """The heavy top-level modules in ``sys.modules`` after running ``code`` in a fresh
    interpreter."""
    probe = f"{code}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))"
    out = subprocess.run(
        [sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    modules = set(json.loads(out.strip().splitlines()[-1]))
    return sorted(m for m in modules if m.split(".")[0] in HEAVY)


def _last_json(code: str):
    """The JSON that ``code`` prints last, run in a fresh interpreter."""
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_package_import_loads_no_heavy_module():
    assert _loaded("import mechsynth") == []


@pytest.mark.parametrize(
    "code",
    [
        "import mechsynth as ms; ms.SliderCrank(0.07, 0.24, 0.01).motion(ms.cycle(36))",
        "import mechsynth as ms; ms.FourBar(1.0, 4.3, 3.0, 5.2).motion(ms.cycle(36))",
        "import mechsynth.objectives, mechsynth.dynamics",
        "import mechsynth.synthesis, mechsynth.machines.pumping_unit, mechsynth.machines.impact",
    ],
)
def test_models_and_layers_load_no_integrator_solver_or_plotting(code):
    # scipy.integrate (0.4 s), the solvers' and the plotting libraries load where they are used
    bad = {"scipy.integrate", "cvxpy", "casadi", "numba", "matplotlib"}
    assert [m for m in _loaded(code) if m in bad or m.split(".")[0] in bad] == []


def test_public_names_resolve_lazily():
    code = (
        "import mechsynth as ms, json\n"
        "missing = [n for n in ms.__all__ if getattr(ms, n, None) is None]\n"
        "print(json.dumps(missing))\n"
    )
    assert _last_json(code) == []
    import mechsynth as ms

    assert set(ms.__all__) <= set(dir(ms))
    with pytest.raises(AttributeError, match="no attribute 'nonesuch'"):
        ms.nonesuch  # noqa: B018


def test_registries_fill_on_demand_without_the_package_api():
    # a problem file naming a machine, and a linkage's force model, work when only the layer
    # that reads them was imported (the machines and the forces layer register on a miss)
    code = (
        "from mechsynth.synthesis.problem_file import load_problem\n"
        "spec = load_problem('examples/optimize_beam_pump.toml')\n"
        "from mechsynth.kinematics import Linkage\n"
        "lk = Linkage(ground={'O': (0, 0)}).crank('A', about='O', length=0.05)"
        ".rrp('B', ('A', 0.2), guide=((0, 0), 0.0))\n"
        "fm = lk.force_model({'AB': (1.0, (0.1, 0.0), 0.01)})\n"
        "print(type(spec).__name__, type(fm).__name__)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["ProblemSpec", "ForceModel"]


def test_a_certified_solve_loads_only_casadi_and_scipy_core():
    # scipy.stats (0.6 s, for the Sobol starts), scipy.optimize (0.4 s, for the certifier's 1-D
    # search) and tqdm (for a bar that is off) once made a solve in a new interpreter take 0.76 s
    code = (
        "import mechsynth as ms\n"
        "from mechsynth import objectives as ob\n"
        "prob = ms.Problem(ms.FourBar, variables={'crank': (0.05, 0.5), 'coupler': (0.3, 2.0),"
        " 'rocker': (0.3, 1.5)}, fixed={'ground': 1.0})\n"
        "prob.maximize(ob.min_transmission_angle())\n"
        "prob.subject_to(ob.swing_angle('rocker') == ms.deg(40), ob.time_ratio() == 1.0)\n"
        "assert prob.solve(starts=2, progress=False).success\n"
    )
    loaded = _loaded(code)
    assert "casadi" in loaded
    bad = ("scipy.stats", "scipy.optimize", "scipy.integrate", "tqdm", "numba", "matplotlib")
    assert [m for m in loaded if m.startswith(bad)] == []


def test_the_synthesis_layer_loads_charts_convex_and_pareto_on_first_use():
    # a solve needs the problem, its result and the solvers, not the charts' file formats
    code = (
        "import json, sys\n"
        "import mechsynth.synthesis as syn\n"
        "before = sorted(m for m in sys.modules if m.startswith('mechsynth.synthesis.'))\n"
        "from mechsynth.synthesis import sweep, minimax_cycle, pareto_front, load_linkage\n"
        "from mechsynth.synthesis import charts, convex, pareto, linkage_file\n"
        "ok = [sweep is charts.sweep, minimax_cycle is convex.minimax_cycle,\n"
        "      pareto_front is pareto.pareto_front, load_linkage is linkage_file.load_linkage,\n"
        "      set(syn.__all__) <= set(dir(syn))]\n"
        "print(json.dumps([before, ok]))\n"
    )
    before, ok = _last_json(code)
    assert not {"charts", "convex", "pareto", "linkage_file"} & {m.split(".")[-1] for m in before}
    assert ok == [True] * 5
    import mechsynth.synthesis as syn

    with pytest.raises(AttributeError, match="no attribute 'nonesuch'"):
        syn.nonesuch  # noqa: B018


def test_the_force_measures_load_the_dynamics_layer_on_first_use():
    code = (
        "import json, sys\n"
        "from mechsynth import objectives as ob\n"
        "before = [m for m in sys.modules if m.startswith('mechsynth.dynamics')]\n"
        "from mechsynth.objectives import forces\n"
        "ok = [ob.peak_torque is forces.peak_torque, ob.rms_torque is forces.rms_torque,\n"
        "      set(ob.__all__) <= set(dir(ob))]\n"
        "print(json.dumps([before, ok]))\n"
    )
    before, ok = _last_json(code)
    assert before == [] and ok == [True] * 3
    from mechsynth import objectives as ob

    with pytest.raises(AttributeError, match="no attribute 'nonesuch'"):
        ob.nonesuch  # noqa: B018

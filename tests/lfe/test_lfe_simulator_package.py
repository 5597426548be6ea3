"""The simulator as a package: its public names, its modules, and what its code may call."""

import ast
from pathlib import Path

import pytest

import lfe
import lfe.simulator
from lfe.simulator import config

LFE = Path(lfe.__file__).parent
SIMULATOR = LFE / "simulator"
MODULES = sorted(SIMULATOR.glob("*.py"))


def test_public_names_still_work():
    from lfe import ScenarioConfig, simulate_scenario  # noqa: F401 - the import is the test
    from lfe.simulator import ScenarioConfig as Config

    assert lfe.simulate_scenario is lfe.simulator.simulate_scenario
    assert lfe.ScenarioConfig is Config is config.ScenarioConfig
    assert lfe.simulator.__all__ == ["ScenarioConfig", "simulate_scenario"]
    for name in lfe.__all__:
        assert getattr(lfe, name) is not None


def test_the_package_has_one_module_per_job():
    names = {p.stem for p in MODULES}
    assert {"config", "_world", "_tactics", "_weapons", "_geometry", "_engine",
            "_output"} <= names
    for path in MODULES:
        tree = ast.parse(path.read_text(encoding="utf-8"))
        assert ast.get_docstring(tree), path.name
        assert len(path.read_text(encoding="utf-8").splitlines()) <= 500, path.name


# Functions whose last bit depends on the CPU or the platform's libm (or whose summation order
# is numpy's choice): the missions and the labels must not go through them.
FORBIDDEN = {
    "np": {"sin", "cos", "tan", "arcsin", "arccos", "arctan", "arctan2", "hypot", "exp", "log",
           "log2", "log10", "power", "sinh", "cosh", "tanh", "mean", "sum", "linspace",
           "average", "dot", "matmul", "einsum"},
    "math": {"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "hypot", "exp", "log",
             "log2", "log10", "pow", "dist", "radians", "degrees", "fsum", "sinh", "cosh",
             "tanh"},
}
# Random draws only through lfe.draws (RandomState's uniform and normal are not safe).
FORBIDDEN_METHODS = {"normal", "uniform", "standard_normal", "exponential", "gamma", "beta"}


def _calls(path):
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            yield ast.unparse(node.func.value), node.func.attr, node


@pytest.mark.parametrize("path", [*MODULES, LFE / "annotate.py", LFE / "extractor.py",
                                  LFE / "propositions.py", LFE / "dataset.py"],
                         ids=lambda p: p.name)
def test_state_is_computed_with_deterministic_operations_only(path):
    bad = []
    in_simulator = path.parent == SIMULATOR
    for owner, attr, node in _calls(path):
        if owner in FORBIDDEN and attr in FORBIDDEN[owner]:
            bad.append(f"{path.name}:{node.lineno} {owner}.{attr}")
        # the simulator's ``rng`` is an lfe.draws.Draws; elsewhere call lfe.draws' functions
        if attr in FORBIDDEN_METHODS and not (in_simulator and owner in {"rng", "self.rng"}):
            bad.append(f"{path.name}:{node.lineno} .{attr}() (use lfe.draws)")
        if attr == "mean" and in_simulator:
            bad.append(f"{path.name}:{node.lineno} .mean() (use an explicit ordered sum)")
    assert bad == []


def test_the_simulation_draws_through_lfe_draws():
    world = (SIMULATOR / "_world.py").read_text(encoding="utf-8")
    assert "self.rng = Draws(np.random.RandomState(seed))" in world


# Numbers the set-up, tactics, weapons and motion may write inline; every other constant is
# named in lfe.simulator.config.
# (0 == 0.0 in a set; 180 and 360 degrees; 1000 m in a km; seeds below 2**31 and 2**32)
ALLOWED_LITERALS = {0, 1, 2, 4, 180, 360, 1000, 1e-9, 31, 32}


@pytest.mark.parametrize("name", ["_world", "_tactics", "_weapons", "_engine"])
def test_constants_are_named_in_the_configuration(name):
    tree = ast.parse((SIMULATOR / f"{name}.py").read_text(encoding="utf-8"))
    indices = {id(n) for sub in ast.walk(tree) if isinstance(sub, ast.Subscript)
               for n in ast.walk(sub.slice)}
    numbers = [(node.lineno, node.value) for node in ast.walk(tree)
               if isinstance(node, ast.Constant) and type(node.value) in (int, float)
               and id(node) not in indices]
    assert [n for n in numbers if n[1] not in ALLOWED_LITERALS] == []


def test_configuration_names_the_set_up_constants():
    for name in ("TARGET_SPREAD_Y", "MARSHAL_X", "LANE_HALF_WIDTH", "LANE_JITTER", "CAP_DEPTH",
                 "CAP_SPREAD_Y", "CAP_JITTER", "AIRBASE_DEPTH", "AIRBASE_SPREAD_Y",
                 "AIRBASE_JITTER", "SCRAMBLE_DELAY", "STATION_DEPTH", "STATION_JITTER",
                 "STATION_LANE_FACTOR", "SAM_DEPTH", "SAM_SPREAD_Y", "SAM_RANGE",
                 "SAM_DETECT_MARGIN", "ESCORT_PUSH_JITTER", "SEAD_PUSH_JITTER",
                 "STRIKER_PUSH_JITTER", "HEADING_JITTER", "ALTITUDE_JITTER"):
        assert hasattr(config, name), name

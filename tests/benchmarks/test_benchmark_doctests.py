"""The docstring examples of the benchmark modules run (pytest does not collect benchmarks/)."""

import doctest
import importlib

import pytest
from _scripts import BENCH

# Modules with examples (bench_roles and bench_external_templates the only bench_* ones).
MODULES = ["external", "external_bsi", "external_scarlet", "run", "reference.webppl",
           "_roles_report", "_common", "bench_roles", "bench_external_templates"]
FLAGS = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS


@pytest.mark.parametrize("name", MODULES)
def test_doctests(name):
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    tests = [t for t in finder.find(module, name) if t.examples]
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"


def test_the_modules_with_examples_are_all_listed():
    with_examples = sorted(
        str(path.relative_to(BENCH).with_suffix("")).replace("/", ".")
        for path in BENCH.rglob("*.py") if ">>> " in path.read_text()
    )
    assert with_examples == sorted(MODULES)

"""``--help`` of every command and subcommand is quick and loads nothing heavy (issue 21).

The parsers live in light modules (``bsi_sklearn.cli._*``, ``lfe.cli._*``, the experiments'
``reproduce``) that import numpy, pandas, scikit-learn, numba, matplotlib or torch only when
a command runs. Before: ``bsi-lfe simulate|compare|study|report --help`` took 1.5-2 s and
loaded scikit-learn (and numba, matplotlib), ``bsi fit --help`` 0.6 s with pandas.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("torch", "matplotlib", "sklearn", "numba", "pandas", "scipy")

_SCRIPT = """
import sys, time
start = time.perf_counter()
from {module} import main
try:
    main({argv!r})
except SystemExit as exc:
    code = exc.code
took = time.perf_counter() - start
heavy = sorted(m for m in {heavy!r} if m in sys.modules)
print("CODE", code, "HEAVY", heavy, "TOOK", took)
"""


def _commands():
    from bsi_sklearn.cli import SUBCOMMANDS as BSI
    from lfe.cli import SUBCOMMANDS as LFE

    yield "bsi_sklearn.cli", []
    for name in BSI:
        yield "bsi_sklearn.cli", [name]
    yield "lfe.cli", []
    for name in LFE:
        yield "lfe.cli", [name]


@pytest.mark.parametrize("module, argv", list(_commands()),
                         ids=lambda v: " ".join(v) if isinstance(v, list) else v)
def test_help_is_quick_and_loads_nothing_heavy(module, argv):
    script = _SCRIPT.format(module=module, argv=[*argv, "--help"], heavy=HEAVY)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         env=env, timeout=300)
    assert "CODE 0 HEAVY [] TOOK" in out.stdout, out.stdout + out.stderr
    assert "usage:" in out.stdout
    took = float(out.stdout.split("TOOK")[1])
    assert took < 1.0, took  # about 0.03 s here


def test_report_choices_are_the_modules():
    from bsi_sklearn.model.likelihood import LIKELIHOODS
    from bsi_sklearn.model.priors import PRIORS
    from lfe.annotate import MISSION_OBJECTIVES
    from lfe.cli import _report as _cli_report
    from lfe.propositions import PROPOSITION_SETS

    assert _cli_report.OBJECTIVE_CHOICES == tuple(MISSION_OBJECTIVES)
    assert _cli_report.PROPOSITION_SET_CHOICES == tuple(PROPOSITION_SETS)
    assert _cli_report.PRIOR_CHOICES == tuple(PRIORS)
    assert _cli_report.LIKELIHOOD_CHOICES == tuple(LIKELIHOODS)


def test_study_and_compare_settings_have_one_home():
    # Issue 22: the settings live in a leaf both the parsers and the real modules import, so
    # neither imports the other back (before: lfe.study <-> lfe.cli._study, and so on).
    from lfe import _settings, compare, report, study
    from lfe.cli import _compare as _cli_compare
    from lfe.cli import _report as _cli_report
    from lfe.cli import _study as _cli_study
    from lfe.compare import _protocol as _compare_protocol
    from lfe.propositions import PROPOSITION_SETS

    assert study.DEFAULTS is _settings.STUDY_DEFAULTS and study.QUICK is _settings.STUDY_QUICK
    assert _cli_study.STUDY_DEFAULTS is study.DEFAULTS and _cli_study.STUDY_QUICK is study.QUICK
    assert _compare_protocol.COMPARE_QUICK is _cli_compare.QUICK is _settings.COMPARE_QUICK
    assert report.REPORT_QUICK is _cli_report.QUICK is _settings.REPORT_QUICK
    for settings in (study.DEFAULTS, study.QUICK):
        assert set(settings["propositions"]) <= set(PROPOSITION_SETS)
    # the command line lives in lfe.cli; lfe.compare does not import it back
    assert not hasattr(compare, "add_arguments") and not hasattr(compare, "run")


def test_light_run_reaches_the_real_command(monkeypatch):
    import argparse

    import lfe.study
    from lfe.cli import _study as _cli_study

    seen = []
    monkeypatch.setattr(lfe.study, "run", lambda args: seen.append(args) or 0)
    parser = argparse.ArgumentParser()
    _cli_study.add_arguments(parser)
    args = parser.parse_args(["--quick"])
    assert _cli_study.run(args) == 0 and seen == [args]

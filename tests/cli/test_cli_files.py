"""``bsi`` and ``bsi-lfe`` under bad paths and faults (issue 21): one line naming the file,
exit status 2, no traceback, no output lost or overwritten; every ``--help`` works.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import Posterior
from bsi_sklearn.cli import main
from bsi_sklearn.io import write_traces_csv

ROOT = Path(__file__).resolve().parents[2]
NAMES = ["safe", "picked", "placed"]
GOOD = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
        np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
BAD = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
ROLES = ["--globals", "safe", "--subtasks", "picked", "placed"]


@pytest.fixture
def demos(tmp_path):
    path = tmp_path / "demos.csv"
    write_traces_csv(GOOD + BAD, [1, 1, 0], path, feature_names=NAMES)
    return path


def _error(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err


# ---------------------------------------------------------------- help
def _help_argvs():
    from bsi_sklearn.cli import SUBCOMMANDS as BSI
    from lfe.cli import SUBCOMMANDS as LFE

    yield "bsi", []
    for name in BSI:
        yield "bsi", [name]
    yield "bsi-lfe", []
    for name in LFE:
        yield "bsi-lfe", [name]


@pytest.mark.parametrize("prog, argv", list(_help_argvs()))
def test_every_help_works(prog, argv, capsys):
    # Issue 21: bsi-lfe --help crashed on the % of "95% intervals" in the study's help.
    if prog == "bsi":
        entry = main
    else:
        from lfe.cli import main as entry
    with pytest.raises(SystemExit) as exc:
        entry([*argv, "--help"])
    assert exc.value.code == 0
    assert "usage:" in capsys.readouterr().out


def test_python_m_lfe_help_runs():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-m", "lfe", "-h"], capture_output=True, text=True,
                         env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "95%" in out.stdout and "%%" not in out.stdout


# ---------------------------------------------------------------- bsi fit: paths
def test_fit_on_a_folder_is_one_line(tmp_path, capsys):
    assert main(["fit", str(tmp_path)]) == 2
    assert f"{tmp_path}: is a folder, not a file" in _error(capsys)


def test_fit_on_a_missing_file_is_one_line(tmp_path, capsys):
    assert main(["fit", str(tmp_path / "nope.csv")]) == 2
    assert "nope.csv: no such file" in _error(capsys)


@pytest.mark.parametrize("save, message", [
    (lambda tmp: tmp, "is a folder; give a file name"),
    (lambda tmp: tmp / "demos.csv" / "post.json", "is a file, not a folder"),
    (lambda tmp: tmp / "no" / "post.json", "does not exist"),
])
def test_save_where_it_cannot_be_written(demos, tmp_path, capsys, save, message):
    assert main(["fit", str(demos), *ROLES, "--save", str(save(tmp_path))]) == 2
    err = _error(capsys)
    assert err.startswith("bsi fit: error: --save ") and message in err


_LIMITED_FIT = """
import resource, signal, sys
from bsi_sklearn.cli import main
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (300, 300))
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.skipif(sys.platform == "win32", reason="file-size limit is POSIX")
def test_a_save_that_fails_half_way_keeps_the_previous_posterior(demos, tmp_path):
    out = tmp_path / "post.json"
    assert main(["fit", str(demos), *ROLES, "--save", str(out)]) == 0
    before = out.read_bytes()
    assert len(before) > 300
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    run = subprocess.run([sys.executable, "-c", _LIMITED_FIT, "fit", str(demos),
                          "--save", str(out)], capture_output=True, text=True, env=env,
                         timeout=300)
    assert run.returncode == 2, run.stderr
    assert "Traceback" not in run.stderr
    assert f"--save {out}: cannot write (File too large)" in run.stderr
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demos.csv", "post.json"]


def test_inputs_with_the_same_name_get_distinct_posteriors(tmp_path, capsys):
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        write_traces_csv(GOOD + BAD, [1, 1, 0], tmp_path / folder / "demos.csv",
                         feature_names=NAMES)
    argv = ["fit", str(tmp_path / "a" / "demos.csv"), str(tmp_path / "b" / "demos.csv"),
            *ROLES, "--save", str(tmp_path / "post.json")]
    assert main(argv) == 0
    written = sorted(p.name for p in tmp_path.glob("post_*.json"))
    assert written == ["post_a_demos_csv.json", "post_b_demos_csv.json"]
    assert main(["fit", str(tmp_path / "a" / "demos.csv"), str(tmp_path / "a" / "demos.csv"),
                 "--save", str(tmp_path / "post.json")]) == 2
    assert "the file is given twice" in _error(capsys)


# ---------------------------------------------------------------- bsi fit: options
def test_pos_label(tmp_path, capsys):
    path = tmp_path / "words.csv"
    frame = pd.DataFrame({"demo_id": [0, 0, 0, 1, 1, 1], "safe": [1, 1, 1, 1, 1, 0],
                          "picked": [0, 1, 1, 0, 1, 1], "label": ["yes"] * 3 + ["no"] * 3})
    frame.to_csv(path, index=False)
    assert main(["fit", str(path)]) == 2
    err = _error(capsys)
    assert "--pos-label" in err and "pass pos_label" not in err
    assert main(["fit", str(path), "--pos-label", "yes", "--subtasks", "picked"]) == 0
    assert "2 demonstrations (1 acceptable)" in capsys.readouterr().out
    assert main(["fit", str(path), "--pos-label", "maybe"]) == 2
    assert "--pos-label 'maybe' is not among the labels ['no', 'yes']" in _error(capsys)


def test_integer_pos_label(demos, capsys):
    assert main(["fit", str(demos), *ROLES, "--pos-label", "0"]) == 0
    assert "3 demonstrations (1 acceptable)" in capsys.readouterr().out


def test_files_after_a_list_option_get_a_hint(demos, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["fit", "--globals", "safe", str(demos)])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "the following arguments are required: FILE" in err
    assert "give the FILEs first" in err and "with --" in err
    assert main(["fit", "--globals", "safe", "--subtasks", "picked", "placed", "--",
                 str(demos)]) == 0


def test_the_extension_decides_the_format(demos, tmp_path, capsys):
    txt = tmp_path / "demos.txt"
    txt.write_text(demos.read_text())
    assert main(["fit", str(txt)]) == 2
    err = _error(capsys)
    assert "demos.txt: the extension '.txt' does not say the format" in err
    assert "--format csv" in err
    assert main(["fit", str(txt), "--format", "csv", *ROLES]) == 0
    assert "G(safe) & F(picked) & F(placed) & (!placed U picked)" in capsys.readouterr().out


def test_a_csv_without_t_is_read_in_row_order(tmp_path, capsys):
    path = tmp_path / "no_t.csv"
    path.write_text("demo_id,safe,picked,placed\n0,1,0,0\n0,1,1,0\n0,1,1,1\n")
    assert main(["fit", str(path), *ROLES]) == 0
    assert "1 demonstrations (1 acceptable)" in capsys.readouterr().out


def test_a_subtask_as_its_own_condition_names_the_option(demos, capsys):
    assert main(["fit", str(demos), *ROLES, "--conditions", "placed=placed"]) == 2
    assert "--conditions['placed']: subtask 'placed' cannot be its own condition" in \
        _error(capsys)


# ---------------------------------------------------------------- bsi monitor
@pytest.fixture
def saved(demos, tmp_path):
    out = tmp_path / "post.json"
    assert main(["fit", str(demos), *ROLES, "--save", str(out)]) == 0
    return out


@pytest.mark.parametrize("posterior, message", [
    (lambda tmp, p: tmp, "is a folder, not a file"),
    (lambda tmp, p: tmp / "none.json", "none.json: no such file"),
])
def test_monitor_bad_posterior_paths(saved, demos, tmp_path, capsys, posterior, message):
    assert main(["monitor", str(posterior(tmp_path, saved)), str(demos), "--no-plot",
                 "--out", str(tmp_path / "out")]) == 2
    assert message in _error(capsys)


def test_monitor_truncated_posterior_names_the_file(saved, demos, tmp_path, capsys):
    saved.write_text(saved.read_text()[:200])
    assert main(["monitor", str(saved), str(demos), "--out", str(tmp_path / "o")]) == 2
    err = _error(capsys)
    assert f"'{saved}': not JSON" in err


def test_monitor_posterior_of_another_task_names_both_files(saved, tmp_path, capsys):
    other = tmp_path / "other.csv"
    write_traces_csv(GOOD, None, other, feature_names=["x", "y", "z"])
    assert main(["monitor", str(saved), str(other), "--out", str(tmp_path / "o")]) == 2
    err = _error(capsys)
    assert f"{other}: its propositions ['x', 'y', 'z'] are not those of the posterior " \
           f"{saved}" in err


def test_monitor_file_lacking_a_fitted_column_names_it(saved, tmp_path, capsys):
    lacking = tmp_path / "lacking.csv"
    write_traces_csv([g[:, [0, 2]] for g in GOOD], None, lacking,
                     feature_names=["safe", "placed"])
    assert main(["monitor", str(saved), str(lacking), "--out", str(tmp_path / "o")]) == 2
    err = _error(capsys)
    assert "the file lacks the proposition 'picked' seen in the posterior" in err
    assert list((tmp_path / "o").glob("*")) == []  # nothing written


def test_monitor_out_that_is_a_file(saved, demos, tmp_path, capsys):
    assert main(["monitor", str(saved), str(demos), "--out", str(demos)]) == 2
    assert "--out " in (err := _error(capsys)) and "is a file, not a folder" in err


def test_monitor_outputs_are_named_by_demo_id_and_unique(saved, tmp_path, capsys):
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        frame = pd.DataFrame({"demo_id": ["run/7"] * 3 + ["ok"] * 3, "t": [0, 1, 2] * 2,
                              "safe": 1, "picked": [0, 1, 1] * 2, "placed": [0, 0, 1] * 2})
        frame.to_csv(tmp_path / folder / "demos.csv", index=False)
    out = tmp_path / "out"
    assert main(["monitor", str(saved), str(tmp_path / "a" / "demos.csv"),
                 str(tmp_path / "b" / "demos.csv"), "--no-plot", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "a_demos_csv_ok_monitor.csv", "a_demos_csv_run_7_monitor.csv",
        "b_demos_csv_ok_monitor.csv", "b_demos_csv_run_7_monitor.csv"]
    assert "[run/7]" in capsys.readouterr().out


def test_monitor_output_files_respect_the_umask(saved, demos, tmp_path):
    old = os.umask(0o022)
    try:
        assert main(["monitor", str(saved), str(demos), "--out", str(tmp_path / "o")]) == 0
    finally:
        os.umask(old)
    modes = {p.suffix: p.stat().st_mode & 0o777 for p in (tmp_path / "o").iterdir()}
    assert modes == {".csv": 0o644, ".png": 0o644}


def test_saved_posterior_round_trips(saved, demos):
    from bsi_sklearn.io import read_traces_csv

    X, _ = read_traces_csv(demos)
    post = Posterior.read_json(saved)
    assert json.loads(saved.read_text())["schema"] == "bsi-sklearn/posterior"
    assert post.predict_proba(X).shape == (3, 2)


# ---------------------------------------------------------------- start-up
_HELP_IMPORTS = """
import sys, time
start = time.perf_counter()
try:
    from {module} import main
    main(["--help"])
except SystemExit:
    pass
took = time.perf_counter() - start
heavy = sorted(m for m in ("sklearn", "numba", "pandas", "scipy", "torch", "matplotlib")
               if m in sys.modules)
print("HEAVY", heavy, "TOOK", took)
"""


@pytest.mark.parametrize("module", ["bsi_sklearn.cli", "lfe.cli"])
def test_top_level_help_is_quick_and_loads_nothing_heavy(module):
    # Issue 21: every command took 7-10 s, --help included (each subcommand module imported).
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", _HELP_IMPORTS.format(module=module)],
                         capture_output=True, text=True, env=env, timeout=300)
    assert "HEAVY [] TOOK" in out.stdout, out.stdout + out.stderr
    took = float(out.stdout.split("TOOK")[1])
    assert took < 1.0, took  # about 0.05 s here


def test_import_bsi_sklearn_is_light_until_a_name_is_used():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    code = ("import sys, bsi_sklearn; print('sklearn' in sys.modules); "
            "from bsi_sklearn import BSIClassifier, Posterior, Specification; "
            "print('sklearn' in sys.modules, BSIClassifier.__module__, "
            "sorted(set(bsi_sklearn.__all__) - set(dir(bsi_sklearn))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, timeout=300)
    assert out.stdout.split() == ["False", "True", "bsi_sklearn.classifier", "[]"], out.stderr


def test_fit_choices_are_the_models():
    from bsi_sklearn.cli._fit import LIKELIHOOD_CHOICES, PRIOR_CHOICES
    from bsi_sklearn.model.likelihood import LIKELIHOODS
    from bsi_sklearn.model.priors import PRIORS

    assert PRIOR_CHOICES == tuple(PRIORS) and LIKELIHOOD_CHOICES == tuple(LIKELIHOODS)

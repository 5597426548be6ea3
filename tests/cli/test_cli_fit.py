"""``bsi fit``: roles by name or index, help for every option, errors with exit status 2."""

import re

import numpy as np
import pytest

from bsi_sklearn.cli import main
from bsi_sklearn.io import write_traces_csv

NAMES = ["safe", "picked", "placed"]


@pytest.fixture
def csv_file(tmp_path):
    good = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
            np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    bad = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    path = tmp_path / "demos.csv"
    write_traces_csv(good + bad, [1, 1, 0], path, feature_names=NAMES)
    return path


@pytest.mark.parametrize("roles", [
    ["--globals", "safe", "--subtasks", "picked", "placed"],
    ["--globals", "0", "--subtasks", "1", "2"],
])
def test_roles_by_name_or_index(csv_file, roles, capsys):
    assert main(["fit", str(csv_file), *roles]) == 0
    out = capsys.readouterr().out
    # every demonstration is safe, picks and places: only the order was tested by the data
    assert ("MAP        : (!placed U picked)  [untested: G(safe) & F(picked) & F(placed)]\n"
            "full MAP   : G(safe) & F(picked) & F(placed) & (!placed U picked)\n") in out
    assert "exact inference" in out


def test_conditions_and_empty_roles(csv_file, capsys):
    argv = ["fit", str(csv_file), "--globals", "--subtasks", "picked", "placed",
            "--conditions", "placed=safe,picked=safe"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "(safe -> F(placed))" in out and "G(" not in out.split("MAP")[1].splitlines()[0]


@pytest.mark.parametrize("argv, message", [
    (["--globals", "speed"], "demos.csv: --globals: unknown proposition 'speed'; known "
                             "propositions are ['safe', 'picked', 'placed']"),
    (["--subtasks", "7"], "--subtasks: proposition index 7 is out of range for 3"),
    (["--subtasks", "picked", "--conditions", "placed=safe"],
     "--conditions: 'placed' is not one of the subtasks"),
    (["--conditions", "picked=nope"], "--conditions['picked']: unknown proposition 'nope'"),
    (["--globals", "safe", "safe"], "--globals: proposition 'safe' is listed more than once"),
])
def test_bad_roles_exit_2_naming_the_option(csv_file, argv, message, capsys):
    assert main(["fit", str(csv_file), *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bsi fit: error: ") and message in err


def test_malformed_conditions_are_usage_errors(csv_file, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(csv_file), "--conditions", "placed"])
    assert exc.value.code == 2
    assert "'placed' is not a pair subtask=condition" in capsys.readouterr().err


def test_help_documents_every_option_and_the_csv_format(capsys):
    with pytest.raises(SystemExit):
        main(["fit", "--help"])
    text = capsys.readouterr().out
    assert "demo_id,t,<proposition>...[,label]" in text
    options = re.findall(r"^  (--[a-z-]+)", text, flags=re.M)
    assert set(options) >= {"--globals", "--subtasks", "--conditions", "--prior",
                            "--likelihood", "--inference", "--n-samples", "--top", "--seed"}
    # Every option line is followed by its help text (no bare option).
    blocks = re.split(r"\n  (?=-)", text.split("options:")[1])
    assert all(len(b.split()) > 3 for b in blocks[1:]), blocks


def test_help_states_the_default_roles(capsys):
    # --roles defaults to infer: the help must not say that every proposition is in every role
    with pytest.raises(SystemExit):
        main(["fit", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "by default (--roles infer)" in text
    assert "{infer,all}" in text and "(default: infer)" in text
    assert "by default every proposition" not in text
    assert "With --roles all, every proposition is a global candidate and a subtask" in text


def test_errors_while_fitting_name_the_file(tmp_path, capsys):
    path = tmp_path / "only_bad.csv"
    write_traces_csv([np.array([[1, 0], [0, 1]])], [0], path, feature_names=["a", "b"])
    assert main(["fit", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bsi fit: error: {path}: ") and "only unacceptable" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["only_bad.csv"]


def test_roles_option_and_the_roles_line(tmp_path):
    import subprocess
    import sys

    path = tmp_path / "demo.trace"
    # x0 then x1; x2 (safe) holds throughout; the bad trace does x1 before x0
    path.write_text("0,0,1;1,0,1;1,1,1\n0,0,1;0,0,1;1,0,1;1,1,1\n---\n0,0,1;0,1,1;1,1,1\n"
                    "---\nF,G\n")
    run = [sys.executable, "-m", "bsi_sklearn", "fit", str(path), "--top", "1"]
    inferred = subprocess.run(run, capture_output=True, text=True)
    assert inferred.returncode == 0, inferred.stderr
    assert "roles      : globals x2; subtasks x0 x1; conditions -" in inferred.stdout
    every = subprocess.run([*run, "--roles", "all"], capture_output=True, text=True)
    assert every.returncode == 0, every.stderr
    assert "roles      : globals x0 x1 x2; subtasks x0 x1 x2; conditions -" in every.stdout
    bad = subprocess.run([*run, "--roles", "some"], capture_output=True, text=True)
    assert bad.returncode == 2 and "--roles" in bad.stderr


@pytest.mark.parametrize("likelihood", ["ci", "calibrated"])
def test_flip_prior_prints_the_flip_rate_of_the_classifier(csv_file, capsys, likelihood):
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.io import read_traces_csv

    argv = ["fit", str(csv_file), "--globals", "safe", "--subtasks", "picked", "placed",
            "--likelihood", likelihood, "--flip-prior", "1", "9"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    X, y = read_traces_csv(csv_file)[:2]
    clf = BSIClassifier(global_candidates=["safe"], subtasks=["picked", "placed"],
                        likelihood=likelihood, flip_prior=(1.0, 9.0), random_state=0).fit(X, y)
    low, high = clf.flip_rate_interval_
    assert (f"flip rate  : {clf.flip_rate_:.3f} [{low:.3f}, {high:.3f}] (posterior mean, "
            "95 % interval)") in out
    assert main(["fit", str(csv_file), "--likelihood", "ci"]) == 0
    assert "flip rate" not in capsys.readouterr().out


def test_inclusion_probabilities_are_the_classifiers(csv_file, capsys):
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.io import read_traces_csv

    X, y = read_traces_csv(csv_file)[:2]
    for value, param in (("learned", "learned"), ("0.3", 0.3)):
        argv = ["fit", str(csv_file), "--globals", "safe", "--subtasks", "picked", "placed",
                "--p-global", value, "--p-eventual", value, "--p-part", value, "--top", "1"]
        assert main(argv) == 0
        out = capsys.readouterr().out
        clf = BSIClassifier(global_candidates=["safe"], subtasks=["picked", "placed"],
                            p_global=param, p_eventual=param, p_part=param,
                            random_state=0).fit(X, y)
        assert clf.map_specification_.to_ltl() in out


def test_bad_inclusion_probabilities_exit_2_naming_the_option(csv_file, capsys):
    assert main(["fit", str(csv_file), "--p-global", "1.5"]) == 2
    assert "--p-global must be" in capsys.readouterr().err
    assert main(["fit", str(csv_file), "--p-part", "-0.1"]) == 2
    assert "--p-part must be" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:  # argparse's own exit for a value it cannot read
        main(["fit", str(csv_file), "--p-eventual", "learnt"])
    assert exc.value.code == 2
    assert "--p-eventual: must be 'learned' or a number" in capsys.readouterr().err


@pytest.mark.parametrize("argv, message", [
    (["--likelihood", "cb", "--flip-prior", "1", "9"],
     "--flip-prior applies to the likelihoods 'ci' and 'calibrated', not --likelihood cb"),
    (["--likelihood", "ci", "--flip-prior", "0", "9"], "--flip-prior"),
    (["--likelihood", "ci", "--flip-prior", "nan", "9"], "--flip-prior"),
])
def test_bad_flip_priors_exit_2_naming_the_option(csv_file, argv, message, capsys):
    assert main(["fit", str(csv_file), *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bsi fit: error: {csv_file}: ") and message in err


# ------------------------------------------------------------------ event logs
def _xes(path, cases):
    body = "".join(
        f'<trace><string key="concept:name" value="{cid}"/>'
        f'<string key="outcome" value="{label}"/>'
        + "".join(f'<event><string key="concept:name" value="{a}"/></event>' for a in acts)
        + "</trace>\n" for cid, acts, label in cases)
    path.write_text('<?xml version="1.0" encoding="UTF-8"?>\n<log xmlns="http://www.xes-'
                    f'standard.org/">\n{body}</log>\n', encoding="utf-8")
    return path


LOG = [("c1", ["order", "pay", "ship"], "accepted"), ("c2", ["order", "ship", "pay"],
                                                     "accepted"),
       ("c3", ["ship", "order", "pay"], "rejected"), ("c4", ["pay", "ship"], "rejected")]


def test_fit_an_xes_event_log_prints_the_map_in_activity_names(tmp_path, capsys):
    path = _xes(tmp_path / "log.xes", LOG)
    assert main(["fit", str(path), "--label", "outcome", "--pos-label", "accepted",
                 "--subtasks", "order", "pay", "ship", "--globals"]) == 0
    out = capsys.readouterr().out
    assert "4 demonstrations (2 acceptable), 6 propositions" in out   # and their negations
    assert "MAP        : F(order) & (!ship U order)" in out
    # ... and as Declare constraints on the cases
    assert ("reading    : existence(order): order occurs.\n             existence(order) and "
            "precedence(order, ship): order occurs, and no ship before the first order.") in out


def test_event_log_negations_read_as_absence_and_the_encoding_options(tmp_path, capsys):
    path = _xes(tmp_path / "log.xes", [
        ("c1", ["order", "pay", "ship"], "accepted"), ("c2", ["order", "ship", "pay"], "accepted"),
        ("c3", ["order", "refund", "ship"], "rejected"), ("c4", ["order", "pay", "refund"],
                                                          "rejected")])
    args = ["fit", str(path), "--label", "outcome", "--pos-label", "accepted"]
    assert main(args + ["--subtasks"]) == 0
    out = capsys.readouterr().out
    assert "4 demonstrations (2 acceptable), 8 propositions" in out
    assert "MAP        : G(!refund)" in out
    assert "reading    : absence(refund): refund never occurs." in out
    assert main(args + ["--no-negations", "--encoding", "current"]) == 0
    out = capsys.readouterr().out
    assert "4 propositions" in out and "G(!refund)" not in out
    with pytest.raises(SystemExit) as exc:
        main(args + ["--encoding", "sometimes"])
    assert exc.value.code == 2
    assert "--encoding: invalid choice: 'sometimes'" in capsys.readouterr().err


def test_event_log_repeats_state_at_most_once(tmp_path, capsys):
    path = _xes(tmp_path / "log.xes", [
        ("c1", ["order", "pay", "ship"], "accepted"), ("c2", ["order", "ship", "pay"], "accepted"),
        ("c3", ["order", "pay", "pay", "ship"], "rejected"),
        ("c4", ["order", "pay", "ship", "pay"], "rejected")])
    args = ["fit", str(path), "--label", "outcome", "--pos-label", "accepted", "--subtasks"]
    assert main(args + ["--repeats"]) == 0
    out = capsys.readouterr().out
    assert "4 demonstrations (2 acceptable), 7 propositions" in out   # negations, pay<=1
    assert "MAP        : G(pay<=1)" in out
    assert "reading    : absence2(pay): pay occurs at most once." in out
    assert main(args) == 0
    assert "pay<=1" not in capsys.readouterr().out


def test_an_activity_named_with_a_bang_is_no_negation_in_the_readable_map(tmp_path, capsys):
    # The encoder's negations are its "!a" columns only: an activity "!late" is an atom
    # (quoted), never the negation of a "late", with or without --negations.
    path = _xes(tmp_path / "log.xes", [
        ("c1", ["order", "!late", "ship"], "accepted"), ("c2", ["order", "!late", "ship"],
                                                         "accepted"),
        ("c3", ["order", "ship"], "rejected"), ("c4", ["ship", "order"], "rejected")])
    args = ["fit", str(path), "--label", "outcome", "--pos-label", "accepted",
            "--subtasks", "order", "!late", "ship", "--likelihood", "cb"]
    for extra in ([], ["--no-negations"]):
        assert main(args + extra) == 0
        out = capsys.readouterr().out
        assert 'MAP        : F("!late") & (!ship U "!late")  [untested: F(order) & F(ship) & ' \
            '(!"!late" U order)]' in out
        assert "!!" not in out.split("full MAP")[0]


def test_fit_an_event_log_csv_told_by_its_case_column(tmp_path, capsys):
    rows = ["case:concept:name,concept:name,time:timestamp,case:outcome"]
    for cid, acts, label in LOG:
        rows += [f"{cid},{a},2024-01-0{k + 1}T10:00:00,{label}" for k, a in enumerate(acts)]
    path = tmp_path / "log.csv"
    path.write_text("\n".join(rows) + "\n")
    assert main(["fit", str(path), "--label", "outcome", "--pos-label", "accepted",
                 "--subtasks", "order", "pay", "ship", "--globals"]) == 0
    assert "MAP        : F(order) & (!ship U order)" in capsys.readouterr().out


@pytest.mark.parametrize("argv, message", [
    (["--label", "outcome", "--pos-label", "acepted"],
     "--pos-label 'acepted' is not among the labels ['accepted', 'rejected']"),
    (["--label", "outcome"], "case 'c1' has the label 'accepted'; labels must be 0/1"),
    (["--pos-label", "accepted"], "--pos-label is given but no label: name the trace "
                                  "attribute with --label"),
])
def test_event_log_errors_exit_2(tmp_path, argv, message, capsys):
    path = _xes(tmp_path / "log.xes", LOG)
    assert main(["fit", str(path), *argv]) == 2
    assert message in capsys.readouterr().err


def test_help_documents_event_logs(capsys):
    with pytest.raises(SystemExit):
        main(["fit", "--help"])
    text = capsys.readouterr().out
    assert "*.xes, *.xes.gz" in text and "case:concept:name,concept:name" in text
    assert "--format {auto,csv,trace,event-log}" in text.replace("\n", " ").replace("  ", " ")


def test_event_log_templates_add_pattern_clauses(tmp_path, capsys):
    # Every pay is followed by a ship in the accepted cases only: Response(pay, ship)
    path = _xes(tmp_path / "log.xes", [
        ("c1", ["order", "pay", "ship"], "accepted"),
        ("c2", ["order", "pay", "ship", "pay", "ship"], "accepted"),
        ("c3", ["order", "ship", "pay", "ship"], "accepted"),
        ("c4", ["order", "pay"], "rejected"), ("c5", ["order", "pay", "ship", "pay"], "rejected"),
        ("c6", ["order", "ship", "pay"], "rejected")])
    args = ["fit", str(path), "--label", "outcome", "--pos-label", "accepted", "--encoding",
            "current", "--no-negations", "--globals", "--subtasks"]
    assert main(args + ["--templates", "Response"]) == 0
    out = capsys.readouterr().out
    assert "MAP        : Response(pay, ship)" in out
    assert "Response(pay, ship): every pay is eventually followed by ship." in out
    assert "accuracy   : 1.000" in out
    assert main(args + ["--templates", "Respons"]) != 0
    err = capsys.readouterr().err
    assert "--templates: unknown template 'Respons'" in err
    # a set's name alone is the set (Response is among Declare's)
    assert main(args + ["--templates", "declare"]) == 0
    assert "Response(pay, ship)" in capsys.readouterr().out

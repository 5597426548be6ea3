"""The external-benchmark evaluation (benchmarks/external.py), its BSI screening
(external_bsi.py), Scarlet formula parser (external_scarlet.py) and statistics
(external_report.py)."""

import itertools
from pathlib import Path

import _scripts  # noqa: F401  (puts benchmarks/ on sys.path)
import numpy as np
import pandas as pd
import pytest
from _shared_data import BENCHMARKS_DATA

from bsi_sklearn.ltl import Atom, parse_ltl

ROOT = Path(__file__).parents[2]
DATA = BENCHMARKS_DATA
SAMPLES = DATA / "samples2LTL" / "traces" / "finite"
SCARLET = DATA / "scarlet" / "All_benchmarks" / "RQ2-benchmarks" / "Varying_form" / "TracesFiles"

import external as E  # noqa: E402
import external_bsi as B  # noqa: E402
import external_report as R  # noqa: E402
import external_scarlet as S  # noqa: E402

needs_data = pytest.mark.shared_data


# -- Scarlet's formulas -------------------------------------------------------------------


def test_parser_reads_both_scarlet_notations():
    names = {"v0": "a", "v1": "b", "v2": "c"}
    pretty = S.parse_scarlet_formula("((F v0) & (F v1)) & (X (! v2))", names=names)
    prefix = S.parse_scarlet_formula("&(&(F(v0),F(v1)),X(!(v2)))", names=names)
    assert pretty == prefix == parse_ltl("F(a) & F(b) & X(!c)")
    # the shapes Scarlet's directed formulas take: F/X chains, G over disjunctions
    assert S.parse_scarlet_formula("F (v0 & (X (F v1)))", names) == parse_ltl("F(a & X(F(b)))")
    assert S.parse_scarlet_formula("X (G ((! v0) | v2))", names) == parse_ltl("X(G(!a | c))")
    assert S.parse_scarlet_formula("v1") == parse_ltl("v1")
    assert S.parse_scarlet_formula("true") == parse_ltl("true")


@pytest.mark.parametrize("text", ["", "   ", "F (", "v0 &", "&(v0)"])
def test_parser_rejects_malformed_text(text):
    with pytest.raises(ValueError):
        S.parse_scarlet_formula(text)


def test_parser_rejects_unknown_atoms():
    with pytest.raises(ValueError, match="unknown atoms"):
        S.parse_scarlet_formula("F (v0 & v7)", names={"v0": "a"})


def _scarlet_truth(f, trace, i):
    """Scarlet's finite-trace semantics (Scarlet.sample.Trace.truthValue), written out."""
    n = len(trace)
    if isinstance(f, Atom):
        return bool(trace[f.name][i])
    kind = type(f).__name__
    if kind == "Constant":
        return f.value
    if kind == "Not":
        return not _scarlet_truth(f.operand, trace, i)
    if kind == "And":
        return _scarlet_truth(f.left, trace, i) and _scarlet_truth(f.right, trace, i)
    if kind == "Or":
        return _scarlet_truth(f.left, trace, i) or _scarlet_truth(f.right, trace, i)
    if kind == "Eventually":
        return any(_scarlet_truth(f.operand, trace, j) for j in range(i, n))
    if kind == "Globally":
        return all(_scarlet_truth(f.operand, trace, j) for j in range(i, n))
    if kind == "Next":  # strong next: false at the last step
        return i + 1 < n and _scarlet_truth(f.operand, trace, i + 1)
    raise AssertionError(kind)


def _random_formula(rng, depth):
    if depth == 0 or rng.random() < 0.25:
        return Atom(str(rng.choice(["a", "b"])))
    op = rng.choice(["!", "X", "F", "G", "&", "|"])
    if op in ("&", "|"):
        left, right = _random_formula(rng, depth - 1), _random_formula(rng, depth - 1)
        return parse_ltl(f"{op}({left.to_prefix()},{right.to_prefix()})")
    return parse_ltl(f"{op}({_random_formula(rng, depth - 1).to_prefix()})")


def test_strong_next_matches_scarlets_semantics():
    rng = np.random.default_rng(0)
    traces = [pd.DataFrame(rng.random((n, 2)) < 0.5, columns=["a", "b"])
              for n in (1, 1, 2, 3, 4, 6) for _ in range(3)]
    differs = 0
    for _ in range(150):
        f = _random_formula(rng, 4)
        ours = S.evaluate_scarlet_formula(f, traces)
        theirs = [_scarlet_truth(f, t, 0) for t in traces]
        np.testing.assert_array_equal(ours, theirs, err_msg=str(f))
        differs += not np.array_equal(f.evaluate(traces), theirs)
    assert differs > 0  # the translation matters: X at the last step differs


def test_strong_next_on_a_short_trace():
    trace = pd.DataFrame({"a": [True]})
    f = S.parse_scarlet_formula("X a")
    assert f.evaluate([trace]).tolist() == [True]  # bsi_sklearn.ltl: repeated last state
    assert S.evaluate_scarlet_formula(f, [trace]).tolist() == [False]  # Scarlet: strong next
    assert S.evaluate_scarlet_formula(S.parse_scarlet_formula("G (X a)"), [trace]).tolist() == [
        False]


def test_last_formula_of_scarlets_progress_csv(tmp_path):
    csv = tmp_path / "progress.csv"
    csv.write_text("Time Elapsed,Formula Size,Formula,is Terminated?\n"
                   "0.1,2,F v0,\n1.5,4,(F v0) & (G v1),\n")
    assert S._last_csv_formula(csv) == "(F v0) & (G v1)"
    csv.write_text("Time Elapsed,Formula Size,Formula,is Terminated?\n")
    assert S._last_csv_formula(csv) is None
    assert S._last_csv_formula(tmp_path / "missing.csv") is None


# -- splits and role screening ------------------------------------------------------------


def test_split_is_stratified_deterministic_and_keeps_lone_traces_for_training():
    y = np.array([1] * 10 + [0] * 7 + [1])
    tr, te = E.split_indices(y, 0.3, seed=3)
    tr2, te2 = E.split_indices(y, 0.3, seed=3)
    np.testing.assert_array_equal(tr, tr2)
    np.testing.assert_array_equal(te, te2)
    assert sorted([*tr, *te]) == list(range(len(y)))
    assert (y[te] == 1).sum() == 3 and (y[te] == 0).sum() == 2
    tr, te = E.split_indices(np.array([1, 0, 0, 0, 0]), 0.3, seed=0)
    assert 0 in tr and len(te) == 1  # the lone positive is never held out


def test_select_roles_screens_on_positives_and_caps():
    rng = np.random.default_rng(0)
    names = ["p", "q", "r", "!p", "!q", "!r"]
    traces, y = [], []
    for i in range(40):
        t = rng.random((6, 3)) < 0.5
        if i % 2 == 0:  # positives: q never holds, r eventually does
            t[:, 1] = False
            t[rng.integers(6), 2] = True
        traces.append(np.hstack([t, ~t]))
        y.append(1 - i % 2)
    g, s, screened = B.select_roles(traces, np.array(y), names, max_subtasks=2)
    assert g == ["!q"]  # G(!q) on every positive; no other G(.) on 90 % of them
    assert len(s) == 2 and screened["subtasks"] >= 2
    assert set(s) <= {"p", "r", "!p", "!q", "!r"} and "q" not in s


# -- the evaluation on published files ----------------------------------------------------


@needs_data
def test_evaluation_on_a_handful_of_files():
    files = [SAMPLES / "perfect_class" / "universality" / "0000.trace",  # G(x0)
             SAMPLES / "perfect_class" / "abscence" / "0000.trace",  # G(!x0)
             SAMPLES / "perfect_class" / "existence" / "0000.trace",  # outside the template
             SCARLET / "f-01-nw-100-ml-10-0.trace",  # F(a)
             SCARLET / "f-03-nw-100-ml-10-0.trace"]  # F(a) & F(b) & F(c)
    cfg = E.Config(scarlet=False, verbose=0)
    df = E.run_evaluation(files, DATA, cfg)
    assert len(df) == len(files)
    for col in ("family", "file", "target", "in_template", "bsi_accuracy", "bsi_fit_s",
                "bsi_map", "recovered", "scarlet_status", "scarlet_accuracy"):
        assert col in df.columns
    assert df["bsi_accuracy"].between(0, 1).all()
    assert df["bsi_map_accuracy"].between(0, 1).all()
    assert (df["bsi_fit_s"] > 0).all() and (df["scarlet_status"] == "skipped").all()
    assert df["in_template"].tolist() == [True, True, False, True, True]
    assert df["recovered"].iloc[[0, 1, 3, 4]].astype(bool).all()
    assert df["recovered"].iloc[2] is None
    # in-template noise-free files: every clause of the target is in the MAP specification
    assert "G(x0)" in df["bsi_map"].iloc[0] and "G(!x0)" in df["bsi_map"].iloc[1]
    assert df["bsi_accuracy"].iloc[[3, 4]].min() >= 0.9
    assert df["family"].tolist()[-1] == "scarlet/Varying_form"
    summary = R.summarize(df)
    assert summary.loc["ALL", "files"] == 5 and summary.loc["ALL", "recovery_rate"] == 1.0
    # the same split and seeds give the same numbers
    again = E.evaluate_file(files[3], DATA, cfg)
    assert again["bsi_map"] == df["bsi_map"].iloc[3]
    assert again["bsi_accuracy"] == df["bsi_accuracy"].iloc[3]


def test_missing_data_directory_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        E.find_trace_files(tmp_path / "nowhere")
    with pytest.raises(ValueError, match="no .trace files"):
        E.find_trace_files(tmp_path)


def test_command_line_errors_without_data(tmp_path, capsys):
    with pytest.raises(SystemExit):
        E.main(["--data", str(tmp_path / "nowhere"), "--no-scarlet"])
    assert "does not exist" in capsys.readouterr().err


def test_scarlet_subset_takes_every_kth_file_per_folder():
    files = [Path(f"a/{i}.trace") for i in range(5)] + [Path(f"b/{i}.trace") for i in range(2)]
    chosen = E.scarlet_subset(files, 2)
    assert chosen == {Path("a/0.trace"), Path("a/2.trace"), Path("a/4.trace"), Path("b/0.trace")}
    assert E.scarlet_subset(files, 1) == set(files)
    assert list(itertools.islice(E.quick_files(files, 1), 5)) == [Path("a/0.trace"),
                                                                  Path("b/0.trace")]

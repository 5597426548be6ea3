"""PosteriorMonitor: three-valued verdicts against a brute-force re-evaluation of every prefix."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn import BSIClassifier, Posterior
from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.monitor.posterior_monitor import PosteriorMonitor, Verdict

NAMES = ["safe", "a", "b", "c_ok"]


def _fitted(conditions=None, prior="sets_of_chains"):
    rng = np.random.default_rng(0)
    X, y = [], []
    for i in range(8):
        T = int(rng.integers(2, 5))
        X.append(pd.DataFrame(rng.integers(0, 2, size=(T, 4)), columns=NAMES))
        y.append(i % 3 != 0)
    clf = BSIClassifier(prior=prior, global_candidates=["safe", "c_ok"],
                        subtasks=["a", "b", "c_ok"], conditions=conditions, random_state=0)
    return clf.fit(X, np.asarray(y, dtype=int))


CLASSIFIERS = {
    "plain": _fitted(),
    "conditions": _fitted(conditions={"a": "c_ok", "b": "safe"}, prior="forest"),
}


def _random_posterior(conditions, n_specs=40, seed=0):
    """A posterior with every kind of clause: random forests, subsets and probabilities."""
    rng = np.random.default_rng(seed)
    roles = resolve_roles(["safe", "c_ok"], ["a", "b", "c_ok"], conditions, 4, NAMES)
    n = roles.n_subtasks
    structures = np.full((n_specs, n), -1)
    for h in range(n_specs):
        order = rng.permutation(n)
        for k in range(1, n):
            if rng.random() < 0.7:
                structures[h, order[k]] = order[rng.integers(k)]
    probs = np.sort(rng.dirichlet(np.ones(n_specs)))[::-1]
    return Posterior(structures, rng.random((n_specs, 2)) < 0.5, rng.random((n_specs, n)) < 0.6,
                     probs, roles)


POSTERIORS = {
    "plain": _random_posterior(None),
    "conditions": _random_posterior({"a": "c_ok", "b": "safe"}, seed=1),
    "fitted": CLASSIFIERS["conditions"].posterior_,
}


def _clause_state(clause, prefix, cond, closed):
    """DESIGN section 10, read literally on ``prefix`` (a DataFrame of steps 0..t)."""
    kind = clause[0]
    if kind == "G":
        if not prefix[clause[1]].all():
            return "violated"
        return "satisfied" if closed else "open"
    first = clause[1]
    if first in cond and not prefix[cond[first]].iloc[0]:
        return "satisfied"
    if kind == "F":
        if prefix[first].any():
            return "satisfied"
        return "violated" if closed else "open"
    b = clause[2]
    for t in range(len(prefix)):
        if prefix[first].iloc[t]:
            return "satisfied"
        if prefix[b].iloc[t]:
            return "violated"
    return "violated" if closed else "open"


def _brute_force(post, trace, closed):
    masses = {"satisfied": 0.0, "violated": 0.0, "open": 0.0}
    states = {}
    for spec, prob in zip(post.specifications, post.probabilities):
        clause_states = []
        for clause in spec.clauses():
            if clause not in states:
                states[clause] = _clause_state(clause, trace, spec.conditions, closed)
            clause_states.append(states[clause])
        if "violated" in clause_states:
            masses["violated"] += prob
        elif "open" in clause_states:
            masses["open"] += prob
        else:
            masses["satisfied"] += prob
    return masses, states


def _check_trace(post, trace):
    mon = PosteriorMonitor(post)
    previous = {}
    for t in range(len(trace)):
        verdict = mon.update(trace.iloc[t].to_numpy())
        masses, states = _brute_force(post, trace.iloc[: t + 1], closed=False)
        assert verdict.step == t and not verdict.closed
        np.testing.assert_allclose(
            [verdict.p_satisfied, verdict.p_violated, verdict.p_open],
            [masses["satisfied"], masses["violated"], masses["open"]], atol=1e-12)
        assert abs(verdict.p_satisfied + verdict.p_violated + verdict.p_open - 1.0) < 1e-9
        expected = {c: s for c, s in states.items() if s != previous.get(c, "open")}
        assert {e.clause: e.state for e in verdict.events} == expected
        previous = states
    final = mon.finish()
    masses, _ = _brute_force(post, trace, closed=True)
    assert final.p_open == 0.0 and final.closed and final.step == len(trace) - 1
    assert final.p_satisfied == post.predict_proba([trace])[0, 1]
    np.testing.assert_allclose(final.p_violated, masses["violated"], atol=1e-12)


@pytest.mark.parametrize("name", POSTERIORS)
@settings(max_examples=30, deadline=None)
@given(data=arrays(np.uint8, st.tuples(st.integers(1, 6), st.just(4)),
                   elements=st.integers(0, 1)))
def test_monitor_matches_brute_force_on_every_prefix(name, data):
    trace = pd.DataFrame(data.astype(bool), columns=NAMES)
    _check_trace(POSTERIORS[name], trace)


@pytest.mark.parametrize("name", CLASSIFIERS)
@settings(max_examples=10, deadline=None)
@given(data=arrays(np.uint8, st.tuples(st.integers(1, 6), st.just(4)),
                   elements=st.integers(0, 1)))
def test_classifier_monitor_finish_equals_predict_proba(name, data):
    clf = CLASSIFIERS[name]
    trace = pd.DataFrame(data.astype(bool), columns=NAMES)
    rows = clf.monitor_proba([trace, trace.iloc[:1]])
    assert [r.shape for r in rows] == [(len(trace), 3), (1, 3)]
    mon = clf.monitor()
    for t in range(len(trace)):
        v = mon.update(trace.iloc[t])
        np.testing.assert_allclose(rows[0][t], [v.p_satisfied, v.p_violated, v.p_open],
                                   atol=1e-12)
    np.testing.assert_allclose(rows[1][0], rows[0][0], atol=1e-12)
    # Closed, the monitor gives the vote: the posterior mass satisfied.
    assert mon.finish().p_satisfied == clf.posterior_.predict_proba([trace])[0, 1]


def test_verdicts_are_monotone_and_reset_starts_over():
    clf = CLASSIFIERS["plain"]
    trace = np.array([[1, 0, 0, 1], [1, 1, 0, 1], [0, 1, 1, 1], [1, 1, 1, 0]])
    mon = clf.monitor()
    verdicts = [mon.update(row) for row in trace]
    sat = [v.p_satisfied for v in verdicts]
    viol = [v.p_violated for v in verdicts]
    assert sat == sorted(sat) and viol == sorted(viol)
    mon.finish()
    mon.reset()
    assert mon.n_steps == 0 and mon.verdict is None and not mon.closed
    again = [mon.update(row) for row in trace]
    assert again == verdicts
    assert isinstance(again[0], Verdict)


def test_step_formats_agree():
    clf = CLASSIFIERS["conditions"]
    row = np.array([1, 0, 1, 1])
    verdicts = []
    for step in (row, row.astype(bool), row.astype(float), row.tolist(),
                 pd.Series(row, index=NAMES), dict(zip(NAMES, row.tolist())),
                 dict(zip(reversed(NAMES), reversed(row.tolist())))):
        verdicts.append(clf.monitor().update(step))
    assert all(v == verdicts[0] for v in verdicts)


def test_clause_states_after_finish_have_no_open_clause():
    mon = PosteriorMonitor(POSTERIORS["plain"])
    mon.update([1, 1, 0, 0])
    assert "open" in set(mon.clause_states())
    mon.finish()
    states = mon.clause_states()
    assert set(states) <= {"satisfied", "violated"}
    assert dict(states.items())[("G", "safe")] == "satisfied"


def test_monitor_proba_accepts_every_trace_format():
    clf = CLASSIFIERS["plain"]
    X = [pd.DataFrame([[1, 0, 0, 1], [1, 1, 1, 1]], columns=NAMES),
         pd.DataFrame([[0, 1, 0, 0]], columns=NAMES)]
    rows = clf.monitor_proba(X)
    assert [r.shape for r in rows] == [(2, 3), (1, 3)]
    np.testing.assert_allclose([r.sum(axis=1) for r in rows][0], 1.0)


@pytest.mark.parametrize("step, message", [
    ([1, 0, 1], "step 0 has 3 propositions, but the posterior was inferred over 4"),
    (np.ones((1, 4)), "step 0 must be a 1-D array"),
    ([1, 2, 0, 0], "step 0: proposition 'a' has value 2"),
    ([1, np.nan, 0, 0], "step 0: proposition 'a' is nan"),
    (["1", "0", "0", "0"], "step 0: proposition 'safe' has the non-numeric value '1'"),
    ({"safe": 1, "a": 0, "b": 0}, "step 0: proposition 'c_ok' is missing"),
    ({"safe": 1, "a": 0, "b": 0, "c_ok": 0, "d": 1}, "step 0: unknown proposition 'd'"),
    (pd.Series([1, 0, 0, 0], index=["safe", "a", "b", "zz"]), "unknown proposition 'zz'"),
])
def test_bad_steps_name_the_step_and_proposition(step, message):
    mon = CLASSIFIERS["plain"].monitor()
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        mon.update(step)
    assert mon.n_steps == 0


def test_bad_step_later_in_the_trace_names_its_index():
    mon = CLASSIFIERS["plain"].monitor()
    mon.update([1, 0, 0, 0])
    mon.update([1, 0, 0, 0])
    with pytest.raises(ValueError, match="step 2: proposition 'b' has value -1"):
        mon.update([1, 0, -1, 0])


def test_update_after_finish_and_finish_twice_are_errors():
    mon = CLASSIFIERS["plain"].monitor()
    with pytest.raises(ValueError, match="at least one step"):
        mon.finish()
    mon.update([1, 0, 0, 0])
    mon.finish()
    with pytest.raises(ValueError, match=r"closed by finish\(\) after 1 steps; call reset"):
        mon.update([1, 0, 0, 0])
    with pytest.raises(ValueError, match="already closed"):
        mon.finish()


def test_binarize_and_monitor_parameters():
    clf = CLASSIFIERS["plain"]
    mon = PosteriorMonitor(clf.posterior_, binarize=0.5)
    assert mon.update([0.9, 0.1, 0.0, 0.7]) == clf.monitor().update([1, 0, 0, 1])
    with pytest.raises(ValueError, match="PosteriorMonitor: posterior must be"):
        PosteriorMonitor("not a posterior")


def test_monitor_needs_a_fitted_classifier():
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        BSIClassifier().monitor()
    with pytest.raises(NotFittedError):
        BSIClassifier().monitor_proba([np.ones((2, 2))])


def test_integer_proposition_names_without_frames():
    X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], random_state=0).fit(X)
    mon = clf.monitor()
    assert mon.names == [0, 1, 2]
    assert mon.update({0: 1, 1: 0, 2: 0}) == clf.monitor().update([1, 0, 0])


def test_bsi_monitor_writes_tables_and_plots(tmp_path, capsys):
    from bsi_sklearn.cli import main
    from bsi_sklearn.io import write_traces_csv
    from bsi_sklearn.monitor.figure import monitor_frame

    clf = CLASSIFIERS["plain"]
    clf.posterior_.to_json(tmp_path / "posterior.json")
    X = [pd.DataFrame([[1, 0, 0, 1], [1, 1, 0, 1], [0, 1, 1, 1]], columns=NAMES),
         pd.DataFrame([[1, 1, 1, 0]], columns=NAMES)]
    write_traces_csv(X, None, tmp_path / "demos.csv")
    assert main(["monitor", str(tmp_path / "posterior.json"), str(tmp_path / "demos.csv"),
                 "--out", str(tmp_path / "out")]) == 0
    printed = capsys.readouterr().out
    assert "demos.csv [0]: 3 steps, P(satisfied) at the end" in printed
    for i, trace in enumerate(X):
        table = pd.read_csv(tmp_path / "out" / f"demos_{i}_monitor.csv", keep_default_na=False)
        expected = monitor_frame(clf.posterior_, trace)
        np.testing.assert_allclose(table[["p_satisfied", "p_violated", "p_open"]],
                                   expected[["p_satisfied", "p_violated", "p_open"]])
        assert table["events"].tolist() == expected["events"].tolist()
        assert table["p_satisfied"].iloc[-1] == pytest.approx(
            clf.posterior_.predict_proba([trace])[0, 1], abs=1e-15)
        assert (tmp_path / "out" / f"demos_{i}_monitor.png").stat().st_size > 1000


def test_monitor_frame_marks_events_and_closes():
    from bsi_sklearn.monitor.figure import monitor_frame, plot_monitor

    post = POSTERIORS["plain"]
    trace = np.array([[1, 0, 0, 1], [1, 1, 0, 1], [0, 1, 1, 1]])
    frame = monitor_frame(post, trace)
    assert frame["closed"].tolist() == [False, False, False, True]
    assert frame["p_open"].iloc[-1] == 0.0
    assert "G(safe) violated" in frame["events"].iloc[2]
    assert plot_monitor(frame, title="t").get_title() == "t"
    with pytest.raises(ValueError, match="no steps"):
        monitor_frame(post, np.zeros((0, 4)))

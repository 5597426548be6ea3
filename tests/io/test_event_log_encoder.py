"""EventLogEncoder: the encodings, the inputs it takes, errors by case, sklearn conventions.

scikit-learn's ``parametrize_with_checks`` does not apply: its checks feed 2-D numeric arrays
and compare the output as an array of shape (n_samples, n_features), while this transformer
reads a list of cases (sequences of activity names) and returns a list of traces of different
lengths. The conventions that do apply (clone, get_params / set_params, parameters left as
given, fit returns self, NotFittedError, pickling, composition in a Pipeline and in
cross_val_score) are tested here one by one.
"""

import pickle

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.model_selection import cross_val_score
from sklearn.pipeline import make_pipeline

from bsi_sklearn import BSIClassifier, Specification
from bsi_sklearn.io import EventLogEncoder, read_event_log

SEQS = [["order", "pay", "ship"], ["order", "ship", "pay"], ["ship", "order"]]


def test_occurred_encoding_steps_and_reading_of_F_and_U():
    traces = EventLogEncoder(negations=False).fit_transform(SEQS)
    assert [t.shape for t in traces] == [(4, 3), (4, 3), (3, 3)]
    assert list(traces[0].columns) == ["order", "pay", "ship"]
    np.testing.assert_array_equal(traces[2].to_numpy(), [[0, 0, 0], [0, 0, 1], [1, 0, 1]])
    # F(pay): pay occurs; (!ship U order): order occurs, before any ship
    f_pay = Specification(eventuals={"pay"})
    order_first = Specification(orders={("order", "ship")})
    assert [f_pay.satisfied_by(t) for t in traces] == [True, True, False]
    assert [order_first.satisfied_by(t) for t in traces] == [True, True, False]


def test_current_encoding():
    (trace,) = EventLogEncoder(encoding="current",
                               negations=False).fit_transform([["a", "b", "a"]])
    np.testing.assert_array_equal(trace.to_numpy(), [[0, 0], [1, 0], [0, 1], [1, 0]])


def test_inputs_agree_and_round_trip_from_an_event_frame():
    frame = pd.DataFrame({
        "case:concept:name": ["c2", "c1", "c1", "c2", "c1"],
        "concept:name": ["b", "c", "a", "a", "b"],
        "time:timestamp": pd.to_datetime(["2024-01-02", "2024-01-03", "2024-01-01",
                                          "2024-01-01", "2024-01-02"]),
        "who": ["x", "y", "x", "y", "x"]})
    cases, _, ids = read_event_log(frame)
    assert ids.tolist() == ["c2", "c1"]
    seqs = [["a", "b"], ["a", "b", "c"]]
    from_frames = EventLogEncoder().fit_transform(cases)
    from_seqs = EventLogEncoder().fit_transform(seqs)
    from_frame = EventLogEncoder().fit_transform(frame)
    from_array = EventLogEncoder().fit_transform(np.array([["a", "b"], ["a", "c"]]))
    assert from_array[1]["c"].tolist() == [False, False, True]
    for got in (from_seqs, from_frame):
        for g, e in zip(got, from_frames):
            pd.testing.assert_frame_equal(g, e)
    # round trip: the traces' steps say which activity each event was
    for trace, seq in zip(from_frames, seqs):
        new = np.diff(trace.to_numpy().astype(int), axis=0).argmax(axis=1)
        assert trace.columns[new].tolist() == seq


def test_attribute_predicates():
    cases, _, _ = read_event_log(pd.DataFrame({
        "case:concept:name": ["c", "c", "c"], "concept:name": ["a", "b", "a"],
        "who": ["x", "y", "x"], "cost": [1, 5, 2]}))
    enc = EventLogEncoder(negations=False,
                          attributes={"by_y": ("who", "y"),
                                      "dear": lambda ev: (ev["cost"] > 4).to_numpy()})
    (trace,) = enc.fit_transform(cases)
    assert enc.get_feature_names_out().tolist() == ["a", "b", "by_y", "dear"]
    assert trace["by_y"].tolist() == [False, False, True, True]
    with pytest.raises(ValueError, match=r"attributes\['by_y'\] needs the cases as DataFrames"):
        enc.fit([["a"]])
    with pytest.raises(ValueError, match=r"returned shape \(1,\); it must return one boolean"):
        EventLogEncoder(attributes={"p": lambda ev: np.ones(1, bool)}).fit_transform(cases)
    with pytest.raises(ValueError, match="the attribute proposition 'a' has the name of an"):
        EventLogEncoder(attributes={"a": ("who", "x")}).fit(cases)


def test_unknown_activities():
    enc = EventLogEncoder().fit(SEQS)
    with pytest.raises(ValueError, match=r"case 1, event 1 has the activity 'refund', unseen"):
        enc.transform([["order"], ["order", "refund"]])
    (trace,) = clone(enc).set_params(handle_unknown="ignore").fit(SEQS).transform(
        [["order", "refund", "ship"]])
    # the unknown event's step changes no column, the negations' neither
    np.testing.assert_array_equal(trace.to_numpy().astype(int),
                                  [[0, 0, 0, 1, 1, 1], [1, 0, 0, 0, 1, 1], [1, 0, 0, 0, 1, 1],
                                   [1, 0, 1, 0, 1, 0]])


@pytest.mark.parametrize("X, message", [
    ([["a"], []], "case 1 has no events"),
    ([["a", None]], "case 0, event 1 has no activity"),
    (["abc"], "case 0 is a str; a case is a DataFrame of events or a sequence"),
    ([], "X has no cases"),
    ([[1, "1"]], "two different activity values read as '1'"),
    ({"a": 1}, "X must be a list of cases"),
])
def test_bad_cases_name_the_case(X, message):
    with pytest.raises(ValueError, match=message):
        EventLogEncoder().fit(X)


def test_parameters_are_validated_in_fit():
    with pytest.raises(ValueError, match="EventLogEncoder: encoding must be one of"):
        EventLogEncoder(encoding="last").fit(SEQS)
    with pytest.raises(ValueError, match="handle_unknown must be one of"):
        EventLogEncoder(handle_unknown="skip").fit(SEQS)


def test_sklearn_conventions_and_pickle():
    enc = EventLogEncoder(encoding="current")
    assert enc.get_params() == {"encoding": "current", "attributes": None,
                                "handle_unknown": "error", "repeats": False, "negations": True,
                                "case_id": "case:concept:name",
                                "activity": "concept:name", "timestamp": "time:timestamp"}
    assert clone(enc).get_params() == enc.get_params()
    with pytest.raises(NotFittedError):
        enc.transform(SEQS)
    assert enc.fit(SEQS) is enc and enc.encoding == "current"
    assert not hasattr(clone(enc), "activities_")
    again = pickle.loads(pickle.dumps(enc))
    for a, b in zip(enc.transform(SEQS), again.transform(SEQS)):
        pd.testing.assert_frame_equal(a, b)


def log_of(n_cases, seed=0):
    """Acceptable cases pay before they ship; others ship first."""
    rng = np.random.default_rng(seed)
    seqs, y = [], []
    for i in range(n_cases):
        good = i % 2 == 0
        tail = ["pay", "ship"] if good else ["ship", "pay"]
        extra = ["check"] if rng.random() < 0.5 else []
        seqs.append(["order", *extra, *tail])
        y.append(int(good))
    return seqs, np.array(y)


def test_pipeline_with_bsi_and_cross_validation():
    seqs, y = log_of(24)
    pipe = make_pipeline(EventLogEncoder(),
                         BSIClassifier(subtasks=["pay", "ship"], global_candidates=[],
                                       conditions={}, random_state=0))
    pipe.fit(seqs, y)
    assert pipe[-1].map_specification_.orders == frozenset({("pay", "ship")})
    assert pipe.score(seqs, y) == 1.0
    scores = cross_val_score(pipe, seqs, y, cv=3)
    assert scores.tolist() == [1.0, 1.0, 1.0]


def test_negations_encode_absence_and_stay_global_candidates():
    seqs = [["order", "pay", "ship"], ["order", "ship"], ["order", "refund", "ship"],
            ["order", "pay", "refund"]]
    enc = EventLogEncoder(negations=True)
    traces = enc.fit_transform(seqs)
    names = ["order", "pay", "refund", "ship", "!order", "!pay", "!refund", "!ship"]
    assert enc.get_feature_names_out().tolist() == names
    for trace in traces:  # each negated column is the complement of its activity's
        data = trace.to_numpy()
        np.testing.assert_array_equal(data[:, 4:], ~data[:, :4])
    # G(!refund) is Declare's absence: refund never occurs
    absence = Specification(globals={"!refund"})
    assert [absence.satisfied_by(t) for t in traces] == [True, True, False, False]
    # under "current" the negation is "the current event is not a", and G still reads absence
    current = EventLogEncoder(encoding="current", negations=True).fit_transform(seqs)
    assert [absence.satisfied_by(t) for t in current] == [True, True, False, False]
    # a negated column starts true and never rises: inferred roles keep it out of the
    # subtasks and the conditions, so it adds G clauses and nothing else
    clf = BSIClassifier(random_state=0).fit(traces, [1, 1, 0, 0])
    assert not any(str(w).startswith("!") for w in clf.roles_["subtasks"])
    assert not any(str(c).startswith("!") for c in clf.roles_["conditions"].values())
    assert "!refund" in clf.roles_["global_candidates"]
    assert "!refund" in clf.map_specification_.globals


def test_negations_with_attributes_and_a_name_clash():
    cases, _, _ = read_event_log(pd.DataFrame({
        "case:concept:name": ["c", "c"], "concept:name": ["a", "b"], "who": ["x", "y"]}))
    enc = EventLogEncoder(negations=True, attributes={"by_x": ("who", "x")}).fit(cases)
    assert enc.get_feature_names_out().tolist() == ["a", "b", "by_x", "!a", "!b", "!by_x"]
    (trace,) = enc.transform(cases)
    assert trace["!by_x"].tolist() == [True, False, False]
    with pytest.raises(ValueError, match=r"negation of 'a' '!a', which is already a proposition"):
        EventLogEncoder(negations=True).fit([["a", "!a"]])


def test_negations_name_the_negated_activities():
    enc = EventLogEncoder().fit([["order", "pay"], ["order"]])
    assert enc.negations_ == {"!order": "order", "!pay": "pay"}
    assert EventLogEncoder(negations=False).fit([["order"]]).negations_ == {}
    spec = Specification(globals=["!pay"], orders=[("order", "!pay")])
    assert spec.readable(negations=enc.negations_) == "G(!pay) & (pay U order)"
    # an activity whose name starts with "!" is no negation without them
    plain = EventLogEncoder(negations=False).fit([["!x", "y"]])
    assert Specification(globals=["!x"]).readable(negations=plain.negations_) == 'G("!x")'


def test_repeats_encode_at_most_once_so_far_against_counting():
    rng = np.random.default_rng(0)
    acts = ["a", "b", "c", "d"]
    seqs = [list(rng.choice(acts[:3], size=rng.integers(1, 7))) for _ in range(60)]
    enc = EventLogEncoder(repeats=True)
    traces = enc.fit_transform(seqs)
    assert enc.repeated_.tolist() == ["a", "b", "c"]
    assert enc.repeats_ == {"a<=1": "a", "b<=1": "b", "c<=1": "c"}
    assert enc.get_feature_names_out().tolist() == [
        "a", "b", "c", "!a", "!b", "!c", "a<=1", "b<=1", "c<=1"]
    for seq, trace in zip(seqs, traces):
        for a in acts[:3]:
            counts = np.cumsum([0] + [e == a for e in seq])
            np.testing.assert_array_equal(trace[a].to_numpy(), counts >= 1)
            np.testing.assert_array_equal(trace[f"!{a}"].to_numpy(), counts < 1)
            np.testing.assert_array_equal(trace[f"{a}<=1"].to_numpy(), counts <= 1)
        # G(a<=1) is Declare's Absence2: a occurs at most once
        at_most_once = Specification(globals=["a<=1"]).satisfied_by(trace)
        assert at_most_once == (seq.count("a") <= 1)
    # only activities seen twice in a fitted case get a<=1; unknown activities never count
    enc = EventLogEncoder(repeats=True, negations=False, handle_unknown="ignore")
    (trace,) = enc.fit([["a", "b", "a"], ["b", "c"]]).transform([["x", "b", "x", "b", "c"]])
    assert enc.repeated_.tolist() == ["a"]
    assert list(trace.columns) == ["a", "b", "c", "a<=1"] and trace["a<=1"].all()
    assert EventLogEncoder().fit([["a", "a"]]).repeated_.tolist() == []


def test_repeats_stay_global_candidates():
    # a<=1 never rises: inferred roles keep it out of the subtasks and the conditions
    seqs = [["order", "pay", "ship"], ["order", "ship", "pay"], ["order", "pay", "pay", "ship"],
            ["order", "pay", "ship", "pay"]]
    traces = EventLogEncoder(repeats=True).fit_transform(seqs)
    clf = BSIClassifier(random_state=0).fit(traces, [1, 1, 0, 0])
    assert "pay<=1" in clf.roles_["global_candidates"]
    assert "pay<=1" not in clf.roles_["subtasks"]
    assert "pay<=1" in clf.map_specification_.globals


def test_repeats_need_the_occurred_encoding_and_their_own_names():
    with pytest.raises(ValueError, match="repeats=True needs encoding='occurred'"):
        EventLogEncoder(repeats=True, encoding="current").fit([["a"]])
    with pytest.raises(ValueError, match=r"names 'a<=1' the repetition of 'a'"):
        EventLogEncoder(repeats=True).fit([["a", "a", "a<=1"]])

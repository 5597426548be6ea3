"""Posterior.to_json / from_json: a portable posterior with identical predictions."""

import json

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import BSIClassifier, Posterior
from bsi_sklearn.posterior import SCHEMA, SCHEMA_VERSION

NAMES = ["safe", "a", "b", "c_ok"]


def _data(seed=0, n=8, frames=True):
    rng = np.random.default_rng(seed)
    X = [rng.integers(0, 2, size=(int(rng.integers(2, 6)), 4)) for _ in range(n)]
    y = np.array([1, 1, 0, 1, 1, 0, 1, 1][:n])
    if frames:
        X = [pd.DataFrame(x, columns=NAMES) for x in X]
    return X, y


@pytest.mark.parametrize("kwargs, frames", [
    (dict(global_candidates=["safe"], subtasks=["a", "b", "c_ok"],
          conditions={"a": "c_ok"}, prior="forest", likelihood="ci"), True),
    (dict(prior="linear_chain", inference="mcmc", n_samples=300, burn_in=10, n_chains=2,
          p_eventual=0.5), False),
])
def test_round_trip_gives_identical_predictions(kwargs, frames, tmp_path):
    X, y = _data(frames=frames)
    clf = BSIClassifier(random_state=0, **kwargs).fit(X, y)
    post = clf.posterior_
    text = post.to_json(tmp_path / "posterior.json")
    loaded = [Posterior.from_json(text), Posterior.from_json(tmp_path / "posterior.json"),
              Posterior.read_json(tmp_path / "posterior.json"),
              Posterior.read_json(str(tmp_path / "posterior.json"))]
    for again in loaded:
        np.testing.assert_array_equal(again.predict_proba(X), post.predict_proba(X))
        np.testing.assert_array_equal(again.probabilities, post.probabilities)
        assert again.specifications == post.specifications
        pd.testing.assert_series_equal(again.clause_marginals(), post.clause_marginals())
        assert again.dropped_mass == post.dropped_mass
        assert again.roles.names == list(post.roles.names)
    doc = json.loads(text)
    # without pattern candidates or a MAP listed after others the file is version 1, as
    # before them; SCHEMA_VERSION is 3
    assert doc["schema"] == SCHEMA and doc["version"] == 1 and SCHEMA_VERSION == 3
    assert doc["specifications"][0]["ltl"] == clf.map_specification_.to_ltl()
    assert set(doc) == {"schema", "version", "names", "roles", "specifications",
                        "probabilities", "clause_marginals", "dropped_mass"}


def test_monitor_of_a_loaded_posterior_agrees():
    from bsi_sklearn.monitor.posterior_monitor import PosteriorMonitor

    X, y = _data()
    clf = BSIClassifier(random_state=0).fit(X, y)
    again = Posterior.from_json(clf.posterior_.to_json())
    a, b = clf.monitor(), PosteriorMonitor(again)
    for row in X[0].to_numpy():
        assert a.update(row) == b.update(row)


def _doc():
    X, y = _data()
    return json.loads(BSIClassifier(random_state=0).fit(X, y).posterior_.to_json())


@pytest.mark.parametrize("edit, message", [
    (lambda d: d.update(schema="something/else"), "schema: expected 'bsi-sklearn/posterior', "
                                                  "got 'something/else'"),
    (lambda d: d.update(version=4), "schema version 4 is not supported; this bsi-sklearn "
                                    "reads versions 1, 2, 3"),
    (lambda d: d["roles"]["subtasks"].append("zz"), "roles.subtasks\\[\\d+\\]: 'zz' is not one "
                                                    "of the names"),
    (lambda d: d["probabilities"].pop(), "probabilities: .* probabilities for .* "
                                         "specifications"),
    (lambda d: d["specifications"][0]["globals"].append("nope"),
     "specifications\\[0\\].globals\\[.\\]: 'nope' is not a global candidate"),
    (lambda d: d["specifications"][0].update(orders=[["a", "b"], ["c_ok", "b"]]),
     "specifications\\[0\\].orders: not a forest"),
    (lambda d: d["clause_marginals"].pop(), "clause_marginals: .* entries for the .* "
                                            "candidate clauses"),
])
def test_bad_documents_say_what_is_wrong(edit, message):
    doc = _doc()
    edit(doc)
    with pytest.raises(ValueError, match=message):
        Posterior.from_json(json.dumps(doc))


def test_not_json_or_not_an_object():
    with pytest.raises(ValueError, match="not JSON"):
        Posterior.from_json("{nope")
    with pytest.raises(ValueError, match="schema: expected"):
        Posterior.from_json("{}")


def test_bsi_fit_save_writes_a_posterior(tmp_path, capsys):
    from bsi_sklearn.cli import main
    from bsi_sklearn.io import read_traces_csv, write_traces_csv

    X, y = _data()
    for name in ("one", "two"):
        write_traces_csv(X, y, tmp_path / f"{name}.csv")
    out = tmp_path / "posterior.json"
    assert main(["fit", str(tmp_path / "one.csv"), "--save", str(out)]) == 0
    assert f"saved      : {out}" in capsys.readouterr().out
    Xr, yr = read_traces_csv(tmp_path / "one.csv")
    clf = BSIClassifier(random_state=0).fit(Xr, yr)
    # The file holds the posterior, so its predictions are the vote (the posterior mass
    # satisfied), bit for bit the classifier's under vote="satisfaction".
    np.testing.assert_array_equal(Posterior.from_json(out).predict_proba(Xr),
                                  clf.set_params(vote="satisfaction").predict_proba(Xr))
    assert main(["fit", str(tmp_path / "one.csv"), str(tmp_path / "two.csv"),
                 "--save", str(out)]) == 0
    assert (tmp_path / "posterior_one.json").exists()
    assert (tmp_path / "posterior_two.json").exists()


def _sampled_posterior(map_index):
    """Four specifications listed by sample frequency, the most probable at ``map_index``."""
    X, y = _data()
    post = BSIClassifier(random_state=0).fit(X, y).posterior_
    rows = np.arange(4)
    return Posterior(post._structures[rows], post._tau[rows], post._w1[rows],
                     [0.5, 0.3, 0.2, 0.0], post.roles, map_index=map_index), X


@pytest.mark.parametrize("map_index", [1, 3])
def test_a_map_listed_after_others_survives_the_file(map_index, tmp_path):
    # A posterior reported by its samples lists them by frequency: the MAP (the most
    # probable found) may come later, sampled less often, or never (probability 0).
    post, X = _sampled_posterior(map_index)
    assert post.map_specification == post.specification(map_index)
    assert f"p_map={post.probabilities[map_index]:.4g}" in repr(post)
    doc = json.loads(post.to_json())
    assert doc["version"] == 3 and doc["map_index"] == map_index
    assert doc["roles"]["patterns"] == []  # version 3 keeps version 2's fields
    again = Posterior.from_json(json.dumps(doc))
    assert again.map_index == map_index and again.map_specification == post.map_specification
    np.testing.assert_array_equal(again.predict_proba(X), post.predict_proba(X))
    # Cut short, the file keeps the MAP, last (no more probable than those kept before it).
    short = Posterior.from_json(post.to_json(max_specifications=2))
    assert short.specifications == [post.specification(0), post.map_specification]
    assert short.map_index == 1
    np.testing.assert_allclose(short.probabilities.sum(), 1.0)
    only = Posterior.from_json(post.to_json(max_specifications=1))
    assert only.specifications == [post.map_specification] and only.map_index == 0
    assert only.probabilities.tolist() == [1.0]
    assert json.loads(post.to_json(max_specifications=1))["version"] == 1


@pytest.mark.parametrize("value, message", [
    (4, "map_index: expected the position of a listed specification \\(an integer from 0 "
        "to 3\\), got .*4"),
    (-1, "map_index: expected .* got .*-1"),
    (1.0, "map_index: expected .* got .*1.0"),
    (True, "map_index: expected .* got .*True"),
])
def test_a_bad_map_index_says_what_is_wrong(value, message):
    doc = json.loads(_sampled_posterior(1)[0].to_json())
    doc["map_index"] = value
    with pytest.raises(ValueError, match=message):
        Posterior.from_json(json.dumps(doc))
    del doc["map_index"]
    with pytest.raises(ValueError, match="missing field 'map_index'"):
        Posterior.from_json(json.dumps(doc))
    doc.update(version=2, map_index=1)
    with pytest.raises(ValueError, match="unknown field 'map_index'"):
        Posterior.from_json(json.dumps(doc))


def test_a_map_index_outside_the_listing_is_refused():
    with pytest.raises(ValueError, match="map_index=4 is not the position of one of the 4"):
        _sampled_posterior(4)


def test_a_version_3_file_follows_the_published_schema():
    import pathlib

    jsonschema = pytest.importorskip("jsonschema")
    root = pathlib.Path(__file__).resolve().parents[1]
    schema = json.loads((root / "docs" / "posterior-schema.json").read_text())
    doc = json.loads(_sampled_posterior(2)[0].to_json())
    jsonschema.validate(doc, schema)
    for edit in (lambda d: d.pop("map_index"), lambda d: d.update(version=2),
                 lambda d: d.update(map_index="2")):
        bad = json.loads(json.dumps(doc))
        edit(bad)
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(bad, schema)

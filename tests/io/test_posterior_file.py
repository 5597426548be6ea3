"""The posterior file under bad input and faults (issue 21): every failure a ValueError naming
the field, text never taken for a path, names enforced at predict time, atomic and small files.
"""

import copy
import json
import os
import pathlib
import subprocess
import sys
import time
import warnings

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bsi_sklearn import BSIClassifier, Posterior
from bsi_sklearn.data.roles import Roles
from bsi_sklearn.io.posterior_file import MAX_LISTED

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAMES = ["safe", "a", "b", "c_ok"]


def _data(seed=0, n=8):
    rng = np.random.default_rng(seed)
    X = [pd.DataFrame(rng.integers(0, 2, size=(int(rng.integers(2, 6)), 4)), columns=NAMES)
         for _ in range(n)]
    return X, np.array([1, 1, 0, 1, 1, 0, 1, 1][:n])


@pytest.fixture(scope="module")
def fitted():
    X, y = _data()
    clf = BSIClassifier(global_candidates=["safe"], subtasks=["a", "b", "c_ok"],
                        conditions={"a": "c_ok"}, random_state=0).fit(X, y)
    return clf, X, y


@pytest.fixture
def doc(fitted):
    return json.loads(fitted[0].posterior_.to_json())


def _load(doc):
    return Posterior.from_json(json.dumps(doc))


# ---------------------------------------------------------------- probabilities
@pytest.mark.parametrize("edit, message", [
    (lambda p: [x / 2 for x in p], r"probabilities: sum to 0\.(5|4999)\d*, not 1"),
    (lambda p: [-0.1] + p[1:], r"probabilities\[0\]: -0\.1 is negative"),
    (lambda p: [float("nan")] + p[1:], r"from_json: NaN is not a JSON number \(JSON has no NaN"),
    (lambda p: ["0.5"] + p[1:], r"probabilities\[0\]: expected a number, got a string '0\.5'"),
    (lambda p: [True] + p[1:], r"probabilities\[0\]: expected a number, got a boolean"),
    (lambda p: [None] + p[1:], r"probabilities\[0\]: expected a number, got null"),
    (lambda p: p[::-1], r"probabilities\[\d+\]: .* is larger than the one before"),
    (lambda p: [1.5] + p[1:], r"probabilities\[0\]: 1\.5 is above 1"),
])
def test_probabilities_must_be_a_distribution(doc, edit, message):
    doc["probabilities"] = edit(doc["probabilities"])
    text = json.dumps(doc)  # json writes NaN as the bare word NaN
    with pytest.raises(ValueError, match=message):
        Posterior.from_json(text)


# ---------------------------------------------------------------- malformed documents
@pytest.mark.parametrize("edit, message", [
    (lambda d: d.pop("roles"), r"\(document\): missing field 'roles'"),
    (lambda d: d.update(roles=3), r"roles: expected an object, got a number"),
    (lambda d: d.update(names=5), r"names: expected a list, got a number"),
    (lambda d: d.update(names=[]), r"names: the list is empty"),
    (lambda d: d["names"].append("safe"), r"names\[4\]: 'safe' is listed twice"),
    (lambda d: d["names"].__setitem__(0, 1.5), r"names\[0\]: a proposition name is a string"),
    (lambda d: d["roles"].update(conditions=[0]), r"roles.conditions\[0\]: expected a pair"),
    (lambda d: d["roles"].update(conditions=[["a", "a"]]),
     r"roles.conditions\[0\]: subtask 'a' is its own condition"),
    (lambda d: d["roles"].update(conditions=[["safe", "a"]]),
     r"roles.conditions\[0\]: 'safe' is not one of the subtasks"),
    (lambda d: d["roles"].update(subtasks=0), r"roles.subtasks: expected a list"),
    (lambda d: d["specifications"].__setitem__(0, 7),
     r"specifications\[0\]: expected an object, got a number"),
    (lambda d: d["specifications"][0].pop("ltl"), r"specifications\[0\]: missing field 'ltl'"),
    (lambda d: d["specifications"][0].update(extra=1),
     r"specifications\[0\]: unknown field 'extra'"),
    (lambda d: d["specifications"][0].update(ltl="true"),
     r"specifications\[0\].ltl: 'true' is not the formula"),
    (lambda d: d["specifications"][0].update(orders=[["a"]]),
     r"specifications\[0\].orders\[0\]: expected a pair"),
    (lambda d: d["specifications"][0].update(orders=[["a", "a"]]),
     r"specifications\[0\].orders\[0\]\[1\]: 'a' is listed twice"),
    (lambda d: d["specifications"][0].update(eventuals=["safe"]),
     r"specifications\[0\].eventuals\[0\]: 'safe' is not a subtask"),
    (lambda d: d["specifications"][0].update(eventuals=[["a"]]),
     r"specifications\[0\].eventuals\[0\]: \['a'\] is not a subtask"),
    (lambda d: d["specifications"].__setitem__(1, d["specifications"][0]),
     r"specifications\[0\]: listed more than once"),
    (lambda d: d.update(specifications=[], probabilities=[]),
     r"specifications: the list is empty"),
    (lambda d: d["clause_marginals"].__setitem__(0, 0.5),
     r"clause_marginals\[0\]: expected a pair"),
    (lambda d: d["clause_marginals"][0].__setitem__(0, ["X", "safe"]),
     r"clause_marginals\[0\]: \['X', 'safe'\] is not a clause key"),
    (lambda d: d["clause_marginals"][0].__setitem__(0, ["F", "safe"]),
     r"clause_marginals\[0\]: the key \['F', 'safe'\] should be \['G', 'safe'\]"),
    (lambda d: d["clause_marginals"][0].__setitem__(1, 2.0),
     r"clause_marginals\[0\]: 2\.0 is above"),
    (lambda d: d.update(dropped_mass="0"), r"dropped_mass: expected a number, got a string"),
    (lambda d: d.update(dropped_mass=-1), r"dropped_mass: -1\.0 is negative"),
    (lambda d: d.update(version=True), r"version: schema version True is not supported"),
    (lambda d: d.update(extra=[]), r"\(document\): unknown field 'extra'"),
])
def test_malformed_documents_name_the_field(doc, edit, message):
    edit(doc)
    with pytest.raises(ValueError, match=message):
        _load(doc)


@pytest.mark.parametrize("text, message", [
    ("[1, 2]", r"\(document\): expected an object, got a list"),
    ("", r"not JSON .*a str is the JSON text: to read a file, pass a pathlib.Path"),
    ("posterior.json", r"not JSON .*Posterior.read_json\(path\)"),
    ("3", r"\(document\): expected an object, got a number"),
    (b"\xff\xfe", r"not UTF-8|not JSON"),
])
def test_text_is_never_taken_for_a_path(text, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "posterior.json").write_text("{}")  # a file of that name changes nothing
    with pytest.raises(ValueError, match=message):
        Posterior.from_json(text)


def test_from_json_refuses_other_objects(doc):
    with pytest.raises(ValueError, match="expected the JSON text as str or bytes"):
        Posterior.from_json(doc)


def test_read_json_names_the_file(tmp_path, doc):
    bad = tmp_path / "bad.json"
    doc["probabilities"][0] = -1
    bad.write_text(json.dumps(doc))
    with pytest.raises(ValueError, match=r"read_json: '.*bad.json': probabilities\[0\]"):
        Posterior.read_json(bad)
    truncated = tmp_path / "cut.json"
    truncated.write_text(json.dumps(doc)[:100])
    with pytest.raises(ValueError, match=r"read_json: '.*cut.json': not JSON"):
        Posterior.read_json(truncated)
    with pytest.raises(ValueError, match=r"read_json: '.*' is a folder"):
        Posterior.read_json(tmp_path)
    with pytest.raises(ValueError, match="read_json: the path is empty"):
        Posterior.read_json("")
    with pytest.raises(FileNotFoundError):
        Posterior.read_json(tmp_path / "missing.json")


_MUTATIONS = st.sampled_from(["drop", "none", "int", "str", "list", "dict", "neg", "nan_str"])


def _paths(value, prefix=()):
    yield prefix
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(value, list):
        for k, v in enumerate(value[:3]):
            yield from _paths(v, (*prefix, k))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_fuzzed_documents_load_or_raise_value_error(doc, data):
    doc = copy.deepcopy(doc)
    paths = [p for p in _paths(doc) if p]
    for _ in range(data.draw(st.integers(1, 3))):
        path = data.draw(st.sampled_from(paths))
        kind = data.draw(_MUTATIONS)
        parent = doc
        try:
            for key in path[:-1]:
                parent = parent[key]
            key = path[-1]
            parent[key]  # noqa: B018 - the path may be gone after an earlier mutation
        except (KeyError, IndexError, TypeError):
            continue
        if not isinstance(parent, (dict, list)):  # an earlier mutation made it a string
            continue
        if kind == "drop":
            del parent[key]
        else:
            parent[key] = {"none": None, "int": 7, "str": "x", "list": [], "dict": {},
                           "neg": -0.5, "nan_str": "NaN"}[kind]
    try:
        _load(doc)
    except ValueError as exc:
        assert str(exc).startswith("Posterior.from_json: ")


# ---------------------------------------------------------------- names at predict time
def test_loaded_posterior_enforces_column_names(fitted):
    clf, X, _ = fitted
    again = Posterior.from_json(clf.posterior_.to_json())
    np.testing.assert_array_equal(again.predict_proba(X), clf.posterior_.predict_proba(X))
    reordered = [x[NAMES[::-1]] for x in X]
    with pytest.raises(ValueError, match="feature names should match"):
        clf.predict_proba(reordered)
    with pytest.raises(ValueError, match="feature names should match"):
        again.predict_proba(reordered)
    renamed = [x.set_axis(["p", "q", "r", "s"], axis=1) for x in X]
    with pytest.raises(ValueError, match="feature names should match"):
        again.predict_proba(renamed)
    with pytest.warns(UserWarning, match="X does not have valid feature names"):
        again.predict_proba([x.to_numpy() for x in X])


def test_posterior_without_names_warns_on_frames():
    X = [np.array([[1, 0], [1, 1]])]
    post = BSIClassifier(random_state=0).fit(X).posterior_
    again = Posterior.from_json(post.to_json())
    assert again.feature_names_in_ is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        again.predict_proba(X)
    with pytest.warns(UserWarning, match="X has feature names"):
        again.predict_proba([pd.DataFrame(X[0], columns=["u", "v"])])


# ---------------------------------------------------------------- writing
def test_to_json_refuses_folders_and_missing_folders(fitted, tmp_path):
    post = fitted[0].posterior_
    with pytest.raises(ValueError, match="is a folder; give a file name"):
        post.to_json(tmp_path)
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match="'.*file' is not a folder"):
        post.to_json(tmp_path / "file" / "posterior.json")
    with pytest.raises(ValueError, match="'.*nope' does not exist"):
        post.to_json(tmp_path / "nope" / "posterior.json")


_FAILING_WRITE = """
import resource, signal, sys
from bsi_sklearn import Posterior
post = Posterior.read_json(sys.argv[1])
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (200, 200))
try:
    post.to_json(sys.argv[1])
except OSError as exc:
    print("failed:", exc.errno)
"""


@pytest.mark.skipif(sys.platform == "win32", reason="file-size limit is POSIX")
def test_a_failed_write_leaves_the_previous_file(fitted, tmp_path):
    path = tmp_path / "posterior.json"
    fitted[0].posterior_.to_json(path)
    before = path.read_bytes()
    assert len(before) > 200
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", _FAILING_WRITE, str(path)], env=env,
                         capture_output=True, text=True, timeout=300)
    assert "failed: 27" in out.stdout, out.stderr  # EFBIG
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["posterior.json"]


def test_written_files_respect_the_umask(fitted, tmp_path):
    path = tmp_path / "posterior.json"
    old = os.umask(0o022)
    try:
        fitted[0].posterior_.to_json(path)
    finally:
        os.umask(old)
    assert path.stat().st_mode & 0o777 == 0o644


def _flat_posterior(n_specs, seed=0):
    rng = np.random.default_rng(seed)
    n_g, n = 12, 8
    codes = rng.choice(2 ** (n_g + n), size=n_specs, replace=False)
    bits = (codes[:, None] >> np.arange(n_g + n)) & 1
    names = [f"prop_{i}" for i in range(n_g + n)]
    roles = Roles(np.arange(n_g), np.arange(n_g, n_g + n), np.full(n, -1), names)
    probs = np.sort(rng.random(n_specs))[::-1]
    return Posterior(np.full((n_specs, n), -1), bits[:, :n_g].astype(bool),
                     bits[:, n_g:].astype(bool), probs / probs.sum(), roles)


@pytest.mark.slow
def test_a_large_posterior_writes_a_small_file_quickly(tmp_path):
    post = _flat_posterior(500_000)
    start = time.perf_counter()
    text = post.to_json(tmp_path / "posterior.json")
    took = time.perf_counter() - start
    size = (tmp_path / "posterior.json").stat().st_size
    assert size < 20e6, size
    assert took < 10, took  # the target is 2 s on an idle machine; shared CI cores are slower
    start = time.perf_counter()
    again = Posterior.read_json(tmp_path / "posterior.json")
    assert time.perf_counter() - start < 10
    assert len(again) == MAX_LISTED
    kept = post.probabilities[:MAX_LISTED].sum()
    assert again.dropped_mass == pytest.approx(1 - kept)
    np.testing.assert_allclose(again.probabilities, post.probabilities[:MAX_LISTED] / kept)
    pd.testing.assert_series_equal(again.clause_marginals(), post.clause_marginals())
    assert json.loads(text)["dropped_mass"] == again.dropped_mass


def test_max_specifications_caps_the_list(fitted):
    clf, X, _ = fitted
    post = clf.posterior_
    short = Posterior.from_json(post.to_json(max_specifications=2))
    assert len(short) == 2 and short.specifications == post.specifications[:2]
    kept = post.probabilities[:2].sum()
    assert short.dropped_mass == pytest.approx(1 - (1 - post.dropped_mass) * kept)
    gap = np.abs(short.predict_proba(X) - post.predict_proba(X)).max()
    assert gap <= 1 - kept + 1e-12
    every = Posterior.from_json(post.to_json(max_specifications=None))
    assert len(every) == len(post)
    with pytest.raises(ValueError, match="max_specifications"):
        post.to_json(max_specifications=0)


# ---------------------------------------------------------------- the published schema
def test_written_files_follow_the_published_schema(doc):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((ROOT / "docs" / "posterior-schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    jsonschema.validate(doc, schema)
    bad = copy.deepcopy(doc)
    bad["probabilities"][0] = "0.5"
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(bad, schema)

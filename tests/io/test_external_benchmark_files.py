"""The published samples2LTL and Scarlet benchmark files in ../shared (skipped when absent)."""

import io
from collections import Counter

import numpy as np
import pandas as pd
import pytest
from _shared_data import BENCHMARKS_DATA

from bsi_sklearn.data.preprocessing import add_negations
from bsi_sklearn.io import load_trace_file, read_trace_file, write_trace_file
from bsi_sklearn.ltl import parse_ltl

DATA = BENCHMARKS_DATA
SAMPLES = DATA / "samples2LTL" / "traces" / "finite"
SCARLET = DATA / "scarlet" / "All_benchmarks" / "RQ2-benchmarks" / "Varying_form"

pytestmark = pytest.mark.shared_data

# Targets the BSI template expresses (G(!x0) only with negated propositions).
IN_TEMPLATE = {"G(x0)", "F(x0)", "G(!(x0))", "F(a)", "&(F(a),F(b))", "&(&(F(a),F(b)),F(c))",
               "&(&(&(F(a),F(b)),F(c)),F(d))", "&(&(&(&(F(a),F(b)),F(c)),F(d)),F(e))"}


@pytest.fixture(scope="module")
def files():
    paths = sorted(SAMPLES.glob("*/*/*.trace")) + sorted((SCARLET / "TracesFiles").glob("*.trace"))
    return {p: read_trace_file(p) for p in paths}


def kind(path):
    if SCARLET.resolve() in path.resolve().parents:
        return "scarlet"
    return path.parent.parent.name  # perfect_class or 5pc_misclass


def test_every_file_parses(files):
    assert len(files) >= 400
    counts = Counter(kind(p) for p in files)
    assert set(counts) == {"perfect_class", "5pc_misclass", "scarlet"}
    for path, tf in files.items():
        assert tf.positives and tf.negatives, path
        widths = {t.shape[1] for t in tf.positives + tf.negatives}
        assert widths == {tf.n_props}, path
        assert tf.target is not None, path
        if kind(path) == "scarlet":
            number = int(path.name.split("-")[1])
            assert tf.target_source.endswith(f"formulas.txt:{number}")
            assert tf.alphabet is not None and tf.feature_names == list(tf.alphabet)
        else:
            assert tf.target_source == "file" and tf.depth == tf.target.depth, path
            assert tf.feature_names == [f"x{i}" for i in range(tf.n_props)]


def test_targets_classify_the_traces(files):
    for path, tf in files.items():
        predicted = tf.target.evaluate(tf.positives + tf.negatives,
                                       feature_names=tf.feature_names)
        accuracy = np.mean(predicted == tf.y.astype(bool))
        if kind(path) == "5pc_misclass":
            assert accuracy >= 0.9, (path, accuracy)
        else:  # noise-free: the target separates positives from negatives exactly
            assert accuracy == 1.0, (path, accuracy)


def test_targets_text_round_trips(files):
    for tf in files.values():
        assert parse_ltl(tf.target.to_prefix(), notation="prefix") == tf.target
        assert parse_ltl(str(tf.target), notation="infix") == tf.target


def test_template_recognition(files):
    recognised = Counter()
    for path, tf in files.items():
        names = tf.feature_names + ["!" + n for n in tf.feature_names]
        spec = tf.target.to_specification(names=names)
        assert (spec is not None) == (tf.target.to_prefix() in IN_TEMPLATE), path
        if spec is None:
            continue
        recognised[kind(path)] += 1
        if tf.target.to_prefix() == "G(!(x0))":
            assert tf.target.to_specification(names=tf.feature_names) is None
        # the specification means what the target means, on the real traces
        frames = [pd.DataFrame(t, columns=tf.feature_names)
                  for t in tf.positives + tf.negatives]
        augmented = add_negations(frames)
        truth = tf.target.evaluate(frames)
        np.testing.assert_array_equal([spec.satisfied_by(a) for a in augmented], truth)
    assert recognised["scarlet"] == 25  # formulas 1-5 of 9, five files each
    assert recognised["perfect_class"] + recognised["5pc_misclass"] >= 90


def test_load_trace_file_on_one_file_per_folder(files):
    seen = set()
    for path, tf in files.items():
        if path.parent in seen:
            continue
        seen.add(path.parent)
        X, y, target = load_trace_file(path)
        assert all(isinstance(x, pd.DataFrame) and list(x.columns) == tf.feature_names
                   for x in X)
        np.testing.assert_array_equal(y, tf.y)
        assert target == tf.target
        if kind(path) != "5pc_misclass":
            np.testing.assert_array_equal(target.evaluate(X), y.astype(bool))
    assert len(seen) == 9


def test_writer_reproduces_the_files(files):
    for path in list(files)[::40]:
        tf = files[path]
        buf = io.StringIO()
        target = tf.target if tf.target_source == "file" else None
        write_trace_file(buf, tf.positives + tf.negatives, tf.y, operators=tf.operators,
                         depth=tf.depth, target=target, alphabet=tf.alphabet)
        assert buf.getvalue().rstrip("\n") == path.read_text().rstrip("\n"), path

import numpy as np
import pandas as pd
import pytest
import scipy.sparse as sp

from baselines._sequences import (
    check_consistent_sequences,
    check_phases,
    check_sequences,
    length_mask,
    pad_sequences,
    reverse_index,
)


def test_list_of_arrays_keeps_lengths_and_values():
    a = np.arange(6.0).reshape(3, 2)
    b = np.array([[True, False]])
    seqs = check_sequences([a, b])
    assert seqs.n_sequences == 2 and seqs.n_features == 2
    assert seqs.lengths.tolist() == [3, 1]
    np.testing.assert_array_equal(seqs.sequence(0), a)
    np.testing.assert_array_equal(seqs.sequence(1), [[1.0, 0.0]])
    assert seqs.feature_names is None


def test_dataframes_give_feature_names():
    frames = [
        pd.DataFrame({"a": [0, 1], "speed": [1.5, 2.5]}),
        pd.DataFrame({"a": [1], "speed": [0.0]}),
    ]
    seqs = check_sequences(frames)
    assert list(seqs.feature_names) == ["a", "speed"]
    assert seqs.lengths.tolist() == [2, 1]


def test_three_d_and_two_d_layouts():
    cube = np.zeros((4, 5, 3))
    assert check_sequences(cube).lengths.tolist() == [5] * 4
    rows = np.arange(6.0).reshape(3, 2)
    seqs = check_sequences(rows)
    assert seqs.lengths.tolist() == [1, 1, 1]
    # a nested list of rows reads like the 2-D array
    np.testing.assert_array_equal(check_sequences(rows.tolist()).data, rows)
    frame = pd.DataFrame(rows, columns=["x", "y"])
    assert list(check_sequences(frame).feature_names) == ["x", "y"]


@pytest.mark.parametrize(
    "X, match",
    [
        ([np.zeros((2, 2)), np.array([[0.0, np.nan]])], "sequence 1, step 0, feature 1 is nan"),
        ([np.zeros((2, 2)), np.zeros((0, 2))], "sequence 1 has zero length"),
        ([np.zeros((2, 2)), np.zeros((2, 3))], "sequence 1 has 3 features"),
        ([np.zeros((2, 2)), np.zeros((2, 2, 2))], "sequence 1 must be a 2-D array"),
        ([np.zeros((2, 2)), np.array([["a", "b"]])], (
            "sequence 1, step 0, feature 0 has the non-numeric value 'a'")),
        ([], "at least one sequence"),
        (np.zeros(3), "Reshape your data"),
        (None, "got None"),
        ([np.zeros((2, 2)), pd.DataFrame({"a": [0], "b": [1]})], "sequence 1"),
        (
            [pd.DataFrame({"a": [0], "b": [1]}), pd.DataFrame({"a": [0], "c": [1]})],
            "sequence 1 has columns",
        ),
        (np.ones((2, 2)) * 1j, "Complex data not supported"),
    ],
)
def test_bad_input_names_the_sequence(X, match):
    with pytest.raises(ValueError, match=match):
        check_sequences(X)


def test_sparse_input_is_refused():
    with pytest.raises(TypeError, match="sparse"):
        check_sequences(sp.csr_matrix(np.eye(3)))


def test_consistency_after_fit():
    seqs = check_sequences([np.zeros((2, 3))])
    with pytest.raises(ValueError, match="X has 3 features, but Est is expecting 2"):
        check_consistent_sequences(seqs, 2, None, "Est")
    named = check_sequences([pd.DataFrame({"a": [0], "b": [1]})])
    with pytest.raises(ValueError, match="feature names should match"):
        check_consistent_sequences(named, 2, np.array(["a", "c"], dtype=object), "Est")
    with pytest.warns(UserWarning, match="X has feature names"):
        check_consistent_sequences(named, 2, None, "Est")


def test_check_phases_aligns_and_validates():
    lengths = np.array([3, 2])
    np.testing.assert_array_equal(check_phases([[0, 1, 2], np.array([3, 3])], lengths, 4),
                                  [0, 1, 2, 3, 3])
    np.testing.assert_array_equal(check_phases([[0.0, 1.0, 1.0], [0, 0]], lengths, 2),
                                  [0, 1, 1, 0, 0])
    with pytest.raises(ValueError, match="phases of sequence 1 has 3 labels"):
        check_phases([[0, 1, 2], [0, 1, 2]], lengths, 4)
    with pytest.raises(ValueError, match="phases of sequence 0 has label 4 at step 2"):
        check_phases([[0, 1, 4], [0, 1]], lengths, 4)
    with pytest.raises(ValueError, match="phases has 1 entries but there are 2 sequences"):
        check_phases([[0, 1, 2]], lengths, 4)
    with pytest.raises(ValueError, match="must be integers"):
        check_phases([[0, 0.5, 1], [0, 1]], lengths, 4)
    with pytest.raises(ValueError, match="must be 1-D"):
        check_phases([np.zeros((3, 2), int), [0, 1]], lengths, 4)


def test_pad_reverse_and_mask():
    data = np.arange(6.0)[:, None]
    offsets = np.array([0, 1, 4, 6])
    padded, lengths = pad_sequences(data, offsets, [1, 0, 2], fill=-1.0)
    assert padded.shape == (3, 3, 1)
    assert padded[..., 0].tolist() == [[1, 2, 3], [0, -1, -1], [4, 5, -1]]
    idx = reverse_index(lengths, 3)
    reversed_ = np.take_along_axis(padded[..., 0], idx, axis=1)
    assert reversed_.tolist() == [[3, 2, 1], [0, -1, -1], [5, 4, -1]]
    # reversing twice is the identity, and the padding stays at the end
    np.testing.assert_array_equal(np.take_along_axis(reversed_, idx, axis=1), padded[..., 0])
    assert length_mask(lengths, 3).tolist() == [
        [True, True, True], [True, False, False], [True, True, False]
    ]

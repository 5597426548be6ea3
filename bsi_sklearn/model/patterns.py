"""The pattern library's truth on demonstrations (DESIGN §12).

The templates are defined once, in :mod:`bsi_sklearn.specification.templates` (their names,
slots, LTLf formulas and sentences: what a specification's pattern clause *is*);
:func:`pattern_truth` computes the truth of instantiated templates on every demonstration, one
pass over each trace per clause, with a small numba recurrence per template (no formula
interpreter in the loop) and the generic evaluator of :mod:`bsi_sklearn.model._ltlf_program`
for user templates. The catalogue's names are re-exported here.

The empty trace is not a demonstration (DESIGN §1: ``T_i >= 1``); :func:`pattern_truth`
refuses it.
"""

import numpy as np

from bsi_sklearn.model._ltlf_program import compile_program, program_truth
from bsi_sklearn.model._pattern_kernels import catalogue_truth
from bsi_sklearn.specification.templates import (
    FAMILIES,
    MAX_SLOTS,
    TEMPLATES,
    Template,
    get_template,
    instance_ltlf,
    instance_text,
    instantiate,
    parse_ltlf,
)

__all__ = ["Template", "TEMPLATES", "FAMILIES", "MAX_SLOTS", "get_template", "instantiate",
           "pattern_truth", "instance_ltlf", "instance_text"]


def pattern_truth(template, data, offsets, columns):
    """Truth of instances of ``template`` on every demonstration.

    Parameters
    ----------
    template : str or Template
    data : ndarray of shape (sum(T_i), n_props)
        The stacked demonstrations (``Traces.data``), bool or 0/1.
    offsets : ndarray of shape (n_demos + 1,)
        Demonstration ``i`` is ``data[offsets[i]:offsets[i + 1]]`` (``Traces.offsets``).
    columns : array-like of shape (n_instances, n_slots)
        For each instance, the column of each slot, in the template's slot order.

    Returns
    -------
    truth : ndarray of shape (n_demos, n_instances), dtype uint8
        ``truth[i, k]`` is 1 when demonstration ``i`` satisfies instance ``k``
        (:func:`bsi_sklearn.model.clauses.pack_rows` packs it like the clause truth).

    Examples
    --------
    >>> data = np.array([[1, 0], [0, 1], [1, 0]], dtype=np.uint8)
    >>> pattern_truth("Response", data, np.array([0, 3]), [[0, 1], [1, 0]]).tolist()
    [[0, 1]]
    """
    t = get_template(template)
    data = np.ascontiguousarray(data, dtype=np.uint8)
    offsets = np.ascontiguousarray(offsets, dtype=np.int64)
    cols = np.asarray(columns, dtype=np.int64).reshape(-1, len(t.slots))
    if data.ndim != 2:
        raise ValueError(f"data must be 2-D (steps, propositions), got shape {data.shape}")
    lengths = np.diff(offsets)
    if offsets.ndim != 1 or offsets.shape[0] < 1 or offsets[0] != 0 \
            or offsets[-1] != data.shape[0] or np.any(lengths < 0):
        raise ValueError("offsets must rise from 0 to the number of rows of data")
    if np.any(lengths == 0):
        raise ValueError(f"demonstration {int(np.argmax(lengths == 0))} has no step; "
                         "a demonstration has at least one step")
    if cols.size and (cols.min() < 0 or cols.max() >= data.shape[1]):
        raise ValueError(f"a column index is outside 0..{data.shape[1] - 1}")
    out = np.zeros((offsets.shape[0] - 1, cols.shape[0]), dtype=np.uint8)
    if t.code < 0:
        program = compile_program(parse_ltlf(t.formula), t.slots)
        program_truth(program, data, offsets, np.ascontiguousarray(cols), out)
    else:
        if cols.shape[1] == 1:  # the kernels take two columns; a unary template reads one
            cols = np.concatenate([cols, cols], axis=1)
        catalogue_truth(t.code, data, offsets, np.ascontiguousarray(cols), out)
    return out

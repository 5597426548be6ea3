"""The catalogue's templates on demonstrations: one small recurrence per template, in numba.

``code`` is the template's position in :data:`bsi_sklearn.model.patterns.TEMPLATES`; each
recurrence reads one demonstration's rows ``d[s:e]`` once (no formula interpreter in the
loop). Their formulas, read by the generic evaluator of :mod:`bsi_sklearn.model._ltlf_program`,
by flloat and by a brute-force evaluator, give the same truth (``tests/test_patterns.py``).
"""

from numba import njit

from bsi_sklearn._jit import helper

__all__ = ["catalogue_truth"]


def catalogue_truth(code, data, offsets, cols, out):
    """Fill ``out[i, k]`` with the truth of template ``code``'s instance ``k`` on demo ``i``."""
    _pattern_truth(code, data, offsets, cols, out)


@njit(cache=True, nogil=True)
def _pattern_truth(code, data, offsets, cols, out):
    for k in range(cols.shape[0]):
        a, b = cols[k, 0], cols[k, 1]
        for i in range(offsets.shape[0] - 1):
            out[i, k] = _one(code, data, offsets[i], offsets[i + 1], a, b)


@helper
def _one(code, d, s, e, a, b):  # noqa: C901 - one branch per template, in catalogue order
    if code == 0:
        return _exists(d, s, e, a)
    if code == 1:
        return not _exists(d, s, e, a)
    if code == 2:
        return _count(d, s, e, a) <= 1
    if code == 3:
        return d[s, a] != 0
    if code == 4:
        return not _exists(d, s, e, a) or _exists(d, s, e, b)
    if code == 5:
        return _exists(d, s, e, a) == _exists(d, s, e, b)
    if code == 6:
        return _response(d, s, e, a, b)
    if code == 7:
        return _precedence(d, s, e, a, b)
    if code == 8:
        return _response(d, s, e, a, b) and _precedence(d, s, e, a, b)
    if code == 9:
        return _alternate_response(d, s, e, a, b)
    if code == 10:
        return _alternate_precedence(d, s, e, a, b)
    if code == 11:
        return _chain_response(d, s, e, a, b)
    if code == 12:
        return _chain_precedence(d, s, e, a, b)
    if code == 13:
        return not (_exists(d, s, e, a) and _exists(d, s, e, b))
    if code == 14:
        return _not_succession(d, s, e, a, b)
    if code == 15:
        return _absence_before(d, s, e, a, b)
    if code == 16:
        return _existence_before(d, s, e, a, b)
    if code == 17:
        return _universality_before(d, s, e, a, b)
    if code == 18:
        return _not_succession(d, s, e, b, a)  # G(q -> G !a): no a at or after a q
    if code == 19:
        return _existence_after(d, s, e, a, b)
    if code == 20:
        return _universality_after(d, s, e, a, b)
    if code == 21:
        return _exists(d, s, e, a) or _exists(d, s, e, b)
    if code == 22:
        return _always(d, s, e, a)
    return _together(d, s, e, a, b)


@helper
def _always(d, s, e, a):
    for t in range(s, e):
        if d[t, a] == 0:
            return False
    return True


@helper
def _together(d, s, e, a, b):
    for t in range(s, e):
        if d[t, a] and d[t, b]:
            return True
    return False


@helper
def _exists(d, s, e, a):
    for t in range(s, e):
        if d[t, a]:
            return True
    return False


@helper
def _count(d, s, e, a):
    n = 0
    for t in range(s, e):
        if d[t, a]:
            n += 1
    return n


@helper
def _response(d, s, e, a, b):
    pending = False  # an a not yet answered by a b at its step or later
    for t in range(s, e):
        pending = (pending or d[t, a] != 0) and d[t, b] == 0
    return not pending


@helper
def _precedence(d, s, e, a, b):
    for t in range(s, e):
        if d[t, a]:
            return True
        if d[t, b]:
            return False
    return True


@helper
def _alternate_response(d, s, e, a, b):
    pending = False  # an a waiting, from the next step on, for b before another a
    for t in range(s, e):
        if pending:
            if d[t, b]:
                pending = False
            elif d[t, a]:
                return False
        if d[t, a]:
            pending = True
    return not pending


@helper
def _alternate_precedence(d, s, e, a, b):
    need = True  # (!b U a) | G !b owed from this step: at the start, and after every b
    for t in range(s, e):
        if need:
            if d[t, a]:
                need = False
            elif d[t, b]:
                return False
        if d[t, b]:
            need = True
    return True


@helper
def _chain_response(d, s, e, a, b):
    for t in range(s, e):
        if d[t, a] and (t + 1 == e or d[t + 1, b] == 0):
            return False
    return True


@helper
def _chain_precedence(d, s, e, a, b):
    for t in range(s, e - 1):
        if d[t + 1, b] and d[t, a] == 0:
            return False
    return True


@helper
def _not_succession(d, s, e, a, b):
    seen = False
    for t in range(s, e):
        if d[t, a]:
            seen = True
        if seen and d[t, b]:
            return False
    return True


@helper
def _absence_before(d, s, e, a, r):
    seen = False
    for t in range(s, e):
        if d[t, r]:
            return not seen
        if d[t, a]:
            seen = True
    return True


@helper
def _existence_before(d, s, e, a, r):
    for t in range(s, e):
        if d[t, r]:
            return False
        if d[t, a]:
            return True
    return True


@helper
def _universality_before(d, s, e, a, r):
    ok = True
    for t in range(s, e):
        if d[t, r]:
            return ok
        if d[t, a] == 0:
            ok = False
    return True


@helper
def _existence_after(d, s, e, a, q):
    seen = False
    for t in range(s, e):
        if d[t, q]:
            seen = True
        if seen and d[t, a]:
            return True
    return not seen


@helper
def _universality_after(d, s, e, a, q):
    seen = False
    for t in range(s, e):
        if d[t, q]:
            seen = True
        if seen and d[t, a] == 0:
            return False
    return True

"""The exact engine's budget: its work, counted, and its memory, charged before allocation.

Work is counted in units of one pair-of-groups evaluation (about 5-10 ns here); memory in
bytes. Both depend on the data only, never on timing, so whether an enumeration runs is the
same on every machine. :class:`ExactWorkExceeded` stops an enumeration over its work budget
(``inference="auto"`` then samples); :class:`ExactMemoryExceeded`, a subclass, one whose
tables would pass the memory limit, which holds also without a work budget.
"""

import numpy as np

__all__ = ["ExactWorkExceeded", "ExactMemoryExceeded", "Budget", "entry_bytes", "SUBSET_BYTES",
           "describe_bytes"]


class ExactWorkExceeded(RuntimeError):
    """The enumeration would take more work than the budget it was given (``max_work``)."""


class ExactMemoryExceeded(ExactWorkExceeded):
    """The enumeration would allocate more than its memory limit (``max_bytes``).

    Raised before the allocation, whatever ``max_work`` is: an exact posterior asked for
    explicitly stops with this rather than with a ``MemoryError``.
    """


def describe_bytes(nbytes):
    """A number of bytes for a message (``"1.5 GiB"``; past a million TiB, ``"7.7e+258 TiB"``).

    Examples
    --------
    >>> describe_bytes(3 * 2**29), describe_bytes(2.0**900)
    ('1.5 GiB', '7.7e+258 TiB')
    """
    if nbytes >= 2.0**60:  # thousands separators past this are a wall of digits
        return f"{nbytes / 2.0**40:.1e} TiB"
    for unit, scale in (("TiB", 2.0**40), ("GiB", 2.0**30), ("MiB", 2.0**20)):
        if nbytes >= scale:
            return f"{nbytes / scale:,.1f} {unit}"
    return f"{nbytes:,.0f} bytes"


class Budget:
    # Work in units of one pair-of-groups evaluation (about 5-10 ns here): a combination of two
    # entries of the structure tables costs _structures.COMBO_COST of them, a structure the
    # last walk rebuilds _LIST_COST per subtask, a (global, eventual) subset pair it looks at
    # _EMIT_COST and one it may list _KEPT_COST more (counted as if every one were listed:
    # the heap, the sort, the result's arrays). Every amount is spent before the work (or the
    # allocation) it pays for, and depends on the data only, never on timing.
    # Memory is counted apart, in bytes, and always (also without a work budget): every large
    # array is charged before it is made, and the charges only add up (a freed table is not
    # given back), so the limit bounds the peak.
    def __init__(self, max_work, max_bytes=None):
        self.left = np.inf if max_work is None else float(max_work)
        self.spent = 0.0
        self.max_bytes = np.inf if max_bytes is None else float(max_bytes)
        self.allocated = 0.0

    def allocate(self, nbytes, what):
        if self.allocated + nbytes > self.max_bytes:
            raise ExactMemoryExceeded(
                f"exact enumeration stopped: {what} would take {describe_bytes(nbytes)} (with "
                f"{describe_bytes(self.allocated)} already held), beyond its memory limit of "
                f"{describe_bytes(self.max_bytes)}")
        self.allocated += nbytes

    def entries_left(self, entry_bytes):
        # How many entries of this size the memory still allows (the structure tables' store).
        return (self.max_bytes - self.allocated) / entry_bytes

    def spend(self, work, what):
        self.left -= work
        self.spent += work
        if self.left < 0:
            raise ExactWorkExceeded(f"exact enumeration stopped: {what} exceeds its work budget")


def entry_bytes(n_words):
    """Bytes of one entry of the structure tables (its store row and its share of the hash)."""
    return 8 * n_words + 5 * 8 + 2 * 8


#: Bytes per subset of subtasks of the arrays over all ``2**n`` subsets (``lo``, ``hi``,
#: ``ref`` of both kinds, ``lists``, the candidates' scratch, and the walk's own scratch).
SUBSET_BYTES = 2 * 3 * 8 + 8 + 4 + 4

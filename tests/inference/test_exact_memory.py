"""The exact engine never allocates past its memory limit: it stops before, with a message.

Every fit here runs in a child process whose address space is limited (``RLIMIT_AS``), at the
sizes real event logs bring (40 to 200 propositions that are all subtasks under the inferred
roles): a ``MemoryError`` there would fail the child. ``inference="auto"`` must fall back to
the sampler, ``inference="exact"`` must raise a ``ValueError`` that names the size and the way
out.
"""

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from bsi_sklearn.inference._budget import Budget
from bsi_sklearn.inference.auto_budget import AUTO_EXACT_BYTES, AUTO_MAX_WORK, auto_work_budget
from bsi_sklearn.inference.exact import ExactMemoryExceeded, ExactWorkExceeded, exact_posterior
from bsi_sklearn.model import make_model

_LIMIT = 3 * 2**30  # address space of the child: far below what the tables would ask for

_CHILD = textwrap.dedent("""
    import json, resource, sys
    import numpy as np
    resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))
    from bsi_sklearn import BSIClassifier

    def occurred(n_props, n_demos, seed):
        # Event-log traces: column a at step t is "activity a occurred among the first t".
        rng = np.random.default_rng(seed)
        X, y = [], []
        for _ in range(n_demos):
            acts = rng.integers(0, n_props, size=rng.integers(1, 12))
            T = np.zeros((len(acts) + 1, n_props), dtype=bool)
            for t, a in enumerate(acts):
                T[t + 1] = T[t]
                T[t + 1, a] = True
            X.append(T)
            y.append(int(T[-1, 0] or T[-1, 1]))
        return X, np.array(y)

    out = {{}}
    for n_props in {sizes}:
        X, y = occurred(n_props, 60, n_props)
        row = {{}}
        try:
            clf = BSIClassifier(inference="auto", n_samples=3, burn_in=1, n_chains=1,
                                n_temperatures=1, random_state=0).fit(X, y)
            row["auto"] = [clf.inference_, len(clf.roles_["subtasks"])]
        except Exception as exc:
            row["auto"] = ["raised", type(exc).__name__, str(exc)]
        try:
            BSIClassifier(inference="exact", random_state=0).fit(X, y)
            row["exact"] = ["fitted"]
        except Exception as exc:
            row["exact"] = ["raised", type(exc).__name__, str(exc)]
        out[n_props] = row
    print(json.dumps(out))
""")


@pytest.mark.slow
def test_fits_of_many_propositions_never_allocate_past_the_limit():
    sizes = (40, 64, 100, 200)
    code = _CHILD.format(limit=_LIMIT, sizes=sizes)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout.strip().splitlines()[-1])
    for n_props in sizes:
        row = out[str(n_props)]
        # auto: the exact attempt stops before its tables, and the sampler answers
        assert row["auto"][0] == "mcmc", (n_props, row)
        assert row["auto"][1] > 24, (n_props, row)  # most propositions are subtasks
        # exact: a ValueError with the size and the way out, never a MemoryError
        assert row["exact"][:2] == ["raised", "ValueError"], (n_props, row)
        message = row["exact"][2]
        assert "subtasks" in message and "memory limit" in message, message
        assert "inference='auto' or 'mcmc'" in message, message


def test_the_budget_refuses_an_allocation_before_it_is_made():
    budget = Budget(None, max_bytes=1000)
    budget.allocate(600, "a table")
    with pytest.raises(ExactMemoryExceeded, match=r"a second table would take 500 bytes "
                                                  r"\(with 600 bytes already held\)"):
        budget.allocate(500, "a second table")
    assert budget.allocated == 600
    assert issubclass(ExactMemoryExceeded, ExactWorkExceeded)  # "auto" samples instead


def _occurred_truth(n_subtasks, n_demos, seed=0):
    rng = np.random.default_rng(seed)
    truth = (rng.random((n_demos, n_subtasks + n_subtasks * n_subtasks)) < 0.7)
    return truth.astype(np.uint8), (rng.random(n_demos) < 0.5).astype(np.int64)


@pytest.mark.parametrize("n_subtasks", [36, 64])
def test_the_subset_tables_are_refused_under_any_work_budget(n_subtasks):
    truth, y = _occurred_truth(n_subtasks, 50)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0,
                       n_subtasks=n_subtasks)
    with pytest.raises(ExactMemoryExceeded, match=f"2\\*\\*{n_subtasks} rows"):
        exact_posterior(truth, y, model, max_work=None)


def test_the_structure_store_stops_at_its_memory_limit():
    # 16 subtasks fit the subset tables but not the order structures' store at 64 MiB.
    truth, y = _occurred_truth(16, 200)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0, n_subtasks=16)
    with pytest.raises(ExactMemoryExceeded, match="order structures' tables over 16 subtasks"):
        exact_posterior(truth, y, model, max_bytes=64 * 2**20)


def test_small_problems_are_unchanged_by_the_memory_limit():
    truth, y = _occurred_truth(5, 80, seed=3)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0, n_subtasks=5)
    free = exact_posterior(truth, y, model, max_bytes=None)
    limited = exact_posterior(truth, y, model)
    np.testing.assert_array_equal(free.log_prob, limited.log_prob)
    np.testing.assert_array_equal(free.structures, limited.structures)
    np.testing.assert_array_equal(free.clause_marginals, limited.clause_marginals)


def test_auto_work_budget_is_capped():
    truth, y = _occurred_truth(30, 400)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0, n_subtasks=30)
    budget = auto_work_budget(truth, y, model, n_chains=4, n_samples=10_000, burn_in=100)
    assert budget == AUTO_MAX_WORK
    assert AUTO_EXACT_BYTES <= 2**30

"""Fitted posteriors are bit-for-bit what they were before the redesign (issue 11).

The digests below were recorded with the code as it stood before the kernels moved behind the
model bundle. Every prior x likelihood x (positive-only, supervised) x (exact, MCMC) fit on a
fixed problem is hashed: the specifications' structures and masks exactly, and every float
(probabilities, clause marginals, dropped mass, R-hat, log-posterior traces, sample
frequencies) to 12 significant digits, so that a change of the sampled chain or of the scores
shows, while a last-bit difference of ``exp`` between CPU types does not.

The exact digests were recorded again when exact inference began to sum over groups of
interchangeable parts (issue 13): on all twelve exact cases the new engine keeps the same
specifications in the same order, with probabilities within 1e-16 and clause marginals within
3e-14 of the old enumeration (compared case by case before re-recording); only the rounding of
sums differs, which moves the dropped mass (``1 - sum``) and some marginals at their last
hashed digits.

The MCMC digests were recorded again when the sampler changed (issue 19: parallel tempering,
structure moves with the eventual bit, chains from the empty hypothesis, the support completed
with the optimum and one-block neighbourhoods, new diagnostics). Before re-recording, every
case was compared with exact enumeration: total variation old / new (same seeds) 1.5e-4 /
1.5e-4, 9.1e-5 / 9.1e-5, 0 / 0, 4e-17 / 4e-17 (Prior 1); 1.1e-5 / 1e-11, 2.1e-6 / 1e-16,
5.9e-4 / 2.0e-4, 9e-17 / 9e-17 (Prior 2); 4.3e-5 / 4e-11, 2.1e-6 / 1e-16, 1.5e-3 / 1.5e-4,
0 / 0 (Prior 3), in the order cb positive, cb supervised, ci positive, ci supervised.
"""

import hashlib

import numpy as np
import pytest
from poi_problems import make_poi_problem

from bsi_sklearn import BSIClassifier

PRIORS = ("linear_chain", "sets_of_chains", "forest")
LIKELIHOODS = ("cb", "ci")


def _problem():
    demos, labels, roles = make_poi_problem(n_demos=18, n_threats=2, n_pois=4, chain=(0, 2),
                                            n_negative=6, seed=3, always_violated=(1,))
    return demos, labels, roles


def _floats(x):
    return np.array2string(np.asarray(x, dtype=float).ravel(), precision=11,
                           floatmode="maxprec", threshold=10**9, separator=",")


def posterior_digest(clf):
    """One SHA-256 over everything a fit computed."""
    h = hashlib.sha256()
    post = clf.posterior_
    for spec in post.specifications:
        h.update(repr(sorted(spec.clauses(), key=repr)).encode())
    h.update(_floats(post.probabilities).encode())
    h.update(repr(sorted((repr(k), round(float(v), 11))
                         for k, v in post.clause_marginals().items())).encode())
    h.update(_floats([post.dropped_mass]).encode())
    diag = clf.mcmc_diagnostics_
    if diag is not None:
        h.update(_floats([diag["rhat"], diag["acceptance_rate"]]).encode())
        h.update(_floats(diag["acceptance_rate_per_chain"]).encode())
        h.update(_floats(diag["log_posterior_traces"]).encode())
        h.update(_floats(diag["sample_frequencies"]).encode())
        h.update(repr((diag["n_updates"], diag["n_visited"])).encode())
    return h.hexdigest()[:16]


def fit_case(prior, likelihood, supervised, inference):
    demos, labels, roles = _problem()
    if not supervised:
        keep = labels == 1
        demos = [d for d, k in zip(demos, keep) if k]
        labels = labels[keep]
    clf = BSIClassifier(prior=prior, likelihood=likelihood, inference=inference,
                        n_samples=1_500, burn_in=50, n_chains=2, random_state=7, **roles)
    return clf.fit(demos, labels)


RECORDED = {
    "linear_chain/cb/positive/exact": "dc79f3838e336d4e",
    "linear_chain/cb/positive/mcmc": "24741bc86f42c94a",
    "linear_chain/cb/supervised/exact": "86a64ac15f5caa18",
    "linear_chain/cb/supervised/mcmc": "05dbe07ce0e36025",
    "linear_chain/ci/positive/exact": "cbd1c70577c45ce5",
    "linear_chain/ci/positive/mcmc": "64031dc008b74bd1",
    "linear_chain/ci/supervised/exact": "7da04ed1fe508bab",
    "linear_chain/ci/supervised/mcmc": "64711d0c29ca41cf",
    "sets_of_chains/cb/positive/exact": "c3ef2c4f3ada4c82",
    "sets_of_chains/cb/positive/mcmc": "9fc1b5d432d09227",
    "sets_of_chains/cb/supervised/exact": "434ab1039ce74a39",
    "sets_of_chains/cb/supervised/mcmc": "4efacbf613eb3c59",
    "sets_of_chains/ci/positive/exact": "537b77d51812b64b",
    "sets_of_chains/ci/positive/mcmc": "ad104f897f9203b6",
    "sets_of_chains/ci/supervised/exact": "920b6b956a65fa16",
    "sets_of_chains/ci/supervised/mcmc": "057f116c58994c2c",
    "forest/cb/positive/exact": "f7dd8f7aa1c72202",
    "forest/cb/positive/mcmc": "64b37add83b2c4e5",
    "forest/cb/supervised/exact": "b06c355858dbe712",
    "forest/cb/supervised/mcmc": "747d894a10afb333",
    "forest/ci/positive/exact": "5eb1710859a34a69",
    "forest/ci/positive/mcmc": "a7335cb8ed09889d",
    "forest/ci/supervised/exact": "9d2230c7b92d0bb1",
    "forest/ci/supervised/mcmc": "3ac8a65ad65ba58d",
}


@pytest.mark.parametrize("key", sorted(RECORDED))
def test_posterior_digest_unchanged(key):
    prior, likelihood, mode, inference = key.split("/")
    clf = fit_case(prior, likelihood, mode == "supervised", inference)
    assert posterior_digest(clf) == RECORDED[key]


def test_every_case_recorded():
    cases = {f"{p}/{lik}/{m}/{i}" for p in PRIORS for lik in LIKELIHOODS
             for m in ("positive", "supervised") for i in ("exact", "mcmc")}
    assert set(RECORDED) == cases


if __name__ == "__main__":  # prints the table above (run from tests/)
    for p in PRIORS:
        for lik in LIKELIHOODS:
            for m in ("positive", "supervised"):
                for i in ("exact", "mcmc"):
                    clf = fit_case(p, lik, m == "supervised", i)
                    print(f'    "{p}/{lik}/{m}/{i}": "{posterior_digest(clf)}",')

"""The sizes a ``bsi-lfe`` command and its parser share: the ``--quick`` runs, the study's grid.

Both the light parsers (``lfe.cli._*``: their help texts) and the modules that run the
commands read them here; this module imports nothing, so neither imports the other.
"""

__all__ = ["COMPARE_QUICK", "REPORT_QUICK", "STUDY_DEFAULTS", "STUDY_QUICK"]

#: ``bsi-lfe compare --quick``: the simulated scenarios (unless ``--dataset``) and the folds.
COMPARE_QUICK = dict(n_scenarios=8, n_splits=2)

#: The default study: 5 sizes x 10 repeats x 2 noise rates x 2 proposition sets.
STUDY_DEFAULTS = dict(sizes=(6, 12, 18, 36, 72), repeats=10, test_size=200, noise=(0.0, 0.04),
                      propositions=("paper", "extended"))
#: ``bsi-lfe study --quick``: a smoke test in about a minute (small networks, short MCMC runs).
STUDY_QUICK = dict(sizes=(4, 8), repeats=2, test_size=12, noise=(0.04,),
                   propositions=("paper",))

#: ``bsi-lfe report --quick``: the simulated scenarios (unless ``--dataset``) and a short MCMC
#: run. The paper's proposition set has 8,296,448 hypotheses under Prior 2: exact enumeration
#: takes a few seconds, so the default run is exact; larger sets fall back to MCMC.
REPORT_QUICK = dict(n_scenarios=8, n_samples=300, n_chains=2, burn_in=50)

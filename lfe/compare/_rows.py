"""The rows of ``bsi-lfe compare`` and ``bsi-lfe study``, and the paper's values beside them.

Which classifiers the comparison fits (the paper's six, BSI with the CI likelihood and without
roles, the practitioner's rows, the majority class), in display order, and the numbers the
paper reports for its rows (for reference only).
"""

import pandas as pd

from baselines import PAPER_BASELINES
from baselines.practitioner import PRACTITIONER_BASELINES
from lfe.annotate import MISSION_OBJECTIVES

__all__ = ["BSI_PRIORS", "BSI_ROWS", "CLASSIFIERS", "MAJORITY", "PAPER_F1", "PAPER_MAP_F1",
           "ROWS", "WITHOUT_ROLES"]

#: BSI classifiers of the comparison: name -> ``BSIClassifier(prior=...)``.
BSI_PRIORS = {"BSI (Prior 2)": "sets_of_chains", "BSI (Prior 3)": "forest"}

#: BSI rows of the comparison and of ``bsi-lfe study``: name -> ``BSIClassifier`` parameters
#: (the paper's two priors with the CB likelihood, Prior 2 with the CI likelihood, and every
#: default without roles: :data:`WITHOUT_ROLES`).
BSI_ROWS = {**{name: {"prior": prior, "likelihood": "cb"} for name, prior in BSI_PRIORS.items()},
            "BSI (Prior 2, CI)": {"prior": "sets_of_chains", "likelihood": "ci"},
            "BSI (no roles)": {}}

#: BSI rows fitted as a user without an expert would: every default, and not the extractor's
#: roles (the classifier then decides which propositions play which role).
WITHOUT_ROLES = frozenset({"BSI (no roles)"})

#: The six classifiers of the paper's table, in its order.
CLASSIFIERS = (*PAPER_BASELINES, *BSI_PRIORS)

#: Reference row: always predict the training folds' most frequent outcome. The paper reports
#: that its recurrent models collapsed to exactly this; its baselines' F1 are the majority
#: class's on its data.
MAJORITY = "Majority class"

#: Every row of the comparison, in display order: the paper's six, BSI with the CI likelihood,
#: BSI without roles, the practitioner's rows and the majority class.
ROWS = (*CLASSIFIERS, "BSI (Prior 2, CI)", "BSI (no roles)", *PRACTITIONER_BASELINES, MAJORITY)

#: The paper's Table "Weighted F1 scores for both scenario outcomes for each of the
#: classifiers" (four-fold cross-validation on its 24 JSAF missions), for reference only.
PAPER_F1 = pd.DataFrame(
    [[0.533, 0.533, 0.481]] * 4 + [[0.674, 0.712, 0.877], [0.674, 0.676, 0.877]],
    index=pd.Index(CLASSIFIERS, name="classifier"), columns=list(MISSION_OBJECTIVES),
)

#: The paper's weighted F1 of the MAP specification under Prior 2 fitted on all 24 missions
#: (it gives none for Prior 3).
PAPER_MAP_F1 = {"BSI (Prior 2)": {"MO1": 0.959, "MO2": 0.918, "MO3": 0.959}}

"""Where the tests find the published benchmark files, ``../shared/benchmarks-data``.

The folder sits beside the repository (it is not part of it). ``BSI_BENCHMARKS_DATA`` names
another one; tests that read it carry ``@pytest.mark.shared_data`` and are skipped, with the
reason in the summary, when it is absent (``tests/conftest.py``).
"""

import os
from pathlib import Path

_GIVEN = os.environ.get("BSI_BENCHMARKS_DATA")
BENCHMARKS_DATA = Path(_GIVEN or Path(__file__).parents[1] / ".." / "shared" / "benchmarks-data")

#: The skip reason: which folder, what is in it, how to point elsewhere.
ABSENT = (f"{'BSI_BENCHMARKS_DATA=' + _GIVEN if _GIVEN else '../shared/benchmarks-data'} is "
          "absent: these tests read the published samples2LTL and Scarlet files there (set "
          "BSI_BENCHMARKS_DATA to their folder)")

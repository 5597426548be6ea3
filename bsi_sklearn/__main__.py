"""``python -m bsi_sklearn``: the ``bsi`` command line."""

import sys

from bsi_sklearn.cli import main

sys.exit(main())

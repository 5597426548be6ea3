"""``python -m bsi_sklearn.cli``: the ``bsi`` command line."""

import sys

from bsi_sklearn.cli import main

sys.exit(main())

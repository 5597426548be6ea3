"""``python -m lfe`` runs the ``bsi-lfe`` command line."""

import sys

from lfe.cli import main

sys.exit(main())

"""``python -m lfe.cli``: the ``bsi-lfe`` command line."""

import sys

from lfe.cli import main

sys.exit(main())

"""``python -m novelty.cli``: the ``novelty`` command line."""

import sys

from . import main

sys.exit(main())

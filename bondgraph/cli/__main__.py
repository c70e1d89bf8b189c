"""``python -m bondgraph.cli``: the command line (as ``bondgraph`` and ``python -m bondgraph``)."""

import sys

from . import main

sys.exit(main())

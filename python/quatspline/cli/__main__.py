"""``python -m quatspline.cli``: the same command line as ``python -m quatspline``."""

import sys

from . import main

sys.exit(main())

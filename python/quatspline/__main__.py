"""``python -m quatspline``: the same command line as the ``quatspline`` console script."""

import sys

from quatspline.cli import main

if __name__ == "__main__":
    sys.exit(main())

"""``python -m quatspline.blender install|uninstall [--blender PATH]``."""

import sys

from .installer import main

sys.exit(main())

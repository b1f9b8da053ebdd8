"""``python -m voxposer.cli``: the ``voxposer`` command."""

import sys

from voxposer.cli import main

sys.exit(main())

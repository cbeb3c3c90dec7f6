"""``python3 -m softpack.bench``: the same as ``./softpack bench``."""

import sys

from softpack.bench import main

sys.exit(main())

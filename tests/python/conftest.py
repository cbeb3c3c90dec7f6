"""pytest set-up for softpack's Python tests.

``./softpack test`` sets ``PYTHONPATH`` and ``SOFTPACK_ROOT``; when run
directly with pytest, the package is found under the repository's
``python/`` folder.
"""

import os
import sys
from pathlib import Path

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
if str(ROOT / "python") not in sys.path:
    sys.path.insert(0, str(ROOT / "python"))

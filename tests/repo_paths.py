"""Where the tests find the repository and the shared data, wherever the test file sits (no absolute paths).

``REPO`` is the repository root.  ``SHARED`` is the folder of data shared between projects: the one named by the
environment variable ``CHAINID_SHARED`` when it is set, else ``shared`` next to the repository
(``REPO.parent / "shared"``).  ``REALDATA`` holds the measured records; tests that read them skip when they are
absent.  The package itself never looks there."""
from __future__ import annotations

import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ["CHAINID_SHARED"]) if os.environ.get("CHAINID_SHARED") else REPO.parent / "shared"
REALDATA = SHARED / "realdata"

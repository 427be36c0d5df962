"""``chainid report``, the main job: every step on one chain into a report folder (:mod:`.build`), with the
paper's figures (:mod:`.figures`), practice (:mod:`.practice`), Table 1 (:mod:`.table1`), Eq. 26 (:mod:`.eq26`) and
the gap sections (:mod:`.gap`, :mod:`.sim`, :mod:`.data`, :mod:`.diagnosis`).
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "run_report": "build",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())

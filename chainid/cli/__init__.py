"""The ``chainid`` command line: the parser (:mod:`.parser`) and one thin module per command group (parse, call,
print). ``main(argv)`` is the console entry point.
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "main": "parser",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())

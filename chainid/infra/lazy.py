"""Lazy public API of a package: names listed in ``__all__`` and imported from their module on first use.

A package's ``__init__`` lists its public names and the module of the package that defines each, and gets
``__getattr__`` / ``__dir__`` from :func:`exports` (PEP 562), so that ``import chainid`` stays cheap while
``chainid.model.ChainModel`` and ``from chainid.model import ChainModel`` both work.
"""
from __future__ import annotations

import importlib
from typing import Any, Callable

__all__ = ["exports"]


def exports(package: str, table: dict[str, str], namespace: dict[str, Any]
            ) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for ``package`` whose public names map to modules in ``table``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    table : dict of str
        Public name -> module name inside the package (``{"ChainSpec": "spec"}``).
    namespace : dict
        The package's ``globals()``; a name is cached there after its first use.
    """

    def __getattr__(name: str) -> Any:
        if name in table:
            value = getattr(importlib.import_module(f"{package}.{table[name]}"), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__

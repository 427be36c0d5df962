"""Lazy exports (chainid.infra.lazy) import on first use and are cached."""
from __future__ import annotations

import pytest


def test_lazy_exports_import_on_first_use_and_cache():
    from chainid.infra.lazy import exports

    ns: dict = {"already": 1}
    getattr_, dir_ = exports("chainid.infra", {"dumps_json": "jsonio", "exports": "lazy"}, ns)
    from chainid.infra.jsonio import dumps_json

    assert getattr_("dumps_json") is dumps_json and ns["dumps_json"] is dumps_json  # cached in the namespace
    with pytest.raises(AttributeError, match="module 'chainid.infra' has no attribute 'nope'"):
        getattr_("nope")
    assert dir_() == ["already", "dumps_json", "exports"]

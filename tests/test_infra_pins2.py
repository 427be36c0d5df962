"""More pins of chainid.infra (issue 20 §5: own-seed mutation survivors 813–).  No units (bytes, counts)."""
from __future__ import annotations


def test_a_loaded_kernel_module_is_returned_without_probing_the_cache_again(monkeypatch):
    """``load_kernel_module`` on a module it loaded before returns that module at once: numba's cache locators are
    not probed again (a probe compiles a stub and builds a cache object, ~0.3 ms, and
    ``chainid.model.kernels.power_module`` loads on every use).  Bug caught: the early return's condition
    negated (every call re-probed)."""
    import chainid.infra.numba_cache as nc

    first = nc.load_kernel_module("contact_power")
    calls = []
    monkeypatch.setattr(nc, "_choose_cache", lambda py_file: calls.append(py_file) or "default")
    assert nc.load_kernel_module("contact_power") is first
    assert calls == [] and first._chainid_cache_mode == nc.cache_mode()

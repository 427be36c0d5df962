"""After the exchange pass, the explanation chain is rebuilt greedily (largest LOTO drop first); when the greedy
order differs from the order of the final fit's names, the chain still ends on the final fit (a real MR-damper set
stopped with 'list.remove(x): x not in list' here)."""
from __future__ import annotations

from types import SimpleNamespace

from chainid.gap.core import selection


def test_the_chain_rebuilds_when_the_greedy_order_differs_from_the_final_fits(monkeypatch):
    loto = {("b",): 0.2, ("a",): 0.3}  # b alone drops the LOTO error most: the greedy order is b, then a

    def fit_score(prob, names, start, base_hold):
        return SimpleNamespace(names=list(names), nrmse_loto=loto[tuple(names)], params={}, name="+".join(names))

    monkeypatch.setattr(selection, "_fit_score", fit_score)
    monkeypatch.setattr(selection, "step_test", lambda prev, new: {})
    base = SimpleNamespace(names=[], nrmse_loto=1.0, params={}, name="baseline")
    final = SimpleNamespace(names=["a", "b"], nrmse_loto=0.1, params={}, name="a+b")
    path = selection._rebuild(None, base, final, 1.0)
    assert [c.names for c in path[:2]] == [[], ["b"]]
    assert path[-1] is final and len(path) == 3
    assert path[-1].name == "b+a"

"""After the exchange pass, the explanation chain is rebuilt greedily (largest LOTO drop first) and ends on the
final fit itself, renamed in the chain's order (a candidate's names are read from its name)."""
from __future__ import annotations

from chainid.gap.core import refine
from chainid.gap.core.candidate import Candidate


def test_the_chain_is_rebuilt_greedily_and_ends_on_the_final_fit_in_the_chains_order(monkeypatch):
    loto = {("b",): 0.2, ("a",): 0.3}  # b alone drops the LOTO error most: the greedy order is b, then a

    def fit_score(prob, names, start, base_hold):
        return Candidate("+".join(names), {}, len(names), nrmse_loto=loto[tuple(names)])

    monkeypatch.setattr(refine, "fit_score", fit_score)
    monkeypatch.setattr(refine, "step_test", lambda prev, new: {})
    base = Candidate("baseline", {}, 0, nrmse_loto=1.0)
    final = Candidate("a+b", {}, 2, nrmse_loto=0.1)
    path = refine.rebuild(None, base, final, 1.0)
    assert [c.names for c in path] == [[], ["b"], ["b", "a"]]
    assert path[-1] is final

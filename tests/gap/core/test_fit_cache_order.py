"""The selection fits every effect set once; a set reached again in another order (a look-ahead fitted b+a, the
chain then extends b by a... or a by b) comes back named in the chain's order, so the chain's newest effect is
always its last name (real MR-damper sets stopped with 'list.remove(x): x not in list' when it was not)."""
from __future__ import annotations

from chainid.gap.core.candidate import Candidate
from chainid.gap.core.selection import fit_cached


def test_a_set_reached_in_another_order_is_not_refitted_and_is_named_in_the_new_order():
    calls = []

    def fit(names):
        calls.append(list(names))
        return Candidate("+".join(names), {"a.F": 1.0, "b.x": 2.0}, 2, nrmse_loto=0.25)

    cache: dict = {}
    first = fit_cached(cache, fit, ["a", "b"])
    again = fit_cached(cache, fit, ["b", "a"])
    assert calls == [["a", "b"]]
    assert (first.names, again.names) == (["a", "b"], ["b", "a"])
    assert again.names[-1] == "a" and first.names[-1] == "b"
    assert (again.params, again.nrmse_loto) == (first.params, first.nrmse_loto)
    assert fit_cached(cache, fit, ["a", "b"]) is first  # the same order: the cached object itself

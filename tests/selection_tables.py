"""The explanation chain's selection on hand-made tables of fits: every effect set's fit is looked up, not made, so a
test states the LOTO errors and checks the choices of :mod:`chainid.gap.core.selection` and
:mod:`chainid.gap.core.refine` against them."""
from __future__ import annotations

from typing import Any, Callable


def table_world(monkeypatch: Any, table: dict, floor: tuple | set = (),
                bic: Callable[[float, int], float] = lambda loto, k: 10.0 * k) -> tuple[Any, Any, list]:
    """Fits looked up in ``table`` (sorted effect names → (LOTO NRMSE, LOTO SSE per test A, B, C, at_bound,
    n_params)); ``floor``: effect sets whose training residual is at the noise floor; ``bic(loto, n_params)``: the
    fits' BIC.  Returns the selection module, the baseline candidate (LOTO NRMSE 1, SSE 100 per test) and the list
    of effect sets fitted, in order."""
    from chainid.gap.core import refine, selection
    from chainid.gap.harmonic.problem import Candidate

    calls: list = []

    def fit_score(prob, names, start, base_hold):  # noqa: ANN001
        key = tuple(sorted(names))
        calls.append(key)
        loto, sse, bound, k = table[key]
        c = Candidate("+".join(names), {f"{n}.p": 1.0 for n in names}, k, at_bound=list(bound))
        c.nrmse_loto, c.loto_num, c.bic = loto, dict(zip("ABC", sse)), bic(loto, k)
        return c

    for mod in (selection, refine):  # the forward steps and the final chain's second look fit through one function
        monkeypatch.setattr(mod, "fit_score", fit_score)
    monkeypatch.setattr(selection, "train_floor", lambda prob, c: tuple(sorted(c.names)) in floor)
    base = Candidate("baseline", {}, 0)
    base.nrmse_loto, base.loto_num = 1.0, {"A": 100.0, "B": 100.0, "C": 100.0}
    return selection, base, calls

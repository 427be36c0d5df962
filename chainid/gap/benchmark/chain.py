"""The chain a ``chainid benchmark-gap`` case runs on: the built-in pair, or the user's chain (``--chain``).

The benchmark's plans and motion programs are written in mm for the paper's 14×50 chain (mean elongation
about :data:`REF_X0` = 2 mm, amplitudes 0.04–0.45 mm).  On another chain the same millimetres would load it to
a different stress: a 76 mm mooring chain at 2 mm carries 0.3 % of the stress of the 14×50 chain there.  A
user's chain therefore runs the same programs with every displacement multiplied by one length scale s, the
elongation at which it carries the same nominal stress F/d² as the 14×50 chain at 2 mm::

    F_ref = F_k,14×50(REF_X0),   x_user(F_ref · (d / 14 mm)²) = s · REF_X0      (paper Eq. 15 for x(F))

so the mean force, the amplitudes and (through the force scale the effects are drawn on) every effect sit
where they sit on the paper's chain.  Times and frequencies are unchanged.  Units: mm, N.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

#: mean elongation [mm] of the benchmark's plans on the paper's chain (``grid3x3`` is at x0 = 2 mm)
REF_X0 = 2.0
#: label of the user's chain in the cases (the built-in ones are ``14x50`` and ``small``)
USER = "user"


def builtin_chains() -> dict[str, Any]:
    """The benchmark's own chains: the paper's 14×50 and a 10×35 (d, pitch, inner width 10, 35, 12 mm)."""
    from chainid.chain.spec import default_chain

    c = default_chain()
    return {"14x50": c, "small": replace(c, d=10.0, pitch=35.0, width=12.0)}


def length_scale(chain: Any) -> float:
    """Length scale s of the user's chain (see the module docstring); 1 for the paper's chain.

    Parameters
    ----------
    chain : chainid.ChainSpec
        The user's chain (d [mm] and the link geometry).

    Returns
    -------
    float
        s > 0 [-]: the chain's elongation at the 14×50 chain's nominal stress at :data:`REF_X0`, over REF_X0.
    """
    from chainid.chain.spec import default_chain
    from chainid.model.kernels import displacement, force

    ref = default_chain()
    F_ref = float(force(REF_X0, ref))
    return float(displacement(F_ref * (chain.d / ref.d) ** 2, chain)) / REF_X0


def case_chain(case: dict[str, Any]) -> Any:
    """The :class:`~chainid.ChainSpec` of a benchmark case: ``case["chain_spec"]`` (a user's chain, as
    :meth:`ChainSpec.to_dict` writes it) or the built-in chain named by ``case["chain"]``."""
    if case.get("chain_spec") is not None:
        from chainid.chain.spec import chain_from_mapping

        return chain_from_mapping(dict(case["chain_spec"]), source="benchmark case chain")
    return builtin_chains()[case["chain"]]


def x_scale(case: dict[str, Any]) -> float:
    """The length scale of a case's displacements: its ``x_scale`` on a user's chain, else 1."""
    return float(case.get("x_scale", 1.0))


def on_chain(cases: list[dict[str, Any]], chain: Any) -> list[dict[str, Any]]:
    """The cases moved onto the user's ``chain``: a harmonic grid keeps one of its two chain slots (the
    14×50 one; the cases of the ``small`` slot would repeat them), every case gets the chain's spec and its
    length scale (``x_scale``)."""
    spec, s = chain.to_dict(), length_scale(chain)
    out = []
    for c in cases:
        if c.get("excitation", "harmonic") == "harmonic" and c["chain"] != "14x50":
            continue
        out.append({**c, "chain": USER, "chain_spec": spec, "x_scale": s})
    return out


def scale_motion(m: Any, s: float) -> Any:
    """A motion program (:class:`chainid.records.excitation.Motion`) with every displacement × s."""
    if s == 1.0:
        return m
    return replace(m, x=m.x * s, xd=m.xd * s, xdd=m.xdd * s, A=m.A * s)

"""``chainid audit --data RECORDS``: c_e(ω, A) identified from the user's harmonic records, then the Eq. 28 audit on
them (:func:`chainid.damping.audit_data.audit_records`) instead of the paper's Table 1."""
from __future__ import annotations

import argparse
import sys
from typing import Any, Callable

__all__ = ["audit_data"]


def audit_data(args: argparse.Namespace, model_of: Callable[[argparse.Namespace], Any],
               steady_tol: float | None) -> tuple[dict, str]:
    """Read the records with the reading options, identify c_e per test and audit Eq. 28 on them.

    Parameters
    ----------
    args : Namespace
        ``audit``'s options (``data``, the model options, ``allow_compression``, ``strict``, reading options).
    model_of : callable
        The command line's stiffness model (None: ``--model linear`` without ``--k``, then fitted from the
        records as ``identify`` does).
    steady_tol : float or None
        Steady-cycle tolerance (fraction); None = adaptive.

    Returns
    -------
    (dict, str)
        The JSON report and its text.  Tests left out are one ``excluded test ID: reason`` line each on stderr.
    """
    from chainid.cli.readopts import chain_for_checks, load_records
    from chainid.damping.audit_data import audit_records, format_audit_data
    from chainid.damping.identify import linear_model_from_records

    from chainid.records.validate import check_channels

    read_doc: dict[str, Any] = {}
    records = load_records(args, args.data, chain_for_checks(args), doc=read_doc, check=check_channels)
    model = model_of(args)
    if model is None:
        model = linear_model_from_records(records, float(args.mass or 0.0), None, steady_tol=steady_tol)
    rep = audit_records(records, model, mass_kg=args.mass, steady_tol=steady_tol, strict=args.strict,
                        allow_compression=bool(args.allow_compression or args.model == "linear"))
    for e in rep["excluded"]:
        print(f"excluded test {e['test']}: {e['reason']}", file=sys.stderr, flush=True)
    rep["data"] = str(args.data)
    if read_doc.get("warnings"):  # what reading noticed goes into the JSON too
        rep.setdefault("warnings", []).extend(read_doc["warnings"])
    return rep, format_audit_data(rep)

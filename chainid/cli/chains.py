"""``chainid chains``: the standard chain presets, and the model against practice.

Units: mm, N, MPa, kg.  ``chainid chains`` lists the presets (name, d, pitch,
inner width, mass per metre, grade, proof and breaking loads); ``chainid chains
studless:120`` shows any size of a family (mooring chain: any d in the family's
range); ``--grade R4`` lists another grade; ``--compare`` adds the model's EA
against the catalogue EA and the elastic-contact limit against the proof load
(:mod:`chainid.model.practice`).  ``--json [F]`` for machines.
"""
from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["add_subparsers", "cmd_chains", "warn_loads"]


def warn_loads(F_max_N: float, chain: Any, doc: dict | None = None) -> list[str]:
    """Print :func:`chainid.model.practice.load_warnings` to stderr (and add them to ``doc["warnings"]``).

    The loads are those of the chain's own grade (:attr:`chainid.chain.spec.ChainSpec.grade`); F_max in N: the
    largest force of the request or record (the limits are exceeded by the largest force, never the smallest).
    """
    from chainid.infra.runlog import warn
    from chainid.model.practice import load_warnings

    msgs = load_warnings(F_max_N, chain)
    for m in msgs:
        warn(m)
    if doc is not None and msgs:
        doc.setdefault("warnings", []).extend(msgs)
    return msgs


def _named_grade(name: str) -> str | None:
    """The ``:grade=`` option written in a preset name, or None."""
    for part in str(name).split(":")[2:]:
        k, eq, v = part.partition("=")
        if eq and k.strip().lower() == "grade":
            return v.strip()
    return None


def _selected(args: argparse.Namespace, notes: list[str] | None = None) -> list[Any]:
    """The presets to show: the names given (any size in range), else the listed sizes of the families.

    ``--grade`` beats a name's own ``:grade=`` option (as an explicit ``n`` beats ``:n=``); where the two
    differ a note saying so is appended to ``notes``.
    """
    from chainid.chain import presets

    if args.names:
        out = []
        for name in args.names:
            p = presets.resolve(name, grade=args.grade)
            if args.family and p.family not in args.family:
                raise ValueError(f"preset {name!r} is of family {p.family!r}, not of --family {args.family}")
            own = _named_grade(name)
            if args.grade is not None and own is not None and presets.resolve(name).grade != p.grade:
                if notes is not None:
                    notes.append(f"--grade {args.grade} replaces the grade {own} written in {name!r}: "
                                 f"{p.name} is listed as grade {p.grade}")
            out.append(p)
        return out
    fams = tuple(args.family) if args.family else presets.FAMILIES
    items = presets.listed(fams)
    if args.grade is None:
        return items
    from chainid.chain.catalogue import canonical_grade

    fit = []
    for p in items:  # the grade applies to one kind of chain: list the families it applies to
        try:
            canonical_grade(args.grade, p.family)
        except ValueError:
            continue
        fit.append(presets.resolve(p.name, grade=args.grade))
    if not fit:
        canonical_grade(args.grade, fams[0], what="--grade")  # raises, naming the valid grades
    return fit


def cmd_chains(args: argparse.Namespace) -> int:
    """``chainid chains [NAME ...] [--grade G]``: presets with proof and breaking loads; ``--compare``: model vs catalogue."""
    from chainid.chain import presets
    from chainid.cli.common import check_json_target, write_json
    from chainid.model.practice import breaking_load_N, proof_load_N

    check_json_target(args.json, args.force)
    notes: list[str] = []
    items = _selected(args, notes)
    for m in notes:
        print(f"chainid chains: note: {m}", file=sys.stderr)
    doc: dict[str, Any] = {"presets": [], "default_n": presets.data()["defaults"]["n"]}
    if notes:
        doc["notes"] = notes
    for p in items:
        c = p.chain
        doc["presets"].append({"name": p.name, "family": p.family, "d_mm": c.d, "pitch_mm": c.pitch,
                               "width_mm": c.width, "outer_width_mm": p.outer_width,
                               "mass_per_m_kg": c.mass_per_m, "grade": p.grade,
                               "proof_load_N": proof_load_N(c.d, p.grade, p.studlink),
                               "breaking_load_N": breaking_load_N(c.d, p.grade), "source": p.source})
    if args.compare:
        from chainid.model.practice import comparison_table

        doc["comparison"] = comparison_table(items)
    if args.json == "-":
        write_json(doc, "-")
        return 0
    print(f"{'name':18s} {'d mm':>6s} {'pitch mm':>9s} {'width mm':>9s} {'outer mm':>9s} {'kg/m':>8s} {'grade':5s} "
          f"{'proof N':>10s} {'MBL N':>10s}")
    for r in doc["presets"]:
        print(f"{r['name']:18s} {r['d_mm']:6g} {r['pitch_mm']:9g} {r['width_mm']:9.4g} {r['outer_width_mm']:9.4g} "
              f"{r['mass_per_m_kg']:8.4g} {r['grade']:5s} {r['proof_load_N']:10.4g} {r['breaking_load_N']:10.4g}")
    print(f"n = {doc['default_n']} links by default (`din22252:14x50:n=32` to change); studless/studlink accept any "
          f"d in their range (`chainid chains studless:120`); another grade: --grade R4; sources: "
          f"chainid/data/chains.toml")
    if args.compare:
        print(f"\n{'name':18s} {'EA model N':>11s} {'EA cat. N':>11s} {'ratio':>6s} {'EA tan(proof)':>13s} "
              f"{'F_lim N':>9s} {'proof N':>10s} {'MBL N':>10s}")
        for r in doc["comparison"]:
            print(f"{r['preset']:18s} {r['EA_model_N']:11.4g} {r['EA_catalogue_orcaflex_N']:11.4g} "
                  f"{r['ratio_model_catalogue']:6.3f} {r['EA_tangent_proof_N']:13.4g} {r['contact_limit_load_N']:9.4g} "
                  f"{r['proof_load_N']:10.4g} {r['breaking_load_N']:10.4g}"
                  + ("  (model has no stud)" if r["model_has_no_stud"] else "")
                  + ("  (EA cat.: studless formula as reference)" if r["family"] == "din22252" else ""))
        print("EA model = n*pitch/c_lin (Eq. 15, linear term); catalogue: OrcaFlex 0.854e8 d^2 kN studless, "
              "1.01e8 d^2 kN studlink (d in m); no catalogue EA exists for DIN 22252 chain: its rows are compared "
              "with the studless mooring-chain formula as a reference only; F_lim: Hertz sigma_max (Eq. 12) = "
              "grade yield")
    write_json(doc, args.json, args.force)
    return 0


def add_subparsers(subparsers: Any) -> None:
    """Register ``chainid chains``."""
    from chainid.chain.presets import FAMILIES

    p = subparsers.add_parser("chains", help="standard chain presets (DIN 22252, mooring) with proof and breaking "
                                             "loads; --compare: model vs practice")
    p.add_argument("names", nargs="*", metavar="PRESET",
                   help="preset names to show, e.g. studless:120 or din22252:26x92 (any d in a mooring family's "
                        "range; default: the listed sizes)")
    p.add_argument("--family", nargs="+", choices=FAMILIES, type=str.lower, help="only these families")
    p.add_argument("--grade", metavar="G", help="list this grade (C for DIN 22252; R3, R3S, R4, R4S, R5 for mooring "
                                                "chain; any case) instead of each family's default")
    p.add_argument("--compare", action="store_true",
                   help="model EA vs catalogue EA, elastic-contact limit vs proof and breaking load")
    p.add_argument("--json", nargs="?", const="-", metavar="FILE", help="JSON to FILE, or to stdout with no FILE")
    p.add_argument("--force", action="store_true", help="overwrite an existing output file")
    p.set_defaults(func=cmd_chains)

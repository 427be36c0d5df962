"""Helpers shared by the command modules: JSON output and target checks, progress lines."""
from __future__ import annotations

import sys
from typing import Any

__all__ = ["write_json", "check_json_target", "check_io", "progress"]

def write_json(doc: Any, target: str | None, force: bool = False, what: str = "--json") -> None:
    """Write ``doc`` as strict JSON to ``target`` ("-" = stdout) atomically; refuse to overwrite without ``force``.

    Non-finite numbers are written as ``null`` (see :func:`chainid.infra.fileio.write_json`).
    """
    from chainid.infra.fileio import write_json as _write

    _write(doc, target, force=force, what=what)


def check_json_target(target: str | None, force: bool, what: str = "--json") -> None:
    """Check a ``--json`` target before the work starts ("-" and None need no check)."""
    from chainid.infra.fileio import check_output_file

    if target is not None and target != "-":
        check_output_file(target, force=force, what=what)


def progress(msg: str) -> None:
    """One progress line on stderr."""
    print(f"  ... {msg}", file=sys.stderr, flush=True)


#: (attribute, option) of the files a command reads ...
INPUT_OPTIONS = (("data", "DATA"), ("side", "--side"), ("chain", "--chain"), ("plan", "--plan"),
                 ("validate", "--validate"), ("model", "MODEL"), ("segment_model", "--segment-model"))
#: ... and of the files it writes (an output that is an input of the same run is refused)
OUTPUT_OPTIONS = (("json", "--json"), ("write_side", "--write-side"), ("out", "OUT"), ("save_model", "--save-model"))


def check_io(args: Any) -> None:
    """Refuse, before any work, an output file of the command that is one of its input files, or two outputs
    that are one file (``diagnose --save-model X.json --json X.json``).

    Every command's options are looked up by name (:data:`INPUT_OPTIONS`, :data:`OUTPUT_OPTIONS`; the step
    files of ``--save-steps`` too); the checks themselves are :func:`chainid.infra.fileio.check_inputs_not_outputs`
    and :func:`chainid.infra.fileio.check_outputs_distinct` (the same file by its real path or
    ``os.path.samefile``: hard and symbolic links included).
    """
    from chainid.infra.fileio import check_inputs_not_outputs, check_outputs_distinct

    def given(pairs: Any) -> list[tuple[str, Any]]:
        return [(opt, getattr(args, a)) for a, opt in pairs if isinstance(getattr(args, a, None), str)]

    outs = given(OUTPUT_OPTIONS)
    if getattr(args, "save_steps", False) and isinstance(getattr(args, "save_model", None), str):
        from chainid.cli.model import step_paths

        outs += [("--save-steps", p) for p in step_paths(args.save_model, 4)]
    check_outputs_distinct(outs)
    check_inputs_not_outputs(outs, given(INPUT_OPTIONS))

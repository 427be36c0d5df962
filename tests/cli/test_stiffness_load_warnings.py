"""``chainid stiffness`` judges the chain's load limits on the largest force of the request (never the smallest),
and every warning it prints on stderr is in its JSON ``warnings`` too.

Limits of the built-in 14×50 DIN 22252 grade C chain from the nominal stresses of DIN 22252 (two link legs of
π d²/4): breaking 800 N/mm², proof 640 N/mm², working load half the proof force.
"""
from __future__ import annotations

import json
import math

import pytest

from chainid.cli import main

D = 14.0
LEGS = 2 * math.pi * D**2 / 4
BREAK_N, PROOF_N = 800.0 * LEGS, 640.0 * LEGS
WORK_N = PROOF_N / 2


def _run(capsys, *argv):
    assert main(["stiffness", *argv, "--json", "-"]) == 0
    cap = capsys.readouterr()
    printed = [ln.split("chainid stiffness: warning: ", 1)[1] for ln in cap.err.splitlines()
               if ln.startswith("chainid stiffness: warning: ")]
    doc = json.loads(cap.out)
    assert printed == doc.get("warnings", []), (printed, doc.get("warnings"))
    return printed, doc


def test_reference_limits_are_those_the_warnings_use(capsys):
    F = 1.05 * PROOF_N
    printed, _ = _run(capsys, "--F", str(F))
    assert any(f"exceeds the working load (half the proof force) {WORK_N:.4g} N" in m for m in printed)
    assert any(f"exceeds the proof force {PROOF_N:.4g} N" in m for m in printed)
    assert not any("breaking" in m for m in printed)


@pytest.mark.parametrize("forces", [["1000", "150000"], ["150000", "1000"]])
def test_the_largest_force_of_the_request_is_judged(capsys, forces):
    assert WORK_N < 150000 < PROOF_N
    printed, doc = _run(capsys, "--F", *forces)
    working = [m for m in printed if "working load" in m]
    assert len(working) == 1 and working[0].startswith("F_max = 150000 N exceeds the working load")
    assert not any("proof force" in m and "exceeds the proof" in m for m in printed)
    assert max(p["F_k_N"] for p in doc["points"]) == pytest.approx(150000, rel=1e-9)


def test_elongations_and_forces_together(capsys):
    printed, doc = _run(capsys, "--x", "0.5", "--F", "150000")
    assert any(m.startswith("F_max = 150000 N exceeds the working load") for m in printed)


def test_a_small_request_has_no_working_load_warning(capsys):
    printed, _ = _run(capsys, "--F", "1000")
    assert not any("working load" in m for m in printed)

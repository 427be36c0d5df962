"""The main job: `chainid report` writes a complete folder and refuses to overwrite without --force."""
from __future__ import annotations

import json

import pytest

from chainid import cli


def test_report_on_builtin_chain(tmp_path):
    out = tmp_path / "rep"
    assert cli.main(["report", "--out", str(out)]) == 0
    md = (out / "report.md").read_text(encoding="utf-8")
    for heading in ("## 1. Verification", "## 2. Stiffness", "## 3. Damping", "## 4. Gap"):
        assert heading in md
    for fig in ("fig8a_stiffness_vs_length.png", "fig8b_stiffness_vs_modulus.png", "fig11_damping_surface.png",
                "fig12_validation.png"):
        assert (out / "figures" / fig).stat().st_size > 10_000
    audit = json.loads((out / "json" / "audit.json").read_text())
    assert audit["eq28_alpha"] == pytest.approx([28.02, -651.57, -8386.50, 7394.84, 4378.89], rel=5e-4)
    stiff = json.loads((out / "json" / "stiffness.json").read_text())
    assert stiff["x_at_11117N_mm"] == pytest.approx(1.9058, abs=5e-4)
    # a second run into the same folder needs --force
    assert cli.main(["report", "--out", str(out)]) == 2
    assert cli.main(["report", "--out", str(out), "--force"]) == 0

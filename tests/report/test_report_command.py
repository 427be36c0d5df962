"""The main job: `chainid report` writes a complete folder and refuses to overwrite without --force."""
from __future__ import annotations

import os

import json

import numpy as np
import pytest

import paper_forms  # tests/paper_forms.py: the paper's closed forms in plain Python
from chainid import cli


def _saved_figures(monkeypatch) -> dict:
    import matplotlib.figure

    figs = {}
    orig = matplotlib.figure.Figure.savefig

    import chainid.infra.fileio

    orig_save = chainid.infra.fileio.save_figure

    def spy(self, fname, *a, **k):
        if isinstance(fname, (str, os.PathLike)):  # atomic saves write to an open temporary file: see spy_save
            figs[str(fname).rsplit("/", 1)[-1]] = self
        return orig(self, fname, *a, **k)

    def spy_save(fig, path, *a, **k):
        figs[str(path).rsplit("/", 1)[-1]] = fig
        return orig_save(fig, path, *a, **k)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", spy)
    monkeypatch.setattr(chainid.infra.fileio, "save_figure", spy_save)
    return figs


def test_fig8_curves_are_the_closed_form_stiffness(tmp_path, monkeypatch):
    """Fig. 8a/8b plot k_e(x) of Eq. 15/16 (typed in paper_forms) for n = 8…64 links and E = 0.5…1.5 E0."""
    from chainid.report.figures import plot_stiffness_vs_length, plot_stiffness_vs_modulus

    figs = _saved_figures(monkeypatch)
    plot_stiffness_vs_length(tmp_path / "a.png")
    plot_stiffness_vs_modulus(tmp_path / "b.png")
    lines = figs["a.png"].axes[0].lines
    assert [ln.get_label().split(" (")[0] for ln in lines] == ["n = 8", "n = 16", "n = 32", "n = 64"]
    for ln, n in zip(lines, (8, 16, 32, 64)):
        x, k = ln.get_xdata(), ln.get_ydata()
        assert x[0] == 0.0 and x[-1] == 10.0 and k[0] == 0.0
        for i in (60, 300, 599):
            assert k[i] == pytest.approx(paper_forms.k_e(x[i], n=n), rel=1e-9), (n, x[i])
    lines = figs["b.png"].axes[0].lines
    assert len(lines) == 5
    for ln, f in zip(lines, (0.5, 0.75, 1.0, 1.25, 1.5)):
        x, k = ln.get_xdata(), ln.get_ydata()
        for i in (60, 300, 599):
            assert k[i] == pytest.approx(paper_forms.k_e(x[i], E=210000.0 * f), rel=1e-9), (f, x[i])


@pytest.mark.slow
def test_report_on_builtin_chain(tmp_path, monkeypatch):
    out = tmp_path / "rep"
    figs = _saved_figures(monkeypatch)
    assert cli.main(["report", "--out", str(out)]) == 0
    # Fig. 11: Table 1's tests (printed omega column, A, c_e) over the Eq. 28 surface
    sc = figs["fig11_damping_surface.png"].axes[0].collections[-1]
    np.testing.assert_allclose(sc.get_offsets(), [[1, 0.25], [4, 0.25], [6, 0.25], [8, 0.25], [10, 0.25],
                                                  [6, 0.2], [6, 0.3], [6, 0.35], [6, 0.4]])
    np.testing.assert_allclose(sc.get_array(), [5095.5, 3503.2, 2834.4, 2332.8, 1964.3, 2614.1, 2906.9, 3058.8,
                                                3090.5])
    # Fig. 12: x = 2.25 + 0.32 sin(14 pi t); the elastic force alone is Eq. 15 inverted (paper_forms), in kN
    fk = [ln for ln in figs["fig12_validation.png"].axes[0].lines if "alone" in ln.get_label()][0]
    x, F = fk.get_xdata(), fk.get_ydata()
    assert np.min(x) == pytest.approx(1.93, abs=1e-3) and np.max(x) == pytest.approx(2.57, abs=1e-3)
    i = int(np.argmax(x))
    assert F[i] * 1000 == pytest.approx(paper_forms.F_of_x(float(x[i])), rel=1e-9)
    md = (out / "report.md").read_text(encoding="utf-8")
    for heading in ("## 1. Verification", "## 2. Stiffness", "## 3. Damping", "## 4. Gap"):
        assert heading in md
    for fig in ("fig8a_stiffness_vs_length.png", "fig8b_stiffness_vs_modulus.png", "fig11_damping_surface.png",
                "fig12_validation.png"):
        assert (out / "figures" / fig).stat().st_size > 10_000
    audit = json.loads((out / "json" / "audit.json").read_text())
    assert audit["eq28_alpha"] == pytest.approx([28.02, -651.57, -8386.50, 7394.84, 4378.89], rel=5e-4)
    stiff = json.loads((out / "json" / "stiffness.json").read_text())
    assert stiff["x_at_11117N_mm"] == pytest.approx(paper_forms.x_of_F(11117.0), rel=1e-9)  # 1.905814 mm
    # a second run into the same folder needs --force
    assert cli.main(["report", "--out", str(out)]) == 2
    assert cli.main(["report", "--out", str(out), "--force"]) == 0


@pytest.mark.slow
def test_report_data_step_with_compressive_records_uses_a_linear_spring(tmp_path):
    """--data records whose force changes sign (not a chain): step 3 says so and fits k, not the chain."""
    import json

    from chainid.model.base import ChainModel, LinearModel
    from chainid.records.files import write_records
    from chainid.report.build import step_identify_data
    from chainid.records.simulate import TestSpec, simulate

    true = LinearModel(150.0, 5.0, mass=0.0)  # k = 150 N/mm, F = 0 at x = 5 mm: F swings through zero
    plan = [TestSpec(str(i), w, 5.0, A) for i, (w, A) in enumerate([(1, 1), (2, 1), (3, 2), (1, 2), (2, 3), (3, 3)])]
    recs = simulate(plan, true, 20.0, seed=0, noise_F=1.0)  # viscous c_e = 20 N·s/mm
    data = tmp_path / "lin.csv"
    write_records(data, recs)
    (tmp_path / "out").mkdir()
    text = step_identify_data(tmp_path / "out", data, ChainModel(), lambda msg: None)
    assert "compressive" in text and "linear spring" in text
    assert "k = 150 N/mm" in text  # fitted k to 4 significant figures
    doc = json.loads((tmp_path / "out" / "json" / "identify.json").read_text())
    assert doc["model"].startswith("linear")
    ce = [t["c_e"] for t in doc["tests"]]
    assert ce == pytest.approx([20.0] * len(ce), rel=0.02)


@pytest.mark.slow
def test_report_json_holds_every_warning_it_printed(tmp_path, capsys, monkeypatch):
    """A report's JSON files carry the run's warnings (``chainid.report.common`` merges them), as every other
    command's JSON does: records in ms read as s are implausibly slow, printed once and in identify.json.  (The gap
    and verification steps, with their own tests, are stubs here: this pins the warnings' path.)"""
    import chainid.report.build as build
    from chainid.model.base import ChainModel
    from chainid.records.files import write_records
    from chainid.records.record import Record
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan()[:4], ChainModel(), 2834.4, n_cycles=4, samples_per_cycle=64)
    data = tmp_path / "slow.csv"
    write_records(data, [Record(r.test, r.t * 1000.0, r.x, r.F) for r in recs])  # t in ms, read as s
    monkeypatch.setattr(build, "step_gap", lambda *a, **k: "## gap (stub)\n")
    monkeypatch.setattr(build, "step_verification", lambda *a, **k: "## verification (stub)\n")
    assert cli.main(["report", "--data", str(data), "--out", str(tmp_path / "rep")]) == 0
    head = "chainid report: warning: "
    printed = [ln[len(head):] for ln in capsys.readouterr().err.splitlines() if ln.startswith(head)]
    assert any("implausibly slow" in w and "--units t=ms" in w for w in printed)
    doc = json.loads((tmp_path / "rep" / "json" / "identify.json").read_text())
    assert [w for w in printed if w not in doc["warnings"]] == []

"""``chainid predict``: the per-test table with the pooled row, the plots, a bad model file in one line."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from chainid.cli import main
from chainid.cli.model import plot_predictions


@pytest.mark.slow
def test_predict_plots_show_the_residuals_over_t_and_x(tmp_path):
    import chainid.infra.fileio

    t = np.linspace(0.0, 2.0, 50)
    x = 1.0 + 0.5 * np.sin(np.pi * t)
    F, Fm, Fb = 200 * x + 3.0, 200 * x + 1.0, 200 * x
    figs = {}
    orig = chainid.infra.fileio.save_figure

    def spy(fig, path, *a, **k):
        figs[Path(path).name] = fig
        return orig(fig, path, *a, **k)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(chainid.infra.fileio, "save_figure", spy)
        out = plot_predictions({"a/1": (t, x, F, Fm, Fb)}, str(tmp_path / "p"))
    # "a/1" cannot be a file name as it is: "a_1" plus a hash of the id (so that "a 1" or "a_1" get other names)
    name = "predict_a_1-" + __import__("hashlib").sha256(b"a/1").hexdigest()[:8] + ".png"
    assert out == [tmp_path / "p" / name] and out[0].stat().st_size > 5000
    ax = np.array(figs[name].axes).reshape(2, 2)
    panels = {(i, j): ax[i, j] for i in range(2) for j in range(2)}
    assert panels[1, 0].get_title() == "residual over time" and panels[1, 0].get_xlabel() == "t [s]"
    assert panels[1, 1].get_title() == "residual over x" and panels[1, 1].get_xlabel() == "x [mm]"
    assert panels[0, 1].get_title() == "force over x" and panels[0, 0].get_title() == "test a/1: force over time"
    base, model = panels[1, 0].lines
    np.testing.assert_allclose(base.get_ydata(), 3.0)  # measured - baseline
    np.testing.assert_allclose(model.get_ydata(), 2.0)  # measured - model
    np.testing.assert_allclose(base.get_xdata(), t)
    np.testing.assert_allclose(panels[1, 1].lines[1].get_xdata(), x)
    np.testing.assert_allclose(panels[1, 1].lines[1].get_ydata(), 2.0)
    assert [ln.get_label() for ln in panels[0, 1].lines] == ["measured", "baseline", "model"]
    assert [ln.get_label() for ln in panels[0, 0].lines] == ["measured", "baseline", "model"]
    for ln, y in zip(panels[0, 0].lines, (F, Fb, Fm)):
        np.testing.assert_allclose(ln.get_xdata(), t)
        np.testing.assert_allclose(ln.get_ydata(), y)


def test_predict_table_lists_each_test_and_the_pooled_row(tmp_path, capsys):
    data, m, js = tmp_path / "d.csv", tmp_path / "m.toml", tmp_path / "p.json"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48", "--noise-F", "5"]) == 0
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3,7", "--max-combo", "1", "--save-model", str(m)]) == 0
    capsys.readouterr()
    assert main(["predict", str(m), str(data), "--tests", " 7, 3 ,", "--json", str(js)]) == 0
    out = capsys.readouterr().out.splitlines()
    doc = json.loads(js.read_text())
    assert sorted(t["test"] for t in doc["tests"]) == ["3", "7"]

    def f(v):
        return "-" if v is None else f"{v:.4g}"

    assert out[0].split() == ["test", "mode", "NRMSE", "base", "NRMSE", "model", "shrinkage"]
    for r, line in zip(doc["tests"], out[1:3]):
        assert line.split() == [r["test"], r["mode"], f(r["nrmse_baseline"]), f(r["nrmse_model"]), f(r["shrinkage"])]
    p = doc["pooled"]
    assert out[3].split()[:4] == ["pooled", f(p["nrmse_baseline"]), f(p["nrmse_model"]), f(p["shrinkage"])]
    assert out[3].endswith(f"(damping: {doc['damping_used']})") and out[4] == f"wrote {js}"


def test_predict_bad_model_file_is_one_line_and_exit_2(tmp_path, capsys):
    """``chainid predict`` on a model file that is not TOML: exit code 2 (bad input, the CLI contract) and one line
    on stderr naming the file; nothing on stdout."""
    from chainid.cli import main

    m, d = tmp_path / "m.toml", tmp_path / "d.csv"
    m.write_text("not = [toml\n")
    d.write_text("test,t,x,F\nT,0,1,1\nT,1,2,2\n")
    assert main(["predict", str(m), str(d)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert err.startswith(f"chainid predict: error: model file {str(m)!r} is not valid TOML")


@pytest.mark.slow
def test_predict_plots_one_figure_per_chosen_test_with_the_measured_force(tmp_path, capsys, monkeypatch):
    """``predict M D --tests 3,7 --plots DIR`` (a fast stand-in for the slow augmented-model file): one PNG per
    chosen test, ``DIR/predict_<test>.png`` as the docs name it, each announced with "wrote"; the figure's first
    panel draws the record's own force samples over their times (read back from the CSV; the steady cycles
    predicted, over 2 periods at least), and the residual-over-x panel
    is there.  Bug caught (seed 24): the plotting loop emptied (``for p in []``: nothing written, exit 0)."""
    from model_texts import SPECIMEN

    import chainid.infra.fileio as fileio
    from chainid.records.files import read_records

    data, model, figs = tmp_path / "d.csv", tmp_path / "m.toml", tmp_path / "fig"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48"]) == 0
    model.write_text(SPECIMEN)
    seen = {}
    real = fileio.save_figure

    def spy(fig, path, **kw):
        seen[path.name] = [(a.get_title(), [ln.get_xydata().copy() for ln in a.get_lines()]) for a in fig.axes]
        return real(fig, path, **kw)

    monkeypatch.setattr(fileio, "save_figure", spy)
    capsys.readouterr()
    assert main(["predict", str(model), str(data), "--tests", "3,7", "--plots", str(figs)]) == 0
    out = capsys.readouterr().out
    assert sorted(p.name for p in figs.iterdir()) == ["predict_3.png", "predict_7.png"]
    for name in ("predict_3.png", "predict_7.png"):
        assert f"wrote {figs / name}" in out
        assert (figs / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rec = {r.test: r for r in read_records(data)}["3"]
    title, lines = seen["predict_3.png"][0]
    assert title == "test 3: force over time"
    t_plot, F_plot = lines[0][:, 0], lines[0][:, 1]
    i = np.searchsorted(rec.t, t_plot)  # the steady part predicted: a run of the record's own samples
    assert np.array_equal(rec.t[i], t_plot) and np.array_equal(rec.F[i], F_plot) and np.all(np.diff(i) == 1)
    assert t_plot[-1] - t_plot[0] >= 2 * (2 * np.pi / 1.885)  # at least 2 periods of test 3 (1.885 rad/s)
    assert [a[0] for a in seen["predict_3.png"]] == ["test 3: force over time", "force over x",
                                                      "residual over time", "residual over x"]

"""The report's steps against independent references: Eq. 26 against the model (closed-form stiffness of
tests/paper_forms.py, harmonics on a fine grid), Table 1's R² and figure, Eq. 28's damping surface and the
validation case (Fig. 11/12) by hand, the practice text, the stiffness step's numbers, the data step's choice of
baseline, and every note inside its panel."""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from chainid.model.base import ChainModel
from chainid.report import build, gap as report_steps, practice as report_practice

import paper_forms


MODEL = ChainModel()


M = MODEL.mass_kg


# Eq. 25/26 and Eq. 27 as printed in the paper (test 3)
X0, A3, W3 = 2.2, 0.25, 1.884


F0, FA, PHI = 11117.21, 19522.1, -0.8350


F_AC27 = 1335.0


# Eq. 28 as printed: c_e = a1 w^2 + a2 w + a3 A^2 + a4 A + a5 [N s/mm]
ALPHA_PAPER = (28.02, -651.57, -8386.50, 7394.84, 4378.89)


def _eq28(w, A):
    a = ALPHA_PAPER
    return a[0] * w**2 + a[1] * w + a[2] * A**2 + a[3] * A + a[4]


def _harmonics(r, psi, k):
    return 2 * float(np.mean(r * np.sin(k * psi))), 2 * float(np.mean(r * np.cos(k * psi)))


def _spy_figures(mp, figs):
    """Keep every figure the report saves (by file name) while ``mp`` is active."""
    import chainid.infra.fileio

    orig = chainid.infra.fileio.save_figure

    def spy(fig, path, *a, **k):
        figs[Path(path).name] = fig
        return orig(fig, path, *a, **k)

    mp.setattr(chainid.infra.fileio, "save_figure", spy)


EQ26_FIGS: dict[str, object] = {}


@pytest.fixture(scope="module")
def eq26(tmp_path_factory):
    folder = tmp_path_factory.mktemp("eq26")
    msgs: list[str] = []
    with pytest.MonkeyPatch.context() as mp:
        _spy_figures(mp, EQ26_FIGS)
        md = report_steps.eq26_section(folder, MODEL, msgs.append)
    doc = json.loads((folder / "json" / "gap_eq26.json").read_text())
    return md, doc, msgs


@pytest.mark.slow
def test_eq26_in_phase_quadrature_and_harmonics_by_hand(eq26):
    _, doc, msgs = eq26
    d = doc["eq26"]
    psi = (np.arange(20000) + 0.5) * 2 * np.pi / 20000
    x = X0 + A3 * np.sin(psi)
    Fk = np.array([paper_forms.F_of_x(v) for v in x[::10]])  # 2000 points of the closed form suffice for h1
    k_h1 = 2 * float(np.mean(Fk * np.sin(psi[::10]))) / A3
    k_in = FA * math.cos(PHI) / A3
    k_inert = M * W3**2 * 1e-3
    ip = d["in_phase"]
    assert ip["k_model_first_harmonic_N_per_mm"] == pytest.approx(k_h1, rel=1e-4)
    assert ip["ratio_in_phase_over_model_dynamic"] == pytest.approx(k_in / (k_h1 - k_inert), rel=1e-4)
    q = d["quadrature"]
    # c_e implied by the record: F_A sin(phi) / (omega A) = -14471.7 / (1.884 * 0.25) = -30725 N s/mm
    assert q["c_e_implied_by_record_N_s_per_mm"] == pytest.approx(FA * math.sin(PHI) / (W3 * A3), rel=1e-9)
    assert q["c_e_implied_by_record_N_s_per_mm"] == pytest.approx(-30725, rel=1e-4)
    assert q["W_eq27_Nmm"] == pytest.approx(math.pi * A3 * F_AC27, rel=1e-12)
    assert q["W_check_Nmm"] == pytest.approx(math.pi * A3 * FA * math.sin(PHI), rel=1e-9)
    # residual r = F_Eq26 - (F_k + m xddot 1e-3) on a fine grid: harmonics 1..3 and their ratios
    r = F0 + FA * np.sin(psi + PHI) - (MODEL.force(x) - M * W3**2 * A3 * np.sin(psi) * 1e-3)
    h = d["residual_harmonics"]
    h1 = math.hypot(*_harmonics(r, psi, 1))
    h2 = math.hypot(*_harmonics(r, psi, 2))
    h3 = math.hypot(*_harmonics(r, psi, 3))
    assert h["h1"] == pytest.approx(h1, rel=1e-4)
    assert h["h3"] == pytest.approx(h3, rel=1e-3, abs=1e-3)
    assert h["h2_over_h1"] == pytest.approx(h2 / h1, rel=1e-3)
    assert h["h3_over_h1"] == pytest.approx(h3 / h1, rel=1e-3, abs=1e-8)
    rec = d["record"]
    assert rec["F_min_N"] == pytest.approx(F0 - FA) and rec["F_max_N"] == pytest.approx(F0 + FA)
    # Eq. 25 (1.884 rad/s) against Eq. 26 (1.883 rad/s): 2 pi * 0.001 / 1.884 rad of phase per cycle
    assert rec["phase_drift_per_cycle_rad"] == pytest.approx(2 * math.pi * 0.001 / 1.884, rel=1e-6)
    sl = d["stiffness_level"]
    assert sl["F0_over_F_k_x0"] == pytest.approx(F0 / paper_forms.F_of_x(X0), rel=1e-6)
    assert sl["offset_x0_minus_x_F0_mm"] == pytest.approx(X0 - paper_forms.x_of_F(F0), abs=1e-6)
    assert msgs == ["gap: the paper's Eq. 26 record and Table 1"]


@pytest.mark.slow
def test_eq26_markdown_says_the_numbers(eq26):
    md, doc, _ = eq26
    Fk0 = paper_forms.F_of_x(X0)
    assert f"is {100 * (1 - F0 / Fk0):.0f} % below" in md
    assert f"= {paper_forms.x_of_F(F0):.3f} mm" in md
    k_in = FA * math.cos(PHI) / A3
    ke0 = paper_forms.k_e(X0)
    assert f"{k_in / ke0:.1f} × stiffer" in md
    lo, hi = sorted((paper_forms.k_e(X0 - A3), paper_forms.k_e(X0 + A3)))
    assert f"k_e(x₀) = {ke0:.0f} N/mm ({lo:.0f}–{hi:.0f} over x₀ ± A;" in md
    assert f"m·ω²·10⁻³ = {M * W3**2 * 1e-3:.3g} N/mm (m = {M:g} kg)" in md
    assert f"(c_e = {FA * math.sin(PHI) / (W3 * A3):.0f} N·s/mm" in md
    assert "energy generated" in md and f"+{F_AC27:g} N" in md
    assert f"{abs(FA * math.sin(PHI)) / F_AC27:.1f} × F_ac" in md
    assert f"differ by {2 * math.pi * 0.001 / 1.884:.4f} rad" in md
    assert f"sin({1.883:g}t − {0.835:.4f}) N" in md
    # Table 1 test 3: W = pi * 1335 * 0.25 = 1048.5 N mm; its loss factor against the record's in-phase stiffness
    assert f"η = {F_AC27 / (k_in * A3):.3f}" in md
    t1 = doc["table1"]
    assert f"R² = {t1['r2_A']:.3f}" in md and f"R² = {t1['r2_omega']:.3f}" in md
    assert "closest to rate-independent (hysteretic) damping" in md
    assert "| 3 | 1.885 | 2.2 | 0.25 | 1335 |" in md
    assert re.search(r"\| 1 \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| excluded \|", md)


@pytest.mark.slow
def test_table1_r2_is_the_squared_correlation(eq26):
    """R² of a straight-line least-squares fit is the squared correlation coefficient of (log x, log y)."""
    _, doc, _ = eq26
    t1 = doc["table1"]
    rows = {t["test"]: t for t in t1["tests"]}
    A = np.array([rows[i]["A_mm"] for i in (3, 6, 7, 8, 9)])
    W = np.array([math.pi * rows[i]["F_ac_N"] * rows[i]["A_mm"] for i in (3, 6, 7, 8, 9)])
    rA = np.corrcoef(np.log(A), np.log(W))[0, 1]
    w = np.array([rows[i]["omega_rad_s"] for i in (2, 3, 4, 5)])
    Ww = np.array([math.pi * rows[i]["F_ac_N"] * rows[i]["A_mm"] for i in (2, 3, 4, 5)])
    rw = np.corrcoef(np.log(w), np.log(Ww))[0, 1]
    assert t1["r2_A"] == pytest.approx(rA**2, rel=1e-9)
    assert t1["r2_omega"] == pytest.approx(rw**2, rel=1e-9)
    assert 0.9 < t1["r2_A"] <= 1.0 and 0.5 < t1["r2_omega"] <= 1.0
    assert [rows[i]["omega_rad_s"] for i in (2, 3)] == pytest.approx([0.4 * math.pi, 0.6 * math.pi], rel=1e-9)


@pytest.fixture(scope="module")
def damping_step(tmp_path_factory):
    folder = tmp_path_factory.mktemp("damp")
    (folder / "figures").mkdir()
    figs: dict[str, object] = {}
    msgs: list[str] = []
    with pytest.MonkeyPatch.context() as mp:
        _spy_figures(mp, figs)
        md = build.step_damping(folder, MODEL, msgs.append)
    return folder, md, figs, msgs


@pytest.mark.slow
def test_damping_surface_is_eq28_over_its_grid(damping_step):
    """Fig. 11: c_e of Eq. 28 over ω 0.5–20 (column), A 0.15–0.45 mm. Its extremes by hand: the minimum over ω is
    at ω = 651.57/(2·28.02) = 11.63, of A at the end A = 0.15; the maximum at ω = 0.5 and A = 7394.84/(2·8386.5)."""
    _, md, figs, msgs = damping_step
    ax = figs["fig11_damping_surface.png"].axes[0]
    cs = next(c for c in ax.collections if hasattr(c, "levels"))
    a = ALPHA_PAPER
    w_min, A_max = -a[1] / (2 * a[0]), -a[3] / (2 * a[2])
    c_min = _eq28(w_min, 0.15)  # 1511.5
    c_max = _eq28(0.5, A_max)  # 5690.2
    assert cs.zmin == pytest.approx(c_min, abs=2.0)
    assert cs.zmax == pytest.approx(c_max, abs=2.0)
    # the Table 1 points are coloured on the surface's own scale (a point's colour reads off the colour bar)
    pts = next(c for c in ax.collections if c.get_label() == "Table 1 tests")
    assert (pts.norm.vmin, pts.norm.vmax) == pytest.approx(cs.get_clim(), rel=1e-12)
    assert pts.norm.vmin < pts.norm.vmax
    assert msgs == ["damping: Table 1 audit", "damping: validation case"]
    assert "(paper: [28.02, −651.57, −8386.50, 7394.84, 4378.89])" in md


@pytest.mark.slow
def test_validation_case_both_readings_of_omega(damping_step):
    """Fig. 12: x = 2.25 + 0.32 sin(14πt); c_e of Eq. 28 at ω = 7 and at 14π; F = F_k(x) + m ẍ + c_e ẋ."""
    folder, _, figs, _ = damping_step
    val = json.loads((folder / "json" / "validation.json").read_text())
    x0, A, w = 2.25, 0.32, 14 * math.pi
    t = np.linspace(0, 2 * math.pi / w, 1201)
    x = x0 + A * np.sin(w * t)
    Fk = np.array([paper_forms.F_of_x(v) for v in x])
    for key, om in (("ω = 7 in Eq. 21 (as the paper)", 7.0), ("ω = 14π rad/s in Eq. 21", w)):
        c = _eq28(om, A)
        v = val[key]
        assert v["omega_in_eq21"] == pytest.approx(om)
        assert v["c_e_N_s_per_mm"] == pytest.approx(c, rel=1e-3)
        F = Fk - M * w * w * A * np.sin(w * t) * 1e-3 + c * w * A * np.cos(w * t)
        assert v["F_max_N"] == pytest.approx(F.max(), rel=2e-3)
        assert v["F_min_N"] == pytest.approx(F.min(), rel=2e-3, abs=20.0)
    ax = figs["fig12_validation.png"].axes[0]
    xs = ax.lines[0].get_xdata()
    assert xs.min() == pytest.approx(x0 - A, abs=1e-4) and xs.max() == pytest.approx(x0 + A, abs=1e-4)


@pytest.mark.slow
def test_practice_section_text(tmp_path):
    from chainid.chain.spec import default_chain

    figs: dict[str, object] = {}
    with pytest.MonkeyPatch.context() as mp:
        _spy_figures(mp, figs)
        md = report_practice.report_section(tmp_path, default_chain(), lambda s: None)
    sec = json.loads((tmp_path / "json" / "practice.json").read_text())
    c = sec["chain"]
    pct = 100 * c["contact_limit_load_N"] / c["proof_load_N"]
    assert f"{pct:.2g} % of the proof force {c['proof_load_N']:.4g} N" in md
    e = sec["explanation"]
    for dw in (1, 2):
        if f"width_minus_{dw}mm" in e:
            assert f"{e[f'width_minus_{dw}mm']:.3f} with the inner width {dw} mm smaller" in md
    assert "width_minus_1mm" in e
    din = [r["ratio_model_catalogue"] for r in sec["table"] if r["family"] == "din22252"]
    assert len(din) >= 3 and min(din) < max(din)
    assert f"Over the presets the ratio is {min(din):.2f}–{max(din):.2f} for DIN 22252 and" in md
    assert md.startswith("## 2b. The model against practice")
    assert (tmp_path / "figures" / "practice_ea.png").stat().st_size > 5000
    # the EA figure: the catalogue formulas as labelled, EA = 0.854e8 d² and 1.01e8 d² kN (d in m) = 85 400 d²
    # and 101 000 d² N (d in mm), over d = 12-160 mm; the ratio panel: model EA over the studless formula
    ax, ax2 = figs["practice_ea.png"].axes[:2]
    d = ax.lines[0].get_xdata()
    assert d.min() == pytest.approx(12.0) and d.max() == pytest.approx(160.0)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), 85_400 * d**2, rtol=1e-9)
    np.testing.assert_allclose(ax.lines[1].get_ydata(), 101_000 * d**2, rtol=1e-9)
    rows = sec["table"]
    for fam in ("din22252", "studless"):
        rr = [r for r in rows if r["family"] == fam]
        line = next(ln for ln in ax2.lines if list(ln.get_xdata()) == [r["d_mm"] for r in rr]
                    and ln.get_linestyle() == "-")
        np.testing.assert_allclose(line.get_ydata(), [r["EA_model_N"] / (85_400 * r["d_mm"] ** 2) for r in rr],
                                   rtol=1e-6)
    # the limits figure: per family the contact limit, first yield, proof and breaking loads; the paper's 11117 N
    axl = figs["practice_limits.png"].axes[0]
    assert any(np.allclose(ln.get_ydata(), 11117.0) for ln in axl.lines)
    rr = [r for r in rows if r["family"] == "studless"]
    ys = [list(ln.get_ydata()) for ln in axl.lines]
    for key in ("contact_limit_load_N", "first_yield_load_N", "proof_load_N", "breaking_load_N"):
        assert [r[key] for r in rr] in ys, key
    # studless R3 breaking force: 0.0223 d² (44 - 0.08 d) kN (d in mm), as the catalogue gives it
    for r in rr:
        assert r["breaking_load_N"] == pytest.approx(22.3 * r["d_mm"] ** 2 * (44 - 0.08 * r["d_mm"]), rel=1e-3)


@pytest.mark.slow
def test_eq26_figure_plots_the_record_the_model_and_the_residual(eq26):
    _, doc, _ = eq26
    d = doc["eq26"]
    left, right = EQ26_FIGS["eq26_record.png"].axes[:2]
    psi = np.linspace(0, 2 * math.pi, 361)
    x = X0 + A3 * np.sin(psi)
    F = F0 + FA * np.sin(psi + PHI)
    base = MODEL.force(x) - M * W3**2 * A3 * np.sin(psi) * 1e-3
    c27 = 2834.4  # Eq. 27's c_e [N s/mm]
    np.testing.assert_allclose(left.lines[0].get_xdata(), x, rtol=1e-12)
    np.testing.assert_allclose(left.lines[2].get_ydata(), (base + c27 * W3 * A3 * np.cos(psi)) / 1000, rtol=1e-9)
    # markers at psi = 0 and 90 deg on the record's loop
    assert left.lines[3].get_xdata()[0] == pytest.approx(X0) and left.lines[4].get_xdata()[0] == pytest.approx(X0 + A3)
    assert left.lines[4].get_ydata()[0] == pytest.approx((F0 + FA * math.sin(math.pi / 2 + PHI)) / 1000)
    deg = right.lines[0].get_xdata()
    np.testing.assert_allclose(deg, np.degrees(psi), rtol=1e-12)
    np.testing.assert_allclose(right.lines[0].get_ydata(), (F - base) / 1000, rtol=1e-9, atol=1e-9)
    h = d["residual_harmonics"]
    np.testing.assert_allclose(right.lines[1].get_ydata(), h["h1_x"] * np.sin(psi) / 1000, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(right.lines[2].get_ydata(), h["h1_xdot"] * np.cos(psi) / 1000, rtol=1e-9,
                               atol=1e-12)
    np.testing.assert_allclose(right.lines[3].get_ydata(), h["mean"] / 1000)
    np.testing.assert_allclose(right.lines[4].get_ydata(), c27 * W3 * A3 * np.cos(psi) / 1000, rtol=1e-9,
                               atol=1e-12)
    assert list(right.get_xticks()) == [0, 90, 180, 270, 360]
    assert right.lines[1].get_label() == f"in phase with x: {h['h1_x'] / 1000:+.1f} kN (stiffness)"
    assert right.lines[2].get_label() == f"in phase with ẋ: {h['h1_xdot'] / 1000:+.1f} kN (damping)"
    assert right.lines[3].get_label() == f"mean {h['mean'] / 1000:+.2f} kN"
    assert left.lines[2].get_label() == "model + Eq. 27 damping (c_e = 2834.4 N·s/mm)"


@pytest.mark.slow
def test_table1_figure_fits_and_reference_slopes(eq26):
    """log W against log A and ω: the fit line has the fitted slope through the geometric means; the reference
    lines have slopes 1, 2, 3 (A) and 0, 1 (ω); test 1 as printed and with F_ac from its c_e."""
    _, doc, _ = eq26
    t1 = doc["table1"]
    axA, axw = EQ26_FIGS["table1_energy.png"].axes[:2]
    for ax, slopes, fit in ((axA, (1, 2, 3), t1["slope_A"]), (axw, (0, 1), t1["slope_omega"])):
        xs, ws = ax.lines[0].get_xdata(), ax.lines[0].get_ydata()
        gx, gw = math.exp(np.mean(np.log(xs))), math.exp(np.mean(np.log(ws)))
        lines = ax.lines[1:2 + len(slopes)]
        got = [np.polyfit(np.log(ln.get_xdata()), np.log(ln.get_ydata()), 1) for ln in lines]
        assert [g[0] for g in got] == pytest.approx([fit, *slopes], abs=1e-9)
        for g in got:  # every line passes through the points' geometric mean
            assert g[0] * math.log(gx) + g[1] == pytest.approx(math.log(gw), abs=1e-9)
        xx = lines[0].get_xdata()
        assert xx.min() == pytest.approx(0.85 * xs.min()) and xx.max() == pytest.approx(1.15 * xs.max())
    for ax in (axA, axw):  # log axes: the minor ticks at 2, 3, 5 and 7 times a decade are labelled, no others
        fmt = ax.yaxis.get_minor_formatter()
        assert [fmt(v, 0) for v in (200.0, 300.0, 500.0, 700.0, 3000.0)] == ["200", "300", "500", "700", "3000"]
        assert [fmt(v, 0) for v in (400.0, 600.0, 800.0, 900.0)] == ["", "", "", ""]
    rows = {t["test"]: t for t in t1["tests"]}
    w1 = rows[1]["omega_rad_s"]
    printed, implied = axw.lines[-2], axw.lines[-1]
    assert printed.get_xdata()[0] == pytest.approx(w1) and implied.get_xdata()[0] == pytest.approx(w1)
    assert printed.get_ydata()[0] == pytest.approx(math.pi * rows[1]["F_ac_N"] * rows[1]["A_mm"])
    assert implied.get_ydata()[0] == pytest.approx(math.pi * t1["test1"]["F_ac_implied_by_c_e_N"] * rows[1]["A_mm"])


@pytest.mark.slow
def test_data_step_with_tension_records_keeps_the_chain(tmp_path):
    """Records of the chain itself (F > 0 everywhere): step 3 identifies with the chain model, no linear spring."""
    from chainid.records.files import write_records
    from chainid.records.simulate import TestSpec, simulate

    plan = [TestSpec(str(i), w, 2.2, A) for i, (w, A) in enumerate([(1, 0.2), (2, 0.2), (3, 0.3)], 1)]
    recs = simulate(plan, MODEL, 500.0, seed=0, noise_F=1.0, n_cycles=6, samples_per_cycle=128)
    assert min(float(r.F.min()) for r in recs) > 0
    data = tmp_path / "chain.csv"
    write_records(data, recs)
    (tmp_path / "out" / "figures").mkdir(parents=True)
    msgs: list[str] = []
    text = build.step_identify_data(tmp_path / "out", data, MODEL, msgs.append)
    assert "compressive" not in text and "linear spring" not in text
    assert "3 tests: fewer than" in text
    doc = json.loads((tmp_path / "out" / "json" / "identify.json").read_text())
    assert doc["model"] == MODEL.name
    assert [t["c_e"] for t in doc["tests"]] == pytest.approx([500.0] * 3, rel=0.02)
    assert msgs[0] == f"identification of 3 tests from {data}"


def test_stiffness_step_numbers_and_figures(tmp_path):
    """Step 2: the table and JSON are Eq. 15 (typed in paper_forms) at x = 0.5…5 mm; x(11117 N) is its inverse;
    Fig. 8b's legend gives E in GPa (MPa / 1000)."""
    from chainid.chain.spec import default_chain

    (tmp_path / "figures").mkdir()
    figs: dict[str, object] = {}
    msgs: list[str] = []
    with pytest.MonkeyPatch.context() as mp:
        _spy_figures(mp, figs)
        md = build.step_stiffness(tmp_path, default_chain(), msgs.append)
    doc = json.loads((tmp_path / "json" / "stiffness.json").read_text())
    assert doc["x_at_11117N_mm"] == pytest.approx(paper_forms.x_of_F(11117.0), rel=1e-9)
    pts = {p["x_mm"]: p for p in doc["points"]}
    assert sorted(pts) == [0.5, 1.0, 2.2, 3.0, 5.0]
    for x, p in pts.items():
        assert p["F_k_paper_N"] == pytest.approx(paper_forms.F_of_x(x), rel=1e-6)
        assert p["k_e_paper_N_per_mm"] == pytest.approx(paper_forms.k_e(x), rel=1e-6)
    assert f"x(11117 N) = {paper_forms.x_of_F(11117.0):.4f} mm" in md
    assert f"| 2.2 | {paper_forms.F_of_x(2.2):.0f} / {paper_forms.k_e(2.2):.0f} |" in md
    labels = [ln.get_label() for ln in figs["fig8b_stiffness_vs_modulus.png"].axes[0].lines]
    assert labels == [f"E = {f:g} E₀ = {210 * f:g} GPa" for f in (0.5, 0.75, 1.0, 1.25, 1.5)]
    assert {"fig8a_stiffness_vs_length.png", "fig8b_stiffness_vs_modulus.png", "stiffness_variants.png"} <= set(figs)
    assert msgs == ["stiffness figures"]
    assert all((tmp_path / "figures" / n).stat().st_size > 5000 for n in figs)
    # the variants figure: x = 0-5 mm; the paper variant's curve is Eq. 16 (k_e of paper_forms)
    lines = {ln.get_label(): ln for ln in figs["stiffness_variants.png"].axes[0].lines}
    assert "paper" in lines and len(lines) >= 2
    x, k = lines["paper"].get_xdata(), lines["paper"].get_ydata()
    assert x[0] == 0.0 and x[-1] == 5.0 and len(x) == 600
    for i in (100, 300, 599):
        assert k[i] == pytest.approx(paper_forms.k_e(x[i]), rel=1e-9)
    # Fig. 8a's legend: n links of the 50 mm pitch
    labels = [ln.get_label() for ln in figs["fig8a_stiffness_vs_length.png"].axes[0].lines]
    assert labels == [f"n = {n} ({50 * n} mm)" for n in (8, 16, 32, 64)]


@pytest.mark.slow
def test_every_note_placed_in_axes_coordinates_is_inside_its_panel(eq26, damping_step):
    """A note placed with axes coordinates (0..1) outside that range is drawn off its panel, over another one."""
    figs = {**EQ26_FIGS, **damping_step[2]}
    n = 0
    for name, fig in figs.items():
        for ax in fig.axes:
            for txt in ax.texts:
                if txt.get_transform() == ax.transAxes:
                    x, y = txt.get_position()
                    assert 0 <= x <= 1 and 0 <= y <= 1, (name, txt.get_text())
                    n += 1
    assert n >= 1

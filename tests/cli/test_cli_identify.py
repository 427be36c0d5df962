"""``chainid identify``: the text table by hand, the mass's inertia, non-elliptic loop notes, progress, a linear
spring fitted when k is not given, plots checked before any work."""
from __future__ import annotations

import json
import math

import pytest

from chainid.cli import main
from chainid.model.base import LinearModel
from chainid.model.effects import parse_effect
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, simulate


def test_identify_mass_moves_the_in_phase_amplitude_by_m_omega2_a(chain_records, tmp_path, capsys):
    """``--mass m`` is the mass whose inertia m·ẍ is taken off F in the dissipated force F_c = F − m·ẍ − F_k
    (Eq. 17/20): the in-phase amplitude of F_c (``F_as``) changes by m·ω²·A·1e-3 N between ``--mass 0`` and
    ``--mass 4000`` (ẍ = −ω²(x − x0)), by hand per test, and each test reports the mass used.  Bug caught:
    ``--mass`` dropped when handing it to the identification (the chain's own 3.2 kg used)."""
    out = {}
    for m in (0, 4000):
        j = tmp_path / f"m{m}.json"
        assert main(["identify", str(chain_records), "--mass", str(m), "--law", "viscous", "--quiet",
                     "--json", str(j)]) == 0
        out[m] = {t["test"]: t for t in json.loads(j.read_text())["tests"]}
    capsys.readouterr()
    assert len(out[0]) == 9
    for test, a in out[0].items():
        b = out[4000][test]
        assert b["F_as"] - a["F_as"] == pytest.approx(4000 * a["omega"] ** 2 * a["A"] * 1e-3, rel=1e-3)
        assert (a["mass_kg"], b["mass_kg"]) == (0.0, 4000.0)


@pytest.fixture(scope="module")
def six_long_ids(tmp_path_factory):
    """Six simulated tests of the paper plan (exactly MIN_TESTS = 6) under ids longer than any table header."""
    from chainid.model.base import ChainModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan()[:6], ChainModel(), ViscousLaw([300.0]), n_cycles=4, samples_per_cycle=100,
                    ramp_rate=None)
    for i, r in enumerate(recs):
        r.test = f"shaker_run_2026_11_24_{i:03d}"
    return write_records(tmp_path_factory.mktemp("six") / "d.csv", recs)


def test_identify_plots_of_six_tests_check_the_surface_figure_before_any_work(six_long_ids, tmp_path, capsys):
    """Six tests (MIN_TESTS, the fewest a damping law is fitted to) also draw ``damping_surface.png``: a user's
    file of that name in the ``--plots`` folder is refused without ``--force`` before any test is identified (no
    "identifying test" progress line), and left byte for byte.  Bug caught (seed 25): the surface counted only
    above six tests (``>= MIN_TESTS`` → ``> MIN_TESTS``), so the check came after the work."""
    figs = tmp_path / "figs"
    figs.mkdir()
    (figs / "damping_surface.png").write_bytes(b"mine")
    capsys.readouterr()
    assert main(["identify", str(six_long_ids), "--plots", str(figs)]) == 2
    err = capsys.readouterr().err
    assert "damping_surface.png" in err and "identifying test" not in err
    assert (figs / "damping_surface.png").read_bytes() == b"mine"


def test_identify_table_columns_widen_to_their_longest_cell(six_long_ids, capsys):
    """The per-test table is right-aligned on the longest of header and cells: with 26-character test ids
    (longer than the header "test") every line of the table has the length of the header line, and each id
    ends where the header "test" ends.  Bug caught (seed 25): widths taken from the headers alone (``if cells``
    → ``if not cells``: the rows run past the header)."""
    capsys.readouterr()
    assert main(["identify", str(six_long_ids), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    i = next(k for k, ln in enumerate(lines) if ln.lstrip().startswith("test ") and "omega rad/s" in ln)
    head = lines[i]
    rows = lines[i + 2:i + 8]  # the six rows under the dashes
    assert head.index("test") + 4 == len("shaker_run_2026_11_24_000")
    for ln in [lines[i + 1]] + rows:
        assert len(ln) == len(head), ln
    assert all(ln.startswith("shaker_run_2026_11_24_") for ln in rows)


SPRING = LinearModel(k=200.0, x_ref=0.0, mass=0.0)


PTS = [(2.0, 1.0, 0.5), (3.0, 1.0, 0.4), (1.5, 1.0, 0.3)]  # (ω rad/s, x0 mm, A mm)


def _mixed(tmp_path):
    """Tests v1-v3: viscous (c_e = 20 N·s/mm, an ellipse); f1-f3: Coulomb friction 300 N on a tiny c_e (six tests:
    enough for the damping law, so that the command succeeds)."""
    visc = simulate([TestSpec(f"v{i}", *p) for i, p in enumerate(PTS, 1)], SPRING, 20.0, n_cycles=6,
                    samples_per_cycle=256, noise_F=0.1, seed=1)
    fric = simulate([TestSpec(f"f{i}", *p) for i, p in enumerate(PTS, 1)], SPRING, 0.01, n_cycles=6,
                    samples_per_cycle=256, noise_F=0.1, seed=2, force_fn=parse_effect("friction:F_c=300", SPRING))
    p = tmp_path / "mixed.csv"
    write_records(p, visc + fric)
    return p


def test_identify_notes_only_the_non_elliptic_loops(tmp_path, capsys):
    """R²(F_c) < 0.97 marks a loop that is not an ellipse. A Coulomb force is a square wave in phase with ẋ, whose
    fundamental carries 8/π² = 0.81 of its power; a viscous loop's F_c is one harmonic (R² = 1)."""
    data = _mixed(tmp_path)
    out = tmp_path / "r.json"
    assert main(["identify", str(data), "--model", "linear", "--k", "200", "--x-ref", "0", "--mass", "0",
                 "--json", str(out), "--quiet"]) == 0
    stdout = capsys.readouterr().out
    r2 = {t["test"]: t["r2_c"] for t in json.loads(out.read_text())["tests"]}
    assert min(r2[f"v{i}"] for i in (1, 2, 3)) > 0.999
    assert [r2[f"f{i}"] for i in (1, 2, 3)] == pytest.approx([8 / math.pi**2] * 3, abs=0.03)
    notes = [ln for ln in stdout.splitlines() if ln.startswith("note: F_c of test(s)")]
    assert len(notes) == 1 and notes[0].startswith("note: F_c of test(s) f1, f2, f3 is far from one harmonic")
    # viscous records only: no note at all
    visc = tmp_path / "visc.csv"
    write_records(visc, simulate([TestSpec(f"v{i}", *p) for i, p in enumerate(PTS * 2, 1)], SPRING, 20.0,
                                 n_cycles=6, samples_per_cycle=256, noise_F=0.1, seed=1))
    assert main(["identify", str(visc), "--model", "linear", "--k", "200", "--x-ref", "0", "--mass", "0",
                 "--quiet"]) == 0
    assert "note: F_c" not in capsys.readouterr().out


def test_identify_progress_counts_every_test(tmp_path, capsys):
    data = _mixed(tmp_path)
    assert main(["identify", str(data), "--model", "linear", "--k", "200", "--x-ref", "0", "--mass", "0"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "identifying test" in ln]
    assert lines == [f"[{i}/6] identifying test {t}" for i, t in enumerate(["v1", "v2", "v3", "f1", "f2", "f3"], 1)]


def test_identify_linear_without_k_fits_the_spring(tmp_path):
    """``--model linear`` without ``--k``: k is fitted on the steady cycles (the records' spring is 200 N/mm)."""
    data = _mixed(tmp_path)
    out = tmp_path / "r.json"
    assert main(["identify", str(data), "--model", "linear", "--mass", "0", "--json", str(out), "--quiet"]) == 0
    doc = json.loads(out.read_text())
    assert doc["model"]["name"].startswith("linear")
    ce = {t["test"]: t["c_e"] for t in doc["tests"]}
    assert [ce[f"v{i}"] for i in (1, 2, 3)] == pytest.approx([20.0] * 3, rel=0.02)  # viscous c_e through the fit
    out2 = tmp_path / "r2.json"
    assert main(["identify", str(data), "--model", "linear", "--k", "200", "--mass", "0", "--json", str(out2),
                 "--quiet"]) == 0
    assert json.loads(out2.read_text())["model"]["name"].startswith("linear")


C = 300.0  # the simulated viscous damping [N·s/mm]


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    from chainid.model.base import LinearModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan(), LinearModel(1e4), ViscousLaw([C]), n_cycles=4, samples_per_cycle=100,
                    ramp_rate=None)
    return write_records(tmp_path_factory.mktemp("id") / "d.csv", recs)


def test_identify_text_report_by_hand(data, capsys):
    """The model line (linear spring, m = 0 kg); one table row per test with c_e = 300 N·s/mm and F_ac = c ω A;
    the kept cycles 1-3 of 4 (the first dropped) and the window T..4T per test; the steady-cycle statement per test; the viscous law c = 300, its standard error 0, cond(X) = cond(G) = 1 for
    a column of ones, dof = 9 − 1 = 8, the residuals per test; the ranking headed by the true (viscous) law."""
    from chainid.records.simulate import paper_plan

    rc = main(["identify", str(data), "--model", "linear", "--k", "10000", "--law", "viscous", "--quiet"])
    out = capsys.readouterr().out.splitlines()
    assert rc == 0
    assert out[0] == "model: linear, mass m = 0 kg"
    head = out[1].split()
    assert head[:4] == ["test", "omega", "rad/s", "x0"] and set(out[2]) <= {"-", " "}
    plan = paper_plan()
    rows = [ln.split() for ln in out[3:12]]
    for s, r in zip(plan, rows):
        assert r[0] == s.test
        assert float(r[1]) == pytest.approx(s.omega, rel=1e-4) and float(r[3]) == pytest.approx(s.A, rel=1e-3)
        assert float(r[8]) == pytest.approx(C * s.omega * s.A, rel=1e-3)  # F_ac
        assert float(r[9]) == pytest.approx(C, rel=1e-3)  # c_e
        T = 2 * math.pi / s.omega  # 4 cycles from t = 0, the first dropped: cycles 1-3, window T..4T
        assert r[13:] == ["1-3", "(3)", f"{T:.4g}-{4 * T:.4g}"]
    assert out[12] == "steady cycles kept:"
    assert [ln.split(":")[0] for ln in out[13:22]] == [f"  {s.test}" for s in plan]
    i = out.index("damping law viscous: c_e = c")
    assert out[i + 1].split() == ["param", "lstsq", "std", "err", "normal", "eq.", "(Eq.", "23)"]
    p = out[i + 3].split()
    assert p[0] == "c" and float(p[1]) == pytest.approx(C, rel=1e-3) and float(p[3]) == pytest.approx(C, rel=1e-3)
    assert float(p[2]) < 1.0  # noise-free: the spread of c_e over the tests is tiny
    assert out[i + 4].startswith("cond(X) = 1, cond(G = X'X) = 1, RMSE = ") and out[i + 4].endswith(", dof = 8")
    assert out[i + 5].startswith("residuals [N.s/mm]: " + f"{plan[0].test}: ")
    assert out[i + 5].count(": ") == 1 + 9
    j = out.index("laws ranked by leave-one-out RMSE:")
    assert out[j + 1].split() == ["law", "params", "RMSE", "N.s/mm", "LOO", "RMSE", "N.s/mm"]
    ranked = [ln.split() for ln in out[j + 3:j + 9]]
    assert ranked[0][:2] == ["viscous", "1"] and {r[0] for r in ranked[-2:]} == {"hysteretic", "coulomb"}
    loo = [float(r[-1]) for r in ranked]
    # ranked by LOO RMSE, errors at round-off (below 1e-9 of c_e) being ties (fewer parameters first)
    key = [max(v, 1e-9 * C) for v in loo]
    assert key == sorted(key) and loo[-1] > 100.0  # Coulomb's 1/(ωA) misses a constant c by far

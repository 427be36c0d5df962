"""``chainid benchmark-gap --chain``: the blind benchmark on a user's chain (chainid.gap.benchmark.chain).

Independent references: linear elasticity and Hertz contact are both scale-free.  A chain whose every length
(d, pitch, width) is λ times the paper's chain carries the same stress at λ times the elongation (the link's
Castigliano terms give c_lin ∝ 1/λ, Hertz c_hertz ∝ λ^(-1/3); at F ∝ λ² both terms of Eq. 15 grow as λ), so
its length scale is λ exactly and its benchmark cases are the paper chain's with x × λ and F × λ²: the same
verdicts and the same residual-to-noise ratios.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import chainid
from chainid.chain.spec import ChainSpec, default_chain
from chainid.cli import main
from chainid.gap.benchmark.grid import grid, run_case
from chainid.gap.benchmark.chain import REF_X0, USER, builtin_chains, length_scale, on_chain


def similar(lam: float, name: str = "14x50") -> ChainSpec:
    """The benchmark's chain ``name`` with every length × lam."""
    c = builtin_chains()[name]
    return c.replace(d=c.d * lam, pitch=c.pitch * lam, width=c.width * lam)


@pytest.mark.parametrize("lam", [0.5, 2.0, 5.0])
def test_a_geometrically_similar_chain_has_the_length_scale_lambda(lam: float) -> None:
    assert length_scale(similar(lam)) == pytest.approx(lam, rel=1e-12)
    assert length_scale(default_chain()) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("preset", ["studless:76:grade=R4", "din22252:26x92", "studlink:48"])
def test_the_scaled_mean_elongation_carries_the_paper_chains_nominal_stress(preset: str) -> None:
    """F(s·2 mm)/d² of the user's chain = F_14x50(2 mm)/14², and the paper's chain at 2 mm is near its x0 =
    2.2 mm test point (README: F_k(1.906 mm) = 11117 N)."""
    c = ChainSpec.preset(preset)
    s = length_scale(c)
    ref = float(chainid.force(REF_X0)) / 14.0 ** 2
    assert 11117 < float(chainid.force(REF_X0)) < 11117 * 1.2
    assert float(chainid.force(REF_X0 * s, chain=c)) / c.d ** 2 == pytest.approx(ref, rel=1e-9)
    assert s > 1.0  # every one of these chains is bigger than 14x50 and needs more elongation for the stress


def test_a_user_chain_carries_every_case_and_keeps_one_harmonic_chain_slot() -> None:
    c = ChainSpec.preset("studless:76:grade=R4")
    base = grid(True, 0)
    cases = grid(True, 0, chain=c)
    assert all("chain_spec" not in k for k in base)  # the built-in grid is unchanged
    assert {k["chain"] for k in cases} == {USER}
    assert all(k["chain_spec"] == c.to_dict() and k["x_scale"] == length_scale(c) for k in cases)
    harm = [k for k in base if k["excitation"] == "harmonic"]
    assert len([k for k in cases if k["excitation"] == "harmonic"]) == len([k for k in harm if k["chain"] == "14x50"])
    assert len([k for k in cases if k["excitation"] != "harmonic"]) == len(base) - len(harm)
    assert [k["seed"] for k in cases if k["excitation"] != "harmonic"] == \
        [k["seed"] for k in base if k["excitation"] != "harmonic"]


def test_the_time_cases_move_every_displacement_by_the_length_scale() -> None:
    from chainid.gap.benchmark.nonharmonic import records

    case = next(k for k in grid(True, 0, ("quake",)) if k["family"] == "single") | {"chain": "14x50"}
    lam = 3.0
    _, dev0 = records(case)
    _, dev1 = records(on_chain([case], similar(lam))[0])
    for m0, m1 in zip(dev0["motions"], dev1["motions"]):
        np.testing.assert_allclose(m1.x, lam * m0.x, rtol=1e-12)
        np.testing.assert_allclose(m1.xd, lam * m0.xd, rtol=1e-12)
        assert m1.A == pytest.approx(lam * m0.A, rel=1e-12)
    assert dev1["S"] == pytest.approx(lam ** 2 * dev0["S"], rel=1e-9)  # force scale k·A: k × λ, A × λ


@pytest.mark.slow
@pytest.mark.parametrize("exc", ["harmonic", "sweep"])
def test_a_similar_chain_gets_the_same_verdict_and_the_same_signal_to_noise(exc: str) -> None:
    """The cases on a chain twice the paper's are the paper chain's with x × 2 and F × 4: the verdict is the
    same and the baseline's residual over the noise agrees to 1e-3 (measured: 3e-5 harmonic, 1e-13 sweep; the
    fits stop on relative tolerances)."""
    case = next(k for k in grid(True, 0, (exc,)) if k["family"] == "single" and k["truth"] == ["friction"])
    case = case | {"chain": "14x50"}  # on_chain moves the cases to the user's chain at the 14x50's stress
    a = run_case(case)
    b = run_case(on_chain([case], similar(2.0))[0])
    assert a["verdict"] == "friction" and b["verdict"] == "friction"
    assert b["snr"] == pytest.approx(a["snr"], rel=1e-3)
    assert b["shrinkage"] == pytest.approx(a["shrinkage"], abs=1e-3)


def _row_without_a_diagnosis(case: dict) -> dict:
    """A benchmark row as :func:`chainid.gap.benchmark.grid.run_case` returns it, without simulating or diagnosing
    (the CLI's handling of ``--chain`` is under test; the cases' physics on a similar chain is checked above)."""
    return {**case, "verdict": "none", "seconds": 0.0, "snr": 0.0, "shrinkage": None, "steps": [], "params": None,
            "params_ci90": {}, "true_params": {}, "stationary": True, "confounded": [],
            "open_world": {"missing_effect": False, "predictable_share": None}}


def test_cli_benchmark_on_a_preset_writes_the_chain_and_its_scale(tmp_path, capsys, monkeypatch) -> None:
    import chainid.gap.benchmark.grid as grid_module

    monkeypatch.setattr(grid_module, "run_case", _row_without_a_diagnosis)
    out = tmp_path / "b.json"
    rc = main(["benchmark-gap", "--small", "--excitations", "harmonic", "--chain", "studless:76:grade=R4",
               "--scheduler", "serial", "--no-progress", "--json", str(out)])
    r = capsys.readouterr()
    assert rc == 0, r.err
    d = json.loads(out.read_text())
    c = ChainSpec.preset("studless:76:grade=R4")
    assert d["chain"]["grade"] == "R4" and d["chain"]["d"] == 76.0
    assert d["chain"]["x_scale"] == pytest.approx(length_scale(c), rel=1e-12)
    assert {row["chain"] for row in d["rows"]} == {USER}
    assert "grade R4" in r.out and "x 5.757" in r.out


def test_cli_benchmark_refuses_an_unknown_chain_before_running(tmp_path, capsys) -> None:
    out = tmp_path / "b.json"
    rc = main(["benchmark-gap", "--small", "--chain", "studless:7x", "--scheduler", "serial", "--json", str(out)])
    r = capsys.readouterr()
    assert rc == 2
    assert "studless:7x" in r.err and "error" in r.err
    assert not out.exists() and r.out == ""  # refused before any case ran
    assert r.err.count("\n") == 1  # one line, no traceback


@pytest.mark.slow
def test_a_transfer_case_on_a_similar_chain_scales_its_harmonic_plan_too() -> None:
    """The transfer case's harmonic set (x̄0 ± 0.1 mm on the paper's chain) moves with the length scale: on a
    chain twice the paper's the other-set shrinkages agree to 1e-5 (measured 3e-8 and 4e-8)."""
    case = grid(True, 0, ("transfer",))[0] | {"chain": "14x50"}
    a = run_case(case)
    b = run_case(on_chain([case], similar(2.0))[0])
    assert a["verdict"] == b["verdict"] == "hysteresis"
    assert b["transfer_shrinkage"] == pytest.approx(a["transfer_shrinkage"], abs=1e-5)
    assert b["transfer_shrinkage_refit"] == pytest.approx(a["transfer_shrinkage_refit"], abs=1e-5)


def test_the_harmonic_plan_of_a_user_chain_is_the_paper_plan_times_the_length_scale() -> None:
    """grid3x3 on the paper's chain: 9 tests at x0 = 2 mm with A 0.1/0.2/0.3 mm, then (2.2, 0.15), (1.8, 0.25)
    (its docstring); on the user's chain every x0 and A × s, ω unchanged."""
    from chainid.gap.benchmark.grid import case_plan

    c = ChainSpec.preset("studless:76:grade=R4")
    case = next(k for k in grid(True, 0, ("harmonic",)) if k["plan"] == "grid3x3")
    s = length_scale(c)
    p0, p1 = case_plan(case), case_plan(on_chain([case], c)[0])
    assert [(p.x0, p.A) for p in p0][:3] == [(2.0, 0.1), (2.0, 0.2), (2.0, 0.3)]
    assert [(p.x0, p.A) for p in p0][-2:] == [(2.2, 0.15), (1.8, 0.25)]
    for a, b in zip(p0, p1):
        assert (b.test, b.omega) == (a.test, a.omega)
        assert b.x0 == pytest.approx(s * a.x0, rel=1e-12) and b.A == pytest.approx(s * a.A, rel=1e-12)


def test_the_transfer_plan_offsets_its_two_extra_tests_by_a_tenth_of_a_millimetre_times_the_scale() -> None:
    from chainid.gap.benchmark.nonharmonic import transfer_plan
    from chainid.records.excitation import Motion

    t = np.linspace(0.0, 10.0, 1001)
    ms = [Motion(t, 2.0 + a * np.sin(2 * np.pi * t), 0 * t, 0 * t, f, a / 2 ** 0.5, "random", f)
          for a, f in ((0.1, 1.0), (0.2, 2.0), (0.3, 3.0))]
    for s in (1.0, 4.0):
        plan = transfer_plan(ms, s)
        assert len(plan) == 11
        x0 = float(np.median([np.median(m.x) for m in ms]))
        assert plan[-2].x0 == pytest.approx(x0 + 0.1 * s, abs=1e-12)
        assert plan[-1].x0 == pytest.approx(x0 - 0.1 * s, abs=1e-12)
        assert plan[-2].omega == pytest.approx(0.75 * 2 * np.pi * 1.0, rel=1e-12)  # ω_lo from the lowest band edge

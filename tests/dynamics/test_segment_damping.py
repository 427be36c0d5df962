"""Time-domain segment damping in dynamics: Jenkins/Iwan hysteresis, Coulomb with stick, scaling, a model file's
damping in the segments.

Independent references: the loop area of a Jenkins element (spring k in series with a slider of force f),
4·f·(A − f/k) per cycle of elongation amplitude A, and its virgin and closing branches; the energy balance.
Units mm, N, s, kg; energies N·mm."""
import math

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.dynamics import ChainLine, Drive, simulate
from chainid.model import kernels
from model_texts import SPECIMEN

K, F = 2_000.0, 150.0  # N/mm, N: the specimen's Jenkins element (stick travel f/k = 0.075 mm)
A = 0.3                 # mm elongation amplitude
X0 = 0.8                # mm mean elongation (taut throughout)


def _jenkins_dissipation(n_cycles, A, k, f):
    """Slip work of x = A·sin(ωt) over n whole cycles from an unstressed element (hand count of the branches):
    virgin quarter f(A − a), 2n − 1 half swings 2f(A − a), the last quarter from −A up to 0: f(A − 2a), a = f/k."""
    a = f / k
    return f * (A - a) + (2 * n_cycles - 1) * 2 * f * (A - a) + f * max(A - 2 * a, 0.0)


def _specimen(n_masses, lumping, **kw):
    chain = default_chain()
    F0 = float(kernels.force(X0, chain))
    return ChainLine(n_links=chain.n, n_masses=n_masses, chain=chain, pretension_N=F0, far_end="fixed",
                     lumping=lumping, **kw)


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_one_segment_dissipates_the_jenkins_loop(scheme):
    """N = 1 (the specimen itself, drive-lumped): the elongation is the drive's sine, the dissipation is exact."""
    line = _specimen(1, "drive", hysteresis=((K, F),))
    w, n = 2.0, 3
    T = 2 * math.pi / w
    res = simulate(line, Drive("sine", A=A, omega=w), n * T, dt=T / 4000, n_out=4000, scheme=scheme)
    assert res.tension.min() > 0
    assert res.dissipated[-1] == pytest.approx(_jenkins_dissipation(n, A, K, F), rel=1e-6)
    assert res.energy_balance()["relative_error"] < 1e-6


def test_specimen_to_segment_scaling_in_series():
    """4 and 8 segments of the same 16-link specimen, quasi-static: the chain dissipates the specimen's loop.

    Series rule: a segment of n_s links of a specimen of n_ref links has k·n_ref/n_s and the same f.  Without
    the scaling each segment would see A/4 = f/k and dissipate nothing."""
    line1 = _specimen(1, "drive", hysteresis=((K, F),))
    line4 = _specimen(4, "half", hysteresis=((K, F),))
    k4, f4 = line4.segment_elements()
    np.testing.assert_allclose(k4, K * 16 / 4, rtol=1e-15)
    np.testing.assert_allclose(f4, F, rtol=1e-15)
    w, n = 20.0, 3
    D = _jenkins_dissipation(n, A, K, F)
    for line in (line1, line4, _specimen(8, "half", hysteresis=((K, F),))):
        res = simulate(line, Drive("sine", A=A, omega=w), n * 2 * math.pi / w, n_out=2000)
        assert res.dissipated[-1] == pytest.approx(D, rel=2e-3)
        assert res.energy_balance()["relative_error"] < 1e-3


def test_coulomb_sticks_below_its_slip_travel():
    """Coulomb with stick (stick stiffness k_s): an amplitude below f/k_s never slips (no dissipation);
    above it, it dissipates the Jenkins loop of (k_s, f)."""
    ks = 5_000.0
    w, n = 2.0, 2
    T = 2 * math.pi / w
    small = _specimen(1, "drive", coulomb_N=F, coulomb_stiffness=ks)
    res = simulate(small, Drive("sine", A=0.02, omega=w), n * T, dt=T / 2000, n_out=2000)  # 0.02 < 0.03 mm
    assert res.dissipated[-1] == 0.0
    # the stuck element is a spring k_s in parallel with the chain: T = F_k(e) + k_s·(e − e_0) at every sample
    e = small.pretension_elongation()[0] + res.u[:, 0]
    Fk = np.array([float(kernels.force(x, default_chain())) for x in e])
    np.testing.assert_allclose(res.tension[:, 0], Fk + ks * res.u[:, 0], rtol=1e-12, atol=1e-9)
    big = simulate(_specimen(1, "drive", coulomb_N=F, coulomb_stiffness=ks), Drive("sine", A=A, omega=w),
                   n * T, dt=T / 2000, n_out=2000)
    assert big.dissipated[-1] == pytest.approx(_jenkins_dissipation(n, A, ks, F), rel=1e-6)


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_hysteretic_chain_keeps_its_energy_balance(scheme):
    """A dynamic chain with an Iwan pair and Coulomb friction in every segment: balance within 1e-3 with
    the hysteretic dissipation counted (it is most of the work done over 10 cycles)."""
    line = ChainLine(n_links=100, n_masses=10, pretension_N=5_000.0, far_end="fixed",
                     hysteresis=((3_000.0, 200.0), (1_000.0, 400.0)), coulomb_N=100.0)
    res = simulate(line, Drive("sine", A=0.3, omega=300.0), 10 * 2 * math.pi / 300.0, scheme=scheme, n_out=2000)
    eb = res.energy_balance()
    assert res.tension.min() > 0
    assert eb["relative_error"] < 1e-3
    assert eb["dissipated"] > 0.9 * eb["work_in"] > 0


@pytest.mark.parametrize("kw, field", [
    (dict(hysteresis=((0.0, 10.0),)), "hysteresis"),
    (dict(hysteresis=((100.0, 0.0),)), "hysteresis"),
    (dict(hysteresis=((100.0,),)), "hysteresis"),
    (dict(coulomb_N=-1.0), "coulomb_N"),
    (dict(coulomb_N=5.0, coulomb_stiffness=0.0), "coulomb_stiffness"),
])
def test_bad_segment_damping(kw, field):
    with pytest.raises(ValueError, match=field):
        ChainLine(n_links=10, n_masses=2, **kw)


# ------------------------------------------------------------------ --segment-model (issue 17 model file)
MODEL = SPECIMEN + """[damping]
form = "{form}"
[damping.params]
{params}
"""


def _model_file(tmp_path, form, params, name="m.toml"):
    p = tmp_path / name
    p.write_text(MODEL.format(form=form, params=params))
    return p


def test_segment_model_hysteretic_loop_is_the_structural_damping_energy(tmp_path):
    """form = hysteretic (η·k, x_max, n): the specimen dissipates π·η·k·A² per steady cycle (A = x_max/2, n even)."""
    from chainid.dynamics.segment_model import segment_kwargs
    eta_k, x_max = 400.0, 0.4
    kw, notes = segment_kwargs(_model_file(tmp_path, "hysteretic", f"eta_k = {eta_k}\nx_max = {x_max}\nn = 8"))
    assert kw["damping_ref_links"] == 16 and len(kw["hysteresis"]) == 8 and notes == []
    F0 = float(kernels.force(X0, kw["chain"]))
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="fixed", lumping="drive", **kw)
    w, Amp = 2.0, x_max / 2
    T = 2 * math.pi / w
    res = simulate(line, Drive("sine", A=Amp, omega=w), 3 * T, dt=T / 4000, n_out=12000)
    i1 = int(np.argmin(np.abs(res.t - T)))
    assert res.dissipated[-1] - res.dissipated[i1] == pytest.approx(2 * math.pi * eta_k * Amp ** 2, rel=1e-6)


def test_a_hysteretic_model_without_x_max_or_n_gets_the_documented_defaults(tmp_path):
    """x_max = 1 mm and n = 32 when the file gives neither: by hand, n Jenkins elements of slip force
    F_c = (π/2)·η·k·x_max/n and stick travel x_s,i = (i − ½)·x_max/n (uniform density, midpoint rule), stiffness
    F_c/x_s,i, the same elements the model's own force uses (chainid.model.timedamping.iwan_elements)."""
    from chainid.dynamics.segment_model import segment_kwargs

    eta_k = 300.0
    kw, _ = segment_kwargs(_model_file(tmp_path, "hysteretic", f"eta_k = {eta_k}"))
    Fc = 0.5 * math.pi * eta_k / 32
    xs = (np.arange(32) + 0.5) / 32
    np.testing.assert_allclose(np.array(kw["hysteresis"], float), np.column_stack([Fc / xs, np.full(32, Fc)]),
                               rtol=1e-12)


def test_cli_segment_model(tmp_path, capsys):
    import json

    from chainid.cli import main
    m = _model_file(tmp_path, "coulomb", "F_c = 80.0\nx_s = 0.01")
    out = tmp_path / "r.json"
    argv = ["dynamics", "--links", "64", "--masses", "4", "--pretension", "2000", "--drive", "sine",
            "--amplitude", "0.3", "--omega", "50", "--t-end", "0.5", "--segment-model", str(m), "--quiet"]
    assert main(argv + ["--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["line"]["hysteresis"] == [[8000.0, 80.0]] and doc["line"]["damping_ref_links"] == 16
    assert doc["summary"]["energy_N_mm"]["dissipated"] > 0
    assert doc["summary"]["energy_N_mm"]["relative_error"] < 1e-3
    capsys.readouterr()
    assert main(argv + ["--damping", "5"]) == 2
    assert "--damping cannot be given with it" in capsys.readouterr().err
    bad = tmp_path / "linear.toml"
    bad.write_text('format_version = 1\nkind = "chainid-augmented-model"\n[base]\nmodel = "linear"\nk = 100.0\n'
                   'x_ref = 0.0\n[damping]\nform = "viscous"\n[damping.params]\nc = 1.0\n')
    assert main(argv[:-3] + ["--segment-model", str(bad), "--quiet"]) == 2
    assert "need a chain base" in capsys.readouterr().err


def test_segment_model_law_needs_and_uses_its_operating_point(tmp_path, capsys):
    """An identified law c_e = p_1·4/(π ω A) (Coulomb-equivalent): resolved (rule viscous) at the stated ω, A."""
    from chainid.cli import main
    from chainid.dynamics.segment_model import segment_kwargs
    p = tmp_path / "law.toml"
    p.write_text(MODEL.replace('form = "{form}"\n[damping.params]\n{params}\n',
                               'form = "law"\nlaw = "coulomb"\ncoefficients = [50.0]\nrule = "viscous"\n'))
    kw, notes = segment_kwargs(p, pretension_N=2000.0, omega=40.0, amplitude=0.2)
    assert kw["damping"] == pytest.approx(50.0 * 4 / (math.pi * 40.0 * 0.2), rel=1e-12)
    assert "resolved" in notes[0]
    argv = ["dynamics", "--links", "64", "--masses", "4", "--pretension", "2000", "--t-end", "0.05",
            "--segment-model", str(p), "--quiet"]
    assert main(argv) == 2
    assert "operating point" in capsys.readouterr().err
    assert main(argv + ["--segment-omega", "40", "--segment-amplitude", "0.2"]) == 0
    assert "note: damping law 'coulomb' resolved" in capsys.readouterr().err


def test_segment_model_carries_a_modified_kernel(tmp_path):
    """A base kernel modifier (slack 0.1 mm of the specimen) goes into the line's field of the same name."""
    from chainid.dynamics.segment_model import segment_kwargs
    p = tmp_path / "slack.toml"
    p.write_text(MODEL.format(form="viscous", params="c = 2.0").replace('variant = "paper"',
                                                                         'variant = "paper"\nslack = 0.1'))
    kw, notes = segment_kwargs(p)
    assert kw["slack"] == 0.1 and kw["damping"] == 2.0 and notes == []


def _dahl_loop(A, F_h, x_h):
    """Steady Dahl loop area [N·mm] by hand: branches z = ±F_h ∓ (…)·exp(−|Δx|/x_h) between ±A, z(±A) = ±F_h·tanh(A/x_h):
    2·∫_{−A}^{A} z_up dx = 4·F_h·(A − x_h·tanh(A/x_h))."""
    return 4.0 * F_h * (A - x_h * math.tanh(A / x_h))


@pytest.mark.parametrize("n_links", [16, 32])
def test_dahl_segment_dissipates_the_dahl_loop(n_links):
    """Dahl (F_h = 120 N, x_h = 0.05 mm of the 16-link specimen; A/x_h = 6: steady after one cycle to 1e-5):
    one segment of 16 or 32 links, two steady cycles = 2 loops with x_h·n_s/16 (the series scaling), balance."""
    F_h, x_h, w = 120.0, 0.05, 2.0
    chain = default_chain()
    line = ChainLine(n_links=n_links, n_masses=1, chain=chain, pretension_N=float(kernels.force(X0, chain)),
                     far_end="fixed", lumping="drive", damping_ref_links=16, dahl=((F_h, x_h),))
    T = 2 * math.pi / w
    res = simulate(line, Drive("sine", A=A, omega=w), 3 * T, dt=T / 4000, n_out=12000)
    i1 = int(np.argmin(np.abs(res.t - T)))
    assert res.tension.min() > 0
    loop = _dahl_loop(A, F_h, x_h * n_links / 16)
    assert res.dissipated[-1] - res.dissipated[i1] == pytest.approx(2 * loop, rel=1e-4)
    assert res.energy_balance()["relative_error"] < 1e-3

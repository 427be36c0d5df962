"""The phase-bin problem (chainid.gap.harmonic.problem): c_e projection, held-out split and its noise in dB, BIC,
parameter keys and spring bounds, the laws a candidate is scored with, when damping is separable."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.harmonic.problem import Candidate, Problem


# ---------------------------------------------------------------- dB over noise, BIC
def _d(test, nbins, sigma, count):
    return SimpleNamespace(test=test, counts=np.full(nbins, float(count)), sigma=sigma)


def test_noise_db_uses_the_requested_split():
    """Hold: residual 1 N in 2 bins of 2 samples at σ = 2 N: r² = 1, floor σ²/n = 2 → −3.0103 dB; train: residual
    3 N, σ = 1, 4 samples: 9 / 0.25 → +15.563 dB.  Bug caught: the split ignored / swapped."""
    hold, train = _d("H", 2, 2.0, 2), _d("T", 3, 1.0, 4)
    fake = SimpleNamespace(hold=[hold], train=[train])
    fake.n_cells = lambda split: Problem.n_cells(fake, split)
    ev = {"res": {"H": np.ones(2), "T": np.full(3, 3.0)}}
    assert Problem.noise_db(fake, ev, "hold") == pytest.approx((1.0, 2.0, 10 * math.log10(0.5)), rel=1e-12)
    assert Problem.noise_db(fake, ev, "train") == pytest.approx((9.0, 0.25, 10 * math.log10(36.0)), rel=1e-12)


def test_bic_sample_size_is_the_training_bins():
    """BIC = χ² + k·ln(n_b) with n_b the training bins (64 + 64 = 128; the held-out 32 not counted) and k the
    effect's plus the law's parameters.  Bugs caught: n_b over hold or all bins, the law's parameters left out."""
    train = [_d("A", 64, 1.0, 4), _d("B", 64, 1.0, 4)]
    hold = [_d("H", 32, 1.0, 4)]
    ev = {"law_params": [0.1, 0.2], "nrmse_train": 0.1, "nrmse_loto": 0.2, "nrmse_holdout": 0.3, "chi2": 50.0,
          "loto_num": {}, "per_test": {}, "res": {"A": np.zeros(64), "B": np.zeros(64), "H": np.zeros(32)}}
    fake = SimpleNamespace(train=train, hold=hold, laws_for=lambda names: ["viscous"],
                           evaluate=lambda names, params, law: ev)
    fake.noise_db = lambda e, split="hold": Problem.noise_db(fake, e, split)
    fake.n_cells = lambda split="train": Problem.n_cells(fake, split)
    cand = Candidate(name="friction", params={"friction.F_c": 1.0}, n_params=1)
    out = Problem.score(fake, cand, ["friction"], 0.5)
    assert out.bic == pytest.approx(50.0 + 3 * math.log(128), rel=1e-12)


# ---------------------------------------------------------------- problem.damping_separable
def test_damping_separable_needs_three_by_three_and_six_tests():
    """Eq. 21 has 5 coefficients: separable on >= 6 tests at >= 3 frequencies and >= 3 amplitudes (full rank);
    five such tests, or 9 tests at 2 amplitudes, are not, and the message counts them."""
    from chainid.gap.harmonic.problem import damping_separable

    plan = [(1.0, 0.1), (2.0, 0.2), (4.0, 0.3), (1.0, 0.3), (2.0, 0.1), (4.0, 0.2)]
    data = [SimpleNamespace(omega=w, A=a) for w, a in plan]
    assert damping_separable(data) == (True, "")
    ok, msg = damping_separable(data[:5])  # full rank (cond 84) but no test left over: not separable
    assert not ok and msg.startswith("the training plan has 5 tests at 3 distinct frequencies and 3 distinct "
                                     "amplitudes (cond 84);")
    two = [SimpleNamespace(omega=w, A=a) for w in (1.0, 2.0, 4.0) for a in (0.1, 0.2, 0.2)]
    ok, msg = damping_separable(two)
    assert not ok and "9 tests at 3 distinct frequencies and 2 distinct amplitudes" in msg


def test_a_given_damping_law_needs_one_training_test_more_than_its_coefficients():
    """Eq. 21 has 5 coefficients: leave-one-out needs >= 6 training tests.  Seven tests, one held out: the given
    law is taken ("given"); two held out (5 training tests): refused, saying so."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.gap.harmonic.problem import Problem
    from chainid.model.base import ChainModel
    from chainid.records.simulate import TestSpec, simulate

    model = ChainModel()
    plan = [TestSpec(str(i), w, 2.0, a) for i, (w, a) in
            enumerate([(1.0, 0.1), (2.0, 0.2), (4.0, 0.3), (1.0, 0.3), (2.0, 0.1), (4.0, 0.2), (3.0, 0.15)], 1)]
    data = [prepare_test(r) for r in simulate(plan, model, 60.0, n_cycles=5, samples_per_cycle=64, noise_F=5.0,
                                              seed=1)]
    prob = Problem(data, model, ["7"], "polynomial")
    assert (prob.law, prob.law_reason) == ("polynomial", "given")
    with pytest.raises(ValueError, match="has 5 coefficients; with 5 training tests at most 4"):
        Problem(data, model, ["6", "7"], "polynomial")


def test_ce_projection_and_candidate_contract():
    """c_e of a test = the count-weighted projection of F̄ − F_n on v (Eq. 27 on the cycle-mean loop): with
    F̄ − F_n = 2.5·v exactly it is 2.5; Candidate names split on '+', the baseline has none; its JSON turns
    non-finite numbers into null."""
    from chainid.gap.harmonic.problem import Candidate, _ce

    v = np.array([1.0, -2.0, 0.5, 3.0])
    d = SimpleNamespace(counts=np.array([4.0, 1.0, 2.0, 3.0]), Fbar=10.0 + 2.5 * v)
    assert _ce(d, np.full(4, 10.0), v) == pytest.approx(2.5, rel=1e-12)
    w = d.counts
    Fn = np.array([9.0, 11.0, 10.0, 10.5])
    assert _ce(d, Fn, v) == pytest.approx(float(np.sum(w * (d.Fbar - Fn) * v) / np.sum(w * v * v)), rel=1e-12)
    assert Candidate("baseline", {}, 0).names == [] and Candidate("", {}, 0).names == []
    c = Candidate("friction+slack", {"friction.F_c": np.float64(3.0)}, 2, nrmse_holdout=float("nan"),
                  param_sd={"friction.F_c": float("inf")}, at_bound=("slack.s",))
    assert c.names == ["friction", "slack"]
    dct = c.to_dict()
    assert dct["effect"] == "friction+slack" and dct["params"] == {"friction.F_c": 3.0}
    assert dct["params_sd"] == {"friction.F_c": None} and dct["nrmse_holdout"] is None
    assert dct["at_bound"] == ["slack.s"] and dct["n_params"] == 2 and dct["damping_law"] == "polynomial"


def test_laws_for_and_a_given_baseline_law():
    """A candidate is scored with the baseline's law, and viscous too once it has an effect; the damping_law
    effect tries the other forms that n_train − 1 coefficients allow.  A given law is refused when unknown or
    when it has more coefficients than n_train − 1 (the messages name the value and the valid choices)."""
    from chainid.gap.harmonic.law_choice import ALT_LAWS
    from chainid.gap.harmonic.problem import Problem

    p = SimpleNamespace(train=[0] * 4, law="coulomb")
    assert Problem.laws_for(p, []) == ["coulomb"] and Problem.laws_for(p, ["friction"]) == ["coulomb", "viscous"]
    assert Problem.laws_for(SimpleNamespace(train=[0] * 4, law="viscous"), ["friction"]) == ["viscous"]
    assert Problem.laws_for(p, ["damping_law"]) == [k for k in ALT_LAWS if k != "coulomb"]  # <= 3 coefficients
    p2 = SimpleNamespace(train=[0] * 2, law="viscous")
    assert Problem.laws_for(p2, ["damping_law"]) == ["coulomb", "hysteretic"]  # 1 coefficient <= 2 − 1
    assert Problem.laws_for(SimpleNamespace(train=[0], law="viscous"), ["damping_law"]) == ["viscous"]
    fake = SimpleNamespace(train=[0] * 4)
    assert Problem._baseline_law(fake, "viscous+coulomb") == ("viscous+coulomb", "given")
    with pytest.raises(ValueError, match=r"--damping-law = 'cubic' is unknown; valid: auto, polynomial, viscous, "
                                         r"coulomb, viscous\+coulomb, hysteretic"):
        Problem._baseline_law(fake, "cubic")
    with pytest.raises(ValueError, match=r"--damping-law polynomial has 5 coefficients; with 4 training tests at most "
                                         "3 can be scored leave-one-out"):
        Problem._baseline_law(fake, "polynomial")
    assert Problem._baseline_law(SimpleNamespace(train=[0] * 6), "polynomial") == ("polynomial", "given")


def test_problem_holdout_errors():
    from chainid.gap.harmonic.problem import Problem

    data = [SimpleNamespace(test=s) for s in ("a", "b", "c", "d")]
    with pytest.raises(ValueError, match=r"--holdout: test id\(s\) \['z'\] not in the usable data; usable ids: a, b, "
                                         "c, d"):
        Problem(data, None, ["a", "z"])
    with pytest.raises(ValueError, match="--holdout: no test held out; give at least one test id"):
        Problem(data, None, [])
    with pytest.raises(ValueError, match=r"--holdout leaves 2 usable training test\(s\); at least 3 are needed"):
        Problem(data, None, ["a", "b"])


def test_problem_keys_spring_bounds_and_no_damping_law_parameters_by_hand():
    """A linear baseline re-fits its spring: k in [0, max(10·k0, 10·F_scale/x_scale)], x_ref within ± 2·x_scale;
    with ``fit_mass`` also its mass m in [0, 10·F_scale·1e3/(x_scale·ω_max²)] kg (m·ω²·1e-3 up to 10·F/x N/mm);
    ``damping_law`` has no fitted effect parameters (its law coefficients are the damping fit's), also when its
    name is a string built at run time (read from a command line), not the interned literal.  On a linear base the
    load-dependent friction μ is held (``identifiable``: μ·|F_k| needs the chain's own spring force); on a chain
    base every friction parameter is fitted."""
    from chainid.gap.harmonic.problem import Problem
    from chainid.model.effects import EFFECT_NAMES, make_effect

    effects = {n: make_effect(n, 100.0, 0.5, 10.0) for n in EFFECT_NAMES}
    fake = SimpleNamespace(_spring_start=lambda: {"spring.k": 30.0, "spring.x_ref": 1.0}, x_scale=0.5,
                           F_scale=100.0, effects=effects, fit_mass=False, is_chain=False, omega_max=10.0)
    law = "".join(["damping", "_law"])
    keys, lo, hi, x0 = Problem._keys(fake, [law, "friction"])
    fr = effects["friction"]
    assert fr.param_names == ("F_c", "mu", "x_s")
    keep = [0, 2]  # F_c and x_s; mu held on a linear base
    assert keys == ["spring.k", "spring.x_ref", "friction.F_c", "friction.x_s"]
    # 10·k0 = 300 < 10·F/x = 2000
    assert lo[:2] == [0.0, 1.0 - 2 * 0.5] and hi[:2] == [2000.0, 1.0 + 2 * 0.5] and x0[:2] == [30.0, 1.0]
    assert lo[2:] == [fr.bounds[i][0] for i in keep] and hi[2:] == [fr.bounds[i][1] for i in keep]
    assert x0[2:] == [fr.x0_guess[i] for i in keep]
    fake.fit_mass = True  # m ≤ 10·100·1e3/(0.5·10²) = 20000 kg, started at 0
    keys, lo, hi, x0 = Problem._keys(fake, [])
    assert keys == ["spring.k", "spring.x_ref", "spring.m"]
    assert (lo[2], hi[2], x0[2]) == (0.0, pytest.approx(20000.0, rel=1e-12), 0.0)
    fake.fit_mass = False
    fake.effects, fake.F_scale = effects, 1.0  # 10·k0 = 300 > 10·1/0.5 = 20
    assert Problem._keys(fake, [])[2] == [300.0, 2.0]
    fake._spring_start, fake.is_chain = (lambda: {}), True  # a chain baseline: no spring parameters
    assert Problem._keys(fake, [law]) == ([], [], [], [])
    keys, lo, hi, x0 = Problem._keys(fake, ["friction"])
    assert keys == [f"friction.{k}" for k in fr.param_names] and x0 == list(fr.x0_guess)
    assert lo == [b[0] for b in fr.bounds] and hi == [b[1] for b in fr.bounds]


def test_the_learners_travel_is_the_distance_since_the_last_reversal():
    """The model-free check's state feature 'travel' on sine tests about x0 = 0 (the linear device of the recovery
    cases, amplitudes 0.6–1.5 mm): the distance moved since the last reversal of a sine lies in [0, 2A], and in the
    bin before the next reversal (its samples within one bin, δ ≤ 2π/B, of it) it is A·(1 + cos δ) ≥ 2A·(1 − (π/B)²)
    (B phase bins).  Read per training test, in the table's order (B rows each)."""
    import warnings

    import recovery_cases as rc
    from chainid.gap.core.selection import baseline_candidate
    from chainid.gap.diagnose import fit_linear_model
    from chainid.gap.harmonic.prepare import prepare_test

    recs = rc.harmonic_set(lambda mo, t, f, A: rc.K_LIN * mo(t)[0] + rc.C_LIN * mo(t)[1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob = Problem([prepare_test(r) for r in recs], fit_linear_model(recs, ["h3"], 0.0), ["h3"], fit_mass=True)
    st = prob.state_table(baseline_candidate(prob)._ev)  # type: ignore[attr-defined]
    travel = st["X_train"][:, st["names"].index("travel")]
    start = 0
    for d in prob.train:
        B = d.counts.size
        tr = travel[start:start + B]
        start += B
        assert tr.min() >= -1e-9 and tr.max() <= 2 * d.A + 1e-9, d.test
        assert tr.max() >= (1 - (math.pi / B) ** 2) * 2 * d.A, d.test
    assert start == travel.size

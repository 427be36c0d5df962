"""On a noisy resonator the verdict's bar is read on the gap a model could close, the part above the kinematic floor
(:func:`chainid.gap.timedomain.route.floor_shrinkage`).

The device: the force-driven resonant device of :mod:`recovery_cases` (m = 2 kg, k = 20 N/mm, c = 0.02 N·s/mm,
random multisine 2–30 Hz, one whole period per record in steady state), 20 µm of white noise on x, σ_F = 0.05 N,
and a force channel lagging by τ = 0.5 ms, F_meas(t) = F(t − τ) (the drive's closed form at the shifted times).
The inertial force of a noisy ẍ is a floor no model lowers: the right chain closes all of the gap above it, and
only 30 % of the held-out NRMSE.
"""
from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import recovery_cases as rc
import sim_devices as sd
from chainid.gap.core.verdict import MIN_SHRINK, floor_shrunk
from chainid.gap.diagnose import diagnose
from chainid.gap.timedomain.route import floor_shrinkage

TAU, SIGMA_X = 5e-4, 0.02  # s, mm


def _records() -> list:
    fs, n = 1000.0, 6000
    t = sd.sample_times(2 * n, fs)
    out = []
    for i in range(5):
        force = sd.force_sines(n / fs, 2.0, 30.0, 5.0, seed=50 + i)
        x, _, _ = sd.resonant_response(force, t, rc.RES_M, rc.RES_C, rc.RES_K)
        out.append(sd.noisy(f"r{i}", t[:n], x[n:], force(t[n:] - TAU), SIGMA_X, 0.05, seed=i))
    return out


@pytest.mark.slow
def test_a_delay_on_a_noisy_resonator_is_named_by_the_gap_above_the_floor():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(_records(), ["r4"], None, quiet=True, uncertainty=False)
    plain = 1.0 - res["left_nrmse_holdout"] / res["baseline"]["nrmse_holdout"]
    assert plain < MIN_SHRINK  # the plain shrinkage alone would leave it unexplained (observed 0.30)
    assert res["residual"]["shrinkage_above_kinematic_floor"] >= MIN_SHRINK
    assert res["verdict"] == "sensor_delay", res["chain_text"]
    assert res["steps"][-1]["params"]["sensor_delay.tau"] == pytest.approx(TAU, rel=0.05)
    assert not res["open_world"]["missing_effect"]


class _Prob:
    """A held-out split of 100 samples on one record: the baseline's kinematic floor ``k2_base`` [N²], the chain's
    ``k2_final``, a force-noise floor of 0.5 N²."""

    def __init__(self, r2_base: float, r2_final: float, k2_final: float = 1.0, k2_base: float = 1.0):
        self.tdata = [SimpleNamespace(test="a")]
        self._r2 = {"base": r2_base, "final": r2_final}
        self._k2 = {"base": k2_base, "final": k2_final}

    def train_mask(self, test: str) -> np.ndarray:
        return np.zeros(100, bool)

    def kinematic_floor(self, d, params) -> float:
        return self._k2[params["who"]]

    def noise_db(self, ev, split):
        return self._r2[ev], 0.5, 0.0

    def n_cells(self, split: str) -> int:
        return 100

    def floor_rel_sd(self, split: str) -> float:
        return 0.0


def _cand(who: str) -> SimpleNamespace:
    return SimpleNamespace(params={"who": who}, _ev=who)


SILENT = {"missing_effect": False, "predictable_share": 0.01}  # the model-free check ran and found nothing


def test_the_shrinkage_above_the_floor_is_one_minus_the_ratio_of_the_excesses():
    got = floor_shrinkage(_Prob(5.0, 2.0), _cand("base"), _cand("final"), SILENT)
    assert got == pytest.approx(1.0 - math.sqrt((2.0 - 1.0) / (5.0 - 1.0)))  # 0.5
    assert floor_shrinkage(_Prob(5.0, 0.8), _cand("base"), _cand("final"), SILENT) == 1.0  # below the floor


def test_the_smaller_of_the_two_floors_is_used():
    # the chain's fitted mass would put the floor at 3 N²: the baseline's 1 N² is used
    got = floor_shrinkage(_Prob(5.0, 3.0, k2_final=3.0), _cand("base"), _cand("final"), SILENT)
    assert got == pytest.approx(1.0 - math.sqrt(2.0 / 4.0))
    # and the chain's when it is the smaller (0.5 N²)
    got = floor_shrinkage(_Prob(5.0, 3.0, k2_final=0.5), _cand("base"), _cand("final"), SILENT)
    assert got == pytest.approx(1.0 - math.sqrt(2.5 / 4.5))


def test_not_read_when_a_missing_effect_is_flagged_the_check_did_not_run_or_the_baseline_is_at_the_floor():
    base, fin = _cand("base"), _cand("final")
    assert floor_shrinkage(_Prob(5.0, 1.0), base, fin, {"missing_effect": True, "predictable_share": 0.4}) is None
    assert floor_shrinkage(_Prob(5.0, 1.0), base, fin, {"missing_effect": False, "predictable_share": None}) is None
    assert floor_shrinkage(_Prob(0.9, 0.8), base, fin, SILENT) is None  # below its floor
    # above its floor of 1 N² by less than the noise test allows (at_noise_floor: excess < ½σ with σ² = 0.5 N²)
    assert floor_shrinkage(_Prob(1.1, 1.0), base, fin, SILENT) is None
    assert floor_shrinkage(_Prob(5.0, 1.0, k2_final=float("nan")), base, fin, SILENT) is None
    assert not floor_shrunk(SimpleNamespace(shrinkage_floor=None))
    assert not floor_shrunk(SimpleNamespace())
    assert floor_shrunk(SimpleNamespace(shrinkage_floor=MIN_SHRINK))
    assert not floor_shrunk(SimpleNamespace(shrinkage_floor=float("nan")))

"""The check of what no library effect explains answers for every kind the diagnosis can see: structure in the
state (the learner), a change in time (the stationarity check) and stick-slip chatter; above the noise floor only,
and silent when none of them is there."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.gap.core.openworld import open_world


def _noise_table(seed: int = 0, n_train: int = 2000, n_hold: int = 800) -> dict:
    """Residuals that are white noise, independent of the state: nothing for the learner."""
    rng = np.random.default_rng(seed)
    names = ["x", "xd", "xdd", "travel", "direction", "x_lag", "load"]
    Xt, Xh = rng.normal(size=(n_train, 7)), rng.normal(size=(n_hold, 7))
    return {"X_train": Xt, "r_train": rng.normal(size=n_train), "X_hold": Xh, "r_hold": rng.normal(size=n_hold),
            "unit_hold": np.repeat(np.arange(4), n_hold // 4), "names": names}


STATIONARY = {"stationary": True, "finding": "stationary"}
DRIFTS = {"stationary": False, "finding": "the mean force drifts by 40 N over the record"}
CHATTER = {"frequency_Hz": 212.0, "rms_N": 35.5}


def test_silent_when_the_residual_is_noise_stationary_and_without_chatter():
    ow = open_world(_noise_table(), at_floor=False, stat=STATIONARY)
    assert ow["kinds"] == [] and ow["missing_effect"] is False and ow["significant"] is False


def test_a_change_in_time_is_a_missing_effect_the_state_cannot_carry():
    ow = open_world(_noise_table(), at_floor=False, stat=DRIFTS)
    assert ow["kinds"] == ["time"] and ow["missing_effect"] is True and ow["significant"] is False
    assert "changes in time" in ow["message"] and "outside the library" in ow["message"]


def test_chatter_is_a_missing_effect_and_its_numbers_are_named():
    ow = open_world(_noise_table(), at_floor=False, stat=STATIONARY, chatter=CHATTER)
    assert ow["kinds"] == ["chatter"] and ow["missing_effect"] is True
    assert "212 Hz" in ow["message"] and "35.5 N" in ow["message"]


def test_structure_in_the_state_is_found_by_the_learner():
    t = _noise_table()
    t["r_train"] = t["r_train"] + 5.0 * np.tanh(t["X_train"][:, 1])  # a velocity law the library lacks
    t["r_hold"] = t["r_hold"] + 5.0 * np.tanh(t["X_hold"][:, 1])
    ow = open_world(t, at_floor=False, stat=DRIFTS)
    assert ow["kinds"] == ["state", "time"] and ow["missing_effect"] is True
    assert ow["predictable_share"] == pytest.approx(1 - 1 / (1 + 25 * np.mean(np.tanh(t["X_hold"][:, 1]) ** 2)),
                                                    abs=0.05)
    assert ow["message"].startswith(f"{100 * ow['predictable_share']:.0f} % of what is left")


def test_at_the_noise_floor_the_state_is_silent_but_a_trend_and_chatter_still_count():
    """A phase bin averages the cycles and a per-sample floor ignores their order: a trend over the cycles and
    chatter carry their own tests, so the floor does not silence them; it does silence the learner."""
    t = _noise_table()
    t["r_train"] = t["r_train"] + 5.0 * np.tanh(t["X_train"][:, 1])
    t["r_hold"] = t["r_hold"] + 5.0 * np.tanh(t["X_hold"][:, 1])
    quiet = open_world(t, at_floor=True, stat=STATIONARY)
    assert quiet["kinds"] == ["state"] and quiet["missing_effect"] is False
    assert quiet["message"] == "what is left is at the noise floor: nothing more to explain"
    ow = open_world(t, at_floor=True, stat=DRIFTS, chatter=CHATTER)
    assert ow["kinds"] == ["state", "time", "chatter"] and ow["missing_effect"] is True
    assert "changes in time" in ow["message"] and "212 Hz" in ow["message"]
    assert "predictable from the state" not in ow["message"] and "noise floor" not in ow["message"]

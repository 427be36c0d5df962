"""A given moving mass (``mass_kg`` > 0) is accepted and its inertia m·ẍ taken out of the force before c_e is
identified: on records simulated with a 50 kg mass at 20 and 40 rad/s (m·ω²·A up to 24 kN against a 0.6 kN
spring force), the viscous c_e comes back as simulated (the law's value) when the same mass is given."""
from __future__ import annotations

import pytest

from chainid.damping.identify import identify_records
from chainid.model.laws import ViscousLaw
from chainid.records.simulate import TestSpec, simulate


class Spring:
    """F_k = k·(x − x_ref) [N], a 50 kg moving mass."""

    name = "test spring"
    mass_kg = 50.0

    def force(self, x):
        return 2000.0 * (x - 1.0)

    def stiffness(self, x):
        import numpy as np

        return np.full(np.shape(x), 2000.0)


def test_a_positive_mass_is_accepted_and_its_inertia_removed():
    plan = [TestSpec(f"w{w}", w, 2.0, 0.3) for w in (20.0, 40.0)]
    recs = simulate(plan, Spring(), ViscousLaw(30.0), n_cycles=6, samples_per_cycle=200, noise_F=0.0, seed=1)
    got = identify_records(recs, Spring(), mass_kg=50.0)
    assert len(got) == 2 and not got.excluded
    for r in got:
        assert r.c_e == pytest.approx(30.0, rel=0.01), r.test
    with pytest.raises(ValueError, match="mass_kg = -1.0 is invalid"):
        identify_records(recs, Spring(), mass_kg=-1.0)

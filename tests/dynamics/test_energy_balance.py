"""The energy account of a run (chainid.dynamics.energy): elastic energy as the integral of the kernel force, the
balance's scale and worst point, non-finite runs, slack hysteretic elements.  Units N·mm."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, simulate


def test_balance_of_a_non_finite_run_reports_the_last_residual():
    """A run whose energy went non-finite mid-way: ``finite`` False, ``residual`` the last value (3 N·mm here),
    not an earlier one.  Bug caught: res[1] for res[-1]."""
    import math

    from chainid.dynamics.energy import balance

    z = np.zeros(4)
    eb = balance(np.array([0.0, 1.0, np.nan, 3.0]), z, z, z)
    assert eb["finite"] is False and eb["residual"] == 3.0 and math.isnan(eb["relative_error"])


@pytest.mark.parametrize("kw", [dict(hysteresis=((3_000.0, 200.0),)), dict(dahl=((200.0, 0.05),))])
def test_slack_release_of_hysteretic_elements_keeps_the_balance(kw):
    """A sine drive larger than the pretension's elongation makes segments go slack every cycle; the energy held
    in a Jenkins element (½·(F/x)·(e − y)²) or a Dahl element (½·(F_h/x_h)·(z·x_h/F_h)²) at release is
    dissipated.  With slack events the scheme's balance error at the default step is 6.0e-3 (Jenkins) and
    4.1e-3 (Dahl), falling with dt (3.4e-3 / 2.4e-3 at safety 0.1; simulate warns, as it should, above 1e-3);
    with the two release energies swapped it is 3.0e-2 and 1.0.  Hence the bound 1e-2.
    Bug caught: the release energies of the two element kinds swapped."""
    import math
    import warnings

    line = ChainLine(n_links=100, n_masses=10, pretension_N=500.0, far_end="fixed", **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the 1e-3 convergence warning (see above)
        res = simulate(line, Drive("sine", A=1.5, omega=300.0), 6 * 2 * math.pi / 300.0, n_out=2000)
    eb = res.energy_balance()
    assert res.tension.min() == 0.0  # segments went slack
    assert eb["relative_error"] < 1e-2


def test_energy_balance_of_a_non_finite_run_reports_the_final_changes():
    """A run whose energies turn non-finite still reports the final work and the final changes of the stored
    energies (kinetic 1 → 3 → 6: +5 N·mm; elastic 2 → 2 → 7: +5), with nan for the worst residual and its scale.
    Bug caught: the kinetic change read at the second-to-last output."""
    from chainid.dynamics.energy import balance

    eb = balance(np.array([0.0, 1.0, np.inf]), np.array([1.0, 3.0, 6.0]), np.array([2.0, 2.0, 7.0]),
                 np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.1, 0.2]))
    assert eb["finite"] is False and eb["work_in"] == np.inf
    assert (eb["kinetic"], eb["elastic"], eb["dissipated"]) == (5.0, 5.0, 2.0)
    assert all(np.isnan(eb[k]) for k in ("worst_residual", "worst_t_s", "relative_error", "scale"))


def test_elastic_energy_is_the_integral_of_the_kernel_force():
    """U(e) = ∫₀^e F_k de' (scipy's quad over the generated kernel) for a segment of 16 links at 0.05–1 mm; 0 when
    slack; the array form sums the segments.  Bug caught: a coefficient of the closed form (½ c_lin, ⅗ c_hertz)."""
    from scipy.integrate import quad

    from chainid.dynamics.energy import elastic_energy, elastic_energy_array
    from chainid.generated.stiffness_paper import force

    cl, ch = ChainLine(n_links=16, n_masses=1).segment_coefficients()
    for e in (0.05, 0.3, 1.0):
        ref = quad(lambda s: force(s, cl[0], ch[0]), 0.0, e, epsabs=0, epsrel=1e-12, limit=200)[0]
        assert elastic_energy(e, cl[0], ch[0]) == pytest.approx(ref, rel=1e-9)
    assert elastic_energy(-0.2, cl[0], ch[0]) == 0.0
    arr = elastic_energy_array(np.array([0.3, -0.1, 1.0]), np.repeat(cl, 3), np.repeat(ch, 3))
    assert arr == pytest.approx(elastic_energy(0.3, cl[0], ch[0]) + elastic_energy(1.0, cl[0], ch[0]), rel=1e-12)


def test_balance_scale_index_and_a_run_where_nothing_happens():
    """The scale is the largest of |W|, |ΔE_kin|, |ΔE_el| and |D| over the run (here D = 40 N·mm leads); without
    times the worst point is given by its output index; nothing happening (all zero) is a relative error of 0."""
    from chainid.dynamics.energy import balance

    W = np.array([0.0, 20.0, 30.0])
    kin = np.array([5.0, 5.0, 5.0])
    el = np.array([1.0, -9.0, -11.0])  # ΔE_el = 0, −10, −12
    D = np.array([0.0, 29.0, 40.0])  # residual W − ΔE_kin − ΔE_el − D = 0, 1, 2
    eb = balance(W, kin, el, D)
    assert eb["scale"] == 40.0 and eb["worst_residual"] == 2.0 and eb["worst_t_s"] == 2.0
    assert eb["relative_error"] == pytest.approx(2.0 / 40.0, rel=1e-15)
    assert (eb["work_in"], eb["kinetic"], eb["elastic"], eb["dissipated"]) == (30.0, 0.0, -12.0, 40.0)
    z = np.zeros(3)
    still = balance(z, z + 7.0, z + 3.0, z, np.array([0.0, 1.0, 2.0]))
    assert still["relative_error"] == 0.0 and still["scale"] == 0.0 and still["finite"] is True


def test_balance_reports_the_final_energies_and_the_worst_residual():
    """W = 0, 50, 100, 130; E_kin = 0, 40, 90, 125; E_el = 0, 5, 6, 3; D = 0, 1, 2, 4 [N·mm]: the residual
    W − ΔE_kin − ΔE_el − D is 0, 4, 2, −2 (by hand), so the balance gives the last values 130, 125, 3, 4, the last
    residual −2 and the worst 4 at sample 1, relative to the largest energy exchanged, 130."""
    from chainid.dynamics.energy import balance

    eb = balance(np.array([0.0, 50.0, 100.0, 130.0]), np.array([0.0, 40.0, 90.0, 125.0]),
                 np.array([0.0, 5.0, 6.0, 3.0]), np.array([0.0, 1.0, 2.0, 4.0]))
    assert (eb["work_in"], eb["kinetic"], eb["elastic"], eb["dissipated"]) == (130.0, 125.0, 3.0, 4.0)
    assert (eb["residual"], eb["worst_residual"], eb["worst_t_s"]) == (-2.0, 4.0, 1.0)
    assert eb["relative_error"] == pytest.approx(4.0 / 130.0, rel=1e-15)


@pytest.mark.parametrize("W, kin, el, D", [
    ([0.0, -30.0], [0.0, -20.0], [0.0, -13.0], [0.0, 0.0]),  # the chain did work on the drive: W = −30 leads
    ([0.0, 0.0], [30.0, 0.0], [0.0, 20.0], [0.0, 7.0]),  # ΔE_kin = −30 leads
    ([0.0, 0.0], [0.0, 20.0], [30.0, 0.0], [0.0, 7.0]),  # ΔE_el = −30 leads
    ([0.0, 0.0], [0.0, 20.0], [0.0, 7.0], [0.0, -30.0]),  # a play returned 30 N·mm (negative dissipation) leads
])
def test_balance_scale_takes_each_energy_by_its_magnitude(W, kin, el, D):
    """The scale is the largest |W|, |ΔE_kin|, |ΔE_el|, |D| (balance docstring): in each case one of them is −30 N·mm
    and the others at most 20 in magnitude, the residual W − ΔE_kin − ΔE_el − D is 3 N·mm at the end (by hand), so
    the scale is 30 and the relative error 0.1.  Bug caught: an ``abs`` dropped from one of the four maxima (the
    scale would be 20: 0.15)."""
    from chainid.dynamics.energy import balance

    eb = balance(*(np.array(a) for a in (W, kin, el, D)))
    assert eb["residual"] == pytest.approx(3.0, abs=1e-12) and eb["scale"] == 30.0
    assert eb["relative_error"] == pytest.approx(0.1, rel=1e-12)


def test_balance_worst_residual_keeps_its_sign():
    """W = 0, 10, 10, 10 and E_kin = 0, 9, 13, 8 [N·mm] (nothing else): the residual is 0, 1, −3, 2 (by hand), so the
    worst is −3 (signed, docstring) at t = 0.2 s, not the largest positive 2, and the relative error |−3| / 13 (the
    scale: ΔE_kin = 13).  Bugs caught: argmax of the signed residual, the relative error not taken in magnitude."""
    from chainid.dynamics.energy import balance

    z = np.zeros(4)
    eb = balance(np.array([0.0, 10.0, 10.0, 10.0]), np.array([0.0, 9.0, 13.0, 8.0]), z, z, np.array([0, 0.1, 0.2, 0.3]))
    assert (eb["worst_residual"], eb["worst_t_s"], eb["residual"]) == (-3.0, 0.2, 2.0)
    assert eb["relative_error"] == pytest.approx(3.0 / 13.0, rel=1e-15)

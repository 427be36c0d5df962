"""``chainid benchmark-gap``: the non-harmonic excitation families and the transfer cases.

Each non-harmonic case is a set of 4 records of one chain under one excitation family
(:mod:`chainid.records.excitation`): ``random`` (band-limited random, some with a wandering
mean), ``sweep`` (linear or exponential chirp), ``startup`` (start-up ramp of the mean load with
load steps and a running vibration that runs up in frequency) and ``quake`` (Kanai–Tajimi
filtered noise under a rise/decay envelope, some with a near-fault pulse and a permanent offset).
The case families are those of the harmonic grid (:mod:`chainid.gap.benchmark.grid`): ``single``,
``mismatch``, ``mismatch+``, ``pair``, ``control``, ``outside``.  Everything a record is made of is
drawn from ranges with the case's seed — not from the diagnosis' grid: sampling rate, length,
band, amplitude and mean, the effect's strength (log-uniform 0.5–3 × typical), the viscous damping,
the noise (0.5–3 % of the dynamic force, some records quantised, a little displacement noise), a rest
lead-in or a taper on some records.  One whole record is held out.

``damping_law`` (a c_e(ω, A) law) is not simulated on a non-harmonic excitation: it has no meaning
without a frequency and an amplitude, and the time route carries rate-independent loss by the
friction/hysteresis effects; the pairs with it are left out of these families.

Out-of-library cases: a slow drift and an exponential relaxation of the force over each record
(``truth_named`` = []), and stick-slip chatter — friction plus an oscillation of the force while the
contact slides — whose right outcome names friction at most and reports the chatter in ``where``.

Transfer cases (``excitation = "transfer"``): one device (chain, effect, viscous damping) measured
twice — 11 steady harmonic tests and 4 band-limited random records; ``harmonic>random`` fits on
the harmonic set and scores on the random one (``chainid diagnose --validate``), ``random>harmonic``
the other way round; the score is the pooled held-out shrinkage on the other set.

Units: mm, N, s, Hz.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from chainid.gap.benchmark.chain import case_chain, scale_motion, x_scale
from chainid.gap.benchmark.report import case_row
from chainid.gap.benchmark.seeds import run_base
from chainid.gap.benchmark.simtruth import case_truth
from chainid.model.effects import EFFECT_NAMES, compose_hooks, parse_effect

#: the non-harmonic excitation families
EXCITATIONS = ("random", "sweep", "startup", "quake")
#: effects simulated on non-harmonic records (damping_law is a harmonic c_e(ω, A) form: see the module docstring)
TIME_EFFECTS = ("stiffness_level", "friction", "hysteresis", "contact_law", "slack", "backlash", "machine_compliance",
                "sensor_delay")
#: the harmonic grid's compound pairs without damping_law
#: effects of the second release, simulated on the chain in every non-harmonic family (cases appended after the
#: first release's, so every earlier case keeps its seed)
NEW_TIME_EFFECTS = ("stribeck", "bouc_wen", "deadband", "fixture_mass")
#: effects simulated on the linear devices (damping-dominated, resonant), random excitation
DEVICE_EFFECTS = ("friction", "hysteresis", "stribeck", "bouc_wen", "deadband", "hardening", "sensor_delay")
#: the spread of the records' damping about its mean in every non-harmonic case (the paper's c_e(ω, A) over the
#: records' band and amplitude: c_r = c·(1 + DAMPING_SPREAD·z_r), z_r in [−1, 1] linear in the features)
DAMPING_SPREAD = 0.18
TIME_PAIRS = (("friction", "sensor_delay"), ("hysteresis", "slack"), ("friction", "slack"),
              ("backlash", "sensor_delay"))
#: records per case and the one held out
N_RECORDS = 4


def effect_spec(effect: str, level: float, S: float, k: float, Amin: float, wmax: float, x_mid: float = 0.0) -> str:
    """``--effect`` text of a library effect at a relative strength ``level`` (1 = typical).

    S [N] is the median dynamic force k_e·A of the plan, k [N/mm] the median stiffness, Amin [mm] the
    smallest amplitude, wmax [rad/s] the highest frequency, x_mid [mm] the mean position (the centre of a
    dead band, the reference of a hardening spring).
    """
    if effect == "friction":
        return f"friction:F_c={0.1 * level * S:.6g}"
    if effect == "hysteresis":
        return f"hysteresis:F_h={0.1 * level * S:.6g},x_h={0.3 * Amin:.6g}"
    if effect == "backlash":
        return f"backlash:b={0.1 * level * Amin:.6g}"
    if effect == "slack":
        return f"slack:s={0.1 * level * Amin:.6g}"
    if effect == "machine_compliance":
        return f"machine_compliance:c={0.1 * level / k:.6g}"
    if effect == "stiffness_level":
        return f"stiffness_level:scale={1 - 0.1 * level if level < 3 else 1.3:.6g}"
    if effect == "contact_law":
        return f"contact_law:scale={1 + 0.3 * level:.6g}"
    if effect == "sensor_delay":
        return f"sensor_delay:tau={0.15 * level / wmax:.6g}"
    if effect == "stribeck":  # kinetic F_c, static excess at rest decaying over a quarter of the typical speed
        return (f"stribeck:F_c={0.05 * level * S:.6g},dF_s={0.1 * level * S:.6g},"
                f"v_s={0.25 * wmax * Amin:.6g}")
    if effect == "bouc_wen":
        return f"bouc_wen:F_y={0.1 * level * S:.6g},x_y={0.3 * Amin:.6g},n=2,r=0.6"
    if effect == "deadband":  # end stops closing at 60 % of the smallest amplitude about the mean position
        g = 0.6 * Amin
        return f"deadband:k_d={0.2 * level * S / (0.4 * Amin) ** 1.5:.6g},g={g:.6g},p=1.5,x_c={x_mid:.6g}"
    if effect == "hardening":
        return f"hardening:k3={0.2 * level * k / Amin ** 2:.6g},x_ref={x_mid:.6g}"
    if effect == "fixture_mass":
        return f"fixture_mass:m_f={0.1 * level * S * 1e3 / (wmax ** 2 * Amin):.6g}"
    return f"damping_law:eta={0.1 * level:.6g}"


def _fs(rng: np.random.Generator, f_max: float, per: float = 25.0) -> float:
    """A sampling rate [Hz] of a data logger, at least ``per`` samples per period of the band edge."""
    ok = [f for f in (100.0, 200.0, 250.0, 500.0, 1000.0, 2000.0) if f >= per * f_max]
    return float(rng.choice(ok[:3]))


def motion(kind: str, rng: np.random.Generator) -> Any:
    """One record's displacement program of family ``kind``, every property drawn from its range.

    Uniform draws (frequencies Hz, lengths mm, times s; n samples, T = n/fs the record's length):

    * ``random``: n 2000–4500, band edge f_hi 1–4, f_lo = max(f_hi × 0.02–0.1, 2.5 fs/n), RMS 0.04–0.11, mean
      1.7–2.3, a wandering mean 0.02–0.08 on 30 % of the records;
    * ``sweep``: 0.2–0.5 → 2–4 (down on 30 %), n 2000–4500 but >= 3 periods of the slowest frequency, amplitude
      0.06–0.3, mean 1.8–2.3, exponential on half;
    * ``startup``: running frequency 1–4, n 2000–4500, 2–4 load levels 1.6–2.5, ramp 0.15–0.3 T, steps of
      0.3–1.5, amplitude 0.04–0.2, start 0.6–1.2;
    * ``quake``: ground frequency f_g 1–3, n 3000–6000, peak 0.15–0.45, mean 1.9–2.4, damping ratio 0.3–0.7,
      high-pass f_c = f_g × 0.05–0.15, band edge 4 f_g, rise 0.08–0.25 T, decay rate (3–8)/T, a pulse 0.5–1.5 on
      half, an offset −0.3–0.3 on 30 %;
    * the sampling rate: one of the three lowest logger rates (100, 200, 250, 500, 1000, 2000) with >= 25 samples
      per period of the band edge (quake: 20);
    * a taper 0.05–0.1 T on 30 % of the random and sweep records, a rest lead-in 0.03–0.1 T on 25 % of all.
    """
    from chainid.records import excitation as ex

    n = int(rng.integers(2000, 4501))
    if kind == "random":
        f_hi = rng.uniform(1.0, 4.0)
        fs = _fs(rng, f_hi)
        f_lo = max(f_hi * rng.uniform(0.02, 0.1), 2.5 * fs / n)
        m = ex.band_random(n, fs, f_lo, f_hi, rng.uniform(0.04, 0.11), rng.uniform(1.7, 2.3), rng,
                           wander=rng.uniform(0.02, 0.08) if rng.random() < 0.3 else 0.0)
    elif kind == "sweep":
        f0, f1 = rng.uniform(0.2, 0.5), rng.uniform(2.0, 4.0)
        if rng.random() < 0.3:
            f0, f1 = f1, f0  # a down-sweep
        fs = _fs(rng, max(f0, f1))
        n = max(n, int(3 * fs / min(f0, f1)))  # at least 3 periods of the slowest frequency
        m = ex.sweep(n, fs, f0, f1, rng.uniform(0.06, 0.3), rng.uniform(1.8, 2.3), log=bool(rng.random() < 0.5))
    elif kind == "startup":
        f_run = rng.uniform(1.0, 4.0)
        fs = _fs(rng, f_run)
        T = n / fs
        levels = list(rng.uniform(1.6, 2.5, int(rng.integers(2, 5))))
        m = ex.startup_steps(n, fs, levels, rng.uniform(0.15, 0.3) * T, rng.uniform(0.3, 1.5), f_run,
                             rng.uniform(0.04, 0.2), x_start=rng.uniform(0.6, 1.2))
    elif kind == "quake":
        f_g = rng.uniform(1.0, 3.0)
        fs = _fs(rng, 4 * f_g, per=20.0)
        n = int(rng.integers(3000, 6001))
        m = ex.earthquake(n, fs, rng.uniform(0.15, 0.45), rng.uniform(1.9, 2.4), rng, f_g=f_g,
                          zeta_g=rng.uniform(0.3, 0.7), f_c=rng.uniform(0.05, 0.15) * f_g, f_hi=4 * f_g,
                          t_rise=rng.uniform(0.08, 0.25) * n / fs, decay=rng.uniform(3.0, 8.0) * fs / n,
                          pulse=rng.uniform(0.5, 1.5) if rng.random() < 0.5 else 0.0,
                          offset=rng.uniform(-0.3, 0.3) if rng.random() < 0.3 else 0.0)
    else:
        raise ValueError(f"excitation = {kind!r} is unknown; valid: {', '.join(EXCITATIONS)}")
    T = m.t[-1]
    if kind in ("random", "sweep") and rng.random() < 0.3:
        m = ex.with_envelope(m, taper=rng.uniform(0.05, 0.1) * T)
    if rng.random() < 0.25:
        m = ex.with_envelope(m, lead=rng.uniform(0.03, 0.1) * T)
    return m


def _outside(kind: str, level: float, S: float, F_c: float, rng: np.random.Generator) -> Any:
    """Force hook of an effect outside the library (N): drift, relaxation or stick-slip chatter.

    ``drift`` adds 0.05·level·S·(t − t0)/(t_end − t0); ``relaxation`` takes off 0.1·level·S·(1 − exp(−3·(t − t0)/
    (t_end − t0))); ``chatter`` is Coulomb friction F_c·sgn(ẋ) plus a tone of amplitude drawn from 0.3–0.8 F_c (random
    phase) at max(12 Hz, fs/20), at most fs/5, while the contact slides faster than a fraction drawn from 0.1–0.25 of
    the record's peak speed.
    """
    if kind == "drift":
        rate = 0.05 * level * S

        def hook(t, x, xd, xdd, F):  # noqa: ANN001
            return F + rate * (t - t[0]) / (t[-1] - t[0])
    elif kind == "relaxation":
        dF = 0.1 * level * S

        def hook(t, x, xd, xdd, F):  # noqa: ANN001
            return F - dF * (1.0 - np.exp(-3.0 * (t - t[0]) / (t[-1] - t[0])))
    else:  # chatter: Coulomb friction and a force oscillation while the contact slides
        from chainid.model.effects import stick_slip

        amp, ph = rng.uniform(0.3, 0.8) * F_c, rng.uniform(0, 2 * np.pi)
        frac = rng.uniform(0.1, 0.25)

        def hook(t, x, xd, xdd, F):  # noqa: ANN001
            fs = 1.0 / (t[1] - t[0])
            fch = min(0.2 * fs, max(12.0, 0.05 * fs))
            slide = np.abs(xd) > frac * np.abs(xd).max()
            return F + F_c * stick_slip(x, xd, 0.0, periodic=False) + amp * np.sin(2 * np.pi * fch * t + ph) * slide
    return hook


def _device(case: dict[str, Any], motions: list[Any]) -> tuple[Any, Any, Any, float, float, dict[str, float]]:
    """Nominal and true models, the effect hooks, the dynamic force scale S [N], the mean damping c [N·s/mm] and the
    true parameters of the in-library effects (:func:`chainid.gap.benchmark.simtruth.case_truth`).

    A chain case runs on its chain (nominal and true kernels).  A device case (``case["base"]``: ``damped`` or
    ``resonant``) runs on a linear mass–spring–damper about the motion's mean: k from the force scale, the
    damping-dominated one with c·ω ≈ 5–10 k at the band edge, the resonant one with its natural frequency inside the
    band (m·ω_n² = k) — its nominal model is None (the diagnosis fits a linear device)."""
    from chainid.model.base import ChainModel, LinearModel

    x0s = np.array([float(np.median(m.x)) for m in motions])
    As = np.array([m.A for m in motions])
    wmax = 2 * np.pi * max(m.f_dom for m in motions)  # the effects' scale: where the motion is
    rng = np.random.default_rng(case["seed"] + 7)
    if case.get("base") in ("damped", "resonant"):
        k = 1000.0
        x_mid = float(np.median(x0s))
        wn = wmax * rng.uniform(0.4, 0.8)
        mass = k / wn**2 * 1e3 if case["base"] == "resonant" else 0.0
        nominal, true = None, LinearModel(k, x_mid, mass=mass)
        c = (rng.uniform(5.0, 10.0) if case["base"] == "damped" else rng.uniform(0.05, 0.2)) * k / wmax
        S = float(k * np.median(As)) * (max(c * wmax / k, 1.0) if case["base"] == "damped" else 1.0)
    else:
        chain = case_chain(case)
        nominal = ChainModel(chain)
        true = ChainModel(chain, ea_scale=case.get("ea_scale", 1.0), hertz_scale=case.get("hertz_scale", 1.0))
        k = float(np.median(nominal.stiffness(x0s)))
        S = float(k * np.median(As))
        c = case["c_rel"] * k / wmax * 2.0  # viscous loss ~ c_rel of k·A at half the top frequency
        x_mid = float(np.median(x0s))
    hooks, specs = [], []
    for eff, lv in zip(case["effects"], case["levels"]):
        if eff in EFFECT_NAMES:
            specs.append(effect_spec(eff, lv, S, k, float(As.min()), wmax, x_mid))
            hooks.append(parse_effect(specs[-1], true))
        else:
            hooks.append(_outside(eff, lv, S, 0.1 * S, rng))
    return nominal, true, hooks, S, c, case_truth(case, specs)


def record_damping(case: dict[str, Any], motions: list[Any], c: float) -> list[float]:
    """The damping [N·s/mm] of each record: c·(1 + ``DAMPING_SPREAD``·z_r), z_r a fixed linear combination of the
    record's band centre and amplitude (the features of :func:`chainid.model.timedamping.record_features`) scaled
    to span [−1, 1] over the case's records — the paper's c_e(ω, A) over records of any excitation."""
    from chainid.model.timedamping import record_features

    if not case.get("damping_varies", True) or len(motions) < 2:
        return [c] * len(motions)
    feats = np.array([record_features(m.t, m.x) for m in motions])
    z = np.zeros(len(motions))
    for j, wgt in ((0, 0.6), (1, 0.4)):
        f = feats[:, j]
        span = float(np.ptp(f))
        if span > 0:
            z += wgt * (2.0 * (f - f.min()) / span - 1.0)
    z = z / max(float(np.max(np.abs(z))), 1e-12)
    return [c * (1.0 + DAMPING_SPREAD * float(v)) for v in z]


def effect_snr(motions: list[Any], model: Any, hooks: list[Any], c: Any, sigmas: list[float]) -> list[float]:
    """Each effect's own detectability: the RMS over the records of the force it adds on top of the others
    (noise-free; its part along ẋ removed, which the fitted viscous c absorbs), over the noise σ."""
    from chainid.records.simulate import model_force

    out = []
    cs = list(c) if np.ndim(c) else [c] * len(motions)
    for j in range(len(hooks)):
        num = den = 0.0
        for m, sg, cr in zip(motions, sigmas, cs):
            F0 = model_force(m.x, m.xd, m.xdd, model, cr)
            d = compose_hooks(hooks)(m.t, m.x, m.xd, m.xdd, F0) - (
                compose_hooks(hooks[:j] + hooks[j + 1:]) or (lambda t, x, xd, xdd, F: F))(m.t, m.x, m.xd, m.xdd, F0)
            d = d - float(np.dot(d, m.xd) / max(np.dot(m.xd, m.xd), 1e-300)) * m.xd
            num += float(np.sum(d * d))
            den += sg * sg * d.size
        out.append(math.sqrt(num / den) if den > 0 else 0.0)
    return out


def records(case: dict[str, Any]) -> tuple[list[Any], dict[str, Any]]:
    """The case's records (``r1`` … ``r4``) and the device: nominal and true models, effect hook, dynamic force
    scale S [N], viscous c [N·s/mm], the records' motions and ``true_params`` (the in-library effects' true
    parameters keyed ``effect.param``, :mod:`chainid.gap.benchmark.simtruth`)."""
    from chainid.records.excitation import simulate_motion

    rng = np.random.default_rng(case["seed"])
    motions = [scale_motion(motion(case["excitation"], rng), x_scale(case)) for _ in range(N_RECORDS)]
    nominal, true, hooks, S, c, truth = _device(case, motions)
    hook = compose_hooks(hooks)
    cs = record_damping(case, motions, c)
    recs, sigmas = [], []
    for i, m in enumerate(motions):
        sig = case["noise"] * S * rng.uniform(0.8, 1.25)
        q = sig * rng.uniform(0.5, 2.0) if rng.random() < 0.3 else 0.0
        recs.append(simulate_motion(f"r{i + 1}", m, true, cs[i], force_fn=hook, noise_F=sig,
                                    noise_x=rng.uniform(0.0, 0.003) * m.A, quantum_F=q, rng=rng))
        sigmas.append(math.sqrt(sig * sig + q * q / 12))
    return recs, {"nominal": nominal, "true": true, "hook": hook, "S": S, "c": c, "c_records": cs,
                  "motions": motions, "hooks": hooks, "sigmas": sigmas, "true_params": truth}


def _row(case: dict[str, Any], res: dict[str, Any], t0: float, truth: dict[str, float]) -> dict[str, Any]:
    where = res.get("where", []) + res.get("residual", {}).get("where", [])
    return case_row(case, res, time.perf_counter() - t0, truth) | {
        "ranked_first": (res.get("ranking") or [{}])[0].get("effect"),
        "chatter": any(f.get("kind") == "chatter" for f in where)}


def _error(case: dict[str, Any], exc: Exception, t0: float) -> dict[str, Any]:
    return {**case, "verdict": f"error: {type(exc).__name__}: {exc}", "seconds": time.perf_counter() - t0,
            "snr": float("inf"), "shrinkage": None, "steps": [], "params": None, "params_ci90": {}, "true_params": {},
            "stationary": None, "confounded": [], "chatter": False, "transfer_shrinkage": None,
            "transfer_shrinkage_refit": None}


def run_case_time(case: dict[str, Any]) -> dict[str, Any]:
    """Simulate one non-harmonic case and diagnose it blind (one whole record held out)."""
    from chainid.gap.diagnose import diagnose

    t0 = time.perf_counter()
    try:
        recs, dev = records(case)
        res = diagnose(recs, [case["hold"]], dev["nominal"], uncertainty=False, quiet=True,
                       resamples=int(case.get("resamples", 0)), seed=int(case.get("seed", 0)))
        snr = effect_snr(dev["motions"], dev["true"], dev["hooks"], dev["c_records"], dev["sigmas"])
    except Exception as exc:  # a crash is a miss to report, not the end of the run
        return _error(case, exc, t0)
    return _row(case, res, t0, dev["true_params"]) | {"effect_snr": snr}


def transfer_plan(motions: list[Any], s: float = 1.0) -> list[Any]:
    """The harmonic set of a transfer case over the random records' band and amplitudes (see
    :func:`run_case_transfer`); ``s`` the chain's length scale (:mod:`chainid.gap.benchmark.chain`): the
    mean-elongation offsets ±0.1 mm of the paper's chain are ±0.1·s mm."""
    from chainid.records.simulate import grid_plan

    f_lo = min(m.f_max for m in motions)
    A = float(np.median([m.A for m in motions]))
    x0 = float(np.median([np.median(m.x) for m in motions]))
    w = 2 * np.pi * f_lo
    return grid_plan((0.25 * w, 0.5 * w, w), (0.5 * A, A, 1.5 * A), x0,
                     extra=[(0.75 * w, x0 + 0.1 * s, 0.75 * A), (0.375 * w, x0 - 0.1 * s, 1.25 * A)], prefix="h")


def run_case_transfer(case: dict[str, Any]) -> dict[str, Any]:
    """One device measured harmonically and under band-limited random excitation; fit on one, score the other.

    The harmonic set (tests ``h1`` … ``h11``): ω ∈ (¼, ½, 1)·ω_lo × A ∈ (½, 1, 1.5)·Ā at x̄0, then (¾ ω_lo, x̄0 + 0.1,
    ¾ Ā) and (⅜ ω_lo, x̄0 − 0.1, 1.25 Ā), with ω_lo = 2π × the lowest band edge of the random records, Ā and x̄0
    their median amplitude and median mean [mm]; 8 cycles of 256 samples, force noise σ = noise·S, seed + 1.
    """
    from chainid.gap.diagnose import diagnose
    from chainid.records.simulate import simulate

    t0 = time.perf_counter()
    try:
        # one device: its viscous c is the same on both sets (the records' c_e(ω, A) spread of the other cases is
        # a law over the case's own records, which the harmonic set, outside their features, would not follow)
        rand, dev = records(case | {"excitation": "random", "damping_varies": False})
        nominal = dev["nominal"]
        # the same device (effect parameters, viscous c) on 11 steady harmonic tests over the random records'
        # band and amplitudes
        plan = transfer_plan(dev["motions"], x_scale(case))
        harm = simulate(plan, dev["true"], dev["c"], n_cycles=8, samples_per_cycle=256,
                        noise_F=case["noise"] * dev["S"], seed=case["seed"] + 1, force_fn=dev["hook"])
        if case["direction"] == "harmonic>random":
            res = diagnose(harm, ["h3", "h6", "h11"], nominal, uncertainty=False, quiet=True, validate=rand)
        else:
            res = diagnose(rand, [case["hold"]], nominal, uncertainty=False, quiet=True, validate=harm)
    except Exception as exc:
        return _error(case, exc, t0)
    row = _row(case, res, t0, dev["true_params"])
    tr = res["transfer"]
    row.update({"transfer_shrinkage": tr["pooled"]["shrinkage"], "transfer_shrinkage_refit": tr["pooled"]["shrinkage_refit"],
                "transfers": tr["transfers"], "transfer_chain": tr["chain"]})
    return row


def time_grid(seed: int = 0, small: bool = False, excitations: tuple[str, ...] = EXCITATIONS + ("transfer",)
              ) -> list[dict[str, Any]]:
    """The non-harmonic and transfer cases (``small``: one single-effect case per family, one control, one
    transfer).  At ``seed`` S the case seeds are ``S·10⁷ + 100000 + 1000·k + i`` (k the excitation's place in
    :data:`EXCITATIONS` + transfer, i the case's place in it; :mod:`chainid.gap.benchmark.seeds`); everything else
    is drawn from them."""
    cases: list[dict[str, Any]] = []
    first = run_base(seed)
    order = EXCITATIONS + ("transfer",)
    count = {e: 0 for e in order}

    def add(exc: str, family: str, truth: list[str], effects: list[str], levels: list[float], **kw: Any) -> None:
        # seeds in a block per excitation: a case is the same whichever excitations run
        s = first + 100000 + 1000 * order.index(exc) + count[exc]
        count[exc] += 1
        r = np.random.default_rng(s)
        cases.append({"excitation": exc, "family": family, "truth": truth, "effects": effects, "levels": levels,
                      "noise": float(r.uniform(0.005, 0.03)), "c_rel": float(r.uniform(0.01, 0.05)),
                      "chain": str(r.choice(["14x50", "small"])), "plan": exc, "seed": s,
                      "hold": f"r{int(r.integers(1, N_RECORDS + 1))}", **kw})

    rng = np.random.default_rng(first + 99)
    lv = lambda: float(np.exp(rng.uniform(math.log(0.5), math.log(3.0))))  # noqa: E731
    fams = [e for e in EXCITATIONS if e in excitations]
    if small:
        for e, eff in zip(fams, ("friction", "hysteresis", "backlash", "stiffness_level")):
            add(e, "single", [eff], [eff], [1.5])
        if fams:
            add(fams[0], "control", [], [], [])
        if "transfer" in excitations:
            add("transfer", "transfer", ["hysteresis"], ["hysteresis"], [1.5], direction="harmonic>random")
        return cases
    for e in fams:
        rng = np.random.default_rng(first + 99 + order.index(e))
        for eff in TIME_EFFECTS:
            for _ in range(2):
                add(e, "single", [eff], [eff], [lv()])
        for _ in range(4):
            add(e, "control", [], [], [])
        mism = [("stiffness_level", {"ea_scale": float(rng.uniform(0.7, 0.85))}),
                ("stiffness_level", {"ea_scale": float(rng.uniform(1.2, 1.4))}),
                ("contact_law", {"hertz_scale": float(rng.choice([rng.uniform(0.5, 0.7), rng.uniform(1.5, 2.0)]))})]
        for m, kw in mism:
            add(e, "mismatch", [m], [], [], **kw)
        for i, eff in enumerate(("friction", "hysteresis", "backlash", "slack", "sensor_delay")):
            m, kw = mism[i % len(mism)]
            add(e, "mismatch+", [m, eff], [eff], [lv()], **kw)
        for a, b in TIME_PAIRS:
            add(e, "pair", [a, b], [a, b], [lv(), lv()])
        for kind in ("drift", "relaxation", "chatter"):
            add(e, "outside", [kind], [kind], [lv()], truth_named=["friction"] if kind == "chatter" else [])
        # the second release: its effects on the chain, then linear devices (random excitation)
        for eff in NEW_TIME_EFFECTS:
            add(e, "single", [eff], [eff], [lv()])
        if e == "random":
            for base in ("damped", "resonant"):
                add(e, "control", [], [], [], base=base)
                for eff in DEVICE_EFFECTS if base == "resonant" else ("friction", "hysteresis", "bouc_wen"):
                    add(e, "single", [eff], [eff], [lv()], base=base)
    if "transfer" in excitations:
        rng = np.random.default_rng(first + 99 + order.index("transfer"))
        for eff in ("friction", "hysteresis", "backlash", "stiffness_level", "slack", "sensor_delay"):
            for d in ("harmonic>random", "random>harmonic"):
                add("transfer", "transfer", [eff], [eff], [lv()], direction=d)
    return cases

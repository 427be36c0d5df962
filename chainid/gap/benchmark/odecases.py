"""Bases, test plans and effect strengths of the ODE world (:mod:`chainid.gap.benchmark.odeworld`).

Bases (every property drawn from its range with the case's seed; units mm, N, s, kg, Hz):

* ``chain14`` — the built-in 14×50 chain (DIN 22252), displacement-driven about x0 1.8–2.3 mm, RMS amplitude
  0.05–0.12 mm (harmonic: the paper's Table 1 plan), band 0.1–0.3 → 1–3 Hz, fs 200/250/500 Hz, viscous c with a
  loss c·ω_c of 3–10 % of k_e(x0) at the band centre ω_c;
* ``chain18`` — the DIN 22252 18×64 preset, the same plans with every displacement × its length scale (the same
  nominal stress, :func:`chainid.gap.benchmark.chain.length_scale`);
* ``resonant`` — a linear mass–spring–damper driven by a force (a shaker): m 1–5 kg, f_n 20–60 Hz (k = m·(2π
  f_n)²·1e-3), damping ratio 0.02–0.08, the spring's rest position x_ref −1–1 mm, preload 0.5–2 mm of spring
  travel, displacement RMS 0.2–1 mm, band 0.5–2 f_n, fs 2000/5000 Hz;
* ``damper`` — a damping-dominated device (a damper on a servo-hydraulic machine): k 2–10 N/mm, band 4–20 Hz,
  c with c·2π·f_lo >= 6 k (the viscous force is more than 5× the spring's dynamic force), RMS stroke 1–4 mm,
  fs 500/1000/2000 Hz;
* ``stiff`` — a lightly damped linear spring (a rubber mount, a bolted joint), displacement-driven: k 50–500 N/mm,
  preloaded about x0 = 5 mm, RMS 0.2–1 mm, band 1–15 Hz, loss 2–6 %, fs 500/1000 Hz.

Test plans: ``harmonic`` (the chain: Table 1's nine (f = column/20 Hz, x0, A), 3 cycles each; the other
bases: sine tests at 6–8 frequencies across the band), ``multisine`` (4–8 records, 1–4 periods, some not a whole
number of periods), ``noise`` (4–8 records, cosine taper 5–15 % of the record), ``chirp`` (4–8 records, 1–3 up or
down sweeps with rests of 5–15 %).  Noise on the force: 0.1–0.5 % of the record's force range; on x: up to 5e-4 of
its range; 30 % of the records quantised by a 12-bit ADC over 1.5× the force range.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.gap.benchmark import odeshapes as sh

__all__ = ["BASES", "DRIVE", "EXCITATIONS", "draw_base", "draw_plan", "make_shape", "effect_params",
           "outside_params", "scales", "chain_spec", "TABLE1"]

BASES = ("chain14", "chain18", "resonant", "damper", "stiff")
DRIVE = {"chain14": "displacement", "chain18": "displacement", "resonant": "force", "damper": "displacement",
         "stiff": "displacement"}
EXCITATIONS = ("harmonic", "multisine", "noise", "chirp")
#: the paper's Table 1: (column value = 20·f [Hz], x0 [mm], A [mm]) of its nine harmonic tests
TABLE1 = ((1, 2.2, 0.25), (4, 2.2, 0.25), (6, 2.2, 0.25), (8, 2.2, 0.25), (10, 2.2, 0.25), (6, 2.15, 0.2),
          (6, 2.25, 0.3), (6, 2.3, 0.35), (6, 2.35, 0.4))


def chain_spec(b: dict[str, Any]) -> Any:
    """The :class:`~chainid.ChainSpec` of a chain base (its DIN 22252 preset)."""
    from chainid.chain.presets import chain

    return chain(b["preset"])


def draw_base(base: str, rng: np.random.Generator) -> dict[str, Any]:
    """The base's parameters (module docstring) as a JSON-able dict."""
    u = rng.uniform
    if base in ("chain14", "chain18"):
        from chainid.gap.benchmark.chain import length_scale

        preset = "din22252:14x50" if base == "chain14" else "din22252:18x64"
        s = 1.0 if base == "chain14" else length_scale(chain_spec({"preset": preset}))
        return {"kind": "chain", "preset": preset,
                "x_scale": s, "x0": u(1.8, 2.3) * s, "A": u(0.05, 0.12) * s, "f_lo": u(0.1, 0.3),
                "f_hi": u(1.0, 3.0), "fs": float(rng.choice([200.0, 250.0, 500.0])), "loss": u(0.03, 0.1)}
    if base == "resonant":
        m, fn, zeta = u(1.0, 5.0), u(20.0, 60.0), u(0.02, 0.08)
        k = m * (2 * math.pi * fn) ** 2 * 1e-3
        return {"kind": "linear", "m": m, "f_n": fn, "zeta": zeta, "k": k, "c": 2 * zeta * m * 2 * math.pi * fn * 1e-3,
                "x_ref": u(-1.0, 1.0), "F0": k * u(0.5, 2.0), "A": u(0.2, 1.0), "f_lo": 0.5 * fn, "f_hi": 2.0 * fn,
                "fs": float(rng.choice([2000.0, 5000.0]))}
    if base == "damper":
        k, f_lo = u(2.0, 10.0), 4.0
        return {"kind": "linear", "m": 0.0, "k": k, "c": 6 * k / (2 * math.pi * f_lo) * u(1.0, 2.0), "x_ref": 0.0,
                "x0": u(-2.0, 2.0), "A": u(1.0, 4.0), "f_lo": f_lo, "f_hi": 20.0,
                "fs": float(rng.choice([500.0, 1000.0, 2000.0]))}
    if base == "stiff":
        k = u(50.0, 500.0)
        f_lo, f_hi = 1.0, 15.0
        return {"kind": "linear", "m": 0.0, "k": k, "c": u(0.02, 0.06) * k / (2 * math.pi * 0.5 * (f_lo + f_hi)),
                "x_ref": 0.0, "x0": 5.0, "A": u(0.2, 1.0), "f_lo": f_lo, "f_hi": f_hi,
                "fs": float(rng.choice([500.0, 1000.0]))}
    raise ValueError(f"base = {base!r} is unknown; valid: {', '.join(BASES)}")


def _k(b: dict[str, Any]) -> float:
    """Tangent stiffness of the base at its mean elongation [N/mm]."""
    if b["kind"] == "chain":
        from chainid.model.base import ChainModel

        return float(ChainModel(chain_spec(b)).stiffness(np.array([b["x0"]]))[0])
    return float(b["k"])


def scales(b: dict[str, Any]) -> dict[str, float]:
    """Scales the effects are drawn on: k [N/mm], A (RMS displacement) [mm], S (dynamic force) [N], v (RMS
    velocity at the band centre) [mm/s], the band and the sampling rate [Hz] and the mean displacement [mm]."""
    k = _k(b)
    fc = 0.5 * (b["f_lo"] + b["f_hi"])
    v = 2 * math.pi * fc * b["A"]
    S = k * b["A"] if b["kind"] == "chain" or b.get("m", 0) > 0 else max(k * b["A"], b["c"] * v)
    x_mean = b.get("x0", b.get("x_ref", 0.0) + b.get("F0", 0.0) / max(k, 1e-12))
    return {"k": k, "A": b["A"], "S": S, "v": v, "f_lo": b["f_lo"], "f_hi": b["f_hi"], "x_mean": x_mean,
            "fs": b["fs"]}


def _frf_gain(b: dict[str, Any], f: np.ndarray) -> np.ndarray:
    w = 2 * np.pi * f
    return 1.0 / np.abs(b["k"] - b["m"] * w * w * 1e-3 + 1j * b["c"] * w)


def draw_plan(base: str, b: dict[str, Any], excitation: str, rng: np.random.Generator) -> list[dict[str, Any]]:
    """Per record: shape kind and parameters, the drive's mean and amplitude (mm, or N for a force drive)."""
    fs, A = b["fs"], b["A"]
    force = DRIVE[base] == "force"
    mean = b["F0"] if force else b["x0"]
    recs: list[dict[str, Any]] = []
    if excitation == "harmonic":
        if b["kind"] == "chain":
            s = b["x_scale"]
            for col, x0, amp in TABLE1:
                f = col / 20.0
                recs.append({"kind": "harmonic", "f": f, "fs": fs, "n": max(2000, int(math.ceil(3 * fs / f))),
                             "mean": x0 * s, "amp": amp * s})
            return recs
        nrec = int(rng.integers(6, 9))
        for f in np.geomspace(b["f_lo"] * 1.2, b["f_hi"] / 1.2, nrec) * rng.uniform(0.97, 1.03, nrec):
            amp = A * math.sqrt(2) * rng.uniform(0.6, 1.4)
            if force:
                amp = amp / float(_frf_gain(b, np.array([f]))[0])
            pre = 3 if not force else max(3, int(math.ceil(1.5 * f / (b["zeta"] * b["f_n"]))))
            recs.append({"kind": "harmonic", "f": float(f), "fs": fs, "n": max(2000, int(math.ceil(8 * fs / f))),
                         "mean": mean, "amp": amp, "pre": pre})
        return recs
    nrec = int(rng.integers(4, 9))
    gain = 1.0
    if force:  # drive RMS for a displacement RMS of about A over a flat band
        ff = np.linspace(b["f_lo"], b["f_hi"], 200)
        gain = float(np.sqrt(np.mean(_frf_gain(b, ff) ** 2)))
    for _ in range(nrec):
        n = int(rng.integers(2000, 8001)) if not force else int(rng.integers(4000, 20001))
        f_lo, f_hi = b["f_lo"] * rng.uniform(0.9, 1.1), b["f_hi"] * rng.uniform(0.9, 1.1)
        r = {"kind": excitation, "fs": fs, "n": n, "f_lo": f_lo, "f_hi": min(f_hi, fs / 10),
             "mean": mean, "amp": A * rng.uniform(0.7, 1.3) / gain}
        if excitation == "multisine":
            T = n / fs
            per = [p for p in (1, 2, 3, 4) if T / p * (r["f_hi"] - f_lo) >= 8]
            r["n_periods"] = float(rng.choice(per or [1])) + (0.5 if rng.random() < 0.3 else 0.0)
            r["pre"] = 1 if not force else max(1, int(math.ceil(1.5 / (b["zeta"] * 2 * math.pi * b["f_n"])
                                                                 / (T / r["n_periods"]))))
        elif excitation == "noise":
            r["taper"] = rng.uniform(0.05, 0.15) * n / fs
            r["rest"] = rng.uniform(0.0, 0.05) * n / fs
        elif excitation == "chirp":
            T = n / fs
            r["n_sweeps"] = int(rng.integers(1, 4))
            r["rest"] = rng.uniform(0.05, 0.15) * T / (r["n_sweeps"] + 1)
            sweep = (T - (r["n_sweeps"] + 1) * r["rest"]) / r["n_sweeps"]
            r["f_lo"] = max(f_lo, 4.0 / sweep)
            r["down"] = bool(rng.random() < 0.4)
            r["log"] = bool(rng.random() < 0.5)
            r["amp"] *= math.sqrt(2)  # a sweep's amplitude is its peak
        else:
            raise ValueError(f"excitation = {excitation!r} is unknown; valid: {', '.join(EXCITATIONS)}")
        recs.append(r)
    return recs


def make_shape(r: dict[str, Any], rng: np.random.Generator) -> sh.Shape:
    """The :class:`~chainid.gap.benchmark.odeshapes.Shape` of one planned record."""
    if r["kind"] == "harmonic":
        return sh.harmonic(r["fs"], r["n"], r["f"], pre_cycles=r.get("pre", 3))
    if r["kind"] == "multisine":
        return sh.multisine(r["fs"], r["n"], r["f_lo"], r["f_hi"], r["n_periods"], rng, pre_periods=r["pre"])
    if r["kind"] == "noise":
        return sh.filtered_noise(r["fs"], r["n"], r["f_lo"], r["f_hi"], r["taper"], rng, rest=r["rest"])
    f0, f1 = (r["f_hi"], r["f_lo"]) if r["down"] else (r["f_lo"], r["f_hi"])
    return sh.chirp(r["fs"], r["n"], f0, f1, r["n_sweeps"], r["rest"], log=r["log"])


def effect_params(name: str, level: float, sc: dict[str, float], rng: np.random.Generator,
                  sign: float = 1.0) -> dict[str, float]:
    """Parameters of library effect ``name`` at relative strength ``level`` (1 = typical) on scales ``sc``
    (:func:`scales`); ``sign`` chooses the lag's channel for ``sensor_delay`` (+1 force lags, −1 displacement)."""
    S, A, v, k = sc["S"], sc["A"], sc["v"], sc["k"]
    if name == "friction":
        F_c = 0.1 * level * S
        asym = rng.random() < 1 / 3  # a third of the sliders slip harder one way
        return {"F_c": F_c, "dF": float(rng.choice([-0.3, 0.3])) * F_c if asym else 0.0, "x_s": 0.02 * A}
    if name == "stribeck":
        F_c = 0.05 * level * S
        v_s = 0.2 * v
        return {"F_c": F_c, "F_s": 2.0 * F_c, "dF": 0.0, "v_s": v_s, "v_e": 0.02 * v_s}
    if name == "hysteresis":
        return {"F_h": 0.1 * level * S, "x_h": 0.2 * A}
    if name == "bouc_wen":
        return {"F_y": 0.1 * level * S, "x_y": 0.2 * A, "n": float(rng.choice([2.0, 4.0])),
                "r": float(rng.uniform(0.5, 1.0))}
    if name == "backlash":
        return {"b": 0.1 * level * A}
    if name == "deadband":
        g = 1.5 * A
        return {"k_d": 0.5 * level * k / A, "g": g, "p": 2.0, "x_c": sc["x_mean"]}
    if name == "hardening":
        return {"k3": 0.1 * level * S / A ** 3, "k2": 0.0, "x_m": sc["x_mean"]}
    if name == "stiffness_level":
        return {"scale": 1.0 - 0.12 * level if level <= 2 else 1.3}
    if name == "contact_law":
        return {"scale": 1.0 + 0.3 * level, "beta": 2.0 / 3.0 if level < 1.5 else 0.8}
    if name == "slack":
        return {"s": 0.1 * level * A}
    if name == "sensor_delay":
        return {"tau": sign * 0.15 * level / (2 * math.pi * sc["f_hi"])}  # 0.15 rad at the band edge
    if name == "damping_law":
        return {"spread": 0.2 * min(level, 1.5)}
    raise ValueError(f"effect {name!r} has no strength rule in the ODE world")


def outside_params(name: str, level: float, sc: dict[str, float], rng: np.random.Generator) -> dict[str, float]:
    """Parameters of a mechanism outside the library (``relaxation``, ``drift``, ``chatter``) at ``level``."""
    S, k, v = sc["S"], sc["k"], sc["v"]
    if name == "relaxation":
        return {"k_m": 0.2 * level * k, "tau_m": float(rng.uniform(0.3, 3.0))}
    if name == "drift":
        return {"total": 0.1 * level * S}
    if name == "chatter":
        k_s = k
        f_s = min(float(rng.uniform(3.0, 5.0)) * sc["f_hi"], sc["fs"] / 5.0)  # a structure above the band
        m_s = k_s * 1e3 / (2 * math.pi * f_s) ** 2
        F_c = 0.05 * level * S
        v_s = 0.2 * v
        return {"k_s": k_s, "m_s": m_s, "c_s": 2 * 0.02 * math.sqrt(k_s * 1e3 * m_s) * 1e-3, "F_c": F_c,
                "F_s": 2.0 * F_c, "v_s": v_s, "v_e": v_s / 50.0, "f_s": f_s}
    raise ValueError(f"outside mechanism {name!r} is unknown; valid: relaxation, drift, chatter")

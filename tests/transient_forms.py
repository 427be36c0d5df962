"""Independent test signals for the time-domain diagnosis: band-limited random displacement and forces
built directly from the library's causal operators (not through chainid.gap.timedomain.data)."""
from __future__ import annotations

import numpy as np

from chainid.records import Record


def random_x(n: int = 6000, fs: float = 200.0, f_band: float = 2.0, amp: float = 1.0, x0: float = 0.0,
             seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """t [s], x [mm], ẋ [mm/s], ẍ [mm/s²]: a sum of sines with random phases, flat spectrum below f_band,
    scaled to RMS amp (exact derivatives)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    T = n / fs
    f = np.arange(1, int(f_band * T) + 1) / T
    ph = rng.uniform(0, 2 * np.pi, f.size)
    w = 2 * np.pi * f[:, None]
    a = 1.0 / np.sqrt(f.size / 2)
    x = a * np.sin(w * t + ph[:, None]).sum(0)
    xd = a * (w * np.cos(w * t + ph[:, None])).sum(0)
    xdd = -a * (w**2 * np.sin(w * t + ph[:, None])).sum(0)
    s = amp / np.std(x)
    return t, x0 + s * x, s * xd, s * xdd


def record(test: str, t: np.ndarray, x: np.ndarray, F: np.ndarray, noise_F: float, seed: int) -> Record:
    rng = np.random.default_rng(seed + 1000)
    return Record(test, t, x.copy(), F + rng.normal(0.0, noise_F, t.size))


def chain_set(effect: str, p: dict, n_rec: int = 3, n: int = 4000, noise_F: float = 5.0, c: float = 30.0,
              amp: float = 0.08, x0: float = 2.0, seed: int = 0, extra=None):
    """Records of the built-in chain under band-limited random x with one effect (composed by hand here from
    the library's operators, evaluated causally on the raw samples)."""
    from chainid.model.effects import dahl_operator, modify_model, play_operator, stick_slip
    from chainid.model import ChainModel

    model = ChainModel()
    recs = []
    for i in range(n_rec):
        t, x, xd, xdd = random_x(n, 200.0, 2.0, amp, x0, seed=seed + i)
        mdl = model
        xe = x
        if effect in ("stiffness_level", "slack", "contact_law"):
            mdl = modify_model(effect, p, model)
        if effect == "sensor_delay":
            xe = np.interp(t - p["tau"], t, x)
            xd = np.interp(t - p["tau"], t, xd)
        if effect == "backlash":
            xe = play_operator(x, 0.5 * p["b"], periodic=False)
        F = np.asarray(mdl.force(xe), float) + c * xd
        if effect == "friction":
            F += p["F_c"] * stick_slip(x, xd, p.get("x_s", 0.0), periodic=False)
        if effect == "hysteresis":
            F += dahl_operator(x, p["F_h"], p["x_h"], periodic=False)
        if extra is not None:
            F += extra(t, x, xd)
        recs.append(record(f"r{i}", t, x, F, noise_F, seed + i))
    return model, recs

"""Plausibility of records read from a rig: warnings that catch unit slips (a file in metres read as mm is
1000x too small and passes every data check).

Each warning names the likely slip and the option that fixes it; nothing is ever rescaled.  Checks:

* sampling: a time step implying a rate above 1 MHz (time in s declared ms/us), fewer than 4 samples per cycle
  of the test's main frequency (the rate is below about twice the test frequency), a main frequency below
  0.01 Hz (time in ms read as s) or above 1 kHz, a displacement moving faster than :data:`V_MAX_MM_S` (5 m/s) or
  accelerating more than :data:`A_MAX_MM_S2` (1000 g), beyond what servo-hydraulic and electrodynamic test
  machines drive a specimen: a record in s declared ms moves 1000x and accelerates 10⁶x too much (estimated as
  2π·f·A and (2π·f)²·A from the main frequency f and half the 1..99 % span of x, so noise does not count).  So a
  slip is caught when the true motion exceeds 5 mm/s or 10⁻³ g (0.3 mm at 0.92 Hz and faster); a slower, smaller
  one is not;
  time steps over 5x the record's median step (gaps: their count and the largest);
* with a chain (its elastic range from :mod:`chainid.model`): a displacement span over 10x the chain's
  elongation at the breaking load (x in um read as mm) or under 1/1000 of its elongation at the working load
  (x in m read as mm); a secant stiffness span(F)/span(x) more than 30x off the chain's k_e over the record's
  force range (x or F 1000x or 25.4x off); a force above 3x the breaking load (F in N declared kN) or a largest
  force below 1/10000 of the working load (F in kN read as N); a harmonic record whose chain inertia at the
  declared main frequency, m·(2πf)²·A, is over :data:`INERTIA_SHARE` (a quarter) of the measured force's
  half-span while the paper's harmonic tests are quasi-static (a test in s declared ms puts the paper's 14x50
  chain, f_n = √(k_e/m)/2π ≈ 200-250 Hz, far above its own natural frequency).

Units: t [s], x [mm], F [N], k [N/mm].
"""
from __future__ import annotations

import math
import re
from functools import lru_cache
from typing import Any, Sequence

import numpy as np

from chainid.records.record import Record

__all__ = ["FS_MAX_HZ", "V_MAX_MM_S", "A_MAX_MM_S2", "GAP_FACTOR", "INERTIA_SHARE", "sampling_warnings", "gap_warnings",
           "chain_warnings",
           "smallest_chain", "not_a_chain", "plausibility_warnings", "grouped"]

#: A sampling rate above this [Hz] is implausible for a chain test rig.
FS_MAX_HZ = 1.0e6
#: A displacement faster than this [mm/s] is implausible for a test rig (time unit slip).
V_MAX_MM_S = 5000.0
#: Standard gravity [mm/s²]; an acceleration of x over :data:`A_MAX_MM_S2` (1000 g) is implausible for a test rig.
G_MM_S2 = 9806.65
A_MAX_MM_S2 = 1000.0 * G_MM_S2
#: A chain inertia m·ω²·A over this share of the measured force's half-span is not a quasi-static test.
INERTIA_SHARE = 0.25
#: A time step over this multiple of the median step is a gap in the record.
GAP_FACTOR = 5.0
_SLIPS = ((1000.0, "x in m read as mm (--units x=m) or F declared kN while in N"),
          (1e-3, "F in kN read as N (--units F=kN) or x in um read as mm (--units x=um)"),
          (25.4, "x in inches declared mm? (--units x=in)"),
          (1 / 25.4, "x declared inches while in mm"),
          (1 / 4448.2, "F in kip read as N (--units F=kip)"),
          (1 / 4.448, "F in lbf read as N (--units F=lbf)"))


def _main_frequency(rec: Record) -> float:
    """Main frequency of x(t) [Hz] from the FFT of the mean-removed x at its median time step; NaN when no
    frequency dominates (the peak and its 2 neighbours on each side hold under half the power: noise)."""
    n = rec.t.size
    dt = float(np.median(np.diff(rec.t)))
    step = max(1, n // 65536)
    x = rec.x[::step] - float(np.mean(rec.x[::step]))
    if x.size < 8 or not np.any(x):
        return float("nan")
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size)))
    spec[0] = 0.0
    k = int(np.argmax(spec))
    power = spec ** 2
    if power[max(k - 2, 0):k + 3].sum() < 0.5 * power.sum():
        return float("nan")
    return k / (x.size * dt * step)


def _half_span(a: np.ndarray) -> float:
    """Half the 1..99 % span of a channel (its amplitude, robust to spikes and noise), in the channel's unit."""
    return 0.5 * float(np.subtract(*np.percentile(a, [99.0, 1.0])))


def sampling_warnings(records: Sequence[Record]) -> list[str]:
    """Time-step warnings of each record (see the module docstring)."""
    out = []
    for r in records:
        if r.t.size < 8:
            continue
        dt = float(np.median(np.diff(r.t)))
        if not (math.isfinite(dt) and dt > 0):
            continue
        fs = 1.0 / dt
        if fs > FS_MAX_HZ:
            out.append(f"test {r.test!r}: time step {dt:.3g} s implies sampling at {fs:.4g} Hz, above "
                       f"{FS_MAX_HZ:.0e} Hz: is t in s while declared ms or us (--units t=...)?")
            continue
        f = _main_frequency(r)
        if not math.isfinite(f) or f <= 0:
            continue
        if fs / f < 4.0:
            out.append(f"test {r.test!r}: {fs:.4g} Hz sampling gives {fs / f:.2g} samples per cycle of the main "
                       f"frequency {f:.4g} Hz (below about twice the test frequency the motion is aliased): "
                       "wrong time unit (--units t=...) or --fs?")
        elif f < 0.01:
            out.append(f"test {r.test!r}: the main frequency {f:.3g} Hz (a cycle of {1 / f:.3g} s) is implausibly "
                       "slow: is t in ms read as s (--units t=ms) or --fs too small?")
        elif f > 1000.0:
            out.append(f"test {r.test!r}: the main frequency {f:.4g} Hz is implausibly fast for a chain test: is t "
                       "in s declared ms (--units t=...) or --fs too large?")
        else:
            amp = _half_span(r.x)
            w = 2 * math.pi * f
            v, acc = w * amp, w * w * amp
            if v > V_MAX_MM_S or acc > A_MAX_MM_S2:
                out.append(f"test {r.test!r}: x moves at about {v:.4g} mm/s and {acc / G_MM_S2:.4g} g ({amp:.4g} mm "
                           f"at {f:.4g} Hz), beyond what a test rig drives a specimen ({V_MAX_MM_S / 1000:g} m/s, "
                           f"{A_MAX_MM_S2 / G_MM_S2:g} g): is t in s declared ms (--units t=ms), or --fs too large?")
    return out + gap_warnings(records)


def gap_warnings(records: Sequence[Record]) -> list[str]:
    """Time steps over :data:`GAP_FACTOR` times the record's median step: their count and the largest."""
    out = []
    for r in records:
        if r.t.size < 8:
            continue
        d = np.diff(r.t)
        med = float(np.median(d))
        if not (math.isfinite(med) and med > 0):
            continue
        big = np.flatnonzero(d > GAP_FACTOR * med)
        if big.size:
            i = int(big[np.argmax(d[big])])
            out.append(f"test {r.test!r}: {big.size} time step(s) over {GAP_FACTOR:g}x the median step "
                       f"{med:.4g} s, the largest {float(d[i]):.4g} s at t = {float(r.t[i]):.6g} s: gaps in the "
                       "record (a paused logger? --split-gap S cuts a file there)")
    return out


def _slip(ratio: float) -> str:
    best = min(_SLIPS, key=lambda s: abs(math.log(ratio / s[0])))
    return best[1] if abs(math.log(ratio / best[0])) < math.log(3.0) else "a unit slip of x or F?"


def chain_warnings(records: Sequence[Record], chain: Any, variant: str = "paper") -> list[str]:
    """Warnings against the chain's elastic range and stiffness (see the module docstring)."""
    from chainid.model import kernels
    from chainid.model.practice import chain_practice

    p = chain_practice(chain)
    x_of = (lambda F: float(np.atleast_1d(kernels.displacement(np.array([F], dtype=float), chain, variant))[0]))
    k_of = (lambda x: float(np.atleast_1d(kernels.stiffness(np.array([x], dtype=float), chain, variant))[0]))
    wl, bl = p["working_load_N"], p["breaking_load_N"]
    x_wl, x_bl = x_of(wl), x_of(bl)
    out = []
    for r in records:
        span_x, span_F = float(np.ptp(r.x)), float(np.ptp(r.F))
        F_max = float(np.max(r.F))
        tag = f"test {r.test!r}"
        if span_x > 10.0 * x_bl:
            out.append(f"{tag}: x spans {span_x:.4g} mm, {span_x / x_bl:.3g}x the chain's elongation at the breaking "
                       f"load ({x_bl:.3g} mm): is x in um read as mm (--units x=um)?")
        elif 0 < span_x < x_wl / 1000.0:
            out.append(f"{tag}: x spans {span_x:.3g} mm, under 1/1000 of the chain's elongation at the working "
                       f"load ({x_wl:.3g} mm): is x in m read as mm (--units x=m)?")
        if F_max > 3.0 * bl:
            out.append(f"{tag}: F reaches {F_max:.4g} N, {F_max / bl:.3g}x the chain's breaking load "
                       f"({bl:.4g} N): is F in N declared kN, or in mN?")
        elif 0 < F_max < wl * 1e-4:
            out.append(f"{tag}: the largest force {F_max:.3g} N is under 1/10000 of the chain's working load "
                       f"({wl:.4g} N): is F in kN read as N (--units F=kN)?")
        if span_x > 0 and span_F > 0:
            F_lo = max(float(np.min(r.F)), 1.0)
            k_lo, k_hi = k_of(x_of(F_lo)), k_of(x_of(max(F_max, F_lo)))
            k_rec = span_F / span_x
            if k_rec > 30.0 * k_hi or k_rec < k_lo / 30.0:
                ref = k_hi if k_rec > k_hi else k_lo
                out.append(f"{tag}: the record's stiffness span(F)/span(x) = {k_rec:.4g} N/mm is {k_rec / ref:.3g}x "
                           f"the chain's k_e ({k_lo:.4g}..{k_hi:.4g} N/mm over the record's forces): "
                           f"{_slip(k_rec / ref)}")
        out += _inertia_warning(r, chain, k_of(x_of(max(float(np.median(r.F)), 1.0))))
    return out


def _inertia_warning(r: Record, chain: Any, k_mid: float) -> list[str]:
    """The chain's own inertia at the record's main frequency against its measured force (Eq. 1's m·ẍ): a quarter
    of the force's half-span or more is not the quasi-static harmonic test of Eq. 21-28.  m [kg], A [mm],
    k_mid [N/mm] (k_e at the median force); the force m·ω²·A in N is 1e-3·m·ω²·A."""
    m = float(chain.mass_kg)
    f = _main_frequency(r) if r.t.size >= 8 else float("nan")
    if not (m > 0 and math.isfinite(f) and f > 0):
        return []
    amp = _half_span(r.x)
    half_F = _half_span(r.F)
    f_in = 1e-3 * m * (2 * math.pi * f) ** 2 * amp
    if not (half_F > 0 and f_in > INERTIA_SHARE * half_F):
        return []
    f_n = math.sqrt(1e3 * k_mid / m) / (2 * math.pi) if k_mid > 0 else float("nan")
    natural = f"{f / f_n:.3g}x the chain's natural frequency √(k_e/m)/2π = {f_n:.4g} Hz" if f_n > 0 else \
        "above a natural frequency the chain's k_e (0 here) cannot give"
    return [f"test {r.test!r}: at the main frequency {f:.4g} Hz the chain's own inertia m·(2πf)²·A = {f_in:.4g} N "
            f"({m:.3g} kg, A {amp:.3g} mm) is {f_in / half_F:.3g}x the measured force's half-span {half_F:.4g} N, "
            f"{natural}; the paper's harmonic tests "
            "are quasi-static: is t in s declared ms (--units t=ms) or --fs too large? (A test this fast needs the "
            "inertia in the base model: the time route carries m·ẍ.)"]


@lru_cache(maxsize=1)
def smallest_chain() -> tuple[str, float, float]:
    """The listed catalogue preset with the smallest proof load: (name, proof load [N], its elongation at that load
    [mm], with the preset's default 16 links)."""
    from chainid.chain import presets
    from chainid.model import kernels
    from chainid.model.practice import chain_practice

    best = min(presets.listed(), key=lambda p: chain_practice(p.chain)["proof_load_N"])
    pl = float(chain_practice(best.chain)["proof_load_N"])
    x_pl = float(np.atleast_1d(kernels.displacement(np.array([pl]), best.chain, "paper"))[0])
    return best.name, pl, x_pl


def not_a_chain(records: Sequence[Record]) -> str | None:
    """Why the records cannot be a chain's, or None.  The rule, from the chain catalogue's physics:

    * a chain only pulls: a force that changes sign with more than 10 % of its largest magnitude on each side
      (min F < −0.1·max|F| and max F > 0.1·max|F|) is not a chain's tension;
    * or every force is under 1 % of the proof load of the smallest listed preset (DIN 22252 14x50, 16 links:
      1970 N) while x spans more than that chain's elongation at its proof load (20.7 mm): a stroke that
      stretches the most compliant catalogue chain to its proof load, at a hundredth of that load.
    """
    recs = [r for r in records if r.F.size and r.x.size]
    if not recs:
        return None
    f_abs = max(float(np.max(np.abs(r.F))) for r in recs)
    if f_abs <= 0:
        return None
    for r in recs:
        lo, hi = float(np.min(r.F)), float(np.max(r.F))
        if lo < -0.1 * f_abs and hi > 0.1 * f_abs:
            return (f"the force changes sign (test {r.test!r}: F from {lo:.4g} N to {hi:.4g} N), and a chain only "
                    "pulls")
    name, pl, x_pl = smallest_chain()
    span = max(float(np.ptp(r.x)) for r in recs)
    if f_abs < 0.01 * pl and span > x_pl:
        return (f"the forces stay under {f_abs:.4g} N, below 1 % of the proof load of the smallest catalogue chain "
                f"({name}: {pl:.4g} N), while x spans {span:.4g} mm, more than that chain stretches at its proof "
                f"load ({x_pl:.3g} mm)")
    return None


def plausibility_warnings(records: Sequence[Record], chain: Any = None, variant: str = "paper") -> list[str]:
    """All plausibility warnings of the records: sampling always, the chain's when ``chain`` is given.

    Parameters
    ----------
    records : sequence of Record
        t [s], x [mm], F [N].
    chain : ChainSpec or None
        The chain the records are read for (None: no chain check, e.g. a linear model or another part).
    variant : str
        Stiffness kernel variant for k_e.

    Returns
    -------
    list of str
        One line per check that fires, naming the likely unit slip: the first test's message, then the other tests
        the same check fired on (a file with one slip in every test gives one line, not one per test).  Nothing
        is rescaled.
    """
    out = sampling_warnings(records)
    if chain is not None:
        out += chain_warnings(records, chain, variant)
    return grouped(out)


_TAG = re.compile(r"^(test|file) '((?:[^'\\]|\\.)*)': ")
_NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?")


def grouped(msgs: Sequence[str]) -> list[str]:
    """Per-test warnings ``test 'ID': text`` (and per-file ``file 'NAME': text``) grouped by check: messages whose
    texts differ only in their numbers are one check; it is reported once (the first test's message) with the
    other tests' ids."""
    groups: dict[str, list[tuple[str, str]]] = {}
    order: list[str] = []
    for m in msgs:
        tag = _TAG.match(m)
        key = (tag.group(1) + ":" + _NUM.sub("#", m[tag.end():])) if tag else m
        if key not in groups:
            groups[key] = []
            order.append(key)
        groups[key].append((tag.group(2) if tag else "", m))
    out = []
    for key in order:
        g = groups[key]
        first = g[0][1]
        if len(g) > 1:
            ids = ", ".join(repr(t) for t, _ in g[1:])
            noun = key.split(":", 1)[0] if _TAG.match(first) else "message"
            first += f" [the same check on {len(g) - 1} more {noun}(s): {ids}]"
        out.append(first)
    return out

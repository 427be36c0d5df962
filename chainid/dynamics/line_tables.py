"""The per-segment tables of a :class:`~chainid.dynamics.model.ChainLine`: spring and elements, scaled in series.

A segment of n_s links of a specimen of n_ref links (``damping_ref_links``, default ``chain.n``) carries the
specimen's force at r = n_s/n_ref times its elongation (springs and dampers in series).  So from the specimen's
values (units mm, N, s):

* every travel-like parameter scales by r: the slack s, the play width b, the dead band's half-width g and centre
  x_c, the stick travels x_s, the Dahl and Bouc–Wen travels x_h, x_y; so does the Stribeck velocity v_s (an
  elongation rate) and the machine compliance [mm/N] (added to the segment's c_lin);
* every stiffness scales by 1/r (Jenkins and Stribeck stick springs, k·n_ref/n_s) and a dead band's k_d
  [N/mm^p] by r^−p (its force k_d·(|u| − g)^p at r times the elongation is unchanged);
* every force is unchanged (slip forces, F_h, F_y, F_c, dF_s, dF), as are the shapes n, r of Bouc–Wen and the
  contact exponent β;
* the kernel's own coefficients are exact for any link count (c_lin ∝ n_s, c_hertz ∝ the contacts), and the
  factors ``ea_scale`` (c_lin/ea_scale) and ``hertz_scale`` (c_hertz·hertz_scale, with β set also
  ·F_ref^(2/3 − β), :attr:`chainid.model.base.ChainModel.coefficients`) apply to every segment alike.

Element table columns (``hd`` kinds of :mod:`.segments`): the play first (its output is the spring's argument),
then the Jenkins elements (``hysteresis``, then the Coulomb element), Dahl, Stribeck and Bouc–Wen.
"""
from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from chainid.model import kernels
from chainid.model.operators import bouc_wen_table

__all__ = ["series_ratio", "spring_coefficients", "spring_table", "extended_spring", "element_arrays",
           "element_stiffness", "deadband_stiffness", "link_stiffness"]


def series_ratio(line: Any) -> np.ndarray:
    """r = n_s/n_ref of every segment (float array, length N)."""
    return line.links_per_segment().astype(float) / line.reference_links()


def link_stiffness(line: Any) -> float:
    """The specimen's link stiffness 1/c_lin [N/mm] (the default stick stiffness), c_lin with ``ea_scale`` and
    ``compliance`` applied (c_lin/ea_scale + compliance)."""
    c_lin = kernels.coefficients(line.chain.replace(n=line.reference_links()), line.variant)[0]
    if line.ea_scale != 1.0 or line.compliance:
        c_lin = c_lin / line.ea_scale + line.compliance
    return 1.0 / c_lin


def spring_coefficients(line: Any) -> tuple[np.ndarray, np.ndarray]:
    """(c_lin [mm/N], c_hertz [mm/N^β]) of every segment with the kernel modifiers applied (module docstring)."""
    ns = line.links_per_segment()
    cl, ch = kernels.coefficients(line.chain.replace(n=int(line.n_links)), line.variant)
    contacts = ns.astype(float)
    contacts[-1] -= 1.0
    c_lin = cl * ns / line.n_links
    c_h = ch * contacts / (line.n_links - 1) if line.n_links > 1 else np.zeros(len(ns))
    c_lin = np.asarray(c_lin, dtype=float)
    c_h = np.asarray(c_h, dtype=float)
    if line.ea_scale != 1.0:
        c_lin = c_lin / line.ea_scale
    if line.compliance:
        c_lin = c_lin + line.compliance * series_ratio(line)
    if line.hertz_scale != 1.0:
        c_h = c_h * line.hertz_scale
    if line.contact_exponent is not None:
        c_h = c_h * line.contact_ref_force ** (2.0 / 3.0 - float(line.contact_exponent))
    return c_lin, c_h


def extended_spring(line: Any) -> bool:
    """Whether a segment's spring needs the spring table (contact exponent, slack, dead band or play)."""
    return bool(line.contact_exponent is not None or line.slack != 0.0 or line.deadband or line.backlash_mm > 0)


def spring_table(line: Any) -> np.ndarray:
    """The spring table (N, 6) of :mod:`.springs`: β flag (0: Hertz), s [mm], k_d [N/mm^p], g [mm], p, x_c [mm]."""
    r = series_ratio(line)
    sp = np.zeros((line.n_masses, 6))
    if line.contact_exponent is not None:
        sp[:, 0] = float(line.contact_exponent)
    sp[:, 1] = line.slack * r
    if line.deadband:
        k_d, g, p, x_c = line.deadband
        sp[:, 2] = k_d * r ** (-p)
        sp[:, 3] = g * r
        sp[:, 4] = p
        sp[:, 5] = x_c * r
    else:
        sp[:, 4] = 1.0
    return sp


@lru_cache(maxsize=32)
def _bw_table(n: float, r: float) -> np.ndarray:
    _, xi, Z = bouc_wen_table(n, r)
    return np.stack([xi, Z])


def element_arrays(line: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(hf, hx, hd, hq, tabs): the element table of every segment, shape (N, n_el) and (N, n_el, 3), and the
    Bouc–Wen travel tables (n_tables, 2, points) (see the module docstring and :mod:`.segments`)."""
    N = line.n_masses
    r = series_ratio(line)
    cols: list[tuple[np.ndarray, np.ndarray, int, tuple[Any, Any, Any]]] = []
    one = np.ones(N)
    if line.backlash_mm > 0:
        cols.append((0.0 * one, 0.5 * line.backlash_mm * r, 4, (0.0, 0.0, 0.0)))
    kj, fj = line.segment_elements()
    with np.errstate(divide="ignore", invalid="ignore"):
        for q in range(kj.shape[1]):
            cols.append((fj[:, q], fj[:, q] / kj[:, q], 0, (0.0, 0.0, 0.0)))
    for F_h, x_h in line.dahl:
        cols.append((F_h * one, x_h * r, 1, (0.0, 0.0, 0.0)))
    for F_c, dF_s, v_s, dF in line.stribeck:
        k = link_stiffness(line) if line.stribeck_stiffness is None else line.stribeck_stiffness
        cols.append((F_c * one, k / r, 2, (dF_s * one, v_s * r, dF * one)))
    tabs: list[np.ndarray] = []
    keys: list[tuple[float, float]] = []
    for F_y, x_y, n, rs in line.bouc_wen:
        if (n, rs) not in keys:
            keys.append((n, rs))
            tabs.append(_bw_table(float(n), float(rs)))
        cols.append((F_y * one, x_y * r, 3, (float(keys.index((n, rs))) * one, n * one, rs * one)))
    n_el = len(cols)
    hf, hx = np.zeros((N, n_el)), np.zeros((N, n_el))
    hd, hq = np.zeros((N, n_el), dtype=np.int64), np.zeros((N, n_el, 3))
    for q, (f, x, kind, extra) in enumerate(cols):
        hf[:, q], hx[:, q], hd[:, q] = f, x, kind
        for i in range(3):
            hq[:, q, i] = extra[i]
    tab = np.stack(tabs) if tabs else np.zeros((0, 2, 2))
    return hf, hx, hd, hq, np.ascontiguousarray(tab)


def element_stiffness(line: Any) -> np.ndarray:
    """The elements' stiffness [N/mm] of every segment at its stiffest (Jenkins and Stribeck sticking, Dahl at a
    reversal 2F_h/x_h, Bouc–Wen unloading max(1, 2r)·F_y/x_y; the play none of its own)."""
    hf, hx, hd, hq, _ = element_arrays(line)
    k = np.zeros(hf.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(hd == 0, hf / np.where(hx > 0, hx, 1.0), k)
        k = np.where(hd == 1, 2.0 * hf / np.where(hx > 0, hx, 1.0), k)
        k = np.where(hd == 2, hx, k)
        k = np.where(hd == 3, np.maximum(1.0, 2.0 * hq[:, :, 2]) * hf / np.where(hx > 0, hx, 1.0), k)
    return k.sum(axis=1)


def deadband_stiffness(line: Any, force: float) -> np.ndarray:
    """Tangent [N/mm] of every segment's dead band where its force is ``force`` [N] (> 0): k_d·p·(F/k_d)^((p−1)/p)."""
    sp = spring_table(line)
    kd, p = sp[:, 2], sp[:, 4]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(kd > 0, kd * p * (force / np.where(kd > 0, kd, 1.0)) ** ((p - 1.0) / p), 0.0)

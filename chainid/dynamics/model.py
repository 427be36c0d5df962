"""The lumped multi-mass chain: geometry, masses, segment springs and dampers, ends and loads.

Layout (units mm, N, s, kg)::

    drive ── seg 1 ── node 1 ── seg 2 ── ... ── node N-1 ── seg N ── node N (far end)
    node 0

Node 0 is the driven node (its motion is prescribed by a :class:`~chainid.dynamics.drives.Drive`); node N
is the far end: ``"fixed"`` (anchored) or ``"tensioner"`` (a constant-force take-up, force
``pretension + tensioner_stiffness·u_N``).  Displacements u_i [mm] are positive in the direction of chain
travel, towards the drive, and are measured from the pre-tensioned static state; segment j (between nodes
j-1 and j) has elongation e_j = e_pre + u_{j-1} - u_j [mm] and tension T_j [N].

Springs.  The chain of ``n_links`` links is split into N segments of n_s links (as equal as possible).  The
generated coefficients are exactly linear in the link count (c_lin ∝ n for the link bending, c_hertz ∝ n − 1
for the n − 1 contacts of a specimen between two fixtures), so a segment gets c_lin·n_s/n and the contact
compliance of the contacts it contains: one per link except in the last segment (n_s − 1).  The series sum
of all segments is then exactly the kernel of the whole chain (spec with n = n_links) for every N, and one
segment is the paper's specimen.  Each segment's tension is the generated F_k(e) (a slack segment, e <= 0,
carries nothing).

Diagnosed physics (``chainid dynamics --segment-model``, :mod:`.segment_model`).  The specimen's kernel
modifiers (``ea_scale``, ``hertz_scale``, ``contact_exponent`` with ``contact_ref_force``, ``compliance``,
``slack``: those of :class:`chainid.model.base.ChainModel`), its play (``backlash_mm``), dead band with hardening
stops (``deadband``), Stribeck friction (``stribeck``) and Bouc–Wen hysteresis (``bouc_wen``) go into every
segment, scaled in series like the damping below (:mod:`.line_tables`; the segment force law in
:mod:`.segments`); ``drive_mass_kg`` adds a mass to the driven node 0 (a test fixture that moved with the
specimen's driven end).

Damping.  The paper identifies c_e(ω, A) from harmonic tests: a *viscous equivalent* c_e [N·s/mm] that
dissipates the measured loop energy W = π c_e ω A² at that ω and A.  A time-domain model has no single ω and
A, so it uses the viscous equivalent at a stated operating point (see :func:`viscous_equivalent`: the first
natural frequency or the polygon frequency, and the expected dynamic elongation amplitude).  This is exact
for the energy per cycle at that point, keeps the model linear in velocity (the energy balance can be checked)
and adds no history state.  Dampers of a chain act in series like its springs: c_e measured on a specimen of
``damping_ref_links`` links gives a segment of n_s links c_e·n_ref/n_s.  The damper acts only while the
segment is taut and can never push: T_j = max(F_k(e_j) + c_j·ė_j + Σ z_jq, 0) for e_j > 0, else 0.

Time-domain hysteretic damping.  Besides (or instead of) the viscous c_e, a segment can carry
Jenkins elements (spring k in series with a Coulomb slider of force f, state z = element force, see
:mod:`.segments`): ``hysteresis`` = ((k [N/mm], f [N]), ...) of the specimen, an Iwan (parallel Masing)
model of rate-independent hysteresis, and ``coulomb_N`` = Coulomb friction with stick (one Jenkins element
of slip force coulomb_N and stick stiffness ``coulomb_stiffness``, default the specimen's link stiffness
1/c_lin).  Specimen-to-segment scaling: springs and dampers in series, so a specimen of n_ref links and a
segment of n_s links carry the same force at n_s/n_ref times the elongation: every compliance scales by
n_s/n_ref (k·n_ref/n_s, c·n_ref/n_s) and every force (the slip forces f) is unchanged.  A harmonic
elongation of amplitude A about a taut mean dissipates, per cycle and element, 4·f·(A − f/k) when
A > f/k (else 0), the loop area of a Jenkins element.

Masses.  ``lumping="half"`` (default) puts half of each segment's mass on each of its nodes (the standard
lumped-mass chain); ``lumping="drive"`` puts each segment's mass on its drive-side node, which for one
segment with a fixed far end is the paper's one-mass test model F = m·ẍ + F_k(x) + c_e·ẋ.  ``tail_mass_kg``
adds a tensioner carriage mass on node N.

Loads.  ``resistance_N``: the total moving resistance of the strand (friction of chain and load on the
trough), distributed over the moving nodes in proportion to their mass: a Coulomb force regularised by
a steep viscous branch around standstill, f_i = −R_i·clip(v_i / resistance_v_eps, −1, 1).  ``loads``: load steps (node, force N, switch-on time s) opposing
the motion.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from chainid.dynamics import line_tables
from chainid.dynamics.effect_fields import check_effects, finite_real
from chainid.dynamics.springs import deadband, spring_stiffness, static_elongations
from chainid.model import kernels
from chainid.chain.spec import ChainSpec, default_chain

__all__ = ["ChainLine", "LoadStep", "viscous_equivalent", "FAR_ENDS", "LUMPINGS"]

FAR_ENDS: tuple[str, ...] = ("fixed", "tensioner")
LUMPINGS: tuple[str, ...] = ("half", "drive")


def _bad(field_name: str, value: object, valid: str) -> ValueError:
    return ValueError(f"{field_name} = {value!r} is invalid: valid range {valid}")


@dataclass(frozen=True)
class LoadStep:
    """A force opposing the motion on one node, switched on at a time.

    Parameters
    ----------
    node : int
        Node index, 0 < node <= N (node 0 is the prescribed drive).
    force_N : float
        Force [N], > 0 opposes the chain travel.
    t_on : float
        Switch-on time [s], >= 0.
    """

    node: int
    force_N: float
    t_on: float = 0.0


@dataclass(frozen=True)
class ChainLine:
    """A chain of ``n_links`` links lumped into ``n_masses`` segments (see the module docstring).

    Parameters
    ----------
    n_links : int
        Links in the chain, >= n_masses.  Length = n_links·pitch [mm] (see :meth:`from_length`).
    n_masses : int
        Number of segments N (>= 1); the nodes are 0 (drive) .. N (far end).
    chain : ChainSpec, optional
        Link geometry, material and mass per metre (its ``n`` is ignored); default the built-in 14x50 chain.
    variant : str
        Kernel variant (``chainid.model.kernels.VARIANTS``).
    pretension_N : float
        Static tension of every segment at t = 0 [N], >= 0 (the tensioner force at the far end).
    far_end : str
        ``"fixed"`` or ``"tensioner"``.
    tensioner_stiffness : float
        Take-up spring [N/mm], >= 0 (0: constant-force take-up).
    tail_mass_kg : float
        Extra mass on node N [kg], >= 0 (tensioner carriage, tail wheel).
    damping : float
        Viscous-equivalent c_e [N·s/mm] of a specimen of ``damping_ref_links`` links, >= 0.
    damping_ref_links : int, optional
        Links of the specimen c_e belongs to; default ``chain.n`` (the tested specimen).
    resistance_N : float
        Total moving resistance [N], >= 0.
    resistance_v_eps : float
        Speed [mm/s] below which the resistance is viscous (R·v/ε) instead of Coulomb (R), > 0.
    loads : tuple of LoadStep
        Load steps.
    lumping : str
        ``"half"`` or ``"drive"``.
    hysteresis : tuple of (k, f)
        Jenkins elements of the specimen (``damping_ref_links`` links): stiffness k [N/mm] > 0 and slip force
        f [N] > 0 each (an Iwan model; see the module docstring for the scaling to segments).
    dahl : tuple of (F_h, x_h)
        Dahl elements of the specimen: force F_h [N] > 0 approached over a travel x_h [mm] > 0 after each
        reversal (segment: x_h·n_s/n_ref, F_h unchanged).
    coulomb_N : float
        Coulomb friction force with stick of the specimen [N], >= 0.
    coulomb_stiffness : float, optional
        Stick stiffness of the Coulomb element for the specimen [N/mm], > 0; default 1/c_lin of the specimen
        (c_lin/ea_scale + compliance).
    ea_scale, hertz_scale : float
        Factors on the links' linear compliance (c_lin/ea_scale; 0.001 to 1000) and on the contact coefficient
        (c_hertz·hertz_scale; > 0), as :class:`chainid.model.base.ChainModel`.
    contact_exponent : float, optional
        Contact exponent β, 0.2 to 1.5 (None: Hertz, the generated kernel), with its reference force
        ``contact_ref_force`` [N] > 0 (default 1e4), as ChainModel.
    compliance : float
        Series compliance of the specimen [mm/N], >= 0 (segment: ·n_s/n_ref, added to c_lin).
    slack : float
        Displacement offset of the specimen [mm], finite: its spring carries load from e = slack (segment:
        ·n_s/n_ref).
    backlash_mm : float
        Play (backlash) of total width b [mm] of the specimen in series with its spring, >= 0 (segment: ·n_s/n_ref).
    deadband : tuple
        () or (k_d [N/mm^p] >= 0, g [mm] >= 0, p [-] 1 to 6, x_c [mm]) of the specimen: a force
        k_d·sgn(u)·max(|u| − g, 0)^p of u = e − x_c (segment: k_d·(n_ref/n_s)^p, g and x_c ·n_s/n_ref).
    stribeck : tuple of (F_c, dF_s, v_s, dF)
        Stribeck friction elements of the specimen: kinetic force F_c [N] >= 0, static excess dF_s [N] >= 0,
        Stribeck speed v_s [mm/s] > 0, direction asymmetry dF [N] with |dF| <= F_c (segment: v_s·n_s/n_ref).
    stribeck_stiffness : float, optional
        Stick stiffness of the Stribeck elements for the specimen [N/mm], > 0; default 1/c_lin of the specimen.
    bouc_wen : tuple of (F_y, x_y, n, r)
        Bouc–Wen elements of the specimen: F_y [N] > 0, x_y [mm] > 0, n 0.1 to 20, r 0 to 1 (segment:
        x_y·n_s/n_ref).
    drive_mass_kg : float
        Extra mass on the driven node 0 [kg], >= 0 (a fixture): it adds m·a_0 to the drive force.
    """

    n_links: int
    n_masses: int
    chain: ChainSpec = field(default_factory=default_chain)
    variant: str = "paper"
    pretension_N: float = 0.0
    far_end: str = "tensioner"
    tensioner_stiffness: float = 0.0
    tail_mass_kg: float = 0.0
    damping: float = 0.0
    damping_ref_links: int | None = None
    resistance_N: float = 0.0
    resistance_v_eps: float = 1.0
    loads: tuple[LoadStep, ...] = ()
    lumping: str = "half"
    hysteresis: tuple[tuple[float, float], ...] = ()
    dahl: tuple[tuple[float, float], ...] = ()
    coulomb_N: float = 0.0
    coulomb_stiffness: float | None = None
    ea_scale: float = 1.0
    hertz_scale: float = 1.0
    contact_exponent: float | None = None
    contact_ref_force: float = 1.0e4
    compliance: float = 0.0
    slack: float = 0.0
    backlash_mm: float = 0.0
    deadband: tuple[float, ...] = ()
    stribeck: tuple[tuple[float, float, float, float], ...] = ()
    stribeck_stiffness: float | None = None
    bouc_wen: tuple[tuple[float, float, float, float], ...] = ()
    drive_mass_kg: float = 0.0

    def __post_init__(self) -> None:
        if self.chain is None:
            object.__setattr__(self, "chain", default_chain())
        if isinstance(self.n_masses, bool) or not isinstance(self.n_masses, (int, np.integer)) or self.n_masses < 1:
            raise _bad("n_masses", self.n_masses, "an int >= 1")
        if isinstance(self.n_links, bool) or not isinstance(self.n_links, (int, np.integer)) or self.n_links < 1:
            raise _bad("n_links", self.n_links, "an int >= 1 (chain length / pitch > 0)")
        if self.n_links < self.n_masses:
            raise _bad("n_masses", self.n_masses, f"1 .. n_links = {self.n_links} (a segment holds >= 1 link)")
        kernels.variant_module(self.variant)
        for name in ("pretension_N", "tensioner_stiffness", "tail_mass_kg", "damping", "resistance_N"):
            v = getattr(self, name)
            if not (finite_real(v) and v >= 0):
                raise _bad(name, v, ">= 0 (finite)")
        if not (math.isfinite(self.resistance_v_eps) and self.resistance_v_eps > 0):
            raise _bad("resistance_v_eps", self.resistance_v_eps, "> 0 mm/s")
        if self.far_end not in FAR_ENDS:
            raise _bad("far_end", self.far_end, f"one of {list(FAR_ENDS)}")
        if self.lumping not in LUMPINGS:
            raise _bad("lumping", self.lumping, f"one of {list(LUMPINGS)}")
        if self.damping_ref_links is not None and not (int(self.damping_ref_links) >= 1):
            raise _bad("damping_ref_links", self.damping_ref_links, "an int >= 1")
        hyst = tuple(tuple(float(x) for x in el) for el in self.hysteresis)
        for el in hyst:
            if len(el) != 2 or not (math.isfinite(el[0]) and el[0] > 0 and math.isfinite(el[1]) and el[1] > 0):
                raise _bad("hysteresis", el, "pairs (k > 0 N/mm, f > 0 N), finite")
        object.__setattr__(self, "hysteresis", hyst)
        dahl = tuple(tuple(float(x) for x in el) for el in self.dahl)
        for el in dahl:
            if len(el) != 2 or not all(math.isfinite(x) and x > 0 for x in el):
                raise _bad("dahl", el, "pairs (F_h > 0 N, x_h > 0 mm), finite")
        object.__setattr__(self, "dahl", dahl)
        if not (finite_real(self.coulomb_N) and self.coulomb_N >= 0):
            raise _bad("coulomb_N", self.coulomb_N, ">= 0 N (finite)")
        if self.coulomb_stiffness is not None and not (math.isfinite(self.coulomb_stiffness)
                                                       and self.coulomb_stiffness > 0):
            raise _bad("coulomb_stiffness", self.coulomb_stiffness, "> 0 N/mm (finite) or None")
        if self.chain.mass_per_m <= 0:
            raise _bad("chain.mass_per_m", self.chain.mass_per_m, "> 0 kg/m (a dynamic model needs mass)")
        for ld in self.loads:
            if not (0 < ld.node <= self.n_masses):
                raise _bad("loads.node", ld.node, f"1 .. n_masses = {self.n_masses}")
            if not (math.isfinite(ld.force_N) and math.isfinite(ld.t_on) and ld.t_on >= 0):
                raise _bad("loads", ld, "finite force_N [N] and t_on >= 0 s")
        if self.lumping == "drive" and self.far_end == "tensioner" and self.tail_mass_kg <= 0:
            raise _bad("tail_mass_kg", self.tail_mass_kg, "> 0 kg with lumping='drive' and a tensioner far end")
        check_effects(self)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_length(cls, length_mm: float, n_masses: int, chain: ChainSpec | None = None, **kw: object) -> "ChainLine":
        """A chain of total length ``length_mm`` [mm] (> 0; rounded to whole links of ``chain.pitch``)."""
        chain = chain or default_chain()
        if not (finite_real(length_mm) and length_mm > 0):
            raise _bad("length_mm", length_mm, "> 0 mm")
        n_links = max(1, int(round(length_mm / chain.pitch)))
        return cls(n_links=n_links, n_masses=n_masses, chain=chain, **kw)

    # ------------------------------------------------------------------ derived arrays
    @property
    def n_nodes(self) -> int:
        return self.n_masses + 1

    @property
    def length_mm(self) -> float:
        """Chain length n_links·pitch [mm]."""
        return self.n_links * self.chain.pitch

    def links_per_segment(self) -> np.ndarray:
        """n_s of every segment (int array, length N; the first n_links mod N segments get one more)."""
        N = self.n_masses
        base, extra = divmod(self.n_links, N)
        return np.array([base + (1 if j < extra else 0) for j in range(N)], dtype=np.int64)

    def segment_coefficients(self) -> tuple[np.ndarray, np.ndarray]:
        """(c_lin [mm/N], c_hertz [mm/N^(2/3)], or mm/N^β with ``contact_exponent``) of every segment (see the
        module docstring), with the kernel modifiers applied (:func:`.line_tables.spring_coefficients`)."""
        return line_tables.spring_coefficients(self)

    def spring_table(self) -> np.ndarray:
        """The segments' spring table (N, 6) of :mod:`.springs` (contact exponent, slack, dead band)."""
        return line_tables.spring_table(self)

    def extended_spring(self) -> bool:
        """Whether the segments need the spring table (a contact exponent, slack, dead band or play)."""
        return line_tables.extended_spring(self)

    def segment_lengths(self) -> np.ndarray:
        """Unstretched segment lengths ℓ_s = n_s·pitch [mm]."""
        return self.links_per_segment() * self.chain.pitch

    def segment_damping(self) -> np.ndarray:
        """Viscous damping of every segment [N·s/mm]: c_e·n_ref/n_s (dampers in series)."""
        return self.damping * self.reference_links() / self.links_per_segment().astype(float)

    def reference_links(self) -> int:
        """Links n_ref of the specimen the damping data belong to (``damping_ref_links``, default chain.n)."""
        return int(self.chain.n if self.damping_ref_links is None else self.damping_ref_links)

    def specimen_elements(self) -> list[tuple[float, float]]:
        """Jenkins elements (k [N/mm], f [N]) of the specimen: ``hysteresis`` plus the Coulomb element."""
        els = list(self.hysteresis)
        if self.coulomb_N > 0:
            k = self.coulomb_stiffness
            if k is None:
                k = line_tables.link_stiffness(self)
            els.append((float(k), float(self.coulomb_N)))
        return els

    def segment_elements(self) -> tuple[np.ndarray, np.ndarray]:
        """(k [N/mm], f [N]) of every segment's Jenkins elements, shape (N, n_elements).

        Series scaling from the specimen of n_ref links to a segment of n_s links: k·n_ref/n_s, f unchanged.
        """
        els = self.specimen_elements()
        scale = self.reference_links() / self.links_per_segment().astype(float)
        k = np.array([[e[0] for e in els]] * self.n_masses, dtype=float).reshape(self.n_masses, len(els))
        f = np.array([[e[1] for e in els]] * self.n_masses, dtype=float).reshape(self.n_masses, len(els))
        return k * scale[:, None], f

    def segment_element_table(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """All elements of every segment for the integrator, shape (N, n_elements) each: (force [N], travel or
        stiffness, kind) in the columns and kinds of :mod:`.segments` (play, Jenkins, Dahl, Stribeck, Bouc–Wen)."""
        return line_tables.element_arrays(self)[:3]

    def segment_element_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(hf, hx, hd, hq, tabs): :meth:`segment_element_table` with the extra parameters (N, n_elements, 3) and
        the Bouc–Wen travel tables (:func:`.line_tables.element_arrays`)."""
        return line_tables.element_arrays(self)

    def node_masses(self) -> np.ndarray:
        """Lumped masses of nodes 0..N [kg] (node N includes ``tail_mass_kg``, node 0 ``drive_mass_kg``)."""
        ms = self.chain.mass_per_m * self.segment_lengths() * 1e-3
        m = np.zeros(self.n_nodes)
        if self.lumping == "half":
            m[:-1] += 0.5 * ms
            m[1:] += 0.5 * ms
        else:
            m[:-1] += ms
        m[-1] += self.tail_mass_kg
        m[0] += self.drive_mass_kg
        return m

    def pretension_elongation(self) -> np.ndarray:
        """Static elongation of every segment at the pretension [mm] (the inverse kernel, Eq. 15; with a slack,
        contact exponent or dead band the inverse of spring(e − s) + dead band(e − x_c), elements unstressed)."""
        c_lin, c_h = self.segment_coefficients()
        if self.extended_spring():
            return static_elongations(float(self.pretension_N), c_lin, c_h, self.spring_table())
        u = np.cbrt(self.pretension_N)
        return c_lin * self.pretension_N + c_h * u * u

    def static_tangent(self) -> np.ndarray:
        """Tangent stiffness [N/mm] of every segment's spring and dead band at the pretension (a play engaged: the
        motion beyond it; the memory elements not counted)."""
        c_lin, c_h = self.segment_coefficients()
        sp = self.spring_table()
        return np.array([spring_stiffness(e - sp[j, 1], c_lin[j], c_h[j], sp[j, 0])
                         + deadband(e - sp[j, 5], sp[j, 2], sp[j, 3], sp[j, 4])[1]
                         for j, e in enumerate(self.pretension_elongation())])

    def resistance_per_node(self) -> np.ndarray:
        """Moving resistance amplitude R_i of nodes 0..N [N] (∝ mass of the moving nodes; 0 on a fixed end)."""
        m = self.node_masses().copy()
        m[0] = 0.0  # the drive node's motion is prescribed: its resistance is the drive's business
        if self.far_end == "fixed":
            m[-1] = 0.0
        tot = m.sum()
        return self.resistance_N * m / tot if tot > 0 else np.zeros_like(m)

    def static_tension_at_speed(self) -> float:
        """Drive-end tension of steady running [N]: pretension + the whole moving resistance (tensioner end).

        With a fixed far end the chain cannot run: the static reference is the pretension.
        """
        if self.far_end == "fixed":
            return float(self.pretension_N)
        return float(self.pretension_N + self.resistance_N)


def viscous_equivalent(law_or_ce: object, omega: float, A: float, x0: float) -> float:
    """The viscous-equivalent c_e [N·s/mm] a time-domain model uses, at a stated operating point.

    Parameters
    ----------
    law_or_ce : chainid.damping.identify.DampingLaw or float
        An identified law c_e(ω, A, x0) or a constant [N·s/mm].
    omega : float
        Operating circular frequency [rad/s], > 0 (e.g. the first natural frequency, or 2π·v/pitch for the
        polygon excitation).
    A : float
        Operating elongation amplitude [mm], > 0.
    x0 : float
        Mean elongation [mm], >= 0 (the specimen's, for laws that depend on it).

    Returns
    -------
    float
        c_e [N·s/mm], >= 0.
    """
    if not (math.isfinite(omega) and omega > 0):
        raise _bad("omega", omega, "> 0 rad/s")
    if not (math.isfinite(A) and A > 0):
        raise _bad("A", A, "> 0 mm")
    if not (math.isfinite(x0) and x0 >= 0):
        raise _bad("x0", x0, ">= 0 mm")
    if isinstance(law_or_ce, (bool, np.bool_)):
        raise _bad("law_or_ce", law_or_ce, "a damping law or a number >= 0 N·s/mm")
    if isinstance(law_or_ce, numbers.Real):
        c = float(law_or_ce)
    elif not hasattr(law_or_ce, "predict"):
        raise _bad("law_or_ce", law_or_ce, "a damping law (with predict) or a number >= 0 N·s/mm")
    else:
        c = float(np.asarray(law_or_ce.predict(omega, A, x0)).reshape(-1)[0])
    if not (math.isfinite(c) and c >= 0):
        raise _bad("c_e", c, ">= 0 N·s/mm (the law gives a negative or non-finite damping at this point)")
    return c

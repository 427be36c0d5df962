"""Print the numba kernels into generated/ (``chainid generate``).

One self-contained module per model variant, ``stiffness_<variant>.py``
(numba's cache does not notice changes in other modules, so nothing is
imported across generated files).  Every expression comes from the
derivation: the chain coefficients (Eq. 15) with common-subexpression
elimination, the displacement, the Newton update of the inverse cubic and
the tangent stiffness (Eq. 16).  The template around them adds only the
domain guards and the loops.

Output is byte-for-byte reproducible for a given SymPy version (pinned in
pyproject.toml); the header records a hash of the derivation source.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from . import chain, power
from .symbols import E, c_hertz, c_lin, d, mu, n, pitch, width, x

__all__ = ["REQUIRED_SYMPY", "source_hash", "module_source", "generate", "GenerateResult"]

#: The SymPy version the committed generated/ files were printed with.
REQUIRED_SYMPY = "1.14.0"

_DERIVE_DIR = Path(__file__).resolve().parent


def source_hash() -> str:
    """SHA-256 (first 16 hex digits) of the derivation source files, in name order."""
    h = hashlib.sha256()
    for p in sorted(_DERIVE_DIR.glob("*.py")):
        h.update(p.name.encode())
        h.update(p.read_bytes().replace(b"\r\n", b"\n"))
    return h.hexdigest()[:16]


class _Printer(PythonCodePrinter):
    """math.* code; rationals as float literals; x**(1/3) as a guarded cube root."""

    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})

    def _print_Rational(self, expr: sp.Rational) -> str:
        return repr(float(expr))

    def _print_Integer(self, expr: sp.Integer) -> str:
        return repr(float(expr))

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        b, ex = expr.as_base_exp()
        if ex == sp.Rational(1, 3):
            return f"np.cbrt({self._print(b)})"
        if ex == -sp.Rational(1, 3):
            return f"(1.0/np.cbrt({self._print(b)}))"
        if ex == sp.Rational(2, 3):
            return f"np.cbrt({self._print(b)})**2"
        if ex == -sp.Rational(2, 3):
            return f"(1.0/np.cbrt({self._print(b)})**2)"
        if ex.is_Integer and 1 < ex <= 4 and b.is_Symbol:
            base = self.parenthesize(b, sp.printing.precedence.PRECEDENCE["Pow"])
            return "*".join([base] * int(ex))
        return super()._print_Pow(expr, rational=rational)


_P = _Printer()


def _code(expr: sp.Expr) -> str:
    return _P.doprint(expr)


def _coefficient_body(a: chain.Assumptions) -> str:
    lin, hz = chain.chain_coefficients(a)
    nu = sp.Symbol("nu", positive=True)
    names = {d: sp.Symbol("d", positive=True), pitch: sp.Symbol("pitch", positive=True),
             width: sp.Symbol("width", positive=True), n: sp.Symbol("n", positive=True), E: E, mu: nu}
    lin = lin.xreplace(names)
    hz = hz.xreplace(names)
    reps, (lin_r, hz_r) = sp.cse([lin, hz], symbols=sp.numbered_symbols("t"), optimizations="basic")
    lines = [f"    {s} = {_code(v)}" for s, v in reps]
    lines.append(f"    c_lin = {_code(lin_r)}")
    lines.append(f"    c_hertz = {_code(hz_r)}")
    return "\n".join(lines)


_TEMPLATE = '''\
# GENERATED FILE - DO NOT EDIT.
# Written by `chainid generate` from chainid.derive (the repository's derive/).
# variant: {name} - {description}
# derivation source hash: {hash}
# generator: SymPy {sympy}
# To change the model, edit derive/ and run `chainid generate`; `chainid generate --check` fails when this is stale.
\"\"\"Kernels of the chain stiffness, variant ``{name}`` ({description}).

x(F) = c_lin*F + c_hertz*F**(2/3)  (paper Eq. 15); k_e = (dx/dF)**-1 (Eq. 16).
Units: mm, N, MPa.  Guards: F_k(x <= 0) = 0 (a slack chain carries no
compression; x below X_TINY mm, where F_k underflows, counts as 0);
x(F < 0) = NaN; NaN in gives NaN out.

The inverse solves c_lin*u**3 + c_hertz*u**2 = x for u = F**(1/3): a start
value within ~10 % (a bit-level cube-root estimate in the blend of the two
one-term roots), two Halley steps (cubic convergence: 1e-1 -> 1e-3 ->
1e-9) and one Newton step (quadratic: 1e-9 -> round-off), which is cheaper
than a third Halley step and as accurate.  No data-dependent loop or
branch, and the numpy error model, so that numba vectorises the array loops.
\"\"\"
import math

import numpy as np
from numba import njit, prange, types
from numba.extending import intrinsic

VARIANT = "{name}"
SOURCE_HASH = "{hash}"
SYMPY_VERSION = "{sympy}"
CONTACT = "{contact}"
SHEAR_FACTOR = {shear}
X_TINY = 1e-290
_CBRT_MAGIC = 0x2A9F7893782DA1CE  # bits of 2**(1023*2/3 - 1023)..., the classic cube-root bias
_FASTMATH = {{"contract", "arcp", "nsz"}}


@intrinsic
def _bits(typingctx, v):
    \"\"\"The IEEE-754 bit pattern of a float64, as int64.\"\"\"
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(types.int64))
    return types.int64(types.float64), codegen


@intrinsic
def _from_bits(typingctx, v):
    \"\"\"The float64 with a given int64 bit pattern.\"\"\"
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(types.float64))
    return types.float64(types.int64), codegen


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def _cbrt_estimate(y):
    \"\"\"y**(1/3) within ~3.5 % for y > 0 (exponent / 3 on the bit pattern).\"\"\"
    return _from_bits(np.int64(_bits(y) * 0.3333333333333333) + _CBRT_MAGIC)


@njit(cache=True)
def coefficients(d, pitch, width, n, E, nu):
    \"\"\"(c_lin [mm/N], c_hertz [mm/N**(2/3)]) of a chain: d, pitch, width mm; n links; E MPa; nu.\"\"\"
    if not (d > 0.0 and width > 0.0 and pitch > width and n >= 1.0 and E > 0.0 and 0.0 < nu < 0.5):
        return math.nan, math.nan
{coeff_body}
    return c_lin, c_hertz


@njit(cache=True)
def displacement(F, c_lin, c_hertz):
    \"\"\"Chain elongation x [mm] at tension F [N] (Eq. 15).\"\"\"
    if F != F or F < 0.0:
        return math.nan
    u = np.cbrt(F)
    return {disp}


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def root_u(x, c_lin, c_hertz):
    \"\"\"u = F_k**(1/3) [N**(1/3)] at elongation x > X_TINY [mm]: positive root of c_lin*u**3 + c_hertz*u**2 = x.\"\"\"
    u = {start}
    for _ in range(2):
        P = {P}
        dP = {dP}
        d2P = {d2P}
        u = u - 2.0 * P * dP / (2.0 * dP * dP - P * d2P)
    P = {P}
    dP = {dP}
    return u - P / dP


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def force(x, c_lin, c_hertz):
    \"\"\"Tension F_k [N] at elongation x [mm] (inverse of Eq. 15); 0 for x <= 0, NaN for NaN.\"\"\"
    xs = x if x > X_TINY else 1.0
    u = root_u(xs, c_lin, c_hertz)
    F = u * u * u
    return F if x > X_TINY else (0.0 if x <= X_TINY else x)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def stiffness(x, c_lin, c_hertz):
    \"\"\"Tangent stiffness k_e [N/mm] at elongation x [mm] (Eq. 16); 0 for x < 0 (slack), NaN for NaN.\"\"\"
    xs = x if x > X_TINY else 1.0
    u = root_u(xs, c_lin, c_hertz)
    k = {stiff}
    k0 = 0.0 if (x < 0.0 or c_hertz > 0.0) else 1.0 / c_lin
    return k if x > X_TINY else (k0 if x <= X_TINY else x)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def damping_residual(F, x, xddot, mass_kg, c_lin, c_hertz):
    \"\"\"F_c = F - m*xddot*1e-3 - F_k(x) [N] (Eq. 17, 20): F N, x mm, xddot mm/s**2, m kg.\"\"\"
    return F - mass_kg * xddot * 1e-3 - force(x, c_lin, c_hertz)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy")
def force_array(x, c_lin, c_hertz):
    \"\"\"force() over a 1-D float64 array [mm] -> [N].\"\"\"
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = force(x[i], c_lin, c_hertz)
    return out


@njit(cache=True)
def displacement_array(F, c_lin, c_hertz):
    \"\"\"displacement() over a 1-D float64 array [N] -> [mm].\"\"\"
    out = np.empty(F.shape[0])
    for i in range(F.shape[0]):
        out[i] = displacement(F[i], c_lin, c_hertz)
    return out


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy")
def stiffness_array(x, c_lin, c_hertz):
    \"\"\"stiffness() over a 1-D float64 array [mm] -> [N/mm].\"\"\"
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = stiffness(x[i], c_lin, c_hertz)
    return out


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy")
def damping_residual_array(F, x, xddot, mass_kg, c_lin, c_hertz):
    \"\"\"damping_residual() over 1-D float64 arrays -> [N].\"\"\"
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = damping_residual(F[i], x[i], xddot[i], mass_kg, c_lin, c_hertz)
    return out


@njit(cache=True, parallel=True, fastmath=_FASTMATH, error_model="numpy")
def force_parallel(x, c_lin, c_hertz):
    \"\"\"force() over a 1-D float64 array on all cores (prange).\"\"\"
    out = np.empty(x.shape[0])
    for i in prange(x.shape[0]):
        out[i] = force(x[i], c_lin, c_hertz)
    return out


@njit(cache=True, parallel=True, fastmath=_FASTMATH, error_model="numpy")
def stiffness_parallel(x, c_lin, c_hertz):
    \"\"\"stiffness() over a 1-D float64 array on all cores (prange).\"\"\"
    out = np.empty(x.shape[0])
    for i in prange(x.shape[0]):
        out[i] = stiffness(x[i], c_lin, c_hertz)
    return out
'''


class _FastPrinter(_Printer):
    """As :class:`_Printer`, but cube roots by the kernel's bit-level estimate (start values only)."""

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        b, ex = expr.as_base_exp()
        if ex == sp.Rational(2, 3):
            return f"_cbrt_estimate({self._print(b)})**2"
        return super()._print_Pow(expr, rational=rational)


def _start_code() -> str:
    """The start value of :func:`chain.start_value` with (c_lin/x)^(2/3) as one estimated cube root."""
    expr = chain.start_value()
    combined = 1 / sp.sqrt(c_hertz / x + sp.Pow(c_lin / x, sp.Rational(2, 3), evaluate=False))
    assert sp.simplify(expr - combined) == 0
    return _FastPrinter().doprint(combined)


def module_source(a: chain.Assumptions, sympy_version: str | None = None) -> str:
    """Full text of ``generated/stiffness_<a.name>.py``."""
    return _TEMPLATE.format(
        name=a.name,
        description=a.description,
        hash=source_hash(),
        sympy=sympy_version or sp.__version__,
        contact=a.contact,
        shear=repr(float(a.shear_factor)),
        coeff_body=_coefficient_body(a),
        disp=_code(chain.generic_displacement()),
        start=_start_code(),
        P=_code(chain.halley_terms()[0]),
        dP=_code(chain.halley_terms()[1]),
        d2P=_code(chain.halley_terms()[2]),
        stiff=_code(chain.stiffness_in_u()),
    )


_POWER_TEMPLATE = '''\
# GENERATED FILE - DO NOT EDIT.
# Written by `chainid generate` from chainid.derive (the repository's derive/power.py).
# variant: contact_power - chain with a free contact exponent, x = c_lin*F + c_hertz*F**beta
# derivation source hash: {hash}
# generator: SymPy {sympy}
# To change the model, edit derive/ and run `chainid generate`; `chainid generate --check` fails when this is stale.
"""Kernels of a chain with a generalised contact law delta = c_hertz*F**beta (beta = 2/3: Hertz).

Used by the gap diagnosis (effect ``contact_law``).  Units: mm, N.  Guards:
F_k(x <= 0) = 0; x(F < 0) = NaN; NaN in gives NaN out.  The inverse is Newton
in s = ln F (monotone from an upper bound: the residual is convex in s).
"""
import math

import numpy as np
from numba import njit

VARIANT = "contact_power"
SOURCE_HASH = "{hash}"
SYMPY_VERSION = "{sympy}"


@njit(cache=True)
def displacement(F, c_lin, c_hertz, beta):
    """Elongation x [mm] at tension F [N]."""
    if F != F or F < 0.0:
        return math.nan
    if F == 0.0:
        return 0.0
    return {disp}


@njit(cache=True)
def log_force(x, c_lin, c_hertz, beta, s_guess):
    """ln F_k [ln N] at elongation x [mm] (-inf at x <= 0, inf at x = inf, NaN for NaN), Newton in s = ln F
    started at s_guess (NaN: none) or the upper bound, whichever is lower.  From below the root one step lands
    above it (h is convex); every iterate is kept under the bound, so from there it falls monotonically to the
    root, each step shorter than the last.  It stops at a step within the rounding of s and of the residual (a
    few ulp of s plus ~eps/beta), or at a step no shorter than the one before (the rounding, not the root, moves
    it): ln F to a few ulp."""
    if x != x:
        return math.nan
    if x <= 0.0:
        return -math.inf
    if x == math.inf:
        return math.inf
    s_hi = math.log(x / c_lin)
    if c_hertz > 0.0:
        s_hi = min(s_hi, math.log(x / c_hertz) / beta)
    s = s_hi
    if s_guess < s_hi:
        s = s_guess
    tol = 8.9e-16 * (abs(s_hi) + 2.0 / beta)
    last = math.inf
    for _ in range(200):
        F = math.exp(s)
        G = math.exp(beta * s)
        step = {newton}
        s = min(s - step, s_hi)
        if abs(step) <= tol or (abs(step) >= last and abs(step) <= 1e3 * tol):
            break
        last = abs(step)
    return s


@njit(cache=True)
def force(x, c_lin, c_hertz, beta):
    """Tension F_k [N] at elongation x [mm]."""
    return math.exp(log_force(x, c_lin, c_hertz, beta, math.nan))


@njit(cache=True)
def stiffness(x, c_lin, c_hertz, beta):
    """Tangent stiffness k_e [N/mm] at elongation x [mm]; 0 for x < 0."""
    if x != x:
        return math.nan
    if x < 0.0:
        return 0.0
    if x == 0.0:
        if c_hertz > 0.0 and beta < 1.0:
            return 0.0
        if c_hertz > 0.0 and beta == 1.0:
            return 1.0 / (c_lin + c_hertz)
        return 1.0 / c_lin
    F = force(x, c_lin, c_hertz, beta)
    return {stiff}


@njit(cache=True)
def force_array(x, c_lin, c_hertz, beta):
    """force() over a 1-D float64 array [mm] -> [N]; each sample's Newton starts at the last finite ln F (a
    record's next sample is close)."""
    out = np.empty(x.shape[0])
    s_last = math.nan
    for i in range(x.shape[0]):
        s = log_force(x[i], c_lin, c_hertz, beta, s_last)
        out[i] = math.exp(s)
        if math.isfinite(s):
            s_last = s
    return out


@njit(cache=True)
def stiffness_array(x, c_lin, c_hertz, beta):
    """stiffness() over a 1-D float64 array [mm] -> [N/mm]."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = stiffness(x[i], c_lin, c_hertz, beta)
    return out


@njit(cache=True)
def displacement_array(F, c_lin, c_hertz, beta):
    """displacement() over a 1-D float64 array [N] -> [mm]."""
    out = np.empty(F.shape[0])
    for i in range(F.shape[0]):
        out[i] = displacement(F[i], c_lin, c_hertz, beta)
    return out
'''


def power_module_source(sympy_version: str | None = None) -> str:
    """Full text of ``generated/contact_power.py`` (derive/power.py)."""
    return _POWER_TEMPLATE.format(
        hash=source_hash(),
        sympy=sympy_version or sp.__version__,
        disp=_code(power.displacement()),
        newton=_code(power.newton_update_log()),
        stiff=_code(power.stiffness()),
    )


def _init_source() -> str:
    names = sorted(chain.VARIANTS)
    return (
        "# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.\n"
        f"# derivation source hash: {source_hash()}\n"
        '"""Generated numba kernels, one module per model variant (see derive/)."""\n\n'
        f"VARIANTS = {tuple(names)!r}\n"
    )


class GenerateResult(dict):
    """Mapping file name -> "written" | "unchanged" | "stale" | "missing"."""


def expected_files() -> dict[str, str]:
    """File name -> expected text of every generated file."""
    files = {"__init__.py": _init_source(), "contact_power.py": power_module_source()}
    for name, a in sorted(chain.VARIANTS.items()):
        files[f"stiffness_{name}.py"] = module_source(a)
    return files


def generate(out_dir: Path, check: bool = False) -> GenerateResult:
    """Write (or, with ``check``, compare) every generated file in ``out_dir``.

    Raises
    ------
    RuntimeError
        If the running SymPy is not :data:`REQUIRED_SYMPY` (CSE output differs
        between versions, so the files would not be byte-for-byte reproducible).
    """
    if sp.__version__ != REQUIRED_SYMPY:
        raise RuntimeError(
            f"SymPy version mismatch: generated/ is printed with SymPy {REQUIRED_SYMPY}, this environment has "
            f"SymPy {sp.__version__}; install sympy=={REQUIRED_SYMPY} (pip install 'sympy=={REQUIRED_SYMPY}')"
        )
    out_dir = Path(out_dir)
    res = GenerateResult()
    for fname, text in expected_files().items():
        p = out_dir / fname
        old = p.read_text(encoding="utf-8") if p.exists() else None
        if check:
            res[fname] = "missing" if old is None else ("unchanged" if old == text else "stale")
        else:
            if old != text:
                out_dir.mkdir(parents=True, exist_ok=True)
                p.write_text(text, encoding="utf-8", newline="\n")
                res[fname] = "written"
            else:
                res[fname] = "unchanged"
    return res

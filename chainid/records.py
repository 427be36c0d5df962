"""Force–displacement records: CSV in/out, validation, harmonic estimation, steady cycles.

File format (long CSV, architecture contract)::

    test,t,x,F
    T1,0.000,0.0000,12.3
    ...

``test`` is an id string, ``t`` time [s], ``x`` elongation [mm], ``F`` tension [N].
Any number of tests; the rows of one test are contiguous; ``t`` is strictly
increasing within a test.  Extra columns are ignored.

Each test is a displacement-controlled harmonic test (paper Eq. 18, 25)::

    x(t) = x0 + A sin(omega t + theta)      after an optional ramp

``omega`` [rad/s], ``x0`` [mm] and ``A`` [mm] are estimated from x(t) by the
FFT peak refined by nonlinear least squares (:func:`estimate_harmonic`); the
phase ``theta`` [rad] is fitted too (the paper takes ``theta = 0``).  Whole
steady-state cycles are selected automatically (:func:`select_steady`): the ramp
and the first oscillation cycle are dropped, and only the contiguous whole
cycles whose amplitude and mean stay within a few per cent of the plateau are
kept, so records whose amplitude tapers in and out are handled.

Input files are never modified; :func:`write_records` refuses to overwrite an
existing file unless ``overwrite=True``.
"""
from __future__ import annotations

import csv
import math
from array import array
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Iterator

import numpy as np
from scipy.optimize import least_squares

__all__ = [
    "Record",
    "HarmonicEstimate",
    "SteadyWindow",
    "read_records",
    "write_records",
    "validate_record",
    "estimate_harmonic",
    "select_steady",
    "analyse_record",
    "read_side_file",
    "write_side_file",
    "REQUIRED_COLUMNS",
]

REQUIRED_COLUMNS = ("test", "t", "x", "F")


# ----------------------------------------------------------------------------
# Data classes
# ----------------------------------------------------------------------------
@dataclass
class Record:
    """One test: samples of time, elongation and force.

    Attributes
    ----------
    test : str
        Test id.
    t : ndarray
        Time [s], strictly increasing.
    x : ndarray
        Elongation [mm].
    F : ndarray
        Axial force (tension positive) [N].
    estimate : HarmonicEstimate or None
        Harmonic estimate and steady window found when the record was
        validated by :func:`read_records` (reused by :func:`analyse_record`).
    """

    test: str
    t: np.ndarray
    x: np.ndarray
    F: np.ndarray
    estimate: "HarmonicEstimate | None" = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.test = str(self.test)
        self.t = np.asarray(self.t, dtype=float)
        self.x = np.asarray(self.x, dtype=float)
        self.F = np.asarray(self.F, dtype=float)
        if not (self.t.ndim == self.x.ndim == self.F.ndim == 1):
            raise ValueError(f"test {self.test!r}: t, x and F must be one-dimensional arrays")
        if not (self.t.size == self.x.size == self.F.size):
            raise ValueError(
                f"test {self.test!r}: t, x and F must have the same length "
                f"(got {self.t.size}, {self.x.size}, {self.F.size})"
            )

    def window(self, t_start: float, t_end: float) -> "Record":
        """The samples with ``t_start <= t < t_end`` [s] as a new :class:`Record`."""
        m = (self.t >= t_start) & (self.t < t_end)
        return Record(self.test, self.t[m], self.x[m], self.F[m])


@dataclass
class SteadyWindow:
    """The steady-state whole cycles kept for identification.

    Attributes
    ----------
    t_start, t_end : float
        Kept time window [s]; it spans exactly ``len(cycles_kept)`` periods.
    cycles_kept : list of int
        Indices of the kept cycles (0 = first whole cycle in the record).
    n_cycles_total : int
        Whole cycles found in the record.
    cycle_amplitudes : list of float
        Amplitude of every whole cycle [mm] (fixed-frequency fit per cycle).
    cycle_means : list of float
        Mean of every whole cycle [mm].
    plateau_A : float
        Plateau amplitude [mm] the cycles were compared with.
    rel_tol : float
        Relative tolerance used for "within the plateau".
    """

    t_start: float
    t_end: float
    cycles_kept: list[int]
    n_cycles_total: int
    cycle_amplitudes: list[float]
    cycle_means: list[float]
    plateau_A: float
    rel_tol: float

    @property
    def n_cycles(self) -> int:
        """Number of kept whole cycles."""
        return len(self.cycles_kept)

    def describe(self) -> str:
        """One-line human-readable description of the choice."""
        if not self.cycles_kept:
            return "no steady cycles"
        return (
            f"cycles {self.cycles_kept[0]}-{self.cycles_kept[-1]} of {self.n_cycles_total} "
            f"(t = {self.t_start:.4g}..{self.t_end:.4g} s)"
        )

    def to_dict(self) -> dict:
        return {
            "t_start": self.t_start,
            "t_end": self.t_end,
            "cycles_kept": list(self.cycles_kept),
            "n_cycles_total": self.n_cycles_total,
            "plateau_A": self.plateau_A,
        }


@dataclass
class HarmonicEstimate:
    """Harmonic model of the displacement, x = x0 + A sin(omega t + theta) (Eq. 18).

    Attributes
    ----------
    omega : float
        Angular frequency [rad/s].
    x0 : float
        Mean elongation [mm].
    A : float
        Amplitude [mm], > 0.
    theta : float
        Phase [rad] in (-pi, pi]; the paper's Eq. 18 has theta = 0.
    noise : float
        RMS residual of x about the harmonic over the kept window [mm].
    window : SteadyWindow or None
        The steady window used (None if estimated over the whole record).
    source : str
        "estimated" or "side file".
    """

    omega: float
    x0: float
    A: float
    theta: float
    noise: float
    window: SteadyWindow | None = None
    source: str = "estimated"

    def phase(self, t: np.ndarray) -> np.ndarray:
        """psi = omega t + theta [rad]."""
        return self.omega * np.asarray(t, dtype=float) + self.theta

    def x(self, t: np.ndarray) -> np.ndarray:
        """Harmonic displacement [mm]."""
        return self.x0 + self.A * np.sin(self.phase(t))

    def xdot(self, t: np.ndarray) -> np.ndarray:
        """Velocity [mm/s]."""
        return self.omega * self.A * np.cos(self.phase(t))

    def xddot(self, t: np.ndarray) -> np.ndarray:
        """Acceleration [mm/s^2]."""
        return -self.omega**2 * self.A * np.sin(self.phase(t))

    @property
    def period(self) -> float:
        """Period 2 pi / omega [s]."""
        return 2.0 * math.pi / self.omega


# ----------------------------------------------------------------------------
# CSV in / out
# ----------------------------------------------------------------------------
def _parse_float(text: str, *, path: str, line: int, test: str, column: str) -> float:
    try:
        v = float(text)
    except (TypeError, ValueError):
        raise ValueError(
            f"{path}, line {line}: test {test!r}: column {column!r} value {text!r} is not a number"
        ) from None
    if math.isnan(v):
        raise ValueError(f"{path}, line {line}: test {test!r}: column {column!r} is NaN")
    if math.isinf(v):
        raise ValueError(f"{path}, line {line}: test {test!r}: column {column!r} is infinite ({text!r})")
    return v


#: Rows parsed per chunk by :func:`read_records` (bounds the temporary memory).
_CHUNK_ROWS = 65536


def _iter_rows(p: Path, spath: str) -> Iterator[tuple[int, list[str]]]:
    """Yield ``(line number, fields)`` of a CSV file; UTF-8 (a BOM is accepted).

    Undecodable bytes or NUL characters (a binary or garbage file) raise a
    ValueError naming the file and the line.
    """
    line_no = 0
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            reader = csv.reader(fh)
            for row in reader:
                line_no = reader.line_num
                yield line_no, row
    except UnicodeDecodeError as exc:
        raise ValueError(
            f"{spath}: not a UTF-8 text CSV file (undecodable byte at file offset {exc.start} near line "
            f"{line_no + 1}); expected a CSV with header {','.join(REQUIRED_COLUMNS)}"
        ) from None
    except csv.Error as exc:
        raise ValueError(
            f"{spath}, line {line_no + 1}: not a readable CSV file ({exc}); expected a CSV with header "
            f"{','.join(REQUIRED_COLUMNS)}"
        ) from None


def read_records(
    path: str | Path,
    *,
    validate: bool = True,
    allow_compression: bool = False,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
) -> list[Record]:
    """Read a long-format CSV ``test,t,x,F`` into a list of :class:`Record`.

    The file is read row by row into preallocated float arrays (8 bytes per
    value, 24 bytes per row), so the peak memory stays below the file size
    plus the arrays themselves (measured in ``benchmarks/records_bench.py``).

    Parameters
    ----------
    path : str or Path
        CSV file (UTF-8, a byte-order mark is accepted); header must contain the
        columns ``test``, ``t`` [s], ``x`` [mm], ``F`` [N].  Every row must have
        as many fields as the header (a decimal comma ``261,004688`` in an
        unquoted cell is an error, never read as 261).  The file is only read,
        never modified.
    validate : bool
        Run :func:`validate_record` on every test (default True).
    allow_compression : bool
        Accept negative (compressive) forces.  False for chain data (a chain
        cannot push); True for parts whose force changes sign (e.g. a friction
        damper identified with ``--model linear``).
    min_cycles : float
        Minimum number of whole oscillation cycles per test (default 2).
    min_snr : float
        Minimum ratio amplitude / RMS noise of x (default 3).

    Returns
    -------
    list of Record
        In file order.

    Raises
    ------
    ValueError
        Naming the file, line and test: missing columns, a row whose field
        count differs from the header's, non-numeric value, NaN, non-contiguous
        test rows, a binary/non-UTF-8 file, and every :func:`validate_record`
        problem.
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"records file {str(p)!r} does not exist")
    spath = str(p)
    rows = _iter_rows(p, spath)
    header: list[str] | None = None
    for _, row in rows:
        if row and any(c.strip() for c in row):
            header = [h.strip() for h in row]
            break
    if header is None:
        raise ValueError(f"{spath}: file is empty; expected header {','.join(REQUIRED_COLUMNS)}")
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise ValueError(
            f"{spath}: missing column(s) {missing}; header is {header}, "
            f"required columns are {list(REQUIRED_COLUMNS)}"
        )
    nf = len(header)
    it_, ix_, iF_ = (header.index(c) for c in ("t", "x", "F"))
    itest = header.index("test")
    # per test: growable float64 buffers (array.array: amortised O(1) append, ~8 bytes/value)
    cols: dict[str, tuple[array, array, array]] = {}
    order: list[str] = []
    last: str | None = None
    cur: tuple[array, array, array] | None = None
    for line_no, row in rows:
        if len(row) != nf:
            if not row or all(not c.strip() for c in row):
                continue
            raise ValueError(
                f"{spath}, line {line_no}: {len(row)} fields but the header has {nf} "
                f"({','.join(header)}); a decimal comma or a stray separator? "
                f"(row starts {','.join(row[:nf + 1])[:80]!r})"
            )
        test = row[itest].strip()
        if test != last:
            if test == "":
                if all(not c.strip() for c in row):
                    continue
                raise ValueError(f"{spath}, line {line_no}: empty test id")
            if test in cols:
                raise ValueError(
                    f"{spath}, line {line_no}: test {test!r}: rows are not contiguous "
                    f"(the test appears again after other tests)"
                )
            cur = (array("d"), array("d"), array("d"))
            cols[test] = cur
            order.append(test)
            last = test
        assert cur is not None
        for buf, j, c in ((cur[0], it_, "t"), (cur[1], ix_, "x"), (cur[2], iF_, "F")):
            cell = row[j]
            try:
                v = float(cell)
            except ValueError:
                v = _parse_float(cell.strip(), path=spath, line=line_no, test=test, column=c)
            if not math.isfinite(v):
                _parse_float(cell.strip(), path=spath, line=line_no, test=test, column=c)
            buf.append(v)
    if not order:
        raise ValueError(f"{spath}: no data rows")
    records = []
    for test in order:
        bt, bx, bF = cols.pop(test)
        rec = Record(test, np.frombuffer(bt, dtype=float), np.frombuffer(bx, dtype=float),
                     np.frombuffer(bF, dtype=float))
        if validate:
            try:
                rec.estimate = validate_record(
                    rec, allow_compression=allow_compression, min_cycles=min_cycles, min_snr=min_snr
                )
            except ValueError as exc:
                raise ValueError(f"{spath}: {exc}") from None
        records.append(rec)
    return records


def write_records(path: str | Path, records: Iterable[Record], overwrite: bool = False) -> Path:
    """Write records as long-format CSV ``test,t,x,F``.

    Parameters
    ----------
    path : str or Path
        Output file.
    records : iterable of Record
        Tests to write (t [s], x [mm], F [N]).
    overwrite : bool
        Replace an existing file.  Default False: an existing file is an error.

    Returns
    -------
    Path
        The written path.

    Raises
    ------
    ValueError
        If ``path`` exists and ``overwrite`` is False (naming the path), or if a
        test id contains a comma or newline.
    """
    p = Path(path)
    if p.exists() and not overwrite:
        raise ValueError(f"{str(p)!r} already exists; refusing to overwrite it (use overwrite=True / --force)")
    records = list(records)
    for r in records:
        if any(ch in r.test for ch in ",\n\r\""):
            raise ValueError(f"test id {r.test!r} must not contain commas, quotes or newlines")
    with p.open("w", newline="") as fh:
        fh.write("test,t,x,F\n")
        for r in records:
            for ti, xi, Fi in zip(r.t, r.x, r.F):
                fh.write(f"{r.test},{ti:.9g},{xi:.9g},{Fi:.9g}\n")
    return p


# ----------------------------------------------------------------------------
# Harmonic estimation and steady-cycle selection
# ----------------------------------------------------------------------------
def _fft_peak_omega(t: np.ndarray, x: np.ndarray) -> float:
    """Angular frequency [rad/s] of the largest FFT peak of x(t) (linear trend removed).

    Non-uniform sampling is handled by interpolating onto a uniform grid first.
    The peak is refined by parabolic interpolation of the log-magnitude.
    """
    n = t.size
    tu = np.linspace(t[0], t[-1], n)
    xu = np.interp(tu, t, x)
    # remove a linear trend (ramp) and taper with a Hann window
    coef = np.polyfit(tu - tu[0], xu, 1)
    xu = xu - np.polyval(coef, tu - tu[0])
    xu = xu * np.hanning(n)
    nfft = 1 << int(math.ceil(math.log2(max((4 if n <= 65536 else 2) * n, 1024))))
    spec = np.abs(np.fft.rfft(xu, nfft))
    freqs = np.fft.rfftfreq(nfft, d=(tu[1] - tu[0]))
    # ignore the lowest bins: at least ~1.5 cycles in the record
    fmin = 1.5 / (tu[-1] - tu[0])
    spec[freqs < fmin] = 0.0
    k = int(np.argmax(spec))
    if 0 < k < spec.size - 1 and spec[k - 1] > 0 and spec[k + 1] > 0:
        a, b, c = np.log(spec[k - 1]), np.log(spec[k]), np.log(spec[k + 1])
        den = a - 2 * b + c
        delta = 0.5 * (a - c) / den if den != 0 else 0.0
    else:
        delta = 0.0
    return 2.0 * math.pi * (freqs[k] + delta * (freqs[1] - freqs[0]))


def _linear_harmonic(t: np.ndarray, x: np.ndarray, omega: float) -> tuple[float, float, float]:
    """Least-squares [1, sin, cos] fit at fixed omega; returns (x0, a, b)."""
    X = np.column_stack([np.ones_like(t), np.sin(omega * t), np.cos(omega * t)])
    sol, *_ = np.linalg.lstsq(X, x, rcond=None)
    return float(sol[0]), float(sol[1]), float(sol[2])


def _nls_harmonic(t: np.ndarray, x: np.ndarray, omega0: float) -> tuple[float, float, float, float, float]:
    """Nonlinear LS refinement of x = x0 + a sin(omega t') + b cos(omega t'), t' = t - mean(t).

    Returns (omega, x0, A, theta, rms) with theta referred to the absolute time t.
    """
    tc = float(np.mean(t))
    tt = t - tc
    x0, a, b = _linear_harmonic(tt, x, omega0)

    def resid(p: np.ndarray) -> np.ndarray:
        w, c0, aa, bb = p
        return c0 + aa * np.sin(w * tt) + bb * np.cos(w * tt) - x

    def jac(p: np.ndarray) -> np.ndarray:
        w, _, aa, bb = p
        s, c = np.sin(w * tt), np.cos(w * tt)
        return np.column_stack([tt * (aa * c - bb * s), np.ones_like(tt), s, c])

    sol = least_squares(resid, np.array([omega0, x0, a, b]), jac=jac, method="lm", x_scale="jac")
    w, c0, aa, bb = sol.x
    if w < 0:  # sin(-wt) = -sin(wt): normalise to w > 0
        w, aa = -w, -aa
    A = math.hypot(aa, bb)
    theta_c = math.atan2(bb, aa)  # phase at t' = 0
    theta = theta_c - w * tc
    theta = math.atan2(math.sin(theta), math.cos(theta))
    rms = float(np.sqrt(np.mean(resid(np.array([w, c0, aa, bb])) ** 2)))
    return float(w), float(c0), float(A), float(theta), rms


def _cycle_stats(
    t: np.ndarray, x: np.ndarray, omega: float, theta: float
) -> tuple[list[float], np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per whole cycle: fit x = c0 + slope (t - tc) + a sin psi + b cos psi at fixed omega.

    Cycle k spans ``omega t + theta`` in [2 pi k, 2 pi (k+1)); all cycles are
    fitted at once (per-cycle normal equations accumulated with ``np.bincount``
    and solved as one batch), so the cost is O(N) in the number of samples.

    Returns
    -------
    bounds : list of float
        Cycle boundaries [s] (n + 1 values).
    amps, means, drifts, resid_sd : ndarray
        Amplitude [mm], mean [mm], drift per period [mm] and residual SD [mm];
        0, NaN, inf, NaN for an incomplete cycle (< 6 samples or a gap).
    n_in : ndarray of int
        Samples per cycle.
    """
    T = 2 * math.pi / omega
    psi0 = omega * t[0] + theta
    psi1 = omega * t[-1] + theta
    k0 = math.ceil(psi0 / (2 * math.pi) - 1e-9)
    dt_med = float(np.median(np.diff(t))) if t.size > 1 else T
    # last boundary: a cycle is whole if its last sample (one step before the boundary) is present
    k1 = math.floor((psi1 + 1.5 * omega * dt_med) / (2 * math.pi) + 1e-9)
    ks = np.arange(k0, k1 + 1, dtype=float)
    b_arr = (2 * math.pi * ks - theta) / omega
    bounds = [float(v) for v in b_arr]
    n = max(len(bounds) - 1, 0)
    if n == 0:
        e = np.zeros(0)
        return bounds, e, e, e, e, np.zeros(0, dtype=int)
    idx = np.searchsorted(t, b_arr - 1e-9 * T, side="left")
    lo, hi = idx[:-1], idx[1:]
    n_in = (hi - lo).astype(int)
    span = np.where(n_in > 0, t[np.maximum(hi - 1, 0)] - t[np.minimum(lo, t.size - 1)], -np.inf)
    valid = (n_in >= 6) & (span >= T - 2.5 * dt_med)
    cyc = np.repeat(np.arange(n), n_in)
    sl = slice(int(lo[0]), int(hi[-1]))
    ts, xs = t[sl], x[sl]
    tc = 0.5 * (b_arr[:-1] + b_arr[1:])
    u = (ts - tc[cyc]) / T  # in [-0.5, 0.5): well scaled against sin/cos
    ph = omega * ts + theta
    s, c = np.sin(ph), np.cos(ph)
    feats = (np.ones_like(u), u, s, c)
    G = np.empty((n, 4, 4))
    r = np.empty((n, 4))
    for i in range(4):
        r[:, i] = np.bincount(cyc, feats[i] * xs, minlength=n)
        for j in range(i, 4):
            g = np.bincount(cyc, feats[i] * feats[j], minlength=n)
            G[:, i, j] = g
            G[:, j, i] = g
    G[~valid] = np.eye(4)
    r[~valid] = 0.0
    beta = np.linalg.solve(G, r[:, :, None])[:, :, 0]
    bc = beta[cyc]
    res = xs - (bc[:, 0] + bc[:, 1] * u + bc[:, 2] * s + bc[:, 3] * c)
    rss = np.bincount(cyc, res * res, minlength=n)
    nf = np.maximum(n_in, 1).astype(float)
    amps = np.where(valid, np.hypot(beta[:, 2], beta[:, 3]), 0.0)
    means = np.where(valid, beta[:, 0], np.nan)
    drifts = np.where(valid, np.abs(beta[:, 1]), np.inf)  # slope [mm/s] * T = coefficient of u
    resid_sd = np.where(valid, np.sqrt(rss / nf), np.nan)
    return bounds, amps, means, drifts, resid_sd, n_in


def _count_within(amps: np.ndarray, rel_tol: float) -> np.ndarray:
    """For each amplitude a > 0: how many amplitudes lie within ``rel_tol * a`` of it (O(n log n))."""
    srt = np.sort(amps)
    lo = np.searchsorted(srt, amps - rel_tol * amps, side="left")
    hi = np.searchsorted(srt, amps + rel_tol * amps, side="right")
    return np.where(amps > 0, hi - lo, 0)


def select_steady(
    t: np.ndarray,
    x: np.ndarray,
    omega: float,
    theta: float,
    *,
    rel_tol: float = 0.03,
    drop_first: bool = True,
    drift_tol: float | None = None,
) -> SteadyWindow:
    """Select the steady-state whole cycles of a harmonic displacement record.

    Cycle k spans ``omega t + theta`` in [2 pi k, 2 pi (k+1)).  For every whole
    cycle inside the record, mean and amplitude are fitted at fixed ``omega``.
    The plateau amplitude is the median amplitude of the largest group of
    cycles that agree within ``rel_tol``; a cycle is steady when its amplitude is within
    ``rel_tol`` of the plateau, its mean within ``rel_tol * plateau`` of the
    median steady mean and its drift per period below ``rel_tol * plateau``; each
    tolerance is widened by four standard errors of the per-cycle estimate, from
    the median per-cycle residual (so measurement noise does not break the run).  The longest contiguous run of steady cycles is kept and,
    if ``drop_first``, its first cycle is dropped (transient after the ramp).

    Parameters
    ----------
    t : ndarray
        Time [s].
    x : ndarray
        Elongation [mm].
    omega : float
        Angular frequency [rad/s], > 0.
    theta : float
        Phase of x = x0 + A sin(omega t + theta) [rad].
    rel_tol : float
        Relative tolerance on amplitude and mean (default 0.03 = 3 %).
    drop_first : bool
        Drop the first cycle of the steady run (default True).
    drift_tol : float, optional
        Relative tolerance on the drift per period (default ``rel_tol``).

    Returns
    -------
    SteadyWindow
        ``cycles_kept`` may be empty if there are no steady cycles.
    """
    if not omega > 0:
        raise ValueError(f"omega = {omega!r} rad/s is invalid: must be > 0")
    T = 2 * math.pi / omega
    bounds, amps_a, means_a, drifts_a, sds, nn_i = _cycle_stats(t, x, omega, theta)
    n = amps_a.size
    if n == 0:
        return SteadyWindow(float(t[0]), float(t[0]), [], 0, [], [], 0.0, rel_tol)
    amps = amps_a.tolist()
    means = means_a.tolist()
    # measurement-noise allowance: 4 standard errors of the per-cycle estimates, from the
    # median residual over the cycles (robust to the few transient cycles)
    s_med = float(np.nanmedian(sds)) if np.any(np.isfinite(sds)) else 0.0
    nn = np.maximum(nn_i.astype(float), 1.0)
    se_amp = 4.0 * s_med * np.sqrt(2.0 / nn)
    se_mean = 4.0 * s_med / np.sqrt(nn)
    se_drift = 4.0 * s_med * np.sqrt(12.0 / nn)
    # plateau: the amplitude most cycles agree with (ties -> the larger one)
    counts = _count_within(amps_a, rel_tol)
    if counts.max() > 0:
        best_i = max(range(n), key=lambda i: (counts[i], amps_a[i]))
        near = np.abs(amps_a - amps_a[best_i]) <= rel_tol * amps_a[best_i]
        plateau = float(np.median(amps_a[near]))
    else:
        plateau = 0.0
    ok_amp = (np.abs(amps_a - plateau) <= rel_tol * plateau + se_amp) & (amps_a > 0)
    if ok_amp.any():
        mean_ref = float(np.nanmedian(means_a[ok_amp]))
        ok = (
            ok_amp
            & (np.abs(means_a - mean_ref) <= rel_tol * plateau + se_mean + 1e-12)
            & (drifts_a <= (rel_tol if drift_tol is None else drift_tol) * plateau + se_drift + 1e-12)
        )
    else:
        ok = ok_amp
    # longest contiguous run
    best: tuple[int, int] = (0, 0)
    i = 0
    while i < n:
        if ok[i]:
            j = i
            while j + 1 < n and ok[j + 1]:
                j += 1
            if (j - i + 1) > (best[1] - best[0]):
                best = (i, j + 1)
            i = j + 1
        else:
            i += 1
    run = list(range(best[0], best[1]))
    # the first oscillation cycle is a transient: drop it if it is in the run
    if drop_first and run:
        run = run[1:]
    if run:
        ts, te = bounds[run[0]], bounds[run[-1] + 1]
    else:
        ts = te = float(t[0])
    return SteadyWindow(float(ts), float(te), run, n, [float(a) for a in amps], [float(m) for m in means], plateau, rel_tol)


#: Candidate search of :func:`estimate_harmonic` on long records: at least this many
#: samples per period and in total are kept when decimating (records shorter than
#: ``2 * _SEARCH_N`` samples are never decimated).
_SEARCH_SPC = 64
_SEARCH_N = 50_000


def _search_stride(t: np.ndarray, omega: float) -> int:
    """Decimation step for the candidate search (1 = every sample)."""
    n = t.size
    if n < 2 * _SEARCH_N:
        return 1
    dt = (t[-1] - t[0]) / (n - 1)
    spc = 2 * math.pi / (omega * dt)
    return max(1, min(n // _SEARCH_N, int(spc // _SEARCH_SPC)))


def estimate_harmonic(
    t: np.ndarray,
    x: np.ndarray,
    *,
    rel_tol: float = 0.03,
    drop_first: bool = True,
    test: str = "?",
) -> HarmonicEstimate:
    """Estimate omega, x0, A (Eq. 18) and the steady window of a displacement record.

    1. FFT peak of the velocity (``numpy.gradient`` of x; a ramp becomes a
       near-constant and does not mask the oscillation), Hann window, zero
       padding and parabolic peak interpolation; over the whole record and its
       last half and third (distinct peaks are all tried).
    2. Nonlinear least-squares refinement of x = x0 + A sin(omega t + theta)
       (``scipy.optimize.least_squares``) on candidate segments: provisional
       whole cycles at that frequency (lenient :func:`select_steady`), the
       second half, the last third, the last fifth and the whole record; the
       candidate whose steady window has the most cycles wins (ties: smallest
       residual), then one more refinement on that window.
    3. Final steady window aligned with the fitted phase, first cycle dropped,
       and a linear least-squares fit of x0, A, theta on it.

    Parameters
    ----------
    t : ndarray
        Time [s], strictly increasing.
    x : ndarray
        Elongation [mm].
    rel_tol : float
        Steady-cycle tolerance (see :func:`select_steady`).
    drop_first : bool
        Drop the first steady cycle.
    test : str
        Test id, used in error messages.

    Returns
    -------
    HarmonicEstimate
        omega [rad/s], x0 [mm], A [mm], theta [rad], noise [mm] and window.

    Raises
    ------
    ValueError
        If no oscillation is found.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.size < 16:
        raise ValueError(f"test {test!r}: only {t.size} samples; need at least 16")
    # 1. FFT peak of the velocity: a ramp becomes a (near) constant, the oscillation
    #    dominates -- over the whole record and over its last half and third (where a
    #    slow ramp that outweighs a small oscillation has ended)
    span = t[-1] - t[0]
    v = np.gradient(x, t)
    w0s: list[float] = []
    for f in (0.0, 0.5, 0.67):
        seg = t >= t[0] + f * span
        if seg.sum() < 16:
            continue
        w0 = _fft_peak_omega(t[seg], v[seg])
        if w0 > 0 and math.isfinite(w0) and all(abs(w0 - u) > 0.01 * u for u in w0s):
            w0s.append(w0)
    if not w0s:
        raise ValueError(f"test {test!r}: no harmonic oscillation found in x(t)")
    # long records: the candidate search (step 2) runs on every k-th sample, keeping
    # >= _SEARCH_SPC samples per period and >= _SEARCH_N samples, so its cost does not grow
    # with N; the final window, refinement and fit (step 3) use every sample
    t_full, x_full = t, x
    stride = _search_stride(t, min(w0s))
    if stride > 1:
        t, x = t[::stride], x[::stride]
    # 2. NLS refinement on candidate segments (provisional steady cycles at w0, the
    #    second half, the last third and fifth, the whole record); keep the candidate
    #    whose steady window has the most cycles (ties: smallest residual)
    best = None
    for w0 in w0s:
        # (lenient provisional selection: w0 may be off by a fraction of a per cent,
        #  which shows up as drift and amplitude wobble in the per-cycle fits)
        win0 = select_steady(t, x, w0, 0.0, rel_tol=max(rel_tol, 0.1), drop_first=False, drift_tol=math.inf)
        segments = []
        if win0.n_cycles >= 1:
            segments.append((t >= win0.t_start) & (t < win0.t_end))
        segments += [t >= t[0] + f * span for f in (0.5, 0.67, 0.8)] + [np.ones(t.size, dtype=bool)]
        for seg in segments:
            if seg.sum() < 16:
                continue
            try:
                w, x0, A, theta, rms = _nls_harmonic(t[seg], x[seg], w0)
            except (ValueError, np.linalg.LinAlgError):
                continue
            if not (w > 0 and math.isfinite(w)):
                continue
            win_c = select_steady(t, x, w, theta, rel_tol=rel_tol, drop_first=drop_first)
            score = (win_c.n_cycles, -rms)
            if best is None or score > best[0]:
                best = (score, (w, x0, A, theta, rms))
    if best is None:
        raise ValueError(f"test {test!r}: no harmonic oscillation found in x(t)")
    w, x0, A, theta, rms = best[1]
    t, x = t_full, x_full
    win = select_steady(t, x, w, theta, rel_tol=rel_tol, drop_first=drop_first)
    if win.n_cycles >= 1:  # one more refinement on the steady cycles themselves
        i0, i1 = np.searchsorted(t, [win.t_start, win.t_end], side="left")
        w, x0, A, theta, rms = _nls_harmonic(t[i0:i1:stride], x[i0:i1:stride], w)
    # 3. final steady window aligned with the phase, linear fit at the refined omega
    win = select_steady(t, x, w, theta, rel_tol=rel_tol, drop_first=drop_first)
    if win.n_cycles >= 1:
        m = (t >= win.t_start) & (t < win.t_end)
        x0, a, b = _linear_harmonic(t[m], x[m], w)
        A = math.hypot(a, b)
        theta = math.atan2(b, a)
        rms = float(np.sqrt(np.mean((x[m] - x0 - a * np.sin(w * t[m]) - b * np.cos(w * t[m])) ** 2)))
    return HarmonicEstimate(omega=w, x0=x0, A=A, theta=theta, noise=rms, window=win)


def _spanned_cycles(t: np.ndarray, x: np.ndarray) -> tuple[float, float]:
    """Best single-sinusoid fit of x(t) with 0.3..3 periods in the record.

    Returns ``(periods spanned, R²)``; used only to say "less than one whole
    cycle" when the regular estimate finds no oscillation.
    """
    step = max(1, t.size // 4096)
    tt, xx = t[::step], x[::step]
    span = float(tt[-1] - tt[0])
    if tt.size < 8 or span <= 0:
        return 0.0, 0.0
    ss = float(np.sum((xx - xx.mean()) ** 2))
    if ss <= 0:
        return 0.0, 0.0
    best = (0.0, -math.inf)
    u = (tt - tt[0]) / span
    for c in np.arange(0.3, 3.0001, 0.05):
        X = np.column_stack([np.ones_like(u), np.sin(2 * math.pi * c * u), np.cos(2 * math.pi * c * u)])
        sol, *_ = np.linalg.lstsq(X, xx, rcond=None)
        r2 = 1.0 - float(np.sum((xx - X @ sol) ** 2)) / ss
        if r2 > best[1]:
            best = (float(c), r2)
    return best


def _raise_if_under_one_cycle(rec: Record) -> None:
    """Raise "less than one whole cycle" if x(t) spans under one period of its oscillation."""
    c, r2 = _spanned_cycles(rec.t, rec.x)
    if c < 1.0 and r2 > 0.5:
        span = float(rec.t[-1] - rec.t[0])
        raise ValueError(
            f"test {rec.test!r}: less than one whole cycle: x(t) spans about {c:.2g} period(s) of its "
            f"oscillation (period ~{span / c:.4g} s, record {span:.4g} s); at least 2 whole cycles are needed"
        )


def validate_record(
    rec: Record,
    *,
    allow_compression: bool = False,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
    estimate: HarmonicEstimate | None = None,
) -> HarmonicEstimate:
    """Check one record; raise ValueError naming the test and the problem.

    Checks: at least 16 samples; no NaN/inf; t strictly increasing; force never
    compressive (unless ``allow_compression``); at least ``min_cycles`` whole
    oscillation cycles in the record and at least one steady cycle after the
    first is dropped; amplitude at least ``min_snr`` times the RMS noise of x.

    Parameters
    ----------
    rec : Record
        The test (t [s], x [mm], F [N]).
    allow_compression : bool
        Accept F < 0 [N].
    min_cycles : float
        Minimum number of whole cycles (default 2).
    min_snr : float
        Minimum amplitude / RMS noise of x (default 3).
    estimate : HarmonicEstimate, optional
        Use this estimate (e.g. from a side file) instead of estimating.

    Returns
    -------
    HarmonicEstimate
        The estimate used for the checks.
    """
    name = rec.test
    for col, arr in (("t", rec.t), ("x", rec.x), ("F", rec.F)):
        bad = ~np.isfinite(arr)
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(f"test {name!r}: column {col!r} has a NaN/non-finite value at sample {i}")
    if rec.t.size < 16:
        raise ValueError(f"test {name!r}: only {rec.t.size} samples; need at least 16")
    dt = np.diff(rec.t)
    if np.any(dt <= 0):
        i = int(np.argmax(dt <= 0))
        raise ValueError(
            f"test {name!r}: t is not strictly increasing at sample {i + 1} "
            f"(t = {rec.t[i]:.9g} s then {rec.t[i + 1]:.9g} s)"
        )
    if not allow_compression and np.any(rec.F < 0):
        i = int(np.argmin(rec.F))
        raise ValueError(
            f"test {name!r}: force goes compressive (min F = {rec.F[i]:.6g} N at t = {rec.t[i]:.6g} s); "
            f"a chain cannot carry compression. Use allow_compression=True (--allow-compression) "
            f"for parts whose force changes sign"
        )
    try:
        est = estimate if estimate is not None else estimate_harmonic(rec.t, rec.x, test=name)
    except ValueError:
        _raise_if_under_one_cycle(rec)
        raise
    if not (est.A >= min_snr * est.noise and est.A > 0) or est.window is None or est.window.n_cycles < 1:
        _raise_if_under_one_cycle(rec)
    cycles_in_record = (rec.t[-1] - rec.t[0]) * est.omega / (2 * math.pi)
    win = est.window
    # whole steady cycles found, counting the first one that selection drops
    n_whole = (win.n_cycles + 1) if (win is not None and win.n_cycles >= 1) else 0
    if est.A < min_snr * est.noise or est.A <= 0:
        raise ValueError(
            f"test {name!r}: amplitude below the noise: A = {est.A:.4g} mm, RMS noise of x = "
            f"{est.noise:.4g} mm (need A >= {min_snr:g} x noise)"
        )
    if cycles_in_record < min_cycles or win is None or n_whole < min_cycles or win.n_cycles < 1:
        raise ValueError(
            f"test {name!r}: fewer than {min_cycles:g} full cycles of steady oscillation: the record spans "
            f"{cycles_in_record:.3g} periods of {2 * math.pi / est.omega:.4g} s and has {n_whole} contiguous "
            f"whole cycle(s) with amplitude and mean within {100 * (win.rel_tol if win else 0.03):g} % of the "
            f"plateau ({win.n_cycles if win else 0} left after dropping the ramp and the first cycle)"
        )
    return est


# ----------------------------------------------------------------------------
# Side file (omega, x0, A per test)
# ----------------------------------------------------------------------------
def read_side_file(path: str | Path) -> dict[str, tuple[float, float, float]]:
    """Read a side file ``test,omega,x0,A`` (omega rad/s, x0 mm, A mm).

    Returns
    -------
    dict
        test id -> (omega, x0, A).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"side file {str(p)!r} does not exist")
    out: dict[str, tuple[float, float, float]] = {}
    with p.open(newline="") as fh:
        reader = csv.DictReader(fh)
        cols = [c.strip() for c in (reader.fieldnames or [])]
        missing = [c for c in ("test", "omega", "x0", "A") if c not in cols]
        if missing:
            raise ValueError(f"{str(p)}: missing column(s) {missing}; required test,omega,x0,A")
        for line_no, row in enumerate(reader, start=2):
            row = {k.strip(): (v or "").strip() for k, v in row.items() if k is not None}
            test = row["test"]
            vals = tuple(
                _parse_float(row[c], path=str(p), line=line_no, test=test, column=c) for c in ("omega", "x0", "A")
            )
            if vals[0] <= 0:
                raise ValueError(f"{str(p)}, line {line_no}: test {test!r}: omega = {vals[0]} rad/s must be > 0")
            if vals[2] <= 0:
                raise ValueError(f"{str(p)}, line {line_no}: test {test!r}: A = {vals[2]} mm must be > 0")
            out[test] = vals  # type: ignore[assignment]
    return out


def write_side_file(path: str | Path, estimates: dict[str, HarmonicEstimate], overwrite: bool = False) -> Path:
    """Write ``test,omega,x0,A`` (rad/s, mm, mm) for the given estimates."""
    p = Path(path)
    if p.exists() and not overwrite:
        raise ValueError(f"{str(p)!r} already exists; refusing to overwrite it (use overwrite=True / --force)")
    with p.open("w", newline="") as fh:
        fh.write("test,omega,x0,A\n")
        for k, e in estimates.items():
            fh.write(f"{k},{e.omega:.10g},{e.x0:.10g},{e.A:.10g}\n")
    return p


def analyse_record(
    rec: Record,
    side: tuple[float, float, float] | None = None,
    *,
    rel_tol: float = 0.03,
    allow_compression: bool = True,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
) -> HarmonicEstimate:
    """Harmonic estimate and steady window of one record, optionally from a side file.

    With ``side = (omega, x0, A)`` (rad/s, mm, mm) those values are used as given;
    only the phase theta [rad] is fitted (fixed-frequency least squares) and the
    steady window is selected at that frequency.

    Returns
    -------
    HarmonicEstimate
        Validated with :func:`validate_record`.
    """
    if side is None:
        cached = rec.estimate
        if cached is not None and cached.window is not None and cached.window.rel_tol == rel_tol:
            est = cached
        else:
            est = estimate_harmonic(rec.t, rec.x, rel_tol=rel_tol, test=rec.test)
    else:
        w, x0, A = side
        _, a, b = _linear_harmonic(rec.t, rec.x, w)
        theta = math.atan2(b, a)
        win = select_steady(rec.t, rec.x, w, theta, rel_tol=rel_tol)
        if win.n_cycles >= 1:
            m = (rec.t >= win.t_start) & (rec.t < win.t_end)
            _, a, b = _linear_harmonic(rec.t[m], rec.x[m], w)
            theta = math.atan2(b, a)
            resid = rec.x[m] - (x0 + A * np.sin(w * rec.t[m] + theta))
            noise = float(np.sqrt(np.mean(resid**2)))
        else:
            noise = float("inf")
        est = HarmonicEstimate(w, x0, A, theta, noise, win, source="side file")
    return validate_record(rec, allow_compression=allow_compression, min_cycles=min_cycles, min_snr=min_snr, estimate=est)

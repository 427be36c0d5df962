"""The benchmark's seed streams: what ``--seed S`` changes.

Every case of the simulated worlds draws its plan, effects, noise and resamples from its own integer seed: the harmonic
grid's ``base + i``, the time grid's ``base + 100000 + 1000·k + i``, the ODE world's ``base + 200000 + crc32(label)
mod 10⁶`` (and a case adds small offsets of its own).  All of these lie below :data:`SEED_STRIDE`, and the run's
``base`` is ``S·SEED_STRIDE`` (:func:`run_base`): the cases of ``--seed 0`` keep their seeds, and two runs at
different ``S`` draw from disjoint seeds, i.e. independent NumPy streams.  (A base of ``S`` itself would make the run at
``S = 1`` re-draw the noise of ``S = 0``'s neighbouring case: two such runs are not independent replicates.)
"""

from __future__ import annotations

#: the spacing of the runs' seed blocks: above every case's offset in its run (module docstring)
SEED_STRIDE = 10_000_000


def run_base(seed: int) -> int:
    """The first seed of the run at ``--seed seed``: ``seed·SEED_STRIDE`` (0 for seed 0).

    Parameters
    ----------
    seed : int
        The benchmark's ``--seed`` (>= 0).

    Returns
    -------
    int
        The base its cases' seeds are offset from.

    Raises
    ------
    ValueError
        ``seed`` negative or not an integer.
    """
    if isinstance(seed, bool) or int(seed) != seed or int(seed) < 0:
        raise ValueError(f"seed = {seed!r} is out of range; valid range: an integer >= 0")
    return int(seed) * SEED_STRIDE

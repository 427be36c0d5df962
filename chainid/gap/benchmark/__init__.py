"""``chainid benchmark-gap``: the blind benchmark of the diagnosis on simulated data with withheld effects.

* :mod:`.grid` — the harmonic case families and the benchmark run;
* :mod:`.nonharmonic` — the non-harmonic excitation families and the transfer cases;
* :mod:`.chain` — the chain a case runs on (built-in or the user's, scaled to the same stress);
* :mod:`.report` — scores per family and the confusion matrix.
"""

__all__ = ["grid", "nonharmonic", "chain", "report"]

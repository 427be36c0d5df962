"""``chainid benchmark-gap``: the blind benchmark of the diagnosis on simulated data with withheld effects.

The project's simulator (``--generator sim``, the default):

* :mod:`.grid` — the harmonic case families and the benchmark run;
* :mod:`.nonharmonic` — the non-harmonic excitation families and the transfer cases;
* :mod:`.chain` — the chain a case runs on (built-in or the user's, scaled to the same stress);
* :mod:`.report` — scores per family and the confusion matrix.

A second world written apart from it (``--generator ode``): effects as ODE states integrated with LSODA, other
excitations, force-driven resonant devices, a logger with lag, noise, ADC steps and offsets:

* :mod:`.odeworld` — building a case's records and truth, the runner;
* :mod:`.odeshapes` — multisine, filtered noise with tapers, chirps with rests, harmonic tests;
* :mod:`.odedevice` — the devices and their integration (displacement- and force-driven);
* :mod:`.odemeasure` — what the logger adds;
* :mod:`.odecases` — bases, test plans and effect strengths;
* :mod:`.odefamilies` — the case families;
* :mod:`.odescore` — right verdicts per family, parameter errors and interval coverage.
"""

__all__ = ["grid", "nonharmonic", "chain", "report", "odeworld", "odeshapes", "odedevice", "odemeasure", "odecases",
           "odefamilies", "odescore"]

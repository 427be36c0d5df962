"""``chainid benchmark-gap``: the blind benchmark of the diagnosis on simulated data with withheld effects.

The project's simulator (``--generator sim``, the default):

* :mod:`.grid` — the harmonic case families and the benchmark run;
* :mod:`.nonharmonic` — the non-harmonic excitation families and the transfer cases;
* :mod:`.chain` — the chain a case runs on (built-in or the user's, scaled to the same stress);
* :mod:`.report` — scores per family, the confusion matrix and, with resamples, the coverage of the 90 % intervals;
* :mod:`.simtruth` — a case's true parameters (its effect specs and base-model mismatch) and the diagnosis' numbers
  to score them with.

Both generators score parameters against their truth with :mod:`.paramscore` (relative error, interval coverage,
the calibration table per effect).

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

__all__ = ["grid", "nonharmonic", "chain", "report", "simtruth", "paramscore", "odeworld", "odeshapes", "odedevice",
           "odemeasure", "odecases", "odefamilies", "odescore"]

"""The time-domain route of the diagnosis: any excitation (transients, sweeps, random, seismic), sample by sample.

* :mod:`.data` — one record prepared for the time domain (band, smooth kinematics, noise, blocks);
* :mod:`.basechoice` — what the base carries from the training records (operating conditions, the damping law);
* :mod:`.problem` — the problem on time records (and harmonic tests in a mixed set): fit, leave-one-block-out score;
* :mod:`.where` — where the model misses against the state, in the spectrum, ringing and drift;
* :mod:`.plots` — the route's figures; :mod:`.route` — the route from records to the verdict.
"""

__all__ = ["data", "basechoice", "problem", "where", "plots", "route"]

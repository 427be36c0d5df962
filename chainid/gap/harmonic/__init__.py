"""The harmonic route of the diagnosis: steady harmonic tests folded into phase bins, damping c_e(ω, A) per test.

* :mod:`.prepare` — one record's steady window, phase bins, noise and cycle statistics;
* :mod:`.problem` — the phase-bin problem: fit and score any effect set, the damping law re-identified;
* :mod:`.law_choice` — the damping laws c_e(ω, A) and their leave-one-test-out choice;
* :mod:`.where` — where the baseline misses over the phase;
* :mod:`.plots` — the route's figures; :mod:`.route` — the route from prepared tests to the verdict.
"""

__all__ = ["prepare", "problem", "law_choice", "where", "plots", "route"]

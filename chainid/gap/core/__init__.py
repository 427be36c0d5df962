"""The shared core of the diagnosis: what both routes (harmonic phase bins, time domain) use alike.

* :mod:`.candidate` — a fitted effect set and its scores; the problem protocol the selection needs;
* :mod:`.selection` — forward selection conditional on what is already explained, and the step rule;
* :mod:`.verdict` — the verdict rule and the JSON contract;
* :mod:`.noise` — noise floor, excitation band and smooth kinematics of a record;
* :mod:`.stationarity` — trends of what is left over the cycles;
* :mod:`.interpret` — the diagnosis in an engineer's words;
* :mod:`.fitgrid` — start points of the bounded fits;
* :mod:`.summary` — terminal summary and JSON writer; :mod:`.plot_steps` — the waterfall figure.
"""

__all__ = ["candidate", "selection", "verdict", "noise", "stationarity", "interpret", "fitgrid", "summary",
           "plot_steps"]

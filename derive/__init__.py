"""chainid.derive — the SymPy derivation of the link stiffness (dev-time only).

Installed as ``chainid.derive`` (the repository keeps it at the top level, as
``derive/``).  Nothing in the runtime package imports it except the
``chainid verify`` and ``chainid generate`` commands.  It never imports the
runtime package: data flows one way, derive -> generated -> chainid.

Modules, in the order of the paper:

* :mod:`.symbols`  — the symbols, named as in the paper;
* :mod:`.section`  — Eq. 5, section properties of the straight and curved bar;
* :mod:`.link`     — Eq. 2–10, internal forces, strain energy, Menabrea, Castigliano;
* :mod:`.hertz`    — Eq. 11–14, general Hertz contact of two crossed links;
* :mod:`.chain`    — Eq. 15–16, chain displacement, stiffness and the inverse;
* :mod:`.paper`    — the paper's closed forms, transcribed as printed;
* :mod:`.verify`   — derived vs paper, equation by equation;
* :mod:`.emit`     — printer of the numba kernels into generated/.
"""

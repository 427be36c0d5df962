"""The dynamics kernels run with numba switched off, where numpy checks every index.

Compiled numba code does not check bounds: a read past an array's end returns whatever lies there, silently.  Run
as plain Python (NUMBA_DISABLE_JIT=1, in a subprocess so this process' compiled kernels are untouched), the same
kernels raise IndexError on such a read.  A few steps of short lines through both schemes and the spring paths (the
plain chain kernel, a contact exponent with and without a play, every element kind, a dead band, slack, the resistance
and the take-up) must run to the end.
"""
from __future__ import annotations

import os
import subprocess
import sys


SCRIPT = """
import warnings
import numpy as np
from chainid.dynamics import ChainLine, Drive, simulate
warnings.simplefilter("ignore")
lines = [ChainLine(n_links=8, n_masses=2, pretension_N=1000.0, damping=5.0),
         ChainLine(n_links=8, n_masses=2, pretension_N=1000.0, contact_exponent=1.0, damping=5.0),
         ChainLine(n_links=8, n_masses=2, pretension_N=1000.0, contact_exponent=1.0, backlash_mm=0.01),
         ChainLine(n_links=8, n_masses=2, pretension_N=1000.0, hysteresis=((2000.0, 50.0),), dahl=((30.0, 0.01),)),
         ChainLine(n_links=8, n_masses=2, pretension_N=1000.0, stribeck=((40.0, 60.0, 1.0, 0.01),),
                   bouc_wen=((50.0, 0.01, 0.5, 1.0),), coulomb_N=30.0),
         ChainLine(n_links=8, n_masses=2, pretension_N=1000.0, deadband=(100.0, 0.01, 2.0, 0.0), slack=0.01,
                   resistance_N=50.0, tail_mass_kg=2.0, tensioner_stiffness=100.0)]
for line in lines:
    for scheme in ("explicit", "implicit"):
        r = simulate(line, Drive("sine", A=0.01, omega=300.0), 5e-4, scheme=scheme, n_out=4)
        assert np.all(np.isfinite(r.tension)), (line, scheme)
print("ok")
"""


def test_the_kernels_read_no_index_past_an_arrays_end():
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=280)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().endswith("ok")

"""moreau from Python: constrained particle motion (PBD), optimal control of spring networks and
motion-capture gap filling. docs/python.md lists every name.

    import moreau
    case = moreau.pbd.SlidingCase(C=10.0)
    x, summary = moreau.pbd.simulate(case.make_drift(), case.make_constraints(),
                                     case.initial_state(), case.T, h=1e-3)

Options are keyword arguments named like the scenario-file keys and are validated as the
command line validates them: a bad value raises ValueError with the same one-line message. A
numerical failure raises moreau.NumericalError carrying .summary and .state (the last good
state). Long C++ work runs with the GIL released; Ctrl-C raises KeyboardInterrupt between steps.
"""

import os as _os
import sys as _sys

# libgomp reads its settings when it loads, with the extension below unless something loaded it
# before. Unless the user chose (OMP_WAIT_POLICY or GOMP_SPINCOUNT), idle threads spin about as
# long as waking a sleeping one costs, then sleep: the command line's choice and its reasons are in
# include/moreau/common/openmp_wait.h.
if "OMP_WAIT_POLICY" not in _os.environ and "GOMP_SPINCOUNT" not in _os.environ:
    _os.environ["GOMP_SPINCOUNT"] = "10000"

from moreau._moreau import NumericalError, control, hash_doubles, mocap, particles, pbd

__version__ = "0.1.0"
__all__ = ["NumericalError", "control", "hash_doubles", "mocap", "particles", "pbd"]

for _name in ("control", "mocap", "particles", "pbd"):
    _sys.modules[f"{__name__}.{_name}"] = globals()[_name]

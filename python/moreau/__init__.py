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

# libgomp reads OMP_WAIT_POLICY when it loads, with the extension below unless something loaded
# it before. Its default busy-waiting costs a scheduler slice per barrier on a shared machine
# (a 20 ms control solve took 0.8 s under load), so unless the user chose, waiting is passive, as
# the command line chooses (apps/moreau/main.cpp).
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")

from moreau._moreau import NumericalError, control, hash_doubles, mocap, particles, pbd

__version__ = "0.1.0"
__all__ = ["NumericalError", "control", "hash_doubles", "mocap", "particles", "pbd"]

for _name in ("control", "mocap", "particles", "pbd"):
    _sys.modules[f"{__name__}.{_name}"] = globals()[_name]

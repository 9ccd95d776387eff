"""Type stubs of moreau._moreau's top level (the parts have their own: particles.pyi, …)."""
from typing import Any

import numpy

from moreau import control, mocap, particles, pbd

class NumericalError(RuntimeError):
    summary: Any  # the summary of the failed run or solve
    state: Any  # the last good state
    step: int  # Engine only: steps completed

def hash_doubles(values: numpy.ndarray) -> str: ...

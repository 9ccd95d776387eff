"""Sizes and values a Python user controls are checked before anything is allocated or run,
as on the command line (docs/reliability.md): a thread count beyond the machine is capped, the
disks case refuses more disks than its all-pairs start can take, a solve or an evaluation whose
memory cannot fit is refused with ValueError, and a drift that returns NaN stops the run like one
that returns infinity. The cases that could exhaust memory or crash run in a child interpreter
under `ulimit -v`, so that a regression fails the test instead of taking the machine down."""
import os
import resource
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import moreau
from moreau import pbd

ADDRESS_SPACE = 3 << 30


def run_child(code):
    """Runs `code` in a child interpreter under ulimit -v ADDRESS_SPACE; its CompletedProcess."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=120, preexec_fn=limit, env=dict(os.environ))


def test_threads_beyond_the_machine_are_capped_not_a_crash():
    r = run_child("""
        import numpy as np
        from moreau import particles
        model = particles.ParticleModel(dimension=2, radius=[0.1] * 4)
        x0 = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
        engine = particles.Engine(model, x0, particles.Forces(), h=1e-3, threads=100000)
        engine.step(3)
        print(engine.threads, engine.step_count)
        """)
    assert r.returncode == 0, r.stderr
    threads, steps = map(int, r.stdout.split())
    assert 1 <= threads <= os.cpu_count() and steps == 3


def test_a_billion_disks_are_refused_before_allocation():
    r = run_child("""
        from moreau import pbd
        try:
            pbd.DisksCase(count=10**9).initial_state()
        except ValueError as e:
            print(e)
        """)
    assert r.returncode == 0, r.stderr
    assert "count must be between 1 and 20000" in r.stdout and "1000000000" in r.stdout


def test_a_solve_on_too_many_steps_is_refused_before_allocation():
    r = run_child("""
        from moreau import control
        try:
            control.solve(control.OscillatorExample(), 100000000)
        except ValueError as e:
            print(e)
        """)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("steps: 100000000 steps need about"), r.stdout


def test_an_evaluation_of_a_billion_trials_is_refused_before_drawing_them():
    r = run_child("""
        import numpy as np
        from moreau import mocap
        t = np.linspace(0.0, 2.0, 201)
        x = np.stack([np.stack([np.sin(t + k), np.cos(t + k), t], axis=1) for k in range(4)], 1)
        r = mocap.Recording(["A", "B", "C", "D"], x * 100.0, 100.0, "mm")
        try:
            mocap.evaluate(r, methods=["linear"], gap_seconds=[0.1], trials=10**9)
        except ValueError as e:
            print(e)
        """)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("trials: 1000000000 trials need about"), r.stdout


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_a_drift_returning_nan_stops_the_run_like_infinity(bad):
    case = pbd.SlidingCase()
    with pytest.raises(moreau.NumericalError) as info:
        pbd.simulate(lambda x: np.full(len(x), bad), case.make_constraints(),
                     case.initial_state(), 0.01, h=1e-3)
    e = info.value
    assert e.summary.termination == "non_finite" and e.summary.failed_step == 1
    assert np.array_equal(e.state, case.initial_state())

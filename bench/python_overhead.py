"""Overhead of the Python package (docs/benchmarks.md, "Python package overhead").

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py

1. engine.step() called from a Python loop on 10^4 disks against the same steps run by the C++
   loop of Engine::Run (engine.run(T), one call): the same model, seed and start, so the same
   arithmetic; the ratio of the wall times is the binding's overhead. Also the engine's own
   per-step time (summary.total_seconds, measured inside C++).
2. A Python drift callback (pbd.simulate with a callable) against the C++ drift of the same
   function: the cost per call, for a 3-vector and for a state of 2·10^4 numbers.
"""
import statistics
import time

import numpy as np

import moreau
from moreau import particles, pbd


def make_engine(n=10000):
    side = 0.2 * np.sqrt(n)
    model = particles.ParticleModel(dimension=2, radius=np.full(n, 0.05))
    model.add_box_walls([0.0, 0.0, 0.0], [side, side, 0.0])
    x0 = particles.random_sequential_addition(model, [0, 0, 0], [side, side, 0], seed=1)
    forces = particles.Forces(trap=particles.HarmonicTrap(gamma=1.0, center=[side / 2] * 3),
                              diffusion=0.01)
    return lambda: particles.Engine(model, x0, forces, h=1e-3, seed=1)


def engine_overhead(steps=300, repeats=5):
    new = make_engine()
    python_loop, cpp_loop, inside = [], [], []
    for _ in range(repeats):
        a, b = new(), new()
        t0 = time.perf_counter()
        for _ in range(steps):
            a.step()
        python_loop.append(time.perf_counter() - t0)
        inside.append(a.summary().total_seconds)
        t0 = time.perf_counter()
        b.run(steps * 1e-3)
        cpp_loop.append(time.perf_counter() - t0)
        assert np.array_equal(a.positions(), b.positions())
    p, c, i = (statistics.median(v) / steps for v in (python_loop, cpp_loop, inside))
    print(f"engine, 10^4 disks, {steps} steps, median of {repeats} (threads {a.threads}):")
    print(f"  engine.step() from Python  {p * 1e3:8.4f} ms/step")
    print(f"  engine.run(T) (C++ loop)   {c * 1e3:8.4f} ms/step")
    print(f"  inside the engine          {i * 1e3:8.4f} ms/step (summary.total_seconds)")
    print(f"  ratio Python / C++ loop    {p / c:8.4f}")


def drift_cost(size, steps=20000, repeats=5):
    f = np.zeros(size)
    f[1] = -1.0
    sets = pbd.ConstraintSetList(size, [pbd.HalfSpace(np.eye(size)[1], -1e9)])
    x0 = np.zeros(size)
    T = steps * 1e-3
    cpp, py = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        pbd.simulate(pbd.ConstantDrift(f), sets, x0, T, h=1e-3, monitor_violation=False)
        cpp.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        pbd.simulate(lambda x: f, sets, x0, T, h=1e-3, monitor_violation=False)
        py.append(time.perf_counter() - t0)
    per_call = (statistics.median(py) - statistics.median(cpp)) / steps
    print(f"Python drift callback, state size {size}: {per_call * 1e6:.2f} µs per call "
          f"(C++ drift {statistics.median(cpp) / steps * 1e6:.2f} µs per step)")


if __name__ == "__main__":
    print(f"moreau {moreau.__version__}")
    engine_overhead()
    drift_cost(3)
    drift_cost(20000, steps=2000)

"""moreau.particles: the engine from numpy, zero-copy views (checked by address), errors, the
last good state, Ctrl-C, the GIL released during steps, no leaks over 10^4 calls."""
import json
import signal
import sys
import threading
import time

import numpy as np
import pytest

import moreau
from moreau import particles
from conftest import run_cli


def disks(n=400, seed=3, **options):
    """n disks of radius 0.05 in a box with walls, a harmonic trap and noise."""
    side = 0.2 * np.sqrt(n)
    model = particles.ParticleModel(dimension=2, radius=np.full(n, 0.05))
    model.add_box_walls([0.0, 0.0, 0.0], [side, side, 0.0])
    x = particles.random_sequential_addition(model, [0.0, 0.0, 0.0], [side, side, 0.0], seed)
    forces = particles.Forces(trap=particles.HarmonicTrap(gamma=1.0, center=[side / 2, side / 2, 0]),
                              diffusion=0.01)
    return particles.Engine(model, x, forces, **options), x


def test_engine_matches_a_second_engine_and_run_matches_step():
    a, x0 = disks(h=1e-3, seed=5)
    b, _ = disks(h=1e-3, seed=5)
    a.step(20)
    summary = b.run(0.02)
    assert a.step_count == b.step_count == 20 and summary.ok and summary.steps == 20
    assert np.array_equal(a.positions(), b.positions())
    assert not np.array_equal(a.positions(), x0)
    assert summary.to_dict()["settings"]["h"] == 1e-3
    assert summary.termination == "completed"


def test_an_observer_returning_false_stops_the_run_and_the_engine_goes_on():
    a, _ = disks(h=1e-3, seed=5)
    b, _ = disks(h=1e-3, seed=5)
    seen = []

    def observer(engine):
        seen.append(engine.step_count)
        return engine.step_count < 6  # False at step 6 stops; True (and None) go on

    summary = a.run(0.02, observer=observer)
    assert summary.termination == "interrupted" and not summary.ok
    assert summary.message == "stopped by the observer"
    assert seen == list(range(7)) and a.step_count == 6 and summary.steps == 6
    assert a.run(0.014).ok and a.step_count == 20  # usable: it goes on from step 6
    assert b.run(0.02, observer=lambda engine: None).ok
    assert np.array_equal(a.positions(), b.positions())


def test_views_are_zero_copy_and_agree_with_the_copy():
    e, _ = disks()
    e.step(5)
    addresses = e._addresses()
    stored, ids, radii = e.stored_positions, e.stored_ids, e.radii
    assert stored.__array_interface__["data"][0] == addresses["stored_positions"]
    assert ids.__array_interface__["data"][0] == addresses["stored_ids"]
    assert radii.__array_interface__["data"][0] == addresses["radii"]
    assert not stored.flags.writeable and stored.base is not None
    x = e.positions()  # id order: a copy
    assert x.__array_interface__["data"][0] != addresses["stored_positions"]
    assert np.array_equal(x[ids], stored)  # no periodic axis: the stored values are the positions
    assert np.all(radii == 0.05)
    with pytest.raises(ValueError):
        stored[0, 0] = 1.0


def test_view_keeps_the_engine_alive():
    e, _ = disks()
    view = e.stored_positions
    before = view.copy()
    del e
    assert np.array_equal(view, before)


def test_observer_and_numerical_error_with_the_last_good_state():
    model = particles.ParticleModel(dimension=2, radius=[0.1, 0.1])
    x0 = np.array([[0.0, 0.0], [1.0, 0.0]])
    e = particles.Engine(model, x0, particles.Forces(constant_force=[1e300, 0.0, 0.0]), h=1e10)
    times = []
    with pytest.raises(moreau.NumericalError) as info:
        e.run(1e11, observer=lambda engine: times.append(engine.time))
    err = info.value
    assert times == [0.0] and err.step == 0
    assert np.array_equal(err.state, x0) and err.summary.termination == "non_finite"
    assert "step 1" in str(err)


def test_errors_carry_the_cpp_messages():
    with pytest.raises(ValueError, match=r"^radius of particle 1 must be > 0 \(got -1\)$"):
        particles.ParticleModel(dimension=2, radius=[0.1, -1.0])
    with pytest.raises(ValueError, match=r"^h: must be > 0 \(got 0\)$"):
        particles.EngineOptions(h=0.0)
    with pytest.raises(ValueError, match=r"^EngineOptions: unknown option 'step'$"):
        particles.EngineOptions(step=1)
    model = particles.ParticleModel(dimension=2, radius=[0.1, 0.1])
    with pytest.raises(ValueError, match="overlap"):
        particles.Engine(model, [[0.0, 0.0], [0.05, 0.0]])
    with pytest.raises(ValueError, match="order"):
        particles.EngineOptions(order="random")


def test_ctrl_c_interrupts_a_run_between_steps():
    e, _ = disks()

    def observer(engine):
        if engine.step_count == 7:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        e.run(1.0, observer=observer)
    assert e.step_count == 7  # the engine stays at its last completed step, usable
    e.step()
    assert e.step_count == 8


def test_the_gil_is_released_during_steps():
    e, _ = disks(n=10000, threads=1)
    e.step()
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1

    thread = threading.Thread(target=spin)
    old = sys.getswitchinterval()
    sys.setswitchinterval(0.1)  # longer than the 20 steps: a held GIL would block the thread
    try:
        thread.start()
        time.sleep(0.01)
        start = count[0]
        e.step(20)
        during = count[0] - start
    finally:
        stop.set()
        thread.join()
        sys.setswitchinterval(old)
    assert during > 1000


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


def test_no_leak_over_ten_thousand_calls():
    e, x0 = disks(n=1000)
    model = e.model

    def calls():
        e.stored_positions.sum()
        e.positions()
        e.summary().to_dict()
        particles.EngineOptions(h=0.01, order="lexicographic")
        try:
            particles.EngineOptions(h=-1.0)
        except ValueError:
            pass

    for _ in range(1000):  # warm-up: caches, allocator pools
        calls()
    refs = sys.getrefcount(e), sys.getrefcount(model)
    before = rss_bytes()
    for _ in range(10000):
        calls()
    growth = rss_bytes() - before
    assert (sys.getrefcount(e), sys.getrefcount(model)) == refs
    assert growth < 2 * 1024 * 1024, growth  # one leaked positions() copy per call: 160 MB


def test_room_and_evacuation():
    room = particles.Room(width=4.0, height=4.0, door_width=1.0)
    model = particles.ParticleModel(dimension=2, radius=[0.2])
    particles.add_room(room, model)
    assert len(model.segments) == 5
    forces = particles.Forces(propulsion=room.walk_to_the_door(1.0), diffusion=1e-4)
    e = particles.Engine(model, [[2.0, 2.0]], forces, h=0.01, seed=2)
    count = particles.EvacuationCount(room, 1)
    e.run(5.0, observer=lambda engine: count.update(engine.positions()))
    assert count.out == 1
    # The door y ∈ [1.5, 2.5] shrunk by the clearance at each post.
    walk = room.walk_to_the_door(1.0, clearance=0.2)
    assert (walk.target[1], walk.target_end[1]) == (1.7, 2.3)
    assert room.walk_to_the_door(1.0, 0.6).target[1] == 2.0  # narrower than 2 clearances


# A periodic 3D layer with gravity and attraction: the same run in the file and in Python.
LAYER = """
[problem]
kind = "particles"
dimension = 3
count = 80
radius = 0.3
T = 0.5
seed = 4

[domain]
lo = [0.0, 0.0, 0.0]
hi = [6.0, 6.0, 6.0]
periodic = [true, true, false]
box_walls = true

[forces]
constant = [0.0, 0.0, -1.0]
attraction_stiffness = 2.0
attraction_range = 0.1
diffusion = 0.005

[solver]
h = 0.005

[output]
hdf5 = false
vtu = false
snapshots = false
"""


def test_engine_run_equals_moreau_run(tmp_path):
    scenario = tmp_path / "layer.toml"
    scenario.write_text(LAYER)
    run_cli("run", scenario, "--out", tmp_path / "out")
    cli = json.loads((tmp_path / "out/summary.json").read_text())
    # The model, start and options the scenario makes (docs/particles.md "Scenario keys").
    lo, hi = [0.0, 0.0, 0.0], [6.0, 6.0, 6.0]
    model = particles.ParticleModel(dimension=3, radius=np.full(80, 0.3), domain_lo=lo,
                                    domain_hi=hi, periodic=[True, True, False])
    model.add_box_walls(lo, hi)
    x0 = particles.random_sequential_addition(model, lo, hi, seed=4)
    forces = particles.Forces(constant_force=[0.0, 0.0, -1.0], diffusion=0.005,
                              attraction=particles.PairAttraction(stiffness=2.0, range=0.1))
    engine = particles.Engine(model, x0, forces, h=0.005, seed=4)
    summary = engine.run(0.5)
    assert len(model.walls) == 2  # z only: x and y are periodic
    assert moreau.hash_doubles(engine.positions()) == cli["positions_hash"]
    for key in ("steps", "neighbour_list_builds", "verlet_retries", "projections",
                "constraint_evaluations", "max_overlap", "last_overlap"):
        assert getattr(summary, key) == cli[key], key


def test_import_bounds_the_openmp_spin_unless_the_user_chose():
    """libgomp prints the spin count it chose at load (OMP_DISPLAY_ENV=verbose): 10000 pauses by
    default (the command line's choice), where an unset policy would give 300000; the user's own
    policy or spin count is kept."""
    import os
    import subprocess

    def spin_count(extra):
        env = {k: v for k, v in os.environ.items()
               if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
        env.update(extra, OMP_DISPLAY_ENV="verbose")
        r = subprocess.run([sys.executable, "-c", "import moreau"], env=env, capture_output=True,
                           text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        line = [l for l in r.stderr.splitlines() if "GOMP_SPINCOUNT" in l]
        assert len(line) == 1, r.stderr
        return int(line[0].split("'")[1])

    assert spin_count({}) == 10000
    assert spin_count({"OMP_WAIT_POLICY": "passive"}) == 0
    assert spin_count({"OMP_WAIT_POLICY": "active"}) > 10000
    assert spin_count({"GOMP_SPINCOUNT": "123"}) == 123

"""moreau.particles' crowds from Python: the collision-free speed model, the walkable area and
its routing field, against the model's formulas and the command-line tool's bits."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import moreau
from moreau import particles

from conftest import ROOT, run_cli

# A 12 m × 8 m room with a 2 m × 2 m pillar and two exits, one on the right wall, one at the top.
ROOM = """walkable 0 0  12 0  12 8  0 8
obstacle 7 3  9 3  9 5  7 5
exit 12 3.5  12 4.5
exit 2 8  3 8
"""


def test_speed_law_and_range_are_the_papers():
    m = particles.CollisionFreeSpeed()
    assert (m.time_gap, m.length, m.repulsion, m.repulsion_range) == (1.0, 0.3, 5.0, 0.1)
    v0 = 1.34
    for s in (0.1, 0.3, 0.5, 1.0, 1.64, 5.0):
        assert particles.collision_free_speed_at(m, v0, s) == min(v0, max(0.0, (s - 0.3) / 1.0))
    assert particles.collision_free_range(m, v0) == pytest.approx(0.3 + max(1.0 * v0, 10 * 0.1))
    with pytest.raises(ValueError, match=r"^time_gap: must be > 0 \(got 0\)$"):
        particles.CollisionFreeSpeed(time_gap=0.0)
    with pytest.raises(ValueError, match="forces.walking needs forces.propulsion"):
        particles.Forces(walking=particles.WalkingSpeeds(collision_free=m))


def test_a_follower_walks_at_the_speed_of_its_headway():
    """Two people in single file along +x, 0.9 m apart: the follower's headway is 0.9 m, so it
    walks at V(0.9) = (0.9 − ℓ)/T = 0.6 m/s; the leader has nobody ahead and walks at v0. The
    repulsion between them lies along x and leaves both directions ±x (its weight a e^{(ℓ−d)/D}
    = 5 e^{−6} is below the desired direction's 1)."""
    model = particles.ParticleModel(dimension=2, radius=[0.15, 0.15])
    walk = particles.WalkingSpeeds(collision_free=particles.CollisionFreeSpeed())
    forces = particles.Forces(propulsion=particles.SelfPropulsion(speed=1.34, direction=[1, 0, 0]),
                              walking=walk)
    x0 = np.array([[0.0, 1.0], [0.9, 1.0]])
    h = 0.01
    engine = particles.Engine(model, x0, forces, h=h)
    engine.step()
    x = engine.positions()
    assert x[0, 0] == pytest.approx(h * 0.6, abs=1e-15)
    assert x[1, 0] == pytest.approx(0.9 + h * 1.34, abs=1e-15)
    assert np.array_equal(x[:, 1], x0[:, 1])


def test_routing_field_gives_the_walking_distance():
    geometry = particles.parse_crowd_geometry(ROOM, "room.txt")
    assert geometry.exits == [[[12.0, 3.5], [12.0, 4.5]], [[2.0, 8.0], [3.0, 8.0]]]
    assert len(geometry.walls()) == 4 + 2 + 4  # the outer edges split at the exits, the pillar
    assert geometry.walkable_at(1.0, 1.0) and not geometry.walkable_at(8.0, 4.0)
    h = 0.05
    field = particles.DistanceField(geometry, spacing=h, clearance=0.0)
    # Straight in front of the right exit: the Euclidean distance, to first order in h.
    for x in (11.0, 10.0, 9.5):
        assert field.distance(x, 4.0) == pytest.approx(12.0 - x, abs=2 * h)
        e = field.direction(x, 4.0)
        assert e[0] == pytest.approx(1.0, abs=1e-6) and abs(e[1]) < 1e-3
    # With the right exit alone, the way from behind the pillar goes round one of its corners:
    # √2 + 2 + √(3² + 0.5²) = 6.456 against the straight line's 6.
    right_only = particles.parse_crowd_geometry(ROOM.replace("exit 2 8  3 8\n", ""))
    behind = particles.DistanceField(right_only, spacing=h, clearance=0.0).distance(6.0, 4.0)
    assert behind == pytest.approx(np.sqrt(2) + 2 + np.hypot(3, 0.5), abs=2 * h)
    # Under the top exit the nearer door wins, and one walks up to it.
    assert field.distance(2.5, 6.0) == pytest.approx(2.0, abs=2 * h)
    e = field.direction(2.5, 6.0)
    assert e[1] == pytest.approx(1.0, abs=1e-3)
    with pytest.raises(ValueError, match=r"^room.txt:1: walkable: needs at least 3 vertices"):
        particles.parse_crowd_geometry("walkable 0 0 1 0\n", "room.txt")
    with pytest.raises(ValueError, match=r"^spacing: must be > 0"):
        particles.DistanceField(geometry, spacing=0.0)


def crowd(geometry, threads, seed=3, count=40):
    """The scenario of test_engine_run_equals_moreau_run below, built in Python."""
    lo, hi = [1.0, 1.0, 0.0], [5.0, 7.0, 0.0]
    model = particles.ParticleModel(dimension=2, radius=np.full(count, 0.15), domain_lo=lo,
                                    domain_hi=hi)
    model.segments = geometry.walls()
    x0 = particles.random_sequential_addition(model, lo, hi, seed)
    route = particles.DistanceField(geometry, spacing=0.1, clearance=0.2)
    forces = particles.Forces(
        propulsion=particles.SelfPropulsion(speed=1.34, route=route),
        walking=particles.WalkingSpeeds(collision_free=particles.CollisionFreeSpeed()))
    return particles.Engine(model, x0, forces, h=0.01, seed=seed, threads=threads), x0


def test_engine_run_equals_moreau_run(tmp_path):
    (tmp_path / "room.txt").write_text(ROOM)
    scenario = tmp_path / "crowd.toml"
    scenario.write_text("""[problem]
kind = "particles"
dimension = 2
count = 40
radius_min = 0.15
radius_max = 0.15
T = 3.0
seed = 3

[geometry]
file = "room.txt"
spacing = 0.1
clearance = 0.2

[domain]
lo = [1.0, 1.0]
hi = [5.0, 7.0]

[forces]
propulsion_speed = 1.34
pedestrian_model = "collision_free"

[solver]
h = 0.01
threads = 2

[output]
hdf5 = false
vtu = false
snapshots = false
""")
    run_cli("run", scenario, "--out", tmp_path / "out")
    cli = json.loads((tmp_path / "out/summary.json").read_text())
    geometry = particles.read_crowd_geometry(str(tmp_path / "room.txt"))
    engine, x0 = crowd(geometry, threads=2)
    engine.run(3.0)
    assert moreau.hash_doubles(engine.positions()) == cli["positions_hash"]
    # They walk to the doors: everybody out, or nearer to an exit than at the start.
    field = particles.DistanceField(geometry, spacing=0.1, clearance=0.2)
    for start, now in zip(x0, engine.positions()):
        assert not geometry.walkable_at(*now) or field.distance(*now) < field.distance(*start) - 0.5


def test_bits_do_not_depend_on_the_thread_count():
    geometry = particles.parse_crowd_geometry(ROOM)
    runs = []
    for threads in (1, 2):
        engine, _ = crowd(geometry, threads, seed=5, count=60)
        engine.run(2.0)
        runs.append(engine.positions())
    assert np.array_equal(runs[0], runs[1])


def test_evacuation_count_by_exit():
    geometry = particles.parse_crowd_geometry(ROOM)
    count = particles.EvacuationCount(geometry, 3)
    # Inside, past the right exit, past the top exit.
    assert count.update(np.array([[1.0, 1.0], [12.5, 4.0], [2.5, 8.5]])) == 2
    assert count.out == 2


def test_the_routing_example_empties_the_room_by_both_exits(tmp_path):
    """examples/python/crowd_routing.py: everybody out, each exit taken by the people nearer to
    it (the crowd starts along the whole bottom of the room), and the figure written."""
    r = subprocess.run([sys.executable, str(ROOT / "examples/python/crowd_routing.py"),
                        str(tmp_path)], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, MPLBACKEND="Agg"))
    assert r.returncode == 0, r.stderr
    line = [l for l in r.stdout.splitlines() if " out after " in l][0]
    out, total = line.split(" of ")[0], line.split(" of ")[1].split()[0]
    assert out == total == "150", line
    right, top = (int(v) for v in line.split("[")[1].split("]")[0].split(","))
    assert right + top == 150 and right > 40 and top > 40, line
    assert (tmp_path / "routing.png").stat().st_size > 10000

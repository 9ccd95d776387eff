"""A crowd leaving a room through a door (the particle engine at scale, as examples/crowd.toml):
people walk to the nearest point of the door, hard non-overlap by PBD, the walls are segments.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/crowd_evacuation.py [OUT_DIR]

Writes OUT_DIR/evacuation.png (default out/python_crowd): people out against time, and the
room at three times.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from moreau import particles  # noqa: E402

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python_crowd")
out.mkdir(parents=True, exist_ok=True)

n = 120
room = particles.Room(width=10.0, height=10.0, door_width=1.2)
radius = np.random.default_rng(7).uniform(0.2, 0.3, n)
model = particles.ParticleModel(dimension=2, radius=radius)
particles.add_room(room, model)
x0 = particles.random_sequential_addition(model, [0.5, 0.5, 0.0], [9.5, 9.5, 0.0], seed=7)
forces = particles.Forces(propulsion=room.walk_to_the_door(1.3), diffusion=0.005)
engine = particles.Engine(model, x0, forces, h=0.002, sweeps=8, skin_factor=2.0, seed=7)

count = particles.EvacuationCount(room, n)
times, outside, snapshots = [], [], {}


def observe(e):
    # stored_positions and stored_ids are views of the engine's arrays: no copy per call.
    times.append(e.time)
    outside.append(count.update_stored(e.stored_ids, e.stored_positions))
    if round(e.time, 6) in (0.0, 10.0, 20.0):
        snapshots[round(e.time, 6)] = e.positions()


summary = engine.run(30.0, observer=observe, every=50)
print(summary.brief_report())
print(f"{count.out} of {n} people out after 30 s")

fig, axes = plt.subplots(1, 4, figsize=(16, 4))
axes[0].plot(times, outside)
axes[0].set_xlabel("time (s)")
axes[0].set_ylabel("people out")
for ax, (t, p) in zip(axes[1:], sorted(snapshots.items())):
    for (cx, cy), r in zip(p, radius):
        ax.add_patch(plt.Circle((cx, cy), r, color="tab:blue"))
    for s in room.walls():
        ax.plot([s.a[0], s.b[0]], [s.a[1], s.b[1]], "k-")
    ax.set_xlim(-0.5, 16.0)
    ax.set_ylim(-0.5, 10.5)
    ax.set_aspect("equal")
    ax.set_title(f"t = {t:g} s")
fig.savefig(out / "evacuation.png", dpi=110)
print(f"wrote {out / 'evacuation.png'}")

"""A crowd leaving a room with a pillar by the nearer of two exits (docs/crowds.md "Geometry and
routing", from Python): the walking distance to the nearest exit on a grid gives each person the
direction −∇d, the collision-free speed model the speed, PBD keeps people apart.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/crowd_routing.py [OUT_DIR]

Writes OUT_DIR/routing.png (default out/python_crowd_routing): the distance field and its
directions, the crowd at two times, and the people out by each exit against time.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from moreau import particles  # noqa: E402

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python_crowd_routing")
out.mkdir(parents=True, exist_ok=True)

room = particles.parse_crowd_geometry("""
walkable 0 0  16 0  16 10  0 10
obstacle 10 4  12 4  12 6  10 6    # a pillar in front of the right exit
exit 16 4.4  16 5.6                # right
exit 2 10  3.2 10                  # top left
""", "room")
n = 150
model = particles.ParticleModel(dimension=2, radius=np.full(n, 0.15))
model.segments = room.walls()
x0 = particles.random_sequential_addition(model, [0.5, 0.5, 0.0], [15.5, 3.5, 0.0], seed=7)
route = particles.DistanceField(room, spacing=0.1, clearance=0.2)
walking = particles.WalkingSpeeds(speed_sd=0.1, collision_free=particles.CollisionFreeSpeed())
forces = particles.Forces(propulsion=particles.SelfPropulsion(speed=1.34, route=route),
                          walking=walking)
engine = particles.Engine(model, x0, forces, h=0.01, seed=7)

count = particles.EvacuationCount(room, n)
times, per_exit, snapshots = [], [], {}


def observe(e):
    times.append(e.time)
    count.update_stored(e.stored_ids, e.stored_positions)
    per_exit.append(list(count.out_per_exit))
    if round(e.time, 6) in (0.0, 6.0):
        snapshots[round(e.time, 6)] = e.positions()
    return count.out < n


summary = engine.run(120.0, observer=observe, every=10)
print(summary.brief_report())
print(f"{count.out} of {n} out after {engine.time:.1f} s: {count.out_per_exit} by exit "
      "(right, top left)")

fig, axes = plt.subplots(1, 4, figsize=(19, 4))
gx, gy = np.meshgrid(np.linspace(0.05, 15.95, 160), np.linspace(0.05, 9.95, 100))
d = np.vectorize(route.distance)(gx, gy)
image = axes[0].imshow(np.where(np.isfinite(d), d, np.nan), origin="lower",
                       extent=(0, 16, 0, 10), cmap="viridis")
fig.colorbar(image, ax=axes[0], label="walking distance to an exit (m)")
qx, qy = np.meshgrid(np.arange(0.5, 16, 1.0), np.arange(0.5, 10, 1.0))
e = np.array([[route.direction(x, y) if room.walkable_at(x, y) else [np.nan, np.nan]
               for x, y in zip(rx, ry)] for rx, ry in zip(qx, qy)])
axes[0].quiver(qx, qy, e[..., 0], e[..., 1], color="white", scale=25)
axes[0].set_title("routing field: d and −∇d")
for ax, (t, p) in zip(axes[1:3], sorted(snapshots.items())):
    for cx, cy in p:
        ax.add_patch(plt.Circle((cx, cy), 0.15, color="tab:blue"))
    ax.set_title(f"t = {t:g} s")
for ax in axes[:3]:
    for s in room.walls():
        ax.plot([s.a[0], s.b[0]], [s.a[1], s.b[1]], "k-")
    ax.set_xlim(-0.5, 18.0)
    ax.set_ylim(-0.5, 11.5)
    ax.set_aspect("equal")
per_exit = np.array(per_exit)
axes[3].plot(times, per_exit[:, 0], label="right exit (behind the pillar)")
axes[3].plot(times, per_exit[:, 1], label="top left exit")
axes[3].set_xlabel("time (s)")
axes[3].set_ylabel("people out")
axes[3].legend()
fig.tight_layout()
fig.savefig(out / "routing.png", dpi=80)
print(f"wrote {out / 'routing.png'}")

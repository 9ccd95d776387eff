"""A cell colony: disks of two sizes with hard volume exclusion (PBD through the particle core)
drift toward a nutrient source and swirl around it, by a force written in Python.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/cell_colony.py [OUT_DIR]

Writes OUT_DIR/colony.png (default out/python_cell_colony): the colony at t = 0 and t = T.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import moreau  # noqa: E402

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python_cell_colony")
out.mkdir(parents=True, exist_ok=True)

n = 300
rng = np.random.default_rng(1)
radius = np.where(rng.random(n) < 0.3, 0.15, 0.1)  # two cell types
model = moreau.particles.ParticleModel(dimension=2, radius=radius)
lo, hi = [-4.0, -4.0, 0.0], [4.0, 4.0, 0.0]
x0 = moreau.particles.random_sequential_addition(model, lo, hi, seed=3)


def chemotaxis_and_swirl(x):
    """Drift (size 2N): speed 1 toward the origin, saturating near it, plus a rotation whose
    rate is larger for the small cells. x is a read-only view of the state (no copy)."""
    p = x.reshape(-1, 2)
    d = np.sqrt((p**2).sum(axis=1, keepdims=True) + 1.0)
    swirl = np.where(radius[:, None] < 0.12, 0.4, 0.1) * np.stack([-p[:, 1], p[:, 0]], axis=1)
    return (-p / d + swirl / d).ravel()


T = 6.0
# PNGS: sweeps until the projections stop moving, so the packed colony keeps its cells apart.
x, summary = moreau.pbd.simulate(chemotaxis_and_swirl, moreau.pbd.ParticleConstraints(model),
                                 x0.ravel(), T, h=0.01, method="pngs", reltol=1e-6,
                                 abstol=1e-9, max_sweeps=200)
print(summary.brief_report())

fig, axes = plt.subplots(1, 2, figsize=(10, 5))
for ax, state, title in ((axes[0], x0.ravel(), "t = 0"), (axes[1], x, f"t = {T:g}")):
    p = state.reshape(-1, 2)
    for (cx, cy), r in zip(p, radius):
        ax.add_patch(plt.Circle((cx, cy), r, color="tab:orange" if r > 0.12 else "tab:green"))
    ax.set_xlim(-4.5, 4.5)
    ax.set_ylim(-4.5, 4.5)
    ax.set_aspect("equal")
    ax.set_title(title)
fig.suptitle(f"cell colony, {n} cells: largest overlap {summary.max_violation:.1e}")
fig.savefig(out / "colony.png", dpi=120)
print(f"wrote {out / 'colony.png'}")

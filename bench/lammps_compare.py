"""Helpers of bench/lammps_compare.sh (run with /usr/bin/python3: numpy, h5py).

  start N DIR STEPS_PER_L THREADS...   writes the shared start of N disks: DIR/start.data (LAMMPS
                                       read_data), DIR/moreau_tT.toml per thread count T, and
                                       DIR/run.env (L, h, steps, stiffness) for the shell script
  overlap FILE                         max, mean and count of pair overlaps in the last frame of
                                       FILE (a LAMMPS custom dump "id x y" or a moreau
                                       trajectory.h5), as one JSON line

The workload is particles_bench's: N = side² disks of radius 0.5 on a square lattice at packing
fraction 0.5 in [−L/2, L/2]², drift −x (mobility 1), h = 0.01/L. The lattice is jittered by up to
0.125 per coordinate (more than the benchmark's 0.08, so that near-contacts exist from the start);
a disk that would overlap a lattice neighbour keeps its lattice site, which leaves every gap ≥ 0.
"""
import json
import math
import sys

import numpy as np

RADIUS = 0.5
PACKING = 0.5
JITTER = 0.125


def lattice_start(n, seed=12345):
    """(positions N×2, L) of the jittered lattice, feasible by construction."""
    side = int(round(math.sqrt(n)))
    a = math.sqrt(math.pi * RADIUS**2 / PACKING)
    length = a * side
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
    site = np.stack([-0.5 * length + a * (i.ravel() + 0.5), -0.5 * length + a * (j.ravel() + 0.5)],
                    axis=1)
    x = site + rng.uniform(-JITTER, JITTER, size=site.shape)
    # Only lattice neighbours can overlap (diagonal ones are ≥ a√2 − 2√2·0.125 > 2r apart); both
    # disks of such a pair go back to their sites, which are ≥ a − √2·0.125 > 2r from any disk.
    i, j, _ = pair_overlaps(x)
    x[i] = site[i]
    x[j] = site[j]
    return x, length


def pair_overlaps(x, cutoff=2 * RADIUS):
    """(i, j, overlap) of every pair i < j closer than cutoff, overlap = cutoff − |x_i − x_j|
    (a cell grid of edge cutoff)."""
    n = len(x)
    cell = np.floor((x - x.min(axis=0)) / cutoff).astype(np.int64)
    nx, ny = cell.max(axis=0) + 3  # a ring of empty cells around, so neighbours never wrap
    key = (cell[:, 0] + 1) * ny + cell[:, 1] + 1
    order = np.argsort(key, kind="stable")
    counts = np.bincount(key, minlength=nx * ny)
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    members = np.full((nx * ny, counts.max()), -1, dtype=np.int64)
    members[key[order], np.arange(n) - start[key[order]]] = order
    pairs_i, pairs_j, overlaps = [], [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            other = members[key + dx * ny + dy]  # n × (most disks in a cell)
            for j in other.T:
                i = np.nonzero(j > np.arange(n))[0]
                overlap = cutoff - np.hypot(*(x[i] - x[j[i]]).T)
                close = overlap > 0
                pairs_i.append(i[close])
                pairs_j.append(j[i][close])
                overlaps.append(overlap[close])
    return np.concatenate(pairs_i), np.concatenate(pairs_j), np.concatenate(overlaps)


def read_last_frame(path):
    if path.endswith(".h5"):
        import h5py
        with h5py.File(path, "r") as f:
            n = int(f["count"][-1])
            return np.asarray(f["positions"][-1, :n, :2], dtype=np.float64)
    # LAMMPS custom dump with columns id x y; the last ITEM: ATOMS block.
    with open(path) as f:
        lines = f.read().splitlines()
    last = max(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    n = int(lines[last - 5])  # ITEM: NUMBER OF ATOMS, then the 4 lines of the box
    table = np.loadtxt(lines[last + 1:last + 1 + n])
    return table[np.argsort(table[:, 0]), 1:3]


def write_start(n, out, steps_per_l, threads):
    x, length = lattice_start(n)
    n = len(x)
    h = 0.01 / length
    steps = max(1, round(steps_per_l * length))
    # Soft repulsion E = A(1 + cos(π r / 2r)): stiffness k = π² A / (2r)² near contact; k·h = 1/2.
    stiffness = 0.5 / h
    amplitude = stiffness * (2 * RADIUS)**2 / math.pi**2
    half = 0.5 * length + 2.0
    with open(f"{out}/start.data", "w") as f:
        f.write(f"disks at packing fraction {PACKING}\n\n{n} atoms\n1 atom types\n\n")
        f.write(f"{-half} {half} xlo xhi\n{-half} {half} ylo yhi\n-0.5 0.5 zlo zhi\n\n")
        f.write("Masses\n\n1 1.0\n\nAtoms # atomic\n\n")
        np.savetxt(f, np.column_stack([np.arange(1, n + 1), np.ones(n), x, np.zeros(n)]),
                   fmt=["%d", "%d", "%.17g", "%.17g", "%g"])
    rows = "\n".join(f"  [{p:.17g}, {q:.17g}]," for p, q in x)
    for t in threads:
        with open(f"{out}/moreau_t{t}.toml", "w") as f:
            f.write(f"""[problem]
kind = "particles"
dimension = 2
count = {n}
radius = {RADIUS}
T = {steps * h!r}

[domain]
lo = [{-half}, {-half}]
hi = [{half}, {half}]

[forces]
trap_gamma = 1.0

[solver]
h = {h!r}
threads = {t}
skin_factor = 1.0

[output]
stride = {steps}
vtu = false
snapshots = false

[initial]
positions = [
{rows}
]
""")
    with open(f"{out}/run.env", "w") as f:
        f.write(f"N={n}\nL={length!r}\nH={h!r}\nSTEPS={steps}\nSOFT_A={amplitude!r}\n"
                f"HALF={half!r}\n")


def main(argv):
    if argv[1] == "start":
        write_start(int(argv[2]), argv[3], float(argv[4]), [int(t) for t in argv[5:]])
    elif argv[1] == "overlap":
        _, _, o = pair_overlaps(read_last_frame(argv[2]))
        print(json.dumps({"max_overlap": float(o.max()) if len(o) else 0.0,
                          "mean_overlap": float(o.mean()) if len(o) else 0.0,
                          "overlapping_pairs": int(len(o))}))
    else:
        sys.exit(f"unknown command {argv[1]}")


if __name__ == "__main__":
    main(sys.argv)

#!/bin/bash
# 10^5 pedestrians (collision-free speed model, r = 0.15 m, v0 = 1.34 m/s) in a 400 m × 400 m
# room with four 4 m exits, one in the middle of each wall, and eight 2 m × 2 m pillars between
# the start area and the walls: the [geometry] routing field (spacing 0.25 m) gives every
# person its walking direction. They start at random in [40, 360]² (0.98 persons/m²).
# With VERTICES=n (default 4) the walkable polygon's sides are cut into about n/4 collinear
# pieces each (a floor plan of n vertices; the exits stay on one piece).
# `moreau run` on THREADS threads (default 2) for T simulated seconds (default 10) with step H
# (default 0.05 s) and Verlet skin SKIN · r (`solver.skin_factor`, default 1, the engine's),
# REPEATS times (default 3); prints per run the simulated seconds per wall second of the time
# loop (setup and the distance field excluded; the engine's total_seconds), the same with the
# process's whole wall time, the engine's phase seconds and the largest overlap after a step.
#
#   bench/crowd_speed.sh [path/to/moreau] [extra --set options ...]
#   H=0.01 T=2 SKIN=1 bench/crowd_speed.sh build/release/moreau
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
moreau=${1:-$here/build/release/moreau}
shift || true
threads=${THREADS:-2}
sim=${T:-10}
h=${H:-0.05}
skin=${SKIN:-1}
repeats=${REPEATS:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 - "$tmp" "$sim" "$h" "$threads" "${VERTICES:-4}" "$skin" <<'PY'
import sys
tmp, T, h, threads, vertices, skin = sys.argv[1:7]
L, m = 400.0, 200.0
pieces = max(1, int(vertices) // 4)
corners = ((0, 0), (L, 0), (L, L), (0, L))
walkable = []
for k in range(4):
    (x0, y0), (x1, y1) = corners[k], corners[(k + 1) % 4]
    for i in range(pieces):
        x, y = x0 + (x1 - x0) * i / pieces, y0 + (y1 - y0) * i / pieces
        if i == 0 or (abs(x - m) > 2.5 and abs(y - m) > 2.5):  # not inside an exit
            walkable.append(f"{x:.6f} {y:.6f}")
lines = ["walkable " + "  ".join(walkable)]
for cx, cy in ((20, m), (L - 20, m), (m, 20), (m, L - 20),
               (20, 20), (L - 20, 20), (20, L - 20), (L - 20, L - 20)):
    lines.append(f"obstacle {cx - 1} {cy - 1}  {cx + 1} {cy - 1}  {cx + 1} {cy + 1}  {cx - 1} {cy + 1}")
lines += [f"exit {L} {m - 2}  {L} {m + 2}", f"exit {m - 2} {L}  {m + 2} {L}",
          f"exit 0 {m - 2}  0 {m + 2}", f"exit {m - 2} 0  {m + 2} 0"]
open(f"{tmp}/room.txt", "w").write("\n".join(lines) + "\n")
open(f"{tmp}/crowd.toml", "w").write(f"""[problem]
kind = "particles"
dimension = 2
count = 100000
radius_min = 0.15
radius_max = 0.15
T = {T}
seed = 1

[geometry]
file = "room.txt"
spacing = 0.25
clearance = 0.2

[domain]
lo = [40.0, 40.0]
hi = [360.0, 360.0]

[forces]
propulsion_speed = 1.34
pedestrian_model = "collision_free"

[solver]
h = {h}
threads = {threads}
skin_factor = {skin}

[output]
stride = 1000000
vtu = false
""")
PY
echo "10^5 people, T = $sim s, h = $h s, skin $skin r, $threads threads, ${VERTICES:-4}-vertex room, $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)"
for ((rep = 1; rep <= repeats; ++rep)); do
  start=$(date +%s.%N)
  "$moreau" run "$tmp/crowd.toml" --out "$tmp/r$rep" "$@" >/dev/null
  end=$(date +%s.%N)
  /usr/bin/python3 - "$tmp/r$rep/summary.json" "$start" "$end" "$sim" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
sim, wall = float(sys.argv[4]), float(sys.argv[3]) - float(sys.argv[2])
loop = d["total_seconds"]  # all steps, setup excluded
steps = d["steps"]
print(f"{sim / loop:.2f}x real time ({1e3 * loop / steps:.1f} ms per step, "
      f"{1e9 * loop / (steps * 1e5):.0f} ns per person-step); whole process {wall:.1f} s "
      f"({sim / wall:.2f}x); force {d['force_seconds']:.2f} s, sweep {d['sweep_seconds']:.2f} s, "
      f"neighbour {d['neighbour_seconds']:.2f} s ({d['neighbour_list_builds']} builds), "
      f"setup {d['setup_seconds']:.2f} s; largest overlap {d['max_overlap']:.3f} m")
PY
done

#!/usr/bin/python3
"""examples/disks_1e6.toml through `moreau run` with several binaries taking turns, for comparing
builds on a machine whose speed drifts (docs/benchmarks.md, "Paired rounds").

    bench/disks_1e6_ab.py THREADS REPEATS T MOREAU [MOREAU ...]

Each round runs every binary once (OMP_NUM_THREADS=THREADS, problem.T=T, its own OpenMP wait
policy unless the caller set one); per binary it prints the minimum and the median over the rounds
of: ms per step (the engine's total_seconds over its steps; setup excluded), ms per list build and
the sweep, prediction and monitor ms per step, and the set of positions hashes (one per binary
when the results agree); then, for each binary after the first, the first's step and build times
over its own, round by round (median and range).
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    threads, repeats, horizon = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    binaries = sys.argv[4:]
    env = dict(os.environ, OMP_NUM_THREADS=threads)
    rows = {b: [] for b in binaries}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(repeats):
            for i, b in enumerate(binaries):
                out = os.path.join(tmp, f"run{i}")
                subprocess.run(["rm", "-rf", out], check=True)
                subprocess.run([b, "run", os.path.join(ROOT, "examples/disks_1e6.toml"), "--out", out,
                                "--set", f"problem.T={horizon}"], env=env, check=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                with open(os.path.join(out, "summary.json")) as f:
                    d = json.load(f)
                steps = d["steps"]
                builds = max(1, d["neighbour_list_builds"])
                rows[b].append((1e3 * d["total_seconds"] / steps, 1e3 * d["neighbour_seconds"] / builds,
                                1e3 * d["sweep_seconds"] / steps, 1e3 * d["force_seconds"] / steps,
                                1e3 * d["monitor_seconds"] / steps, d.get("positions_hash", "")))
    for b in binaries:
        cols = list(zip(*rows[b]))
        def stat(i):
            return f"{min(cols[i]):6.2f}/{statistics.median(cols[i]):6.2f}"
        print(f"{b}: threads {threads}, min/median: step ms {stat(0)} ({1e3 / min(cols[0]):.1f} "
              f"steps/s), build ms {stat(1)}, sweep {stat(2)}, prediction {stat(3)}, "
              f"monitor {stat(4)}; hashes {sorted(set(cols[5]))}")
    # Each round runs the binaries back to back, so the ratio within a round cancels the slower
    # drifts of the machine's speed: the first binary's time over each other's, round by round.
    ref = binaries[0]
    for b in binaries[1:]:
        def paired(i):
            r = sorted(x[i] / y[i] for x, y in zip(rows[ref], rows[b]))
            return f"{statistics.median(r):.2f}x ({r[0]:.2f}-{r[-1]:.2f})"
        print(f"{b}: {ref} over it, round by round, median (range): step {paired(0)}, "
              f"build {paired(1)}")


if __name__ == "__main__":
    main()

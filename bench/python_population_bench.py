"""The cost of Python user code on a population (moreau.particles.Population), in paired rounds.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_population_bench.py \
        [--cli build/release/moreau] [--rounds 3] [--agents 100000] [--threads 2]

1. A trivial Python drift (it writes nothing) against no drift, at 10^5 agents that neither grow
   nor divide: the step time with the drift over the step time without, per round.
2. The colony of examples/python/cell_colony.py (growth, division, its chemotaxis drift and
   activation rule in numpy) against `moreau run` of the same types and rules without user code
   (the tool cannot run the Python parts), as time per agent-step; and the same model in Python
   without user code, whose positions must equal the tool's bit for bit (the same model).
Prints one JSON object.
"""
import argparse
import json
import pathlib
import runpy
import subprocess
import sys
import tempfile
import time

import numpy as np

import moreau
from moreau import particles

ROOT = pathlib.Path(__file__).resolve().parents[1]


def still_population(n, threads):
    """n agents of radius 0.5 packed at area fraction 0.5 in a periodic square, no rules."""
    side = float(np.sqrt(n * np.pi * 0.25 / 0.5))
    model = particles.ParticleModel(dimension=2, radius=np.full(n, 0.5))
    x = particles.random_sequential_addition(model, [0.0, 0.0, 0.0], [side, side, 0.0], seed=1)
    rules = particles.PopulationRules(types=[particles.AgentType(name="cell")], interval=10**6)
    geometry = particles.ParticleModel(dimension=2, radius=[0.5],
                                       periodic=[True, True, False], domain_lo=[0.0, 0.0, 0.0],
                                       domain_hi=[side, side, 1.0])
    return particles.Population(rules, [0] * n, x, geometry=geometry,
                                forces=particles.Forces(diffusion=1e-3), h=0.01,
                                threads=threads)


def drift_overhead(n, threads, rounds, steps=20):
    ratios, plain_ms, drift_ms = [], [], []
    for _ in range(rounds):
        times = {}
        for name in ("plain", "drift"):
            p = still_population(n, threads)
            if name == "drift":
                p.drift = lambda pop, velocity: None
            p.step(2)  # warm
            start = time.perf_counter()
            p.step(steps)
            times[name] = (time.perf_counter() - start) / steps * 1e3
        plain_ms.append(times["plain"])
        drift_ms.append(times["drift"])
        ratios.append(times["drift"] / times["plain"])
    return {"agents": n, "threads": threads, "steps_per_round": steps,
            "ms_per_step_plain": plain_ms, "ms_per_step_drift": drift_ms,
            "ratio_per_round": ratios, "median_ratio": float(np.median(ratios))}


def colony_toml(example, path):
    """The example's types, rules and engine options as a scenario file for `moreau run`."""
    r = example["rules"]
    # problem.seed keys both the rules and the engine's noise (the example uses 3 for both).
    lines = ['[problem]', 'kind = "particles"', 'dimension = 2', 'count = 1',
             f'T = {example["T"]}', 'seed = 3', '[initial]', 'positions = [[0.0, 0.0]]']
    for t in r.types:
        lines.append("[[types]]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in t.to_dict().items()]
    lines += ["[population]", f"interval = {r.interval}",
              f"relax = {str(r.relax).lower()}", f"relax_tolerance = {r.relax_tolerance}",
              "[forces]", "diffusion = 1e-4", "[solver]", "h = 0.02",
              "[output]", "stride = 1000000"]
    path.write_text("\n".join(lines) + "\n")


def colony(cli, rounds):
    example = runpy.run_path(str(ROOT / "examples/python/cell_colony.py"),
                             run_name="cell_colony_bench")
    out = {"T": example["T"]}
    with tempfile.TemporaryDirectory() as tmp:
        scenario = pathlib.Path(tmp) / "colony.toml"
        colony_toml(example, scenario)
        cli_s, py_s, user_s = [], [], []
        for k in range(rounds):
            folder = pathlib.Path(tmp) / f"run{k}"
            subprocess.run([cli, "run", str(scenario), "--out", str(folder)], check=True,
                           capture_output=True)
            s = json.loads((folder / "summary.json").read_text())
            cli_s.append(s["total_seconds"] / max(1, s["engine"]["steps"] * s["final_count"]))
            plain = example["make"](user_code=False)
            ps = plain.run(example["T"])
            py_s.append(ps.total_seconds / max(1, ps.to_dict()["engine"]["steps"] * plain.count))
            same = s["positions_hash"] == moreau.hash_doubles(plain.positions)
            user = example["make"](user_code=True)
            us = user.run(example["T"])
            user_s.append(us.total_seconds / max(1, us.to_dict()["engine"]["steps"] * user.count))
        out.update({
            "tool_final_count": s["final_count"], "python_final_count": plain.count,
            "same_positions_as_the_tool": same, "python_with_user_code_final_count": user.count,
            "us_per_agent_step_tool": [1e6 * v for v in cli_s],
            "us_per_agent_step_python": [1e6 * v for v in py_s],
            "us_per_agent_step_python_user_code": [1e6 * v for v in user_s],
            "median_ratio_user_code_over_tool": float(np.median(np.array(user_s) / cli_s)),
        })
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=str(ROOT / "build/release/moreau"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--agents", type=int, default=100000)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    result = {"drift_overhead": drift_overhead(a.agents, a.threads, a.rounds),
              "colony": colony(a.cli, a.rounds)}
    json.dump(result, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()

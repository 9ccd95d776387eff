#!/usr/bin/env python3
"""The collision-free speed model side by side in moreau and in JuPedSim (docs/crowds.md).

Run with the Python of the virtual environment that `make crowds-venv` makes (JuPedSim and PedPy
from PyPI, pinned in tests/crowds/requirements.txt):

    build/crowds-venv/bin/python scripts/crowd_jupedsim.py build/release/moreau out/jupedsim

The same people (the same start, moreau's random sequential addition, read from its first frame;
one desired speed v0 = 1.34 m/s) walk with the same parameters in both codes, mapped explicitly:
moreau's T, ℓ, a, D, a_w, D_w are JuPedSim's agent `time_gap`, the agents' `radius` ℓ/2
(JuPedSim's length of a pair is the sum of the two radii), `strength_neighbor_repulsion`,
`range_neighbor_repulsion`, `strength_geometry_repulsion` and `range_geometry_repulsion`; the time
step is h = 0.01 s in both, frames every 0.1 s. Scenarios:

- the bottleneck of scripts/crowd_bottleneck.py: an 8 m × 8 m room, N = 150 people, a door of
  width b in the middle of its right wall (for JuPedSim a wall 0.01 m thick; moreau's walls are
  segments), open space behind it; a person leaves the data 2 m past the door (JuPedSim removes
  them there, moreau's rows beyond are dropped);
- a corridor 3 m wide between two walls, not periodic (JuPedSim has no periodic boundaries): a
  block of people at density ρ over 60 m walks in +x; measured in [40, 50] m × [0, 3] m between
  15 and 30 s, while that area is inside the block and away from its front.

PedPy analyses both trajectory files (JuPedSim's SQLite file; moreau's trajectory.txt, or, where
this moreau does not write one, its trajectory.h5 converted to the same text format id frame x y z):
the passages of the door line (compute_n_t), the steady flow J = (N − 20)/(t_(N−10) − t_10), the
evacuation times of the first N − 10 and of all, the classic and Voronoi densities in the 1 m deep
area of the door's width in front of the door during the steady part, and in the corridor the
classic and Voronoi densities and the mean speed in the measurement area.

--timing also times both codes on one corridor 10 m wide at 1 person/m² with 10^3 and 10^4 people
(5 s of simulated time, h = 0.01 s, no output; moreau on 2 threads, JuPedSim on one, as it runs),
in paired rounds, and writes docs/results/crowds/speed_vs_jupedsim.csv.

usage: crowd_jupedsim.py MOREAU OUT_DIR [--widths B ...] [--densities RHO ...] [--people N]
                         [--block L] [--seeds N] [--csv CSV] [--figure PNG] [--timing]
                         [--timing-csv CSV] [--reuse]
"""
import argparse
import csv
import json
import pathlib
import re
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import crowd_bottleneck  # noqa: E402
import crowd_jupedsim_plot  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs/results/crowds"
# The model's parameters (moreau's defaults), given to both codes explicitly.
TIME_GAP, LENGTH, REPULSION, RANGE, WALL_REPULSION, WALL_RANGE = 1.0, 0.3, 5.0, 0.1, 5.0, 0.02
V0, STEP, STRIDE = 1.34, 0.01, 10  # desired speed (m/s), time step (s), steps per frame
ROOM, WALL, LEAVE = 8.0, 0.01, 10.0  # room size, JuPedSim's wall thickness, where people leave
PEOPLE, SKIP = 150, 10
DOOR_DURATION = 160.0
WIDTHS = [0.8, 1.2, 2.0]
DENSITIES = [1.0, 2.0]
CORRIDOR_WIDTH, BLOCK, CORRIDOR_DURATION = 3.0, 60.0, 30.0
CORRIDOR_AREA, CORRIDOR_WINDOW = (40.0, 50.0), (15.0, 30.0)


def model_keys():
    """The model's parameters as lines of [forces] (moreau)."""
    values = {"time_gap": TIME_GAP, "length": LENGTH, "repulsion": REPULSION,
              "repulsion_range": RANGE, "wall_repulsion": WALL_REPULSION,
              "wall_repulsion_range": WALL_RANGE}
    return [f"collision_free.{k} = {v!r}" for k, v in values.items()]


def jupedsim_model():
    import jupedsim as jps
    return jps.CollisionFreeSpeedModel(
        strength_neighbor_repulsion=REPULSION, range_neighbor_repulsion=RANGE,
        strength_geometry_repulsion=WALL_REPULSION, range_geometry_repulsion=WALL_RANGE)


def writes_text(moreau):
    """Whether this moreau writes trajectory.txt (output.trajectory_txt)."""
    keys = subprocess.run([moreau, "keys"], capture_output=True, text=True).stdout
    return "output.trajectory_txt" in keys


def with_output(text, stride=STRIDE, hdf5=True, txt=False):
    """The scenario text with its [output] table replaced."""
    head = text[:text.index("[output]")]
    lines = [f"stride = {stride}", f"hdf5 = {str(hdf5).lower()}", "vtu = false",
             "snapshots = false"] + (["trajectory_txt = true"] if txt else [])
    return head + "[output]\n" + "\n".join(lines) + "\n"


REUSE = False  # --reuse: keep the runs already in OUT_DIR (the same scenario text), analyse again


def moreau_run(moreau, out, name, text, threads=None):
    """Runs the scenario as OUT/name; returns (folder, wall-clock seconds)."""
    toml = out / f"{name}.toml"
    if REUSE and toml.is_file() and toml.read_text() == text and (
            out / name / "summary.json").is_file():
        return out / name, float("nan")
    (out / f"{name}.toml").write_text(text)
    args = [moreau, "run", str(out / f"{name}.toml"), "--out", str(out / name)]
    if threads:
        args += ["--set", f"solver.threads={threads}"]
    start = time.perf_counter()
    r = subprocess.run(args, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if r.returncode != 0:
        sys.exit(f"{name}: {r.stderr.strip()}")
    return out / name, seconds


def first_frame(run_dir):
    import h5py
    with h5py.File(run_dir / "trajectory.h5", "r") as f:
        n = int(f["count"][0])
        order = np.argsort(f["ids"][0, :n])
        return f["positions"][0, :n][order]


def h5_to_txt(run_dir):
    """moreau's trajectory.h5 as trajectory.txt, id frame x y z (PeTrack's text format)."""
    import h5py
    with h5py.File(run_dir / "trajectory.h5", "r") as f:
        t, counts, x, ids = f["time"][()], f["count"][()], f["positions"][()], f["ids"][()]
    rate = round(1.0 / (t[1] - t[0]), 6)
    rows = [np.column_stack([ids[k, :n], np.full(n, k), x[k, :n, 0], x[k, :n, 1], np.zeros(n)])
            for k, n in enumerate(counts)]
    path = run_dir / "trajectory_converted.txt"
    np.savetxt(path, np.vstack(rows), fmt="%d %d %.6f %.6f %.6f",
               header=f"framerate: {rate:g}\nid frame x/m y/m z/m", comments="# ")
    return path


def trajectory(path, leave):
    """PedPy's trajectory of a text or SQLite file, rows at x ≥ leave dropped."""
    import pedpy
    if path.suffix == ".sqlite":
        traj = pedpy.load_trajectory_from_jupedsim_sqlite(trajectory_file=path)
    else:
        try:
            traj = pedpy.load_trajectory_from_txt(trajectory_file=path)
        except pedpy.PedPyValueError:
            traj = pedpy.load_trajectory_from_txt(
                trajectory_file=path, default_frame_rate=1.0 / (STEP * STRIDE),
                default_unit=pedpy.TrajectoryUnit.METER)
    data = traj.data[traj.data.x < leave].reset_index(drop=True)
    return pedpy.TrajectoryData(data=data[["id", "frame", "x", "y"]], frame_rate=traj.frame_rate)


def moreau_trajectory(run_dir, leave):
    txt = run_dir / "trajectory.txt"
    return trajectory(txt if txt.is_file() else h5_to_txt(run_dir), leave)


def jupedsim_run(geometry, exit_area, positions, duration, sqlite=None, steer=None):
    """JuPedSim's CollisionFreeSpeedModel from the positions until everybody has left or
    `duration`; returns the seconds it took (set-up included). Without `steer` people follow
    JuPedSim's own routing to the exit area (its centroid, along the shortest path through the
    navigation mesh); with it they walk toward steer(x, y) each step (a direct-steering stage:
    moreau's desired direction) and leave once inside the exit area."""
    import jupedsim as jps
    if REUSE and sqlite is not None and sqlite.is_file():
        return float("nan")
    start = time.perf_counter()
    writer = None if sqlite is None else jps.SqliteTrajectoryWriter(
        output_file=sqlite, every_nth_frame=STRIDE)
    sim = jps.Simulation(model=jupedsim_model(), geometry=geometry, dt=STEP,
                         trajectory_writer=writer)
    stage = sim.add_exit_stage(exit_area) if steer is None else sim.add_direct_steering_stage()
    journey = sim.add_journey(jps.JourneyDescription([stage]))
    for p in positions:
        sim.add_agent(jps.CollisionFreeSpeedModelAgentParameters(
            position=(float(p[0]), float(p[1])), time_gap=TIME_GAP, desired_speed=V0,
            radius=LENGTH / 2, journey_id=journey, stage_id=stage))
    steps = round(duration / STEP)
    leave = exit_area.bounds[0]
    while sim.agent_count() > 0 and sim.iteration_count() < steps:
        if steer is not None:
            for agent in sim.agents():
                x, y = agent.position
                if x >= leave:
                    sim.mark_agent_for_removal(agent.id)
                else:
                    agent.target = steer(x, y)
        sim.iterate()
    if writer is not None:
        writer.close()  # commits the last frames
    return time.perf_counter() - start


def door_steer(b):
    """moreau's desired direction in the room (Room::WalkToTheDoor with the clearance l/2) as a
    target: the nearest point of the door's opening shrunk by l/2 at each post for someone
    beside it, straight on (+x) in front of it and past it."""
    lo, hi = (ROOM - b) / 2 + LENGTH / 2, (ROOM + b) / 2 - LENGTH / 2

    def steer(x, y):
        if x >= ROOM or lo <= y <= hi:
            return (min(x + 1.0, LEAVE + 0.4), y)
        return (ROOM, min(max(y, lo), hi))
    return steer


def room_geometry(b):
    """(walkable area, exit area) of the room with the door of width b, as JuPedSim takes them."""
    from shapely import box, union_all
    lo, hi = (ROOM - b) / 2, (ROOM + b) / 2
    walkable = union_all([box(0, 0, ROOM, ROOM), box(ROOM - 0.001, lo, ROOM + WALL + 0.001, hi),
                          box(ROOM + WALL, 0, LEAVE + 0.5, ROOM)])
    return walkable, box(LEAVE, 0, LEAVE + 0.5, ROOM)


def door_measures(traj, walkable, b, people):
    """Passages of the door line x = ROOM and densities in front of the door (PedPy)."""
    import pedpy
    from shapely import box
    lo, hi = (ROOM - b) / 2, (ROOM + b) / 2
    # The door line drawn across the whole wall: nobody passes the wall, and a straight step
    # between frames that rounds a door post would cross x = ROOM just beside the door.
    line = pedpy.MeasurementLine([(ROOM, 0.0), (ROOM, ROOM)])
    _, crossing = pedpy.compute_n_t(traj_data=traj, measurement_line=line)
    t = np.sort(crossing["frame"].to_numpy()) / traj.frame_rate
    row = {"passages": len(t), "evac_first_s": np.nan, "evac_all_s": np.nan, "flow_per_s": np.nan,
           "classic_density_per_m2": np.nan, "voronoi_density_per_m2": np.nan}
    if len(t) == 0:
        return row, t
    row["evac_all_s"] = t[-1] if len(t) == people else np.nan
    if len(t) >= people - SKIP and people > 2 * SKIP:
        row["evac_first_s"] = t[people - SKIP - 1]
        row["flow_per_s"] = (people - 2 * SKIP) / (t[people - SKIP - 1] - t[SKIP - 1])
        window = (t[SKIP - 1], t[people - SKIP - 1])
    else:
        window = (t[0], t[-1])
    frames = traj.data.frame / traj.frame_rate
    steady = pedpy.TrajectoryData(
        data=traj.data[(frames >= window[0]) & (frames <= window[1])].reset_index(drop=True),
        frame_rate=traj.frame_rate)
    area = pedpy.MeasurementArea(box(ROOM - 1.0, lo, ROOM, hi))
    row["classic_density_per_m2"] = float(pedpy.compute_classic_density(
        traj_data=steady, measurement_area=area).density.mean())
    every_other = steady.data[steady.data.frame % 2 == 0].reset_index(drop=True)  # 5 per second
    cells = pedpy.compute_individual_voronoi_polygons(
        traj_data=pedpy.TrajectoryData(data=every_other, frame_rate=traj.frame_rate),
        walkable_area=pedpy.WalkableArea(walkable),
        cut_off=pedpy.Cutoff(radius=1.0, quad_segments=3))
    density, _ = pedpy.compute_voronoi_density(individual_voronoi_data=cells,
                                               measurement_area=area)
    row["voronoi_density_per_m2"] = float(density.density[density.frame % 2 == 0].mean())
    return row, t


def thick_wall(text, b):
    """The scenario with segments that give the wall around the door JuPedSim's thickness WALL:
    the door's two sides and the wall's outer face."""
    lo, hi = (ROOM - b) / 2, (ROOM + b) / 2
    segments = [((ROOM, lo), (ROOM + WALL, lo)), ((ROOM, hi), (ROOM + WALL, hi)),
                ((ROOM + WALL, 0.0), (ROOM + WALL, lo)), ((ROOM + WALL, hi), (ROOM + WALL, ROOM))]
    tables = "".join(f"[[segments]]\na = [{p[0]!r}, {p[1]!r}]\nb = [{q[0]!r}, {q[1]!r}]\n"
                     for p, q in segments)
    i = text.index("[forces]")
    return text[:i] + tables + "\n" + text[i:]


def bottleneck(moreau, out, b, people, txt, seed):
    """Both codes through the door of width b: rows of the CSV and the passage times. moreau
    runs twice: with the room's walls (segments, no thickness) and with the wall around the
    door as thick as JuPedSim's (`moreau_wall`)."""
    text = crowd_bottleneck.scenario(b, seed=seed, people=people, duration=DOOR_DURATION,
                                     extra=model_keys(), radius=LENGTH / 2)
    name = f"door_{b:g}_s{seed}"
    run_dir, _ = moreau_run(moreau, out, name, with_output(text, txt=txt))
    wall_dir, _ = moreau_run(moreau, out, f"{name}_wall", with_output(thick_wall(text, b),
                                                                     txt=txt))
    walkable, exit_area = room_geometry(b)
    files = {}
    for code, steer in (("jupedsim", None), ("jupedsim_steered", door_steer(b))):
        files[code] = out / f"{name}_{code}.sqlite"
        if not REUSE:
            files[code].unlink(missing_ok=True)
        jupedsim_run(walkable, exit_area, first_frame(run_dir), DOOR_DURATION, files[code],
                     steer)
    projections = {code: json.loads((d / "summary.json").read_text())["projections"]
                   for code, d in (("moreau", run_dir), ("moreau_wall", wall_dir))}
    rows, passages = [], {}
    for code, traj in [("moreau", moreau_trajectory(run_dir, LEAVE)),
                       ("moreau_wall", moreau_trajectory(wall_dir, LEAVE))] + [
            (code, trajectory(path, LEAVE)) for code, path in files.items()]:
        row, t = door_measures(traj, walkable, b, people)
        row.update(scenario="bottleneck", parameter=b, seed=seed, code=code, people=people,
                   projections=projections.get(code, ""))
        rows.append(row)
        passages[code] = t
    return rows, passages


def corridor_text(people, length, domain, duration, width=CORRIDOR_WIDTH, seed=1):
    """moreau's corridor: walls all round (the far one never reached), people at random in
    [0.2, length] × [0.2, width − 0.2], walking in +x."""
    return f"""[problem]
kind = "particles"
dimension = 2
count = {people}
radius = {LENGTH / 2!r}
T = {duration!r}
seed = {seed}

[domain]
lo = [0.0, 0.0]
hi = [{domain!r}, {width!r}]
box_walls = true

[initial]
lo = [0.2, 0.2]
hi = [{length!r}, {width - 0.2!r}]

[forces]
propulsion_speed = {V0}
direction = [1.0, 0.0]
pedestrian_model = "collision_free"
{chr(10).join(model_keys())}

[solver]
h = {STEP}

[output]
"""


def corridor(moreau, out, rho, block, txt, seed):
    """Both codes in the corridor at density rho: rows of the CSV."""
    import pedpy
    from shapely import box
    people = round(rho * block * CORRIDOR_WIDTH)
    end = block + 2.0 * V0 * CORRIDOR_DURATION  # nobody gets there
    text = corridor_text(people, block, end + 1.0, CORRIDOR_DURATION, seed=seed)
    name = f"corridor_{rho:g}_s{seed}"
    run_dir, _ = moreau_run(moreau, out, name, with_output(text, txt=txt))
    walkable = box(0.0, 0.0, end + 1.0, CORRIDOR_WIDTH)  # moreau's domain.box_walls
    exit_area = box(end, 0.0, end + 1.0, CORRIDOR_WIDTH)
    files = {}
    for code, steer in (("jupedsim", None),
                        ("jupedsim_steered", lambda x, y: (min(x + 1.0, end + 0.9), y))):
        files[code] = out / f"{name}_{code}.sqlite"
        if not REUSE:
            files[code].unlink(missing_ok=True)
        jupedsim_run(walkable, exit_area, first_frame(run_dir), CORRIDOR_DURATION, files[code],
                     steer)
    scale = block / BLOCK  # a shorter block: the area and the window scaled with it
    x0, x1 = (scale * x for x in CORRIDOR_AREA)
    area = pedpy.MeasurementArea(box(x0, 0, x1, CORRIDOR_WIDTH))
    rows = []
    for code, traj in [("moreau", moreau_trajectory(run_dir, end))] + [
            (code, trajectory(path, end)) for code, path in files.items()]:
        speed = pedpy.compute_individual_speed(
            traj_data=traj, frame_step=5,
            speed_calculation=pedpy.SpeedCalculation.BORDER_SINGLE_SIDED)
        mean = pedpy.compute_mean_speed_per_frame(traj_data=traj, individual_speed=speed,
                                                  measurement_area=area)
        classic = pedpy.compute_classic_density(traj_data=traj, measurement_area=area)
        lo, hi = (round(scale * s * traj.frame_rate) for s in CORRIDOR_WINDOW)
        window = traj.data[(traj.data.frame >= lo) & (traj.data.frame <= hi)]
        cells = pedpy.compute_individual_voronoi_polygons(
            traj_data=pedpy.TrajectoryData(data=window.reset_index(drop=True),
                                           frame_rate=traj.frame_rate),
            walkable_area=pedpy.WalkableArea(walkable))
        voronoi, _ = pedpy.compute_voronoi_density(individual_voronoi_data=cells,
                                                   measurement_area=area)

        def in_window(frame):
            return frame[(frame.index >= lo) & (frame.index <= hi)]
        rows.append({"scenario": "corridor", "parameter": rho, "seed": seed, "code": code,
                     "people": people,
                     "classic_density_per_m2": float(in_window(classic).density.mean()),
                     "voronoi_density_per_m2": float(voronoi.density.mean()),
                     "mean_speed_m_s": float(in_window(mean).speed.mean())})
    return rows


COLUMNS = ["scenario", "parameter", "seed", "code", "people", "passages", "flow_per_s",
           "specific_flow_per_m_s", "evac_first_s", "evac_all_s", "classic_density_per_m2",
           "voronoi_density_per_m2", "mean_speed_m_s", "projections"]


def write_csv(rows, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        f.write("# scripts/crowd_jupedsim.py: the collision-free speed model in moreau and "
                "JuPedSim 1.4.2, analysed by PedPy 1.5.1 (docs/crowds.md)\n")
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            r = dict(r)
            if r["scenario"] == "bottleneck":
                r["specific_flow_per_m_s"] = r["flow_per_s"] / r["parameter"]
            w.writerow({k: (f"{v:.4f}" if isinstance(v, float) and k != "parameter" else
                            r.get(k, "")) for k, v in ((k, r.get(k, "")) for k in COLUMNS)})


def timing(moreau, out, sizes, rounds, path, duration=5.0, width=10.0):
    """Paired rounds on the same corridor block: moreau on 2 threads and on 1 (the whole `moreau
    run`, and its own engine time, summary.json total_seconds), then JuPedSim (one thread)."""
    from shapely import box
    rows = []
    for people in sizes:
        block = people / width  # 1 person/m^2
        end = block + 2.0 * V0 * duration + 5.0
        text = corridor_text(people, block, end + 1.0, duration, width)
        start_dir, _ = moreau_run(moreau, out, f"timing_{people}_start",
                                  with_output(re.sub(r"T = [\d.]+", f"T = {STEP!r}", text)))
        positions = first_frame(start_dir)
        walkable = box(0.0, 0.0, end + 1.0, width)
        quiet = with_output(text, stride=10**6, hdf5=False)
        for k in range(rounds[people]):
            row = [people, k + 1, duration]
            for threads in (2, 1):
                run_dir, seconds = moreau_run(moreau, out, f"timing_{people}_{threads}", quiet,
                                              threads=threads)
                engine = json.loads((run_dir / "summary.json").read_text())["total_seconds"]
                row += [seconds, engine]
            row.append(jupedsim_run(walkable, box(end, 0, end + 1.0, width), positions,
                                    duration))
            rows.append(row)
            print(f"timing: {people} people, round {k + 1}: moreau {row[3]:.2f} s (2 threads), "
                  f"{row[5]:.2f} s (1 thread), JuPedSim {row[7]:.2f} s")
    with open(path, "w", newline="") as f:
        f.write("# scripts/crowd_jupedsim.py --timing: wall-clock seconds for the same corridor "
                f"(10 m wide, 1 person/m^2, {duration:g} s simulated, h = 0.01 s, no output); "
                "moreau: the whole `moreau run` and its engine's total_seconds, on 2 and on 1 "
                "thread; JuPedSim 1.4.2: set-up and steps, one thread; rounds paired, in turn\n")
        w = csv.writer(f)
        w.writerow(["people", "round", "simulated_s", "moreau_2threads_s",
                    "moreau_2threads_engine_s", "moreau_1thread_s", "moreau_1thread_engine_s",
                    "jupedsim_s", "jupedsim_over_moreau_2threads", "jupedsim_over_moreau_1thread"])
        for r in rows:
            w.writerow(r[:3] + [f"{x:.3f}" for x in r[3:]] + [f"{r[7] / r[3]:.2f}",
                                                                f"{r[7] / r[5]:.2f}"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("moreau")
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--widths", type=float, nargs="*", default=WIDTHS)
    ap.add_argument("--densities", type=float, nargs="*", default=DENSITIES)
    ap.add_argument("--people", type=int, default=PEOPLE, help="in the room")
    ap.add_argument("--block", type=float, default=BLOCK, help="corridor block length (m)")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--csv", type=pathlib.Path, default=RESULTS / "jupedsim_side_by_side.csv")
    ap.add_argument("--figure", type=pathlib.Path, default=RESULTS / "jupedsim_side_by_side.png")
    ap.add_argument("--timing", action="store_true")
    ap.add_argument("--reuse", action="store_true",
                    help="analyse the runs already in OUT_DIR again instead of rerunning them")
    ap.add_argument("--timing-csv", type=pathlib.Path, default=RESULTS / "speed_vs_jupedsim.csv")
    args = ap.parse_args()
    global REUSE
    REUSE = args.reuse
    args.out.mkdir(parents=True, exist_ok=True)
    txt = writes_text(args.moreau)
    rows, passages = [], {}
    for b, seed in ((b, seed) for b in args.widths for seed in range(1, args.seeds + 1)):
        mine, t = bottleneck(args.moreau, args.out, b, args.people, txt, seed)
        passages.setdefault(b, t)
        rows += mine
        for r in mine:
            print(f"bottleneck b = {b:g} m, seed {seed}, {r['code']}: "
                  f"J/b = {r['flow_per_s'] / b:.3f}, t_first = {r['evac_first_s']:.1f} s, "
                  f"density {r['classic_density_per_m2']:.2f} (classic), "
                  f"{r['voronoi_density_per_m2']:.2f} (Voronoi)")
    for rho, seed in ((rho, seed) for rho in args.densities for seed in range(1, args.seeds + 1)):
        mine = corridor(args.moreau, args.out, rho, args.block, txt, seed)
        rows += mine
        for r in mine:
            print(f"corridor rho = {rho:g}, seed {seed}, {r['code']}: "
                  f"v = {r['mean_speed_m_s']:.3f} m/s, density {r['classic_density_per_m2']:.2f} "
                  f"(classic), {r['voronoi_density_per_m2']:.2f} (Voronoi)")
    if rows:
        write_csv(rows, args.csv)
    if args.widths:
        crowd_jupedsim_plot.plot(rows, passages, args.figure)
    if args.timing:
        timing(args.moreau, args.out, [1000, 10000], {1000: 3, 10000: 3}, args.timing_csv)


if __name__ == "__main__":
    main()

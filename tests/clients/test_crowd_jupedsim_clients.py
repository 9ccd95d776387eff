"""The side-by-side comparison with JuPedSim (scripts/crowd_jupedsim.py, docs/crowds.md) on a
small room: 30 people, one door of 1.2 m, and a corridor block of 10 m at 1 person/m².

The script runs in CROWDS_VENV (JuPedSim and PedPy from PyPI, tests/crowds/requirements.txt,
made by the Makefile; env MOREAU_CROWDS_VENV); without it these tests skip, saying why. Checked:
both codes let everybody through the door exactly once; PedPy's passages of moreau's trajectory
(moreau's trajectory.txt, or its trajectory.h5 converted by the script) fall in the frame where
moreau's own evacuation.csv counts them; nobody in either code reaches the door sooner than
walking straight to it at v0 allows; the corridor's measures are densities and speeds; and in the
corridor, where no wall stands between neighbours and nothing is projected, moreau's trajectory
and JuPedSim's with moreau's desired direction (`jupedsim_steered`) are the same to within what
JuPedSim's longer neighbour range (3 m against moreau's R) can add."""
import csv
import math
import os
import sqlite3
import subprocess

import h5py
import numpy as np
import pytest

from conftest import CLI, ROOT

VENV = os.environ.get("MOREAU_CROWDS_VENV", str(ROOT / "build/crowds-venv"))
PEOPLE, WIDTH, ROOM, V0, FRAME = 30, 1.2, 8.0, 1.34, 0.1
LENGTH, TIME_GAP, REPULSION, RANGE, STEP = 0.3, 1.0, 5.0, 0.1, 0.01  # the script's parameters
JUPEDSIM_RANGE = 3.0  # JuPedSim's CollisionFreeSpeedModel counts neighbours up to 3 m


@pytest.fixture(scope="module")
def side_by_side(tmp_path_factory):
    if not os.path.isfile(os.path.join(VENV, "installed")):
        pytest.skip(f"{VENV} not made: JuPedSim and PedPy come from PyPI "
                    "(tests/crowds/requirements.txt); `make crowds-venv` makes it when the "
                    "network is reachable")
    out = tmp_path_factory.mktemp("jupedsim")
    table = out / "side_by_side.csv"
    script = str(ROOT / "scripts/crowd_jupedsim.py")
    r = subprocess.run([os.path.join(VENV, "bin", "python"), script, CLI, str(out),
                        "--widths", str(WIDTH), "--people", str(PEOPLE), "--seeds", "1",
                        "--densities", "1.0", "--block", "10", "--csv", str(table),
                        "--figure", str(out / "side_by_side.png")],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-3000:]
    with open(table) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return out, rows


def door_rows(rows):
    return {r["code"]: r for r in rows if r["scenario"] == "bottleneck"}


def test_everybody_passes_the_door_once_in_both_codes(side_by_side):
    _, rows = side_by_side
    door = door_rows(rows)
    assert set(door) == {"moreau", "moreau_wall", "jupedsim", "jupedsim_steered"}
    for code, r in door.items():
        if code == "moreau_wall":  # may leave someone standing at a post: tested below
            continue
        assert int(r["passages"]) == PEOPLE, (code, r)
        flow = float(r["flow_per_s"])
        assert flow > 0 and math.isclose(float(r["specific_flow_per_m_s"]), flow / WIDTH,
                                         rel_tol=1e-3), r


def test_pedpy_counts_moreaus_passages_where_moreau_does(side_by_side):
    out, rows = side_by_side
    with open(out / "door_1.2_s1" / "evacuation.csv") as f:
        counted = [(float(r["t"]), int(r["out"])) for r in csv.DictReader(f)]

    def moreau_time(n):
        return next(t for t, k in counted if k >= n)
    r = door_rows(rows)["moreau"]
    # PedPy sees a passage in the first frame (every 0.1 s) after the step moreau counts it in.
    for column, n in (("evac_first_s", PEOPLE - 10), ("evac_all_s", PEOPLE)):
        lag = float(r[column]) - moreau_time(n)
        assert -1e-9 <= lag <= FRAME + 1e-9, (column, lag)


def test_pedpy_counts_who_is_out_with_the_thick_wall_too(side_by_side):
    # With the wall around the door 0.01 m thick (moreau_wall) someone can stand still in front
    # of a post, where the unit desired direction toward the post's corner and the repulsions of
    # the three segments that meet there cancel (e = 0); PedPy's count is moreau's all the same.
    out, rows = side_by_side
    with open(out / "door_1.2_s1_wall" / "evacuation.csv") as f:
        out_at_end = int(list(csv.DictReader(f))[-1]["out"])
    assert int(door_rows(rows)["moreau_wall"]["passages"]) == out_at_end


def test_nobody_reaches_the_door_faster_than_v0(side_by_side):
    out, rows = side_by_side
    with h5py.File(out / "door_1.2_s1" / "trajectory.h5", "r") as f:
        start = f["positions"][0]
    lo, hi = (ROOM - WIDTH) / 2, (ROOM + WIDTH) / 2
    to_door = np.hypot(ROOM - start[:, 0], np.maximum(0, np.maximum(lo - start[:, 1],
                                                                     start[:, 1] - hi)))
    # The 20th passage comes no sooner than the 20th shortest straight walk at v0.
    bound = np.sort(to_door)[PEOPLE - 11] / V0
    for code, r in door_rows(rows).items():
        assert float(r["evac_first_s"]) >= bound, (code, r["evac_first_s"], bound)


def test_the_corridor_measures_are_densities_and_speeds(side_by_side):
    _, rows = side_by_side
    corridor = [r for r in rows if r["scenario"] == "corridor"]
    assert {r["code"] for r in corridor} == {"moreau", "jupedsim", "jupedsim_steered"}
    for r in corridor:
        assert 0 < float(r["mean_speed_m_s"]) <= V0 + 1e-6, r
        assert float(r["classic_density_per_m2"]) > 0 and float(r["voronoi_density_per_m2"]) > 0


def test_the_corridor_is_the_same_walk_in_both_codes_for_a_second(side_by_side):
    # moreau counts neighbours up to R = ℓ + max(T v0, 10 D) (forces.h), JuPedSim up to 3 m.
    # Beyond R the speed is v0 in both, and a neighbour's weight in the direction is below
    # w = a exp((ℓ − R)/D): the sums u = e0 + Σ differ by at most n w (n neighbours between R
    # and 3 m), ê(u) by 2 n w / |u| with |u| ≈ 1 in a one-way corridor (e0 = (1, 0), the
    # repulsions small), a step by h v0 2 n w; over the first second, 100 steps, the positions
    # by about 100 h v0 2 n w (2.6e-4 m here), the growth of earlier differences aside. A
    # parameter mapped wrongly (ℓ against the radii, D_w, a) moves them by centimetres.
    out, _ = side_by_side
    with h5py.File(out / "corridor_1_s1" / "trajectory.h5", "r") as f:
        order = np.argsort(f["ids"][0])
        moreau = f["positions"][:11][:, order]
    with sqlite3.connect(out / "corridor_1_s1_jupedsim_steered.sqlite") as db:
        rows = np.array(db.execute("SELECT frame, id, pos_x, pos_y FROM trajectory_data "
                                   "WHERE frame <= 10 ORDER BY frame, id").fetchall())
    jupedsim = rows[:, 2:].reshape(11, -1, 2)  # agents in the order they were added: moreau's ids
    start = moreau[0]
    assert np.array_equal(jupedsim[0], start)
    r = np.hypot(*(start[:, None, :] - start[None, :, :]).transpose(2, 0, 1))
    reach = LENGTH + max(TIME_GAP * V0, 10 * RANGE)
    n = int(((r > reach) & (r < JUPEDSIM_RANGE)).sum(axis=1).max())
    w = REPULSION * math.exp((LENGTH - reach) / RANGE)
    bound = 100 * STEP * V0 * 2 * n * w
    gap = np.hypot(*(moreau - jupedsim).transpose(2, 0, 1)).max()
    assert 0 < bound < 1e-3 and gap <= bound, (gap, bound, n)

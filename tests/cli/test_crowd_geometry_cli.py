"""Crowd geometry and routing through `moreau run`: the two-exit room with a pillar evacuates
with nobody inside the pillar, each person leaves by the exit nearer by walking distance, the
bottleneck's passage holds its walls, bad geometry gives one line and exit 2, and a run has the
same bits on 1 and 2 threads."""

import h5py
import numpy as np

from conftest import ROOT, run_cli, rejected

EXAMPLE = ROOT / "examples/crowds/two_exits_pillar.toml"
PILLAR = [(6.5, 3.0), (8.0, 3.0), (8.0, 5.0), (6.5, 5.0)]  # examples/crowds/two_exits_pillar.txt
EXITS = [((10.0, 3.4), (10.0, 4.6)), ((0.5, 8.0), (1.7, 8.0))]


def segment_distance(p, a, b):
    ab = np.subtract(b, a)
    t = np.clip(np.dot(np.subtract(p, a), ab) / np.dot(ab, ab), 0.0, 1.0)
    return float(np.hypot(*(np.subtract(p, a) - t * ab)))


def pillar_distance(p):
    """Distance from p to the pillar's edges, negative inside the pillar."""
    d = min(segment_distance(p, PILLAR[i], PILLAR[(i + 1) % 4]) for i in range(4))
    inside = 6.5 < p[0] < 8.0 and 3.0 < p[1] < 5.0
    return -d if inside else d


def positions(out):
    with h5py.File(out / "trajectory.h5", "r") as f:
        return f["positions"][()], f["radii"][()]


def test_two_exit_room_evacuates_around_the_pillar(tmp_path):
    out = tmp_path / "room"
    r = run_cli("run", EXAMPLE, "--out", out)
    assert r.returncode == 0, r.stderr
    x, radii = positions(out)
    clearance = min(pillar_distance(p) - rad for frame, rf in zip(x, radii)
                    for p, rad in zip(frame, rf))
    assert clearance >= -1e-3, clearance  # the engine keeps r_i from every wall segment
    with open(out / "evacuation.csv") as f:
        header, *rows = f.read().split()
    assert header == "t,out"
    assert int(rows[-1].split(",")[1]) == 60
    exits = np.loadtxt(out / "exits.csv", delimiter=",", skiprows=1, dtype=int)
    assert sorted(exits[:, 0]) == list(range(60))
    assert set(exits[:, 1]) == {0, 1}  # both exits are used


def test_each_person_leaves_by_the_nearer_exit(tmp_path):
    # In a clear case the straight line to one exit misses the pillar and is shorter than the
    # straight-line (a lower bound of the walking) distance to the other exit.
    start = [(8.8, 0.8), (9.4, 1.5), (8.8, 7.2), (9.4, 6.6), (1.0, 6.0), (2.0, 6.8), (1.5, 5.0),
             (3.0, 7.0)]
    expected = []
    for p in start:
        d = [segment_distance(p, *e) for e in EXITS]
        expected.append(int(np.argmin(d)))
        assert max(d) > 2.0 * min(d), (p, d)
    scenario = tmp_path / "nearer.toml"
    text = EXAMPLE.read_text().replace('file = "two_exits_pillar.txt"',
                                       f'file = "{ROOT / "examples/crowds/two_exits_pillar.txt"}"')
    text = text.replace("count = 60", f"count = {len(start)}").replace("T = 30.0", "T = 12.0")
    text += "\n[initial]\npositions = [" + ", ".join(f"[{a}, {b}]" for a, b in start) + "]\n"
    scenario.write_text(text)
    out = tmp_path / "nearer"
    r = run_cli("run", scenario, "--out", out)
    assert r.returncode == 0, r.stderr
    exits = np.loadtxt(out / "exits.csv", delimiter=",", skiprows=1, dtype=int)
    assert [int(e) for e in exits[np.argsort(exits[:, 0]), 1]] == expected


def test_bottleneck_passage_holds_its_walls(tmp_path):
    out = tmp_path / "bottleneck"
    r = run_cli("run", ROOT / "examples/crowds/bottleneck.toml", "--out", out)
    assert r.returncode == 0, r.stderr
    x, radii = positions(out)
    in_passage = (x[..., 0] > 8.0) & (x[..., 0] < 10.0)
    # Passage y ∈ [2.1, 2.9] (height 5, door_width 0.8): centres keep r from its walls.
    gap = np.minimum(x[..., 1] - 2.1, 2.9 - x[..., 1]) - radii
    assert in_passage.any()
    assert gap[in_passage].min() >= -1e-3
    with open(out / "evacuation.csv") as f:
        header, *rows = f.read().split()
    assert header == "t,out"
    assert int(rows[-1].split(",")[1]) == 40


def test_inline_polygons_give_the_same_run_as_the_file(tmp_path):
    inline = tmp_path / "inline.toml"
    text = EXAMPLE.read_text().replace(
        'file = "two_exits_pillar.txt"   # relative to this file',
        "walkable = [[0, 0], [10, 0], [10, 8], [0, 8]]\n"
        "obstacles = [[[6.5, 3], [8, 3], [8, 5], [6.5, 5]]]\n"
        "exits = [[[10, 3.4], [10, 4.6]], [[0.5, 8], [1.7, 8]]]")
    inline.write_text(text.replace("T = 30.0", "T = 3.0"))
    runs = []
    for name, scenario in (("file", EXAMPLE), ("inline", inline)):
        out = tmp_path / name
        r = run_cli("run", scenario, "--out", out, "--set", "problem.T=3", "--set",
                    "output.snapshots=false", "--set", "output.snapshot_times=[]")
        assert r.returncode == 0, r.stderr
        runs.append(positions(out)[0])
    assert np.array_equal(runs[0], runs[1])


def test_same_bits_on_one_and_two_threads(tmp_path):
    runs = []
    for threads in (1, 2):
        out = tmp_path / f"t{threads}"
        r = run_cli("run", EXAMPLE, "--out", out, "--set", f"solver.threads={threads}",
                    "--set", "problem.T=3", "--set", "output.snapshots=false", "--set",
                    "output.snapshot_times=[]")
        assert r.returncode == 0, r.stderr
        runs.append(positions(out)[0])
    assert np.array_equal(runs[0], runs[1])


def test_bad_geometry_is_one_line(tmp_path):
    def scenario_with(geometry_text, name="bad.txt"):
        (tmp_path / name).write_text(geometry_text)
        toml = tmp_path / f"{name}.toml"
        toml.write_text(EXAMPLE.read_text().replace("two_exits_pillar.txt", name))
        return toml

    cases = [
        ("walkable 0 0 10 0 10 8 0 8\n# a pillar of two points\nobstacle 6 3 8 3\n"
         "exit 10 3 10 4\n", "bad.txt:3: obstacle 0: needs at least 3 vertices (got 2)"),
        ("walkable 0 0 10 0 10 nan 0 8\n", "bad.txt:1: nan is not a finite number"),
        ("walkable 0 0 10 0 10 8 0 8\nexit 5 5 6 5\n",
         "bad.txt:2: exit 0: not on an edge of the walkable polygon"),
        ("walkable 0 0 10 8 10 0 0 7\nexit 10 1 10 2\n", "bad.txt:1: walkable: edges 0 and 2 cross"),
    ]
    for k, (text, message) in enumerate(cases):
        r = run_cli("run", scenario_with(text, f"bad{k}.txt"), "--out", tmp_path / f"o{k}")
        rejected(r, "geometry.file", message.replace("bad.txt", f"bad{k}.txt"))
        assert not (tmp_path / f"o{k}").exists()
    r = run_cli("run", scenario_with("", "empty.txt"), "--out", tmp_path / "e")
    rejected(r, "empty.txt: no walkable polygon")
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "m", "--set", 'geometry.file="missing.txt"')
    rejected(r, "missing.txt: cannot be read")
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "d", "--set", 'geometry.file="."')
    rejected(r, "geometry.file", ".: not a regular file")
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "s", "--set", "geometry.spacing=0")
    rejected(r, "geometry.spacing", "must be > 0")
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "c", "--set", "geometry.clearance=0.7")
    rejected(r, "geometry.clearance", "no free grid node")
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "p", "--set", "domain.hi=[8.0, 6.5]")
    rejected(r, "geometry", "is not inside the walkable area")
    r = run_cli("run", ROOT / "examples/crowds/bottleneck.toml", "--out", tmp_path / "r",
                "--set", "geometry.spacing=0.2")
    rejected(r, "geometry.spacing and geometry.clearance need a geometry")

"""End-to-end tests of `moreau run` on agent-based scenarios (docs/abm.md): a small
growing colony writes its observables, agents and frames; the same seed gives the same bits; the
crowd leaves through the exit; bad input (negative rates, a division size below the radius, an
unknown type name) gets one line naming the file, the key and the reason, exit code 2, nothing
written."""
import csv
import json

import pytest

from conftest import ROOT, assert_rejected, rejected, run_cli

COLONY = """
[problem]
kind = "particles"
dimension = 2
count = 2
T = 20.0
seed = 4

[initial]
positions = [[-0.6, 0.0], [0.6, 0.0]]
types = ["normal", "tumour"]

[[types]]
name = "normal"
radius = 0.5
growth_rate = 0.02
division_radius = 0.7071
division_rate = 0.1

[[types]]
name = "tumour"
radius = 0.5
growth_rate = 0.04
division_radius = 0.7071
death_rate = 0.01
speed = 0.05
persistence_time = 5.0

[population]
interval = 5

[solver]
h = 0.02
"""


def test_colony_writes_observables_agents_and_frames(tmp_path, write_scenario):
    out = tmp_path / "out"
    r = run_cli("run", write_scenario(COLONY), "--out", out)
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(open(out / "population.csv")))
    assert rows[0]["count"] == "2" and rows[0]["t"] == "0"
    last = rows[-1]
    assert int(last["count"]) == int(last["count_normal"]) + int(last["count_tumour"])
    assert int(last["count"]) == 2 + int(last["births"]) - int(last["deaths"])
    agents = list(csv.DictReader(open(out / "agents.csv")))
    assert len(agents) == int(last["count"])
    assert len({a["id"] for a in agents}) == len(agents)
    summary = json.load(open(out / "summary.json"))
    assert summary["ok"] and summary["final_count"] == len(agents)
    assert summary["settings"]["types"][1]["name"] == "tumour"
    assert (out / "vtu" / "frame.pvd").exists()
    assert (out / "trajectory.xdmf").exists()


def test_changing_population_trajectory_holds_each_frames_count(tmp_path, write_scenario):
    h5py = pytest.importorskip("h5py")  # installed by scripts/install-deps
    out = tmp_path / "out"
    r = run_cli("run", write_scenario(COLONY), "--out", out)
    assert r.returncode == 0, r.stderr
    agents = list(csv.DictReader(open(out / "agents.csv")))
    with h5py.File(out / "trajectory.h5", "r") as f:
        counts = f["count"][:]
        assert counts[0] == 2 and counts[-1] == len(agents)
        assert len(set(counts.tolist())) > 1  # the count did change
        for i, n in enumerate(counts):
            ids = f["ids"][i, :n]
            assert (ids >= 0).all() and len(set(ids.tolist())) == n
            assert (f["ids"][i, n:] == -1).all()
        last_ids = sorted(f["ids"][len(counts) - 1, :counts[-1]].tolist())
    assert last_ids == sorted(int(a["id"]) for a in agents)


def test_same_seed_same_bits_on_one_and_two_threads(tmp_path, write_scenario):
    hashes = []
    for threads in (1, 2):
        out = tmp_path / f"out{threads}"
        r = run_cli("run", write_scenario(COLONY), "--out", out, "--set",
                    f"solver.threads={threads}")
        assert r.returncode == 0, r.stderr
        hashes.append(json.load(open(out / "summary.json"))["positions_hash"])
    assert hashes[0] == hashes[1]


def test_crowd_leaves_through_the_exit(tmp_path):
    out = tmp_path / "crowd"
    r = run_cli("run", ROOT / "examples/abm/crowd_exit.toml", "--out", out, "--set",
                "problem.count=40", "--set", "problem.T=20")
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(open(out / "population.csv")))
    assert int(rows[-1]["removals"]) == 40 - int(rows[-1]["count"])
    assert int(rows[-1]["removals"]) > 0
    # Everybody is out well before T = 60 s of the full example; with 40 people, by 20 s.
    assert rows[-1]["count"] == "0" and rows[-1]["removals"] == "40"


BAD = [
    ("negative_rate", COLONY.replace("death_rate = 0.01", "death_rate = -0.5"), "types.tumour.death_rate",
     "must be ≥ 0 (got -0.5)"),
    ("negative_growth", COLONY.replace("growth_rate = 0.02", "growth_rate = -1"), "types.normal.growth_rate",
     "must be ≥ 0"),
    ("division_below_radius", COLONY.replace("division_radius = 0.7071\ndivision_rate",
                                             "division_radius = 0.4\ndivision_rate"), "types.normal.division_radius",
     "must be > the radius 0.5 (got 0.4)"),
    ("unknown_type", COLONY.replace('types = ["normal", "tumour"]', 'types = ["normal", "stroma"]'),
     "initial.types", "unknown type 'stroma' (types: normal, tumour)"),
    ("unknown_type_key", COLONY.replace("speed = 0.05", "sped = 0.05"), "types.tumour.sped",
     "unknown key"),
    ("radius_with_types", COLONY.replace("T = 20.0", "T = 20.0\nradius = 0.5"), "problem.radius",
     "come from [[types]]"),
    ("interval", COLONY.replace("interval = 5", "interval = 0"), "population.interval", "must be ≥ 1 (got 0)"),
]


@pytest.mark.parametrize("name,text,key,reason", BAD, ids=[b[0] for b in BAD])
def test_bad_abm_input(tmp_path, write_scenario, name, text, key, reason):
    assert_rejected(write_scenario(text), tmp_path / "out", key, reason)


CROWD_SPEEDS = ["forces.propulsion_speed=1.34", "forces.propulsion_speed_sd=0.26",
                "forces.density_radius=1.0"]


def crowd_args(out, *sets):
    args = ["run", ROOT / "examples/abm/crowd_exit.toml", "--out", out]
    for s in ("problem.count=40", "problem.T=4") + sets:
        args += ["--set", s]
    return args


def test_crowd_with_speed_distribution_and_weidmann_same_bits_on_one_and_two_threads(tmp_path):
    hashes = []
    for threads in (1, 2):
        out = tmp_path / f"out{threads}"
        r = run_cli(*crowd_args(out, *CROWD_SPEEDS, f"solver.threads={threads}"))
        assert r.returncode == 0, r.stderr
        hashes.append(json.load(open(out / "summary.json"))["positions_hash"])
    assert hashes[0] == hashes[1]


BAD_CROWD = [
    (["forces.propulsion_speed_sd=0.6"], "forces.propulsion_speed_sd",
     "must be at most propulsion_speed / 3"),
    (["forces.propulsion_speed_sd=-0.1"], "forces.propulsion_speed_sd", "must be ≥ 0 (got -0.1)"),
    (["forces.density_radius=-1"], "forces.density_radius", "must be > 0 (got -1)"),
    (["forces.density_radius=1", "forces.density_max=0"], "forces.density_max",
     "must be > 0 (got 0)"),
    (["forces.density_gamma=2"], "forces.density_radius", "required by forces.density_gamma"),
]


@pytest.mark.parametrize("sets,key,reason", BAD_CROWD, ids=[str(i) for i in range(len(BAD_CROWD))])
def test_bad_crowd_speeds(tmp_path, sets, key, reason):
    out = tmp_path / "out"
    r = run_cli(*crowd_args(out, *sets))
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0] and reason in lines[0], r.stderr
    assert not out.exists()


def test_type_keys_by_name_on_the_command_line_and_in_a_sweep(tmp_path, write_scenario):
    """types.<name>.<key> sets one type's parameter from --set and from a sweep's axes."""
    scenario = write_scenario(COLONY)
    r = run_cli("run", scenario, "--set", "types.tumour.death_rate=0.5", "--out", tmp_path / "a")
    assert r.returncode == 0, r.stderr
    types = json.loads((tmp_path / "a/summary.json").read_text())["settings"]["types"]
    assert [t["death_rate"] for t in types] == [0.0, 0.5]
    r = run_cli("run", scenario, "--set", "types.stroma.radius=1", "--out", tmp_path / "b")
    rejected(r, "types.stroma.radius=1", 'no [[types]] entry has name = "stroma"')
    # In a sweep's axes the key reaches the type's field and its check (a bad value is refused
    # before any run, naming the run and the reason the tool gives).
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(f'command = "run"\nscenario = "{scenario}"\n'
                     "[axes]\ntypes.tumour.death_rate = [0.5, -1.0]\n")
    rejected(run_cli("sweep", sweep, "--out", tmp_path / "s"), "axes.types.tumour.death_rate",
             "run 1", "types.tumour.death_rate: must be ≥ 0 (got -1)")
    assert not (tmp_path / "s").exists()
    sweep.write_text(sweep.read_text().replace("[0.5, -1.0]", "[0.5]"))
    r = run_cli("sweep", sweep, "--out", tmp_path / "s")
    with open(tmp_path / "s/results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [row["types.tumour.death_rate"] for row in rows] == ["0.5"], r.stderr
    assert rows[0]["status"] == "completed", rows[0]

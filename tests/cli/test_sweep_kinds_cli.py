"""`moreau sweep` runs every kind of scenario `moreau run` runs (agent-based models, rooms with a
fixed crowd or a population, the paper's cases) through the run command's own dispatch: each row
holds what the single `moreau run` with the same --set values writes in its summary.json. The
first run of the grid is checked before anything runs (exit 2, one line, nothing written), and a
sweep with failed runs exits 3."""
import csv
import json

import pytest

from conftest import ROOT, run_cli

MONOLAYER = ROOT / "examples/abm/monolayer.toml"
CROWD_EXIT = ROOT / "examples/abm/crowd_exit.toml"
CROWD_ROOM = ROOT / "examples/sweeps/crowd_room.toml"
SLIDING = ROOT / "examples/sliding.toml"
OSCILLATOR = ROOT / "examples/control/oscillator_1d.toml"


def rows(out):
    with open(out / "results.csv", newline="") as f:
        return list(csv.DictReader(f))


def cell(text):
    """A CSV cell as the JSON value it was written from (integers, floats, strings)."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def sweep_text(scenario, collect, fixed=None, axes=None, seeds=None, command="run"):
    lines = [f'command = "{command}"', f'scenario = "{scenario}"',
             "collect = [" + ", ".join(f'"{k}"' for k in collect) + "]"]
    if seeds:
        lines.append(f"seeds = {seeds}")
    for table, entries in (("set", fixed or {}), ("axes", axes or {})):
        lines.append(f"[{table}]")
        lines += [f"{k} = {v}" for k, v in entries.items()]
    return "\n".join(lines) + "\n"


def single_run(out, scenario, sets):
    args = ["run", scenario, "--out", out]
    for key, value in sets.items():
        args += ["--set", f"{key}={value}"]
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr
    return json.loads((out / "summary.json").read_text())


# (name, base scenario, [set], [axes], seeds, collected keys): small runs of a second or less
# (the single runs of a fixed crowd and of the paper's case draw figures: one row each).
KINDS = [
    ("population", MONOLAYER, {"problem.T": "30.0"}, {"types.cell.division_rate": "[0.1, 0.15]"},
     "[1, 2]", ["final_count", "positions_hash", "births", "deaths", "removals"]),
    ("population_room", CROWD_EXIT, {"problem.count": "40", "problem.T": "8.0"},
     {"room.door_width": "[0.8, 1.6]"}, None, ["final_count", "removals", "positions_hash"]),
    ("particles_room", CROWD_ROOM, {"problem.T": "10.0"}, {"room.door_width": "[2.0]"}, "[3]",
     ["evacuated", "evacuation_time", "msd", "positions_hash", "steps"]),
    ("paper_case", SLIDING, {}, {"solver.h": "[0.005]"}, None, ["error", "steps"]),
]
ROWS = {"population": 4, "population_room": 2, "particles_room": 1, "paper_case": 1}


@pytest.mark.parametrize("name,scenario,fixed,axes,seeds,keys", KINDS, ids=[k[0] for k in KINDS])
def test_each_row_is_the_single_run_with_the_same_settings(tmp_path, name, scenario, fixed, axes,
                                                          seeds, keys):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(sweep_text(scenario, keys, fixed, axes, seeds))
    r = run_cli("sweep", sweep, "--out", tmp_path / "sweep", "--jobs", "2")
    assert r.returncode == 0, r.stderr
    table = rows(tmp_path / "sweep")
    assert len(table) == ROWS[name]
    seed_key = ["problem.seed"] if seeds else []
    for row in table:
        sets = dict(fixed)
        sets.update({key: row[key] for key in list(axes) + seed_key})
        summary = single_run(tmp_path / f"run{row['run']}", scenario, sets)
        assert row["status"] == summary["termination"] == "completed", row
        for key in keys:
            expected = "" if summary[key] is None else summary[key]
            assert cell(row[key]) == expected, (key, row, summary[key])
    if name == "population":  # the colony grows (not a run of the one initial cell)
        assert all(int(row["final_count"]) > 1 for row in table), table
        assert len({row["positions_hash"] for row in table}) == 4
    if name == "population_room":  # people leave, more of them through the wider door
        assert 0 < int(table[0]["removals"]) < int(table[1]["removals"]), table
    if name == "particles_room":
        assert float(table[0]["evacuation_time"]) > 0 and float(table[0]["msd"]) > 0, table


def test_run_folders_hold_what_the_run_writes_but_the_figures(tmp_path):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text("run_folders = true\n" + sweep_text(
        CROWD_EXIT, ["removals"], {"problem.count": "20", "problem.T": "2.0",
                                   "output.vtu": "false"}, {"room.door_width": "[1.2]"}))
    assert run_cli("sweep", sweep, "--out", tmp_path / "out").returncode == 0
    (row,) = rows(tmp_path / "out")
    folder = tmp_path / "out/runs" / row["hash"]
    assert sorted(p.name for p in folder.iterdir()) == [
        "agents.csv", "geometry.vtp", "lineage.csv", "population.csv", "summary.json",
        "trajectory.h5", "trajectory.xdmf"]
    assert json.loads((folder / "summary.json").read_text())["removals"] == int(row["removals"])


# (name, base, [set], [axes], the key the message names, the reason)
BAD_FIRST_RUN = [
    ("axis_key_typo", CROWD_EXIT, {}, {"room.door_widht": "[0.8, 1.2]"}, "axes.room.door_widht",
     "unknown key (did you mean room.door_width?)"),
    ("bad_axis_value", CROWD_ROOM, {}, {"forces.propulsion_speed": "[-1.0, 1.0]"},
     "axes.forces.propulsion_speed", "must be ≥ 0 (got -1)"),
    ("bad_type_value", MONOLAYER, {}, {"types.cell.division_rate": "[-0.1, 0.1]"},
     "axes.types.cell.division_rate", "must be ≥ 0 (got -0.1)"),
    ("unknown_type", MONOLAYER, {}, {"types.stroma.radius": "[1.0]"},
     "axes.types.stroma.radius", 'no [[types]] entry has name = "stroma"'),
    ("bad_set_value", MONOLAYER, {"problem.T": "-1.0"}, {}, "set.problem.T", "must be > 0"),
    ("control_key_typo", OSCILLATOR, {}, {"discretization.stepz": "[100, 200]"},
     "axes.discretization.stepz", "unknown key"),
]


@pytest.mark.parametrize("name,scenario,fixed,axes,key,reason", BAD_FIRST_RUN,
                         ids=[b[0] for b in BAD_FIRST_RUN])
def test_first_run_is_checked_before_anything_runs(tmp_path, name, scenario, fixed, axes, key,
                                                   reason):
    sweep = tmp_path / "sweep.toml"
    command = "control" if scenario == OSCILLATOR else "run"
    sweep.write_text(sweep_text(scenario, [], fixed, axes, command=command))
    out = tmp_path / "out"
    r = run_cli("sweep", sweep, "--out", out)
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert str(sweep) in lines[0] and f": {key}: " in lines[0] and reason in lines[0], lines[0]
    assert not out.exists()  # no journal, no table: nothing ran


BLOWS_UP = """
[problem]
kind = "particles"
dimension = 2
count = 4
radius = 0.1
T = 1.0
seed = 1
[domain]
lo = [-1.0, -1.0]
hi = [1.0, 1.0]
[forces]
trap_gamma = 1e6   # explicit steps of h·γ = 10^4: the positions overflow
[solver]
h = 0.01
"""


def test_sweep_whose_runs_all_fail_exits_3_with_its_table(tmp_path):
    base = tmp_path / "base.toml"
    base.write_text(BLOWS_UP)
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(sweep_text(base, ["steps"], seeds=2))
    out = tmp_path / "out"
    r = run_cli("sweep", sweep, "--out", out)
    assert r.returncode == 3, (r.returncode, r.stderr)
    assert [row["status"] for row in rows(out)] == ["non_finite"] * 2
    summary = json.loads((out / "summary.json").read_text())
    assert summary["runs"] == 2 and summary["runs_failed"] == 2
    assert "2 of 2 runs failed" in r.stderr.strip().splitlines()[-1], r.stderr

"""End-to-end tests of differential adhesion (docs/abm.md "Cell sorting"): a short, small run of
examples/abm/cell_sorting.toml sorts (its segregation index rises well above the equal-adhesion
control's), the same seed gives the same bits on one and two threads, population.adhesion keys are
reached by --set and a sweep, and bad pairs get one line naming the key."""
import csv
import json

import pytest

from conftest import ROOT, rejected, run_cli

SORTING = ROOT / "examples/abm/cell_sorting.toml"
SMALL = ["problem.count=160", "initial.lo=[-9.0, -9.0]", "initial.hi=[9.0, 9.0]", "problem.T=500",
         "output.hdf5=false", "output.vtu=false"]
EQUAL = ["population.adhesion.dark.dark=1.25", "population.adhesion.light.light=1.25"]


def run_sorting(out, *sets):
    args = ["run", SORTING, "--out", out]
    for s in SMALL + list(sets):
        args += ["--set", s]
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr
    return list(csv.DictReader(open(out / "population.csv")))


def test_differential_adhesion_sorts_and_equal_adhesion_does_not(tmp_path):
    sorting = run_sorting(tmp_path / "sorting")
    control = run_sorting(tmp_path / "control", *EQUAL)
    start = float(sorting[0]["segregation"])
    assert start == float(control[0]["segregation"])  # the same random mixture
    assert abs(start - 0.5) < 0.1
    # The mean index over the last five rows (t = 420 … 500): 0.74 against 0.52.
    late = [sum(float(r["segregation"]) for r in rows[-5:]) / 5 for rows in (sorting, control)]
    assert late[0] > late[1] + 0.15, late
    assert abs(late[1] - 0.5) < 0.1, late


def test_same_bits_on_one_and_two_threads_with_an_adhesion_matrix(tmp_path):
    hashes = []
    for threads in (1, 2):
        out = tmp_path / f"out{threads}"
        run_sorting(out, "problem.T=50", f"solver.threads={threads}")
        hashes.append(json.load(open(out / "summary.json"))["positions_hash"])
    assert hashes[0] == hashes[1]


def test_adhesion_keys_from_the_command_line_and_a_sweep(tmp_path):
    run_sorting(tmp_path / "a", "problem.T=5", "population.adhesion.dark.light=0.5",
                "population.adhesion.light.dark=0.5")  # the same pair, given twice alike
    settings = json.loads((tmp_path / "a/summary.json").read_text())["settings"]
    assert settings["adhesion"]["dark"] == {"dark": 4.0, "light": 0.5}
    assert settings["adhesion"]["light"] == {"light": 1.0, "dark": 0.5}
    sweep = tmp_path / "sweep.toml"
    sets = "".join(f"{s}\n" for s in SMALL if not s.startswith("problem.T"))
    sweep.write_text(f'command = "run"\nscenario = "{SORTING}"\n[set]\n{sets}problem.T = 5\n'
                     "[axes]\npopulation.adhesion.dark.dark = [2.0, -1.0]\n")
    # A bad value of an axis is refused before any run, naming the run and the reason.
    rejected(run_cli("sweep", sweep, "--out", tmp_path / "s"), "axes.population.adhesion.dark.dark",
             "run 1", "population.adhesion.dark.dark: must be ≥ 0 (got -1)")
    assert not (tmp_path / "s").exists()
    sweep.write_text(sweep.read_text().replace("[2.0, -1.0]", "[2.0]"))
    run_cli("sweep", sweep, "--out", tmp_path / "s")
    with open(tmp_path / "s/results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [row["population.adhesion.dark.dark"] for row in rows] == ["2.0"]
    assert rows[0]["status"] == "completed", rows[0]


BAD = [
    (["population.adhesion.dark.grey=1"], "population.adhesion.dark.grey",
     "unknown type 'grey' (types: dark, light)"),
    (["population.adhesion.light.dark=2"], "population.adhesion.dark.light",
     "(1.25) differs from adhesion.light.dark (2)"),
    (["population.adhesion.dark.light=-1"], "population.adhesion.dark.light", "must be ≥ 0"),
    (["population.adhesion.dark.light=\"x\""], "population.adhesion.dark.light",
     "expected a number"),
    (["initial.types=[\"dark\", \"light\", \"dark\"]"], "initial.types",
     "3 names for 160 agents"),
]


@pytest.mark.parametrize("sets,key,reason", BAD, ids=[str(i) for i in range(len(BAD))])
def test_bad_adhesion_names_the_key(tmp_path, sets, key, reason):
    args = ["run", SORTING, "--out", tmp_path / "out"]
    for s in SMALL + sets:
        args += ["--set", s]
    rejected(run_cli(*args), key, reason)
    assert not (tmp_path / "out").exists()


def test_adhesion_needs_the_attraction_range(tmp_path, write_scenario):
    text = SORTING.read_text().replace("attraction_range = 0.25", "")
    r = run_cli("run", write_scenario(text), "--out", tmp_path / "out")
    rejected(r, "population.adhesion", "needs forces.attraction_range")

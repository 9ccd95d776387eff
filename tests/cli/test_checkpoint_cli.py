"""`moreau run --checkpoint-every K` and `--resume DIR` (docs/reliability.md): a run killed after a
checkpoint and resumed from it writes the same bits (positions hash, counters, trajectory
datasets) as a run that never stopped, with noise, on 1 and 2 threads — plain particle runs,
rooms (the evacuation count) and agent-based runs (agents, lineage, population.csv, the frames'
per-agent arrays); a corrupt checkpoint or one made for another scenario is refused with one
line and exit code 2."""
import json
import os
import signal
import subprocess
import time

import pytest

from conftest import CLI, ROOT, run_cli

# 400 disks in a periodic box with noise and a trap: the neighbour lists are rebuilt and the
# storage reordered during the run, so a resume must restore the last build to keep the bits.
SCENARIO = """
[problem]
kind = "particles"
dimension = 2
count = 400
radius = 0.5
T = 4.0
seed = 3

[domain]
lo = [0.0, 0.0]
hi = [40.0, 40.0]
periodic = [true, true]

[forces]
trap_gamma = 0.2
trap_center = [20.0, 20.0]
diffusion = 0.3

[solver]
h = 0.01
block_cells = 2

[output]
stride = 25
"""

COUNTERS = ("positions_hash", "neighbour_list_builds", "verlet_retries", "projections",
            "constraint_evaluations", "max_overlap", "steps")


def summary(out):
    with open(out / "summary.json") as f:
        return json.load(f)


def same_trajectories(a, b):
    h5py = pytest.importorskip("h5py")  # installed by scripts/install-deps
    with h5py.File(a / "trajectory.h5", "r") as fa, h5py.File(b / "trajectory.h5", "r") as fb:
        for name in ("time", "step", "count", "positions", "ids", "radii"):
            assert fa[name].shape == fb[name].shape, name
            assert fa[name][...].tobytes() == fb[name][...].tobytes(), name


def run_killed_after_first_checkpoint(args, checkpoint):
    """Starts `moreau run ARGS`, kills it (SIGKILL) as soon as CHECKPOINT exists; returns whether
    it was still running then (a fast machine may finish first: the resume is tested anyway)."""
    proc = subprocess.Popen([CLI, *map(str, args)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 300
    while not checkpoint.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    killed = proc.poll() is None
    if killed:
        proc.send_signal(signal.SIGKILL)
    proc.wait()
    return killed


@pytest.mark.parametrize("threads", [1, 2])
def test_resumed_run_has_the_bits_of_an_uninterrupted_one(tmp_path, threads):
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO)
    t = ["--set", f"solver.threads={threads}"]
    r = run_cli("run", path, "--out", tmp_path / "whole", *t)
    assert r.returncode == 0, r.stderr

    stopped = tmp_path / "stopped"
    checkpoint = tmp_path / "stopped.checkpoint" / "checkpoint.bin"
    run_killed_after_first_checkpoint(
        ["run", path, "--out", stopped, "--checkpoint-every", 100, *t], checkpoint)
    assert checkpoint.exists()
    # The resume may use another thread count: the bits do not depend on it.
    other = ["--set", f"solver.threads={3 - threads}"]
    r = run_cli("run", path, "--out", tmp_path / "resumed", "--resume", checkpoint.parent, *other)
    assert r.returncode == 0, r.stderr
    whole, resumed = summary(tmp_path / "whole"), summary(tmp_path / "resumed")
    for key in COUNTERS:
        assert resumed[key] == whole[key], key
    same_trajectories(tmp_path / "whole", tmp_path / "resumed")


def test_checkpoints_keep_the_bits_and_continue_after_a_resume(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO)
    assert run_cli("run", path, "--out", tmp_path / "whole").returncode == 0
    r = run_cli("run", path, "--out", tmp_path / "a", "--checkpoint-every", 100)
    assert r.returncode == 0, r.stderr
    assert summary(tmp_path / "a")["positions_hash"] == summary(tmp_path / "whole")["positions_hash"]
    # The last checkpoint (step 300 of 400), resumed twice: once with more checkpoints into the
    # same folder, then from the checkpoint that run left (the same step: nothing later).
    ck = tmp_path / "a.checkpoint"
    r = run_cli("run", path, "--out", tmp_path / "b", "--resume", ck, "--checkpoint-every", 50)
    assert r.returncode == 0, r.stderr
    r = run_cli("run", path, "--out", tmp_path / "c", "--resume", ck)
    assert r.returncode == 0, r.stderr
    for out in ("b", "c"):
        assert summary(tmp_path / out)["positions_hash"] == summary(tmp_path / "whole")["positions_hash"]
        same_trajectories(tmp_path / "whole", tmp_path / out)


def assert_refused(args, needle):
    r = run_cli(*args)
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], r.stderr


def test_corrupt_or_foreign_checkpoints_are_refused(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO.replace("T = 4.0", "T = 1.0"))
    r = run_cli("run", path, "--out", tmp_path / "a", "--checkpoint-every", 40)
    assert r.returncode == 0, r.stderr
    ck = tmp_path / "a.checkpoint"
    # Another scenario: a different seed.
    other = tmp_path / "other.toml"
    other.write_text(SCENARIO.replace("T = 4.0", "T = 1.0").replace("seed = 3", "seed = 4"))
    out = tmp_path / "refused"
    assert_refused(["run", other, "--out", out, "--resume", ck], "made for another scenario")
    assert_refused(["run", path, "--out", out, "--resume", ck, "--set", "forces.diffusion=0.2"],
                   "made for another scenario")
    # A flipped byte, a truncated file, a missing one, a folder that is not there.
    data = bytearray((ck / "checkpoint.bin").read_bytes())
    data[len(data) // 2] ^= 0x01
    (ck / "checkpoint.bin").write_bytes(bytes(data))
    assert_refused(["run", path, "--out", out, "--resume", ck], "corrupt")
    (ck / "checkpoint.bin").write_bytes(bytes(data[:100]))
    assert_refused(["run", path, "--out", out, "--resume", ck], "corrupt")
    os.remove(ck / "checkpoint.bin")
    assert_refused(["run", path, "--out", out, "--resume", ck], "cannot be opened")
    assert_refused(["run", path, "--out", out, "--resume", tmp_path / "nowhere"],
                   "is not a directory")
    assert_refused(["run", path, "--out", out, "--checkpoint-every", -1], "--checkpoint-every")
    assert not out.exists()


# Agent-based runs and rooms, shortened: (example, --set overrides, --checkpoint-every, the files
# that must be equal). A population checkpoints at the first rule step past each multiple of K.
SHORT = {
    "monolayer": ("abm/monolayer.toml", ["problem.T=16", "output.stride=100"], 200,
                  ("population.csv", "lineage.csv", "agents.csv")),
    "crowd_exit": ("abm/crowd_exit.toml", ["problem.T=3", "output.stride=100"], 400,
                   ("population.csv", "lineage.csv", "agents.csv")),
    "crowd_room": ("sweeps/crowd_room.toml", ["problem.T=4", "output.stride=50"], 100,
                   ("evacuation.csv",)),
    "two_exits": ("crowds/two_exits_pillar.toml",
                  ["problem.T=12", "output.stride=100", "output.snapshots=false",
                   "output.snapshot_times=[]"], 800, ("evacuation.csv", "exits.csv")),
}
POPULATION_COUNTERS = ("positions_hash", "rule_steps", "births", "deaths", "removals",
                       "relax_sweeps", "final_count", "max_overlap_before")


def datasets(f, h5py):
    found = []
    f.visititems(lambda name, obj: found.append(name) if isinstance(obj, h5py.Dataset) else None)
    return found


def same_datasets(a, b):
    """Every dataset of A/trajectory.h5 has the bits of B's (the per-agent arrays included)."""
    h5py = pytest.importorskip("h5py")
    with h5py.File(a / "trajectory.h5", "r") as fa, h5py.File(b / "trajectory.h5", "r") as fb:
        names = datasets(fa, h5py)
        assert names and names == datasets(fb, h5py)
        for name in names:
            assert fa[name][...].tobytes() == fb[name][...].tobytes(), name


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("name", sorted(SHORT))
def test_populations_and_rooms_resume_with_the_bits_of_an_uninterrupted_run(tmp_path, name,
                                                                           threads):
    example, sets, every, files = SHORT[name]
    scenario = ROOT / "examples" / example
    common = [a for s in sets for a in ("--set", s)]
    t = ["--set", f"solver.threads={threads}"]
    r = run_cli("run", scenario, "--out", tmp_path / "whole", *common, *t)
    assert r.returncode == 0, r.stderr

    checkpoint = tmp_path / "stopped.checkpoint" / "checkpoint.bin"
    run_killed_after_first_checkpoint(["run", scenario, "--out", tmp_path / "stopped", *common,
                                       "--checkpoint-every", every, *t], checkpoint)
    assert checkpoint.exists()
    other = ["--set", f"solver.threads={3 - threads}"]
    r = run_cli("run", scenario, "--out", tmp_path / "resumed", *common, "--resume",
                checkpoint.parent, *other)
    assert r.returncode == 0, r.stderr
    whole, resumed = summary(tmp_path / "whole"), summary(tmp_path / "resumed")
    keys = POPULATION_COUNTERS if "rule_steps" in whole else COUNTERS
    for key in keys:
        assert resumed[key] == whole[key], key
    if isinstance(whole.get("engine"), dict):  # a population: its engine's counters too
        for key in COUNTERS[1:]:
            assert resumed["engine"][key] == whole["engine"][key], key
    for f in files:
        assert (tmp_path / "resumed" / f).read_bytes() == (tmp_path / "whole" / f).read_bytes(), f
    same_datasets(tmp_path / "whole", tmp_path / "resumed")


def test_population_checkpoint_flags_are_checked(tmp_path):
    scenario = ROOT / "examples" / "abm" / "monolayer.toml"
    out = tmp_path / "out"
    assert_refused(["run", scenario, "--out", out, "--checkpoint-every", -1], "--checkpoint-every")
    assert_refused(["run", scenario, "--out", out, "--resume", tmp_path / "nowhere"],
                   "is not a directory")
    assert not out.exists()


def test_the_paper_cases_refuse_the_checkpoint_flags(tmp_path):
    scenario = ROOT / "examples" / "sliding.toml"
    out = tmp_path / "out"
    for flags in (["--checkpoint-every", 10], ["--resume", tmp_path]):
        assert_refused(["run", scenario, "--out", out, *flags], "only particle scenarios")
    assert not out.exists() and not (tmp_path / "out.checkpoint").exists()

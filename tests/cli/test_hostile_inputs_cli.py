"""Hostile inputs (docs/reliability.md, "Limits and validation"): sizes a user controls checked
against the memory before anything is allocated, special files (FIFOs, devices) refused instead
of read for ever, tables nested without bound, unknown empty tables, labels that are not UTF-8,
values that make no sense, and messages that name what the user wrote. Every bad input is one
stderr line, exit code 2, nothing written. The memory cases run under `ulimit -v` so that a
regression fails instead of taking the machine down."""
import json
import os
import resource
import subprocess

import pytest

from conftest import CLI, CROWD, OSCILLATOR, ROOT, SLIDING, rejected, run_cli

DATA = (ROOT.parent / "shared" / "data" / "mocap").resolve()
QUALISYS = DATA / "Qualisys.c3d"
GAIT = DATA / "Gait.c3d"
GAPS = ROOT / "examples/mocap/qualisys_10_gaps.csv"
ADDRESS_SPACE = 3 << 30  # 3 GiB of address space: enough for every refusal, far from the asks

needs_data = pytest.mark.skipif(not QUALISYS.exists(), reason=f"{DATA} is not there")


def run_limited(*args, timeout=60):
    """`moreau ARGS` under `ulimit -v` ADDRESS_SPACE, killed after `timeout` seconds."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, preexec_fn=limit)


def nothing_written(out):
    assert not out.exists() or not any(out.iterdir()), list(out.iterdir())


# Sizes checked before allocation.

def test_a_control_study_checks_its_finest_level_before_running(tmp_path):
    out = tmp_path / "out"
    r = run_limited("control", OSCILLATOR, "--study-steps", "10,100000000", "--out", out)
    rejected(r, "--study-steps", "100000000 steps need about", "ulimit -v")
    nothing_written(out)


def test_a_sweep_of_billions_of_seeds_is_refused_before_they_are_listed(tmp_path):
    sweep = tmp_path / "seeds.toml"
    sweep.write_text(f'command = "run"\nscenario = "{SLIDING}"\nseeds = 4294967297\n')
    out = tmp_path / "out"
    r = run_limited("sweep", sweep, "--out", out)
    rejected(r, str(sweep), "seeds", "≤ 10000000", "4294967297")
    nothing_written(out)


def test_a_grid_whose_runs_overflow_is_refused(tmp_path):
    # 40 axes of 3 values: 3^40 points, an overflow of a 64-bit count.
    axes = "\n".join(f"a{i}.x = [1, 2, 3]" for i in range(40))
    sweep = tmp_path / "grid.toml"
    sweep.write_text(f'command = "run"\nscenario = "{SLIDING}"\n[axes]\n{axes}\n')
    r = run_limited("sweep", sweep, "--out", tmp_path / "out")
    rejected(r, str(sweep), "more than 10000000 points", "runs a sweep may have")


@needs_data
def test_a_billion_trials_are_refused_before_they_are_drawn(tmp_path):
    out = tmp_path / "out"
    r = run_limited("evaluate-gaps", QUALISYS, "--trials", "1000000000", "--methods", "linear",
                    "--out", out)
    rejected(r, "trials", "trials need about", "ulimit -v")
    nothing_written(out)


@needs_data
@pytest.mark.parametrize("gaps", ["/dev/zero", "DIR", "FIFO"])
def test_a_gap_list_that_is_not_a_regular_file_is_refused(tmp_path, gaps):
    reasons = {"/dev/zero": "is a character device, not a regular file",
               "DIR": "is a directory", "FIFO": "is a FIFO (named pipe), not a regular file"}
    path = {"/dev/zero": "/dev/zero", "DIR": str(tmp_path), "FIFO": str(tmp_path / "gaps.csv")}
    if gaps == "FIFO":
        os.mkfifo(path[gaps])
    out = tmp_path / "out"
    r = run_limited("fill-gaps", QUALISYS, "--gaps", path[gaps], "--out", out, timeout=30)
    rejected(r, path[gaps], reasons[gaps])
    nothing_written(out)


# Special files: refused, never read for ever.

@pytest.mark.parametrize("kind", ["fifo", "dev_zero"])
def test_a_scenario_that_is_not_a_regular_file_is_refused(tmp_path, kind):
    path = tmp_path / "scenario.toml" if kind == "fifo" else "/dev/zero"
    if kind == "fifo":
        os.mkfifo(path)
    r = run_limited("run", path, "--out", tmp_path / "out", timeout=30)
    rejected(r, str(path), "FIFO (named pipe)" if kind == "fifo" else "character device",
             "not a regular file")


def test_a_recording_that_is_a_fifo_is_refused(tmp_path):
    path = tmp_path / "walk.c3d"
    os.mkfifo(path)
    r = run_limited("inspect", path, timeout=30)
    rejected(r, str(path), "is a FIFO (named pipe), not a regular file")


def test_a_checkpoint_that_is_a_folder_is_refused_naming_it(tmp_path):
    (tmp_path / "ck" / "checkpoint.bin").mkdir(parents=True)
    r = run_limited("run", CROWD, "--resume", tmp_path / "ck", "--out", tmp_path / "out")
    rejected(r, str(tmp_path / "ck" / "checkpoint.bin"), "is a directory")


# Tables nested without bound; unknown empty tables.

@pytest.mark.parametrize("levels", [65, 20000, 40000])
def test_deeply_nested_tables_are_refused_before_parsing(tmp_path, write_scenario, levels):
    path = write_scenario("[" + ".".join(["a"] * levels) + "]\n")
    r = run_limited("run", path, "--out", tmp_path / "out")
    rejected(r, str(path), f"tables nest {levels} levels deep", "more than the 64 accepted")


@pytest.mark.parametrize("text", ["x." * 100 + "y = 1\n", "x = {" + "a." * 100 + "b = 1}\n",
                                  "[t]\n" + "a." * 70 + "b = 1\n"])
def test_deep_dotted_keys_are_refused_too(tmp_path, write_scenario, text):
    r = run_limited("run", write_scenario(text), "--out", tmp_path / "out")
    rejected(r, "levels deep", "more than the 64 accepted")


def test_an_empty_unknown_table_is_refused(tmp_path, write_scenario):
    path = write_scenario(SLIDING.read_text() + "\n[bogus]\n")
    rejected(run_cli("run", path, "--out", tmp_path / "out"), str(path), "bogus: unknown table")
    # An empty table the command knows is fine.
    known = write_scenario(SLIDING.read_text().replace("[solver]", "[output]\n\n[solver]"),
                           name="known.toml")
    assert run_cli("run", known, "--out", tmp_path / "ok").returncode == 0


# Labels that are not UTF-8.

@needs_data
def test_labels_that_are_not_utf8_are_written_with_replacement_characters(tmp_path):
    data = bytearray(GAIT.read_bytes())
    at = data.find(b"R.Shoulder")
    assert at > 0
    data[at + 2] = 0xFF
    gait = tmp_path / "gait.c3d"
    gait.write_bytes(bytes(data))
    r = run_cli("inspect", gait, "--json")
    assert r.returncode == 0, r.stderr
    assert "R.\ufffdhoulder" in json.loads(r.stdout)["labels"]
    out = tmp_path / "out"
    r = run_cli("fill-gaps", gait, "--method", "linear", "--out", out)
    assert r.returncode == 0, r.stderr
    report = json.loads((out / "report.json").read_text(encoding="utf-8"))
    assert any("\ufffd" in gap["label"] for gap in report["gaps"])


# Values that make no sense.

def test_a_sweep_setting_an_unknown_key_is_refused_up_front(tmp_path):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(f'command = "run"\nscenario = "{SLIDING}"\nseeds = 2\n'
                     '[set]\n"problem.bogus" = 1\n')
    rejected(run_cli("sweep", sweep, "--out", tmp_path / "out"), "problem.bogus: unknown key")


def test_arm_lengths_must_be_positive(tmp_path):
    arm = ROOT / "examples/control/arm_2d.toml"
    r = run_cli("control", arm, "--set", "arm.upper_bone=-1", "--out", tmp_path / "out")
    rejected(r, str(arm), "arm.upper_bone", "must be > 0 (got -1)")


@pytest.mark.parametrize("value, reason", [("2.5", "must be a whole number of contacts"),
                                           ("1e308", "must be in [0, 1000]")])
def test_max_contacts_is_a_whole_number(tmp_path, value, reason):
    monolayer = ROOT / "examples/abm/monolayer.toml"
    r = run_cli("run", monolayer, "--set", f"types.cell.max_contacts={value}",
                "--out", tmp_path / "out")
    rejected(r, "types.cell.max_contacts", reason)


@needs_data
def test_a_csv_coordinate_beyond_any_lab_is_refused(tmp_path):
    out = tmp_path / "linear"
    assert run_cli("fill-gaps", QUALISYS, "--method", "linear", "--out", out).returncode == 0
    lines = (out / "filled.csv").read_text().splitlines()
    fields = lines[100].split(",")
    fields[3] = "1e308"
    lines[100] = ",".join(fields)
    big = tmp_path / "big.csv"
    big.write_text("\n".join(lines) + "\n")
    r = run_cli("fill-gaps", big, "--gaps", GAPS, "--method", "pca", "--out", tmp_path / "pca")
    rejected(r, str(big), "line 101, x", "1e308 is beyond ±1e+12")


@needs_data
def test_a_csv_with_a_byte_order_mark_is_read(tmp_path):
    out = tmp_path / "linear"
    assert run_cli("fill-gaps", QUALISYS, "--method", "linear", "--out", out).returncode == 0
    bom = tmp_path / "bom.csv"
    bom.write_text("\ufeff" + (out / "filled.csv").read_text(), encoding="utf-8")
    r = run_cli("inspect", bom, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["frames"] > 0


# Messages name what the user wrote.

def test_a_reference_step_that_does_not_divide_the_run_names_the_key(tmp_path):
    disks = ROOT / "examples/disks.toml"
    r = run_cli("run", disks, "--set", "reference.compute=true", "--set", "reference.h=1e308",
                "--out", tmp_path / "out")
    rejected(r, str(disks), "reference.h", "h = 1e+308")
    r = run_cli("run", disks, "--set", "reference.compute=true", "--set", "reference.h=0.0004",
                "--out", tmp_path / "out")
    rejected(r, str(disks), "reference.h", "must divide solver.h")


@needs_data
def test_a_truncated_recording_names_the_flag_of_the_command(tmp_path):
    data = QUALISYS.read_bytes()
    cut = tmp_path / "cut.c3d"
    cut.write_bytes(data[:len(data) // 2])
    rejected(run_cli("inspect", cut), str(cut), "(truncated); --allow-truncated reads")
    rejected(run_cli("fill-gaps", cut, "--out", tmp_path / "out"), str(cut),
             "--set read.allow_truncated=true reads")


@needs_data
def test_a_seed_that_is_not_an_integer_says_what_it_got(tmp_path):
    r = run_cli("evaluate-gaps", QUALISYS, "--seed", "1e23", "--trials", "2", "--methods",
                "linear", "--out", tmp_path / "out")
    rejected(r, "evaluation.seed", "expected an integer, got a number")


@pytest.fixture
def full_disk(tmp_path):
    """A folder on a 64 KiB tmpfs (mounting needs root: skipped otherwise), unmounted after."""
    folder = tmp_path / "small"
    folder.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(folder)],
                      capture_output=True).returncode != 0:
        pytest.skip("cannot mount a small tmpfs here (needs root)")
    yield folder
    subprocess.run(["umount", str(folder)], check=True)


@needs_data
def test_a_full_disk_is_one_line_naming_the_folder_the_file_and_the_reason(full_disk):
    r = run_cli("control", OSCILLATOR, "--out", full_disk / "control")
    rejected(r, f"{full_disk / 'control'}: cannot write", "(No space left on device)")
    r = run_cli("fill-gaps", QUALISYS, "--method", "linear", "--out", full_disk / "filled")
    line = rejected(r, str(full_disk / "filled" / "filled.c3d"), "No space left on device")
    assert ".moreau-staging" not in line
    assert not any(full_disk.iterdir()), list(full_disk.iterdir())


def test_a_full_disk_under_a_particle_run_is_one_line_and_no_crash(full_disk):
    # The HDF5 trajectory fills the disk while the run steps: no crash at exit (HDF5's exit
    # handler is off), one line naming the user's folder and the reason, nothing left behind.
    r = run_cli("run", ROOT / "examples/disks_1e4.toml", "--set", "problem.T=2",
                "--out", full_disk / "run")
    assert r.returncode == 1, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert str(full_disk / "run" / "trajectory.h5") in lines[0], lines[0]
    assert "No space left on device" in lines[0] and ".moreau-staging" not in lines[0]
    assert not any(full_disk.iterdir()), list(full_disk.iterdir())

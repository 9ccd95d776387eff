"""Checked limits (docs/reliability.md): step and frame counts, integer ranges, memory
estimates that respect `ulimit -v`, thread counts capped at the hardware. Each bad input is one
stderr line naming the key and the user's own number, exit code 2, nothing written."""
import json
import os
import resource
import subprocess

from conftest import CLI, CROWD, NETWORK, OSCILLATOR, ROOT, SLIDING, rejected, run_cli


PARTICLES = """
[problem]
kind = "particles"
dimension = 2
count = 20
radius = 0.5
T = 0.1
seed = 2

[domain]
lo = [0.0, 0.0]
hi = [20.0, 20.0]
box_walls = true

[solver]
h = 0.01
"""


def run_with_address_space(limit_bytes, *args):
    """`moreau ARGS` under `ulimit -v` (RLIMIT_AS) of limit_bytes."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=60,
                          preexec_fn=limit)


def test_a_tiny_step_is_refused_not_run_as_zero_steps(tmp_path):
    out = tmp_path / "out"
    line = rejected(run_cli("run", SLIDING, "--out", out, "--set", "solver.h=1e-300"),
                    "solver.h", "4e+300 steps", "more than the 1000000000 allowed")
    assert "completed" not in line
    assert not out.exists()


def test_a_huge_final_time_is_refused_before_writing(tmp_path):
    out = tmp_path / "out"
    rejected(run_cli("run", SLIDING, "--out", out, "--set", "problem.T=4294967297"),
             "solver.h", "4.29497e+12 steps")
    assert not out.exists()


def test_integers_are_range_checked_before_narrowing(tmp_path):
    rejected(run_cli("run", CROWD, "--out", tmp_path / "a", "--set", "solver.sweeps=4294967297"),
             "solver.sweeps", "4294967297")
    rejected(run_cli("control", NETWORK, "--out", tmp_path / "b", "--set",
                     "network.dimension=4294967298"), "network.dimension", "4294967298")


def test_too_many_frames_are_refused_with_the_counts(tmp_path, write_scenario):
    scenario = write_scenario(PARTICLES)
    line = rejected(run_cli("run", scenario, "--out", tmp_path / "out", "--set", "problem.T=20000",
                            "--set", "output.stride=1"), "output.stride", "2000001 frames")
    assert "2000000 steps, one every 1" in line


def test_the_all_pairs_disks_case_refuses_a_million_disks_at_once(tmp_path):
    r = run_cli("run", ROOT / "examples/disks.toml", "--out", tmp_path / "out", "--set",
                "problem.count=1000000")
    rejected(r, "problem.count", "1000000", "all N²/2 pairs", "particles")


def test_the_particle_memory_check_respects_ulimit_v(tmp_path, write_scenario):
    scenario = write_scenario(PARTICLES.replace("count = 20", "count = 10000000"))
    r = run_with_address_space(1 << 30, "run", scenario, "--out", tmp_path / "out")
    line = rejected(r, "problem.count", "10000000 particles need about", "ulimit -v")
    assert "bad_alloc" not in line


def test_control_estimates_its_memory_before_allocating(tmp_path):
    r = run_with_address_space(1 << 30, "control", OSCILLATOR, "--out", tmp_path / "out", "--set",
                               "discretization.steps=100000000")
    rejected(r, "discretization.steps", "100000000 steps need about", "GiB", "ulimit -v")


def test_memory_messages_use_sensible_units(tmp_path):
    line = rejected(run_cli("run", CROWD, "--out", tmp_path / "out", "--set",
                            "solver.memory_limit=1000"),
                    "problem.count", "200 particles need about 56.2 KiB",
                    "more than the 1000 B available")
    assert "0.0 GiB" not in line
    assert line.count("count") == 1  # the key once, as the user writes it


def capped_threads(command, scenario, table, *sets, out):
    """Runs with `table.threads = 100000`; checks the one warning line and the capped setting."""
    r = run_cli(command, scenario, "--out", out, "--set", f"{table}.threads=100000", *sets)
    assert r.returncode == 0, r.stderr
    hardware = os.cpu_count()
    assert (f"{table}.threads: 100000 threads is more than the {hardware} hardware threads; "
            f"using {hardware}") in r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["settings"][table]["threads"] == hardware
    return summary, hardware


def test_threads_beyond_the_hardware_are_capped_with_a_warning(tmp_path, write_scenario):
    summary, hardware = capped_threads(
        "run", write_scenario(PARTICLES), "solver", "--set", "output.hdf5=false", "--set",
        "output.vtu=false", "--set", "output.snapshots=false", out=tmp_path / "out")
    assert 1 <= summary["threads"] <= hardware


def test_control_threads_beyond_the_hardware_are_capped_with_a_warning(tmp_path):
    capped_threads("control", OSCILLATOR, "newton", out=tmp_path / "out")


def test_running_out_of_memory_is_one_line_naming_what_was_read(tmp_path, write_scenario):
    # 300 000 positions take about 100 MiB as parsed TOML: more than 96 MiB of address space.
    rows = ",".join(["[1.0, 2.0]"] * 300000)
    scenario = write_scenario(f'[problem]\nkind = "particles"\n[initial]\npositions = [{rows}]\n')
    r = run_with_address_space(96 << 20, "run", scenario, "--out", tmp_path / "out")
    assert r.returncode == 3, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith(f"moreau: out of memory: {scenario}: out of memory while reading the file")
    assert not (tmp_path / "out").exists()


def test_the_fields_memory_is_checked_before_the_grid_is_allocated(tmp_path):
    # A voxel of 1e-3 on the 32 × 32 box of the example: 10^9 voxels, two substrates.
    example = ROOT / "examples/abm/oxygen_spheroid_2d.toml"
    r = run_with_address_space(1 << 31, "run", example, "--set", "fields.spacing=0.001",
                               "--out", tmp_path / "out")
    line = rejected(r, "fields.spacing", "voxels × 2 substrates need about", "ulimit -v")
    assert "out of memory" not in line

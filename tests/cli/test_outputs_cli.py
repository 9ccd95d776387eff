"""End-to-end tests of how `moreau` writes its output folders (docs/reliability.md):
no shell ever sees a path, a folder always holds exactly one complete run, a second run into the
same folder is refused, staging folders of dead processes are removed, nothing is created for
bad input, and an installed tool finds its figure scripts."""
import json
import os
import pathlib
import shutil
import socket
import subprocess

import pytest

from conftest import CLI, ROOT, run_cli
from test_particles_cli import SMALL

PARTICLES = SMALL  # 50 disks in a trap, 100 steps

# Every character a shell would act on, spaces and non-ASCII letters.
HOSTILE = "q'$(touch PWNED)'x \"`touch PWNED`\" ; touch PWNED é ü ∂"


def hidden_leftovers(folder):
    """The staging, set-aside and lock files moreau made in FOLDER."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") and "moreau" in p.name)


def test_no_path_reaches_a_shell(tmp_path):
    """Reproducer 1: `--out "o/q'$(touch PWNED)'x"` ran `touch`; so did a quoted scenario name."""
    folder = tmp_path / HOSTILE
    folder.mkdir()
    scenario = folder / f"s {HOSTILE}.toml"
    shutil.copy(ROOT / "examples" / "sliding.toml", scenario)
    out = folder / "o" / HOSTILE
    r = run_cli("run", scenario, "--out", out, "--set", "solver.h=0.01", cwd=folder)
    assert r.returncode == 0, r.stderr
    assert not list(tmp_path.rglob("PWNED")), r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "completed" and summary["steps"] == 400
    assert summary["scenario_file"] == str(scenario)
    assert (out / "trajectory.csv").stat().st_size > 0
    assert (out / "trajectory.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert hidden_leftovers(out.parent) == []


def test_particle_figures_with_hostile_paths(tmp_path):
    folder = tmp_path / HOSTILE
    folder.mkdir()
    scenario = folder / f"{HOSTILE}.toml"
    scenario.write_text(PARTICLES)
    out = folder / HOSTILE / "out"
    r = run_cli("run", scenario, "--out", out, cwd=folder)
    assert r.returncode == 0, r.stderr
    assert not list(tmp_path.rglob("PWNED"))
    assert json.loads((out / "summary.json").read_text())["particles"] == 50
    assert (out / "snapshots.png").read_bytes()[:4] == b"\x89PNG"


def test_a_rerun_replaces_the_whole_folder(tmp_path):
    """Reproducer 3: a rerun left the previous run's trajectory.h5 beside the new summary.json."""
    scenario = tmp_path / "p.toml"
    scenario.write_text(PARTICLES)
    out = tmp_path / "out"
    assert run_cli("run", scenario, "--out", out, "--set", "problem.count=100").returncode == 0
    assert (out / "trajectory.h5").exists()
    r = run_cli("run", scenario, "--out", out, "--set", "output.hdf5=false")
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "summary.json").read_text())["particles"] == 50
    assert not (out / "trajectory.h5").exists() and not (out / "trajectory.xdmf").exists()
    assert hidden_leftovers(tmp_path) == []


def test_a_folder_of_other_files_is_not_replaced(tmp_path):
    scenario = tmp_path / "p.toml"
    scenario.write_text(PARTICLES)
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    r = run_cli("run", scenario, "--out", out)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "not a moreau result" in r.stderr
    assert [p.name for p in out.iterdir()] == ["notes.txt"]
    assert hidden_leftovers(tmp_path) == []


def process_start_time(pid):
    """Field 22 of /proc/PID/stat, as moreau names its staging folders."""
    stat = pathlib.Path(f"/proc/{pid}/stat").read_text()
    return int(stat[stat.rindex(")") + 2:].split()[19])


def test_stale_staging_is_removed_and_never_pulled_in(tmp_path):
    """Reproducer 2: staging folders stayed forever, and a reused PID pulled stale frames into a
    new result. A dead PID, and a live PID with another start time (a reused PID), are stale; the
    staging folder of a live process is kept."""
    host = socket.gethostname()
    dead = subprocess.Popen(["true"])
    dead.wait()
    me = os.getpid()
    stale = [f".moreau-staging.{dead.pid}.12345.0000beef.{host}",
             f".moreau-staging.{me}.{process_start_time(me) + 1}.0000cafe.{host}",
             f".moreau-old.{dead.pid}.1.00000001.{host}"]
    live = f".moreau-staging.{me}.{process_start_time(me)}.0000f00d.{host}"
    for name in [*stale, live]:
        (tmp_path / name).mkdir()
        (tmp_path / name / "stale_frame.vtu").write_text("old")
    scenario = tmp_path / "p.toml"
    scenario.write_text(PARTICLES)
    out = tmp_path / "out"
    r = run_cli("run", scenario, "--out", out)
    assert r.returncode == 0, r.stderr
    assert hidden_leftovers(tmp_path) == [live]
    assert not list(out.rglob("stale_frame.vtu"))


def test_a_second_run_into_the_same_folder_is_refused(tmp_path):
    """Reproducer 3: two concurrent runs into one folder mixed their files."""
    scenario = tmp_path / "p.toml"
    scenario.write_text(PARTICLES.replace("T = 1.0", "T = 100000.0"))
    out = tmp_path / "out"
    first = subprocess.Popen([CLI, "run", str(scenario), "--out", str(out)],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        deadline = 60.0
        while not list(tmp_path.glob(".moreau-staging.*")) and deadline > 0:
            assert first.poll() is None, first.stderr.read()
            subprocess.run(["sleep", "0.05"])
            deadline -= 0.05
        second = run_cli("run", scenario, "--out", out, "--set", "problem.count=10")
        assert second.returncode == 2
        lines = second.stderr.strip().splitlines()
        assert len(lines) == 1 and "another moreau run" in lines[0] and str(out) in lines[0]
        assert f"process {first.pid}" in lines[0]
    finally:
        first.terminate()
        first.wait(timeout=60)
    assert first.returncode == 143
    assert json.loads((out / "summary.json").read_text())["particles"] == 50
    assert hidden_leftovers(tmp_path) == []


def test_bad_input_creates_nothing(tmp_path):
    scenario = tmp_path / "p.toml"
    scenario.write_text(PARTICLES.replace("count = 50", "count = -5"))
    r = run_cli("run", scenario, "--out", tmp_path / "new" / "deep" / "out")
    assert r.returncode == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.toml"]


@pytest.mark.parametrize("shape", ["total", "component"])
def test_an_overlong_path_is_one_line_and_exit_2(tmp_path, shape):
    """Reproducer 3: a 4 k path exited with code 1."""
    scenario = tmp_path / "p.toml"
    scenario.write_text(PARTICLES)
    if shape == "total":
        out = tmp_path.joinpath(*["d" * 200] * 21)
    else:
        out = tmp_path / ("d" * 300)
    r = run_cli("run", scenario, "--out", out)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "--out" in lines[0] and "characters long" in lines[0], lines
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.toml"]


def test_installed_tool_finds_its_scripts_and_examples(tmp_path):
    build = pathlib.Path(CLI).parent
    if not (build / "cmake_install.cmake").exists():
        pytest.skip("the tool was not built by CMake here")
    prefix = tmp_path / "prefix"
    r = subprocess.run(["cmake", "--install", str(build), "--prefix", str(prefix)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    tool = prefix / "bin" / "moreau"
    # A line added to the installed copy proves that copy (not the source tree's) drew the figure.
    script = prefix / "share" / "moreau" / "scripts" / "plot_run.py"
    script.write_text(script.read_text() + "\nimport pathlib\n"
                      "pathlib.Path(sys.argv[1] + '.installed').touch()\n")
    example = prefix / "share" / "moreau" / "examples" / "sliding.toml"
    out = tmp_path / "out"
    r = subprocess.run([str(tool), "run", str(example), "--out", str(out), "--set",
                        "solver.h=0.01"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (out / "trajectory.png").exists() and (out / "trajectory.png.installed").exists()


def test_scripts_beside_the_executable_come_first(tmp_path):
    """Reproducer 1: scripts were found through a source-tree path fixed at build time. A copied
    tool looks in ../share/moreau/scripts first; a script that fails there gives one warning and
    the numbers."""
    prefix = tmp_path / "prefix"
    (prefix / "bin").mkdir(parents=True)
    shutil.copy(CLI, prefix / "bin" / "moreau")
    scripts = prefix / "share" / "moreau" / "scripts"
    scripts.mkdir(parents=True)
    (scripts / "plot_run.py").write_text("import sys\nsys.exit(1)\n")
    out = tmp_path / "out"
    r = subprocess.run([str(prefix / "bin" / "moreau"), "run", str(ROOT / "examples/sliding.toml"),
                        "--out", str(out), "--set", "solver.h=0.01"], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    assert "moreau: warning: plot_run.py failed (exit status 1); figures skipped" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert (out / "summary.json").exists() and not (out / "trajectory.png").exists()

"""The room's door in the collision-free speed model through `moreau run`: a person beside the
door on the line of a post's end leaves (the walk aims at the opening shrunk by ℓ/2, not at the
post's end), and everybody leaves the bottleneck example within its time, with and without its
noise."""
import re
import sys

from conftest import ROOT, run_cli

sys.path.insert(0, str(ROOT / "scripts"))
import crowd_bottleneck  # noqa: E402

BOTTLENECK = ROOT / "examples/crowds/bottleneck.toml"


def run(tmp_path, name, scenario, *sets):
    """`moreau run SCENARIO` into tmp_path/name with `--set` for each of sets."""
    r = run_cli("run", scenario, "--out", tmp_path / name, *(a for s in sets for a in ("--set", s)))
    assert r.returncode == 0, r.stderr
    return tmp_path / name


def out_count(out):
    """The people out at the end of the run (the last row of evacuation.csv)."""
    with open(out / "evacuation.csv") as f:
        header, *rows = f.read().split()
    assert header == "t,out"
    return int(rows[-1].split(",")[1])


def test_person_beside_the_door_on_a_posts_line_leaves(tmp_path):
    # The bottleneck study's room (8 m × 8 m, a 0.8 m door: its lower post ends at y = 3.6) with
    # one person at (7, 3.5) and no noise. Aimed at the post's end they stopped 0.17 m before it,
    # the post's repulsion cancelling the desired direction; now they are out within 3 s (1.1 m
    # at 1.34 m/s).
    text = crowd_bottleneck.scenario(0.8, people=1, duration=3.0)
    text = re.sub(r"\[domain\]", "[initial]\npositions = [[7.0, 3.5]]\n\n[domain]", text)
    toml = tmp_path / "beside.toml"
    toml.write_text(text)
    assert out_count(run(tmp_path, "beside", toml)) == 1


def test_everybody_leaves_the_bottleneck_example(tmp_path):
    # Without noise the old walk left two of the forty at the jambs' corners.
    for name, sets in (("noise", []), ("no_noise", ["forces.diffusion=0.0"])):
        out = run(tmp_path, name, BOTTLENECK, "output.hdf5=false", *sets)
        assert out_count(out) == 40, name

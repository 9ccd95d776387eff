"""The collision-free speed model in the two-dimensional corridor of scripts/crowd_corridor.py
through `moreau run`: free walkers walk at exactly v0, a dense corridor keeps everybody at least
the body length ℓ apart, runs have the same bits on one and two threads, and the bottleneck
script's steady flow is the count over the time between the chosen passages."""
import re
import sys

import h5py
import numpy as np

from conftest import ROOT, run_cli

sys.path.insert(0, str(ROOT / "scripts"))
import crowd_bottleneck  # noqa: E402
import crowd_corridor  # noqa: E402


def corridor(tmp_path, name, text, *sets):
    toml = tmp_path / f"{name}.toml"
    toml.write_text(text)
    out = tmp_path / name
    args = ["run", toml, "--out", out]
    for s in sets:
        args += ["--set", s]
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr
    return out


def test_free_walkers_on_the_axis_walk_at_v0(tmp_path):
    # Five people on the corridor's axis 4 m apart: every headway (4 m) exceeds ℓ + T v0, the
    # repulsions of the one ahead and the one behind are equal and opposite, and so are the two
    # walls' at equal distances: e = (1, 0) and V = v0 exactly, nobody leaves the axis.
    text = crowd_corridor.scenario(0.25, duration=10.0)
    y = crowd_corridor.WIDTH / 2
    start = ", ".join(f"[{x!r}, {y!r}]" for x in (2.0, 6.0, 10.0, 14.0, 18.0))
    text = re.sub(r"count = \d+", "count = 5", text)
    text = re.sub(r"\[initial\]\nlo = .*\nhi = .*\n", f"[initial]\npositions = [{start}]\n", text)
    out = corridor(tmp_path, "free", text)
    assert abs(crowd_corridor.mean_speed(out) - crowd_corridor.V0) < 1e-9
    with h5py.File(out / "trajectory.h5", "r") as f:
        assert np.all(f["positions"][()][..., 1] == y)


def min_distance(out, length):
    with h5py.File(out / "trajectory.h5", "r") as f:
        x = f["positions"][()]
    worst = np.inf
    for frame in x:
        d = frame[:, None, :] - frame[None, :, :]
        d[..., 0] -= length * np.round(d[..., 0] / length)
        r = np.hypot(d[..., 0], d[..., 1])
        np.fill_diagonal(r, np.inf)
        worst = min(worst, r.min())
    return worst


def test_dense_corridor_keeps_everybody_a_body_length_apart(tmp_path):
    # The model is collision-free (Tordeux et al. 2016): the speed is zero at a headway ℓ and a
    # step moves a person by at most h (s − ℓ)/T < s − ℓ toward the one in their path, so in a
    # one-way flow nobody comes closer than ℓ = 2r: the disks never touch, nothing is projected.
    out = corridor(tmp_path, "dense", crowd_corridor.scenario(3.0, duration=10.0))
    summary = (out / "summary.json").read_text()
    assert re.search(r'"max_overlap": 0(\.0)?,', summary), summary[:200]
    assert min_distance(out, crowd_corridor.LENGTH) >= 0.3 - 1e-12


def test_corridor_is_bit_identical_on_one_and_two_threads(tmp_path):
    text = crowd_corridor.scenario(2.0, duration=5.0)
    runs = [corridor(tmp_path, f"t{n}", text, f"solver.threads={n}") for n in (1, 2)]
    frames = []
    for out in runs:
        with h5py.File(out / "trajectory.h5", "r") as f:
            frames.append(f["positions"][()])
    assert np.array_equal(frames[0], frames[1])


def test_steady_flow_counts_between_the_chosen_passages(tmp_path):
    # 30 passages, one every 0.5 s from t = 1 s: between the 10th (t = 5.5) and the 20th
    # (t = 10.5) pass 10 people in 5 s.
    path = tmp_path / "evacuation.csv"
    path.write_text("t,out\n0,0\n" + "".join(f"{1 + 0.5 * k},{k + 1}\n" for k in range(30)))
    assert crowd_bottleneck.steady_flow(path, people=30, skip=10) == 2.0
    assert np.isnan(crowd_bottleneck.steady_flow(path, people=45, skip=10))

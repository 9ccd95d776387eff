"""An agent-based run's outputs as ParaView reads them: a small colony (growing, dividing, dying,
leaving; tests/cli/abm_colony.toml) written by `moreau run`, its trajectory.xdmf opened with the
three XDMF readers and vtu/frame.pvd with the PVD reader, every agent array (type, generation, divisions, mother, display_id, age,
polarity, contacts) compared with h5py's view of trajectory.h5; and geometry.vtp of the crowd
example (its room and door) opened with ParaView's XML PolyData reader."""
import subprocess

import h5py
import numpy as np
import pytest

from conftest import CLI, ROOT, XDMF_READERS, paraview_read

ARRAYS = ("type", "generation", "divisions", "mother", "display_id", "age", "polarity", "contacts")


@pytest.fixture(scope="module")
def colony(tmp_path_factory):
    folder = tmp_path_factory.mktemp("abm_colony")
    r = subprocess.run([CLI, "run", str(ROOT / "tests/cli/abm_colony.toml"), "--out",
                        str(folder / "out")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return folder / "out"


@pytest.fixture(scope="module")
def colony_paraview(colony, tmp_path_factory):
    jobs = [(reader, colony / "trajectory.xdmf") for reader in XDMF_READERS]
    jobs.append(("PVDReader", colony / "vtu" / "frame.pvd"))
    results = paraview_read(jobs, tmp_path_factory.mktemp("abm_colony_paraview"))
    return {reader: result for (reader, _), result in zip(jobs, results)}


@pytest.mark.parametrize("reader", XDMF_READERS + ("PVDReader",))
def test_paraview_reads_every_agent_array(colony, colony_paraview, reader):
    with h5py.File(colony / "trajectory.h5", "r") as f:
        counts, time = f["count"][:], f["time"][:]
        data = {name: f["point_data"][name][:] for name in ARRAYS}
    result = colony_paraview[reader]
    # The sidecar leaves empty frames out; the VTU series keeps them.
    kept = np.arange(len(counts)) if reader == "PVDReader" else np.flatnonzero(counts > 0)
    np.testing.assert_array_equal(result["times"], time[kept])
    assert len(set(counts.tolist())) > 1
    for i, f in enumerate(kept):
        n = counts[f]
        for name in ARRAYS:
            got = result[f"point_{name}_{i}"]
            np.testing.assert_array_equal(got.reshape(data[name][f, :n].shape), data[name][f, :n])


def test_paraview_reads_the_room_and_its_door(example_runs, tmp_path_factory):
    _, out, _ = example_runs("crowd")
    (result,) = paraview_read([("XMLPolyDataReader", out / "geometry.vtp")],
                              tmp_path_factory.mktemp("geometry_paraview"))
    assert int(result["cells_0"]) == 6  # five wall segments and the door
    np.testing.assert_array_equal(np.sort(result["cell_kind_0"]), [1, 1, 1, 1, 1, 3])
    door = result["points_0"][np.flatnonzero(result["cell_kind_0"] == 3)[0] * 2:][:2]
    np.testing.assert_allclose(door[:, 0], 15.0)

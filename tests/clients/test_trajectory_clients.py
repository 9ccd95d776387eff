"""The particle outputs of `moreau run` (trajectory.h5 + .xdmf, vtu/frame.pvd, evacuation.csv),
opened with the programs people use — h5py, ParaView's three XDMF readers and its PVD reader
(through pvbatch), VTK's XML reader, numpy — on the crowd, 3D packing and 10^4-disk examples
(shortened), and checked against the run's own summary.json."""
import numpy as np
import pytest
import h5py
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

from conftest import XDMF_READERS, paraview_read


def expected_frames(summary):
    """The steps and times the run wrote frames at: every stride steps, and the last."""
    steps, stride = summary["steps"], summary["settings"]["output"]["stride"]
    frame_steps = [s for s in range(steps + 1) if s % stride == 0 or s == steps]
    return np.array(frame_steps), np.array(frame_steps) * summary["h"]


@pytest.fixture(scope="session")
def trajectory(example_run):
    """The HDF5 trajectory read with h5py: dict of arrays and attributes."""
    name, out, summary = example_run
    with h5py.File(out / "trajectory.h5", "r") as f:
        data = {key: f[key][()] for key in ("time", "step", "count", "positions", "ids", "radii")}
        data["attrs"] = dict(f.attrs)
    return data


@pytest.fixture(scope="session")
def paraview(example_run, tmp_path_factory):
    """Every ParaView reader's view of the run: {reader: arrays} (one pvbatch process)."""
    name, out, summary = example_run
    jobs = [(reader, out / "trajectory.xdmf") for reader in XDMF_READERS]
    jobs.append(("PVDReader", out / "vtu" / "frame.pvd"))
    results = paraview_read(jobs, tmp_path_factory.mktemp(f"{name}_paraview"))
    return {reader: result for (reader, _), result in zip(jobs, results)}


def test_h5py_reads_the_trajectory_the_summary_describes(example_run, trajectory):
    name, out, summary = example_run
    n, k = summary["particles"], summary["dimension"]
    steps, times = expected_frames(summary)
    f = len(steps)
    attrs = trajectory["attrs"]
    assert attrs["format"] == b"moreau-trajectory" and attrs["format_version"] == 2
    assert attrs["dimension"] == k and attrs["count"] == n
    np.testing.assert_array_equal(trajectory["step"], steps)
    np.testing.assert_allclose(trajectory["time"], times, rtol=1e-12, atol=1e-12)
    assert trajectory["time"][-1] == summary["final_time"]
    np.testing.assert_array_equal(trajectory["count"], np.full(f, n))
    assert trajectory["positions"].shape == (f, n, k)
    assert np.isfinite(trajectory["positions"]).all()
    for frame_ids in trajectory["ids"]:
        np.testing.assert_array_equal(np.sort(frame_ids), np.arange(n))
    problem = summary["settings"]["problem"]
    lo = problem.get("radius_min", problem.get("radius"))
    hi = problem.get("radius_max", problem.get("radius"))
    assert ((trajectory["radii"] >= lo) & (trajectory["radii"] <= hi)).all()


@pytest.mark.parametrize("reader", XDMF_READERS)
def test_paraview_xdmf_reader_opens_every_frame_with_its_values(example_run, trajectory,
                                                                 paraview, reader):
    """Each XDMF reader: the time steps of the file, N points and N cells per step, positions
    (z = 0 in 2D), radius and id equal to the HDF5 values bit for bit."""
    name, out, summary = example_run
    expect_same_frames(paraview[reader], trajectory, summary, cells=True)


def test_paraview_pvd_reader_opens_the_vtu_series(example_run, trajectory, paraview):
    name, out, summary = example_run
    expect_same_frames(paraview["PVDReader"], trajectory, summary, cells=True)


def expect_same_frames(result, trajectory, summary, cells):
    n, k = summary["particles"], summary["dimension"]
    np.testing.assert_array_equal(result["times"], trajectory["time"])
    for i in range(len(trajectory["time"])):
        points = result[f"points_{i}"]
        assert points.shape == (n, 3)
        np.testing.assert_array_equal(points[:, :k], trajectory["positions"][i])
        if k == 2:
            np.testing.assert_array_equal(points[:, 2], 0.0)
        np.testing.assert_array_equal(result[f"radius_{i}"], trajectory["radii"][i])
        np.testing.assert_array_equal(result[f"id_{i}"], trajectory["ids"][i])
        if cells:
            assert int(result[f"cells_{i}"]) == n


def test_vtk_xml_reader_reads_each_vtu_file(example_run, trajectory):
    """VTK's own XML reader (vtkmodules, no ParaView server) on every file of the series."""
    name, out, summary = example_run
    files = sorted((out / "vtu").glob("frame_*.vtu"))
    assert len(files) == len(trajectory["time"])
    k = summary["dimension"]
    for i, path in enumerate(files):
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(path))
        reader.Update()
        grid = reader.GetOutput()
        assert grid.GetNumberOfPoints() == summary["particles"] == grid.GetNumberOfCells()
        points = vtk_to_numpy(grid.GetPoints().GetData())
        np.testing.assert_array_equal(points[:, :k], trajectory["positions"][i])
        data = grid.GetPointData()
        np.testing.assert_array_equal(vtk_to_numpy(data.GetArray("radius")), trajectory["radii"][i])
        np.testing.assert_array_equal(vtk_to_numpy(data.GetArray("id")), trajectory["ids"][i])
        time = vtk_to_numpy(grid.GetFieldData().GetArray("TimeValue"))
        assert time[0] == trajectory["time"][i]


def test_numpy_reads_the_evacuation_series(example_runs):
    name, out, summary = example_runs("crowd")  # the example with a room
    table = np.genfromtxt(out / "evacuation.csv", delimiter=",", names=True)
    assert table.dtype.names == ("t", "out")
    assert len(table) == summary["steps"] + 1  # every step, and the start
    assert table["t"][-1] == pytest.approx(summary["final_time"], rel=1e-9)
    assert table["out"][-1] == summary["evacuated"]
    assert (np.diff(table["out"]) >= 0).all()  # nobody comes back in

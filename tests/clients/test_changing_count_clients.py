"""Trajectories whose particle count changes from frame to frame (growing, dividing, dying,
an empty frame), as the HDF5 writer writes them: the unit tests of tests/io write the samples
(Hdf5Writer.ChangingParticleCount… in 2D, Hdf5Writer.GrowingPastOneChunk… in 3D, and the same
with float32 positions and/or deflate: Hdf5Writer.SinglePrecision…, Hdf5Writer.Compression…; with
extra point arrays, an int64 and a float64 scalar and a vector: Hdf5Writer.PointArrays…) and
this suite opens them with h5py and ParaView's three XDMF readers."""
import os
import subprocess

import h5py
import numpy as np
import pytest

from conftest import UNIT_TESTS, XDMF_READERS, paraview_read

SAMPLES = {"t": 2, "grow": 3, "single": 2, "single3d": 3, "deflate": 2, "single_deflate": 3}
SINGLE = {"single", "single3d", "single_deflate"}  # float32 positions; ParaView keeps them float32


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    out = tmp_path_factory.mktemp("samples")
    r = subprocess.run(
        [UNIT_TESTS, "--gtest_filter=Hdf5Writer.ChangingParticleCount*:Hdf5Writer.Growing*:"
         "Hdf5Writer.SinglePrecision*:Hdf5Writer.Compression*:Hdf5Writer.PointArrays*"],
        capture_output=True, text=True, timeout=120, env={**os.environ, "MOREAU_IO_SAMPLE_DIR": str(out)})
    assert r.returncode == 0, r.stdout[-3000:]
    return out


def read_h5(path):
    with h5py.File(path, "r") as f:
        return {key: f[key][()] for key in ("time", "count", "positions", "ids", "radii")}


@pytest.mark.parametrize("stem", sorted(SAMPLES))
def test_h5py_reads_each_frame_as_its_first_count_rows(samples, stem):
    data = read_h5(samples / f"{stem}.h5")
    rows = data["count"].max()
    assert data["positions"].shape == (len(data["time"]), rows, SAMPLES[stem])
    assert len(set(data["count"])) > 2  # the count does change
    for f, n in enumerate(data["count"]):
        assert np.isfinite(data["positions"][f, :n]).all() and np.isnan(data["positions"][f, n:]).all()
        assert (data["ids"][f, :n] >= 0).all() and (data["ids"][f, n:] == -1).all()
        assert len(set(data["ids"][f, :n])) == n


@pytest.fixture(scope="module")
def paraview(samples, tmp_path_factory):
    """{(stem, reader): arrays} for every sample and XDMF reader (one pvbatch process)."""
    jobs = [(stem, reader) for stem in sorted(SAMPLES) + ["agents"] for reader in XDMF_READERS]
    results = paraview_read([(reader, samples / f"{stem}.xdmf") for stem, reader in jobs],
                            tmp_path_factory.mktemp("samples_paraview"))
    return dict(zip(jobs, results))


@pytest.mark.parametrize("stem", sorted(SAMPLES))
@pytest.mark.parametrize("reader", XDMF_READERS)
def test_paraview_xdmf_reader_opens_every_nonempty_frame(samples, paraview, stem, reader):
    """Each reader: one time step per frame with particles (an empty frame is left out of the
    sidecar), N_f points and cells, and the frame's positions, radii and ids."""
    data = read_h5(samples / f"{stem}.h5")
    k = SAMPLES[stem]
    kept = np.flatnonzero(data["count"] > 0)
    result = paraview[(stem, reader)]
    np.testing.assert_array_equal(result["times"], data["time"][kept])
    for i, f in enumerate(kept):
        n = data["count"][f]
        points = result[f"points_{i}"]
        assert points.shape == (n, 3) and int(result[f"cells_{i}"]) == n
        assert points.dtype == (np.float32 if stem in SINGLE else np.float64)
        np.testing.assert_array_equal(points[:, :k], data["positions"][f, :n])
        np.testing.assert_array_equal(result[f"radius_{i}"], data["radii"][f, :n])
        np.testing.assert_array_equal(result[f"id_{i}"], data["ids"][f, :n])


@pytest.mark.parametrize("reader", XDMF_READERS)
def test_paraview_xdmf_reader_reads_the_extra_point_arrays(samples, paraview, reader):
    """The agents sample's arrays type (int64), age (float64) and polarity (3 × float64) as each
    reader gives them, frame by frame (the empty frame is left out)."""
    with h5py.File(samples / "agents.h5", "r") as f:
        count = f["count"][:]
        arrays = {name: f["point_data"][name][:] for name in ("type", "age", "polarity")}
    result = paraview[("agents", reader)]
    for i, f in enumerate(np.flatnonzero(count > 0)):
        n = count[f]
        for name, values in arrays.items():
            got = result[f"point_{name}_{i}"]
            np.testing.assert_array_equal(got.reshape(values[f, :n].shape), values[f, :n])

"""Fields on a uniform grid (io/grid_writer.h) opened as a person would: fields.xdmf with
ParaView's three XDMF readers, vti/fields.pvd with the PVD reader, and the particles'
trajectory.xdmf of the same run beside them. The unit test FieldSample.* (tests/io) writes a 2D
and a 3D sample whose field c = x + 2y + 3z + t at each voxel's centre (z = 0 in 2D) and whose
field noise holds random doubles; this suite checks the times, the cell counts, the bounds, c at
the centres VTK computes for its cells, and every value against h5py bit for bit."""
import os
import subprocess

import h5py
import numpy as np
import pytest

from conftest import UNIT_TESTS, XDMF_READERS, paraview_read

SAMPLES = ("fields2d", "fields3d")
FIELD_READERS = XDMF_READERS + ("PVDReader",)


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    out = tmp_path_factory.mktemp("field_samples")
    r = subprocess.run([UNIT_TESTS, "--gtest_filter=FieldSample.*"], capture_output=True,
                       text=True, timeout=120, env={**os.environ, "MOREAU_IO_SAMPLE_DIR": str(out)})
    assert r.returncode == 0, r.stdout[-3000:]
    return out


def field_file(sample_dir, reader):
    return sample_dir / ("vti/fields.pvd" if reader == "PVDReader" else "fields.xdmf")


@pytest.fixture(scope="module")
def paraview(samples, tmp_path_factory):
    """{(sample, what, reader): arrays} for the fields with every reader and the particles with
    every XDMF reader (one pvbatch process)."""
    jobs = [(s, "fields", r) for s in SAMPLES for r in FIELD_READERS]
    jobs += [(s, "particles", r) for s in SAMPLES for r in XDMF_READERS]
    files = [(r, field_file(samples / s, r) if what == "fields" else samples / s / "trajectory.xdmf")
             for s, what, r in jobs]
    return dict(zip(jobs, paraview_read(files, tmp_path_factory.mktemp("field_paraview"))))


def read_fields(path):
    with h5py.File(path, "r") as f:
        return {"time": f["time"][:], "c": f["fields/c"][:], "noise": f["fields/noise"][:],
                "dimension": int(f.attrs["dimension"]), "origin": f.attrs["origin"][:],
                "spacing": float(f.attrs["spacing"]), "cells": f.attrs["cells"][:]}


@pytest.mark.parametrize("sample", SAMPLES)
@pytest.mark.parametrize("reader", FIELD_READERS)
def test_paraview_reads_every_frame_as_cell_data_on_the_grid(samples, paraview, sample, reader):
    data = read_fields(samples / sample / "fields.h5")
    result = paraview[(sample, "fields", reader)]
    np.testing.assert_array_equal(result["times"], data["time"])
    k, h, origin, cells = data["dimension"], data["spacing"], data["origin"], data["cells"]
    upper = origin + h * cells
    if k == 3:
        bounds = [origin[0], upper[0], origin[1], upper[1], origin[2], upper[2]]
    elif reader == "PVDReader":  # a flat image at z = 0
        bounds = [origin[0], upper[0], origin[1], upper[1], 0.0, 0.0]
    else:  # XDMF: one layer of voxels centred on the particles' plane z = 0
        bounds = [origin[0], upper[0], origin[1], upper[1], -h / 2, h / 2]
    for i, t in enumerate(data["time"]):
        assert int(result[f"cells_{i}"]) == np.prod(cells)
        np.testing.assert_allclose(result[f"bounds_{i}"], bounds, rtol=0, atol=1e-12)
        centres = result[f"cellcentres_{i}"]
        c = result[f"cell_c_{i}"]
        np.testing.assert_allclose(c, centres[:, 0] + 2 * centres[:, 1] + 3 * centres[:, 2] + t,
                                   rtol=0, atol=1e-12)
        np.testing.assert_array_equal(c, data["c"][i].ravel())  # x fastest, as written
        np.testing.assert_array_equal(result[f"cell_noise_{i}"], data["noise"][i].ravel())


@pytest.mark.parametrize("sample", SAMPLES)
@pytest.mark.parametrize("reader", XDMF_READERS)
def test_the_particles_open_beside_the_fields_at_the_same_times(samples, paraview, sample, reader):
    fields = paraview[(sample, "fields", reader)]
    particles = paraview[(sample, "particles", reader)]
    np.testing.assert_array_equal(particles["times"], fields["times"])
    bounds = fields["bounds_0"]
    for i in range(len(particles["times"])):
        points = particles[f"points_{i}"]
        assert points.shape == (3, 3)
        assert (points[:, 0] > bounds[0]).all() and (points[:, 0] < bounds[1]).all()
        assert (points[:, 1] > bounds[2]).all() and (points[:, 1] < bounds[3]).all()

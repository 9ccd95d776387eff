"""scripts/plot_field.py on the 2D and 3D samples the unit test FieldSample.* (tests/io) writes:
fields.h5 (c = x + 2y + 3z + t on the grid) and the particles' trajectory.h5 at the same times."""
import os
import pathlib
import subprocess
import struct

import matplotlib.image
import numpy as np
import pytest

from conftest import ROOT

UNIT_TESTS = os.environ.get("MOREAU_TESTS", str(ROOT / "build/release/moreau_tests"))
SCRIPT = ROOT / "scripts/plot_field.py"


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    out = tmp_path_factory.mktemp("field_samples")
    r = subprocess.run([UNIT_TESTS, "--gtest_filter=FieldSample.*"], capture_output=True,
                       text=True, timeout=120, env={**os.environ, "MOREAU_IO_SAMPLE_DIR": str(out)})
    assert r.returncode == 0, r.stdout[-3000:]
    return out


def plot(*args):
    return subprocess.run(["/usr/bin/python3", str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, timeout=120)


def png_size(path):
    """(width, height) from the PNG's IHDR chunk."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


@pytest.mark.parametrize("sample,extra", [("fields2d", []), ("fields3d", []),
                                          ("fields3d", ["--z", "2.3", "--frame", "0"])])
def test_draws_the_field_with_the_agents(samples, tmp_path, sample, extra):
    out = tmp_path / "field.png"
    r = plot(samples / sample / "fields.h5", "--trajectory", samples / sample / "trajectory.h5",
             "--field", "c", "--unit", "µm", "--out", out, *extra)
    assert r.returncode == 0, r.stderr
    width, height = png_size(out)
    assert width == 900 and 300 <= height <= 1500, (width, height)
    assert out.stat().st_size > 10_000
    pixels = matplotlib.image.imread(out)
    assert len(np.unique(pixels.reshape(-1, pixels.shape[-1]), axis=0)) > 50  # a gradient, not blank


def test_bad_usage_is_one_line_and_status_2(samples, tmp_path):
    fields2d = samples / "fields2d" / "fields.h5"
    for args, needle in [((fields2d, "--z", "0"), "--z is for 3D fields"),
                         ((fields2d, "--field", "oxygen"), "no field 'oxygen' (fields: c, noise)"),
                         ((fields2d, "--frame", "3"), "frame 3 out of range (3 frames)"),
                         ((samples / "fields3d" / "fields.h5", "--z", "9"), "outside the grid"),
                         ((tmp_path / "none.h5",), "cannot read"),
                         ((samples / "fields2d" / "trajectory.h5",), "not a moreau fields file")]:
        r = plot(*args, "--out", tmp_path / "x.png")
        assert r.returncode == 2, (args, r.stderr)
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and needle in lines[0], (needle, r.stderr)
    assert not (tmp_path / "x.png").exists()

"""The files `moreau fill-gaps` writes (filled.c3d, filled.csv, report.json), read by other
programs. Debian 12 packages no C3D reader (no ezc3d, btk or c3d module; `apt-cache search c3d`
finds none), so the C3D file is decoded here with numpy from its published layout (header block,
parameter block, float32 point records) and compared with the CSV that numpy reads; the tool
writes no TRC file."""
import json
import subprocess

import numpy as np
import pytest

from conftest import CLI, ROOT

RECORDING = ROOT.parent / "shared" / "data" / "mocap" / "Vicon.c3d"


@pytest.fixture(scope="module")
def filled(tmp_path_factory):
    out = tmp_path_factory.mktemp("fill_gaps") / "vicon"
    r = subprocess.run([CLI, "fill-gaps", str(RECORDING), "--method", "linear", "--out", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return out, json.loads((out / "report.json").read_text())


def read_c3d_points(path):
    """(header dict, points F×M×4 float32: x, y, z, residual) of a float-format Intel C3D."""
    raw = path.read_bytes()
    words = np.frombuffer(raw[:512], dtype="<u2")
    parameter_block = raw[0]
    assert raw[1] == 0x50  # the C3D signature
    processor = raw[(parameter_block - 1) * 512 + 3]
    assert processor == 84, "not an Intel (little-endian) C3D"
    markers, analog_per_frame, first, last = (int(w) for w in words[1:5])
    scale = float(np.frombuffer(raw[12:16], dtype="<f4")[0])
    data_block = int(words[8])
    rate = float(np.frombuffer(raw[20:24], dtype="<f4")[0])
    assert scale < 0, "integer C3D"  # the tool writes float32 samples
    frames = last - first + 1
    record = 4 * markers + analog_per_frame  # float32 words per frame
    body = np.frombuffer(raw, dtype="<f4", offset=(data_block - 1) * 512, count=frames * record)
    points = body.reshape(frames, record)[:, : 4 * markers].reshape(frames, markers, 4)
    return {"markers": markers, "first": first, "frames": frames, "rate": rate}, points


def test_numpy_reads_the_filled_csv_as_the_report_says(filled):
    out, report = filled
    table = np.genfromtxt(out / "filled.csv", delimiter=",", names=True, dtype=None,
                          encoding="utf-8")
    assert table.dtype.names == ("frame", "time", "marker", "x", "y", "z")
    assert len(table) == report["frames"] * report["markers"]
    assert len(set(table["marker"])) == report["markers"]
    assert report["gaps_unfilled"] == 0
    xyz = np.stack([table["x"], table["y"], table["z"]], axis=1)
    assert np.isfinite(xyz).all()  # every gap filled
    np.testing.assert_allclose(table["time"], (table["frame"] - table["frame"][0]) / report["rate"])


def test_c3d_header_and_points_match_the_csv(filled):
    out, report = filled
    header, points = read_c3d_points(out / "filled.c3d")
    assert header["markers"] == report["markers"]
    assert header["frames"] == report["frames"]
    assert header["rate"] == report["rate"]
    assert (points[:, :, 3] >= 0).all()  # residual −1 would mark a missing sample
    table = np.genfromtxt(out / "filled.csv", delimiter=",", names=True, dtype=None,
                          encoding="utf-8")
    csv_xyz = np.stack([table["x"], table["y"], table["z"]], axis=1)
    csv_xyz = csv_xyz.reshape(report["frames"], report["markers"], 3)
    np.testing.assert_allclose(points[:, :, :3], csv_xyz, rtol=1e-6, atol=1e-4)

"""The files `moreau fill-gaps` writes (filled.c3d, filled.csv, report.json), read by other
programs; fill-gaps is the only command that writes C3D (the library's WriteC3d, also reached
from Python's `moreau.mocap.write_recording`, is called by no other command).

Two ways in. numpy decodes the C3D from its published layout (header block, parameter block,
float32 point records) with /usr/bin/python3, as Debian 12 packages no C3D reader. The readers of
the field, ezc3d and Kinetics Toolkit (`ktk.read_c3d`, which reads through ezc3d and returns the
points as a TimeSeries), come from PyPI into the virtual environment the Makefile makes
(CLIENTS_VENV, pinned by requirements.txt): c3d_read.py runs there, one process for all files,
and saves what each reader returns as .npz files that the tests here compare with filled.csv,
report.json and the input recording as ezc3d reads it. Without that environment (no network when
the Makefile tried) those tests skip, saying why; the numpy ones still run.

Residuals: moreau keeps no residuals or camera masks. Every sample of filled.c3d that holds a
position, measured or filled, has residual 0 and camera mask 0 (ezc3d: residual 0.0, no camera);
a sample left missing (a marker never observed) has residual −1 and coordinates 0, which ezc3d
and Kinetics Toolkit read as NaN. The files are Vicon.c3d filled by `--method linear`,
PlugInC3D.c3d so filled (model outputs: POINT:ANGLES, FORCES, … written back), and recordings
written here as CSV for what those lack: more than 255 markers (POINT:LABELS2), more than 65535
frames (the header and POINT:FRAMES saturated, the TRIAL fields holding the range; a float
POINT:FRAMES, as moreau once wrote it, ezc3d refuses), first frames other than 1, a marker never
observed."""
import json
import subprocess

import numpy as np
import pytest

from conftest import CLI, ROOT, c3d_read

MOCAP = ROOT.parent / "shared" / "data" / "mocap"
RECORDING = MOCAP / "Vicon.c3d"
MODEL_OUTPUTS = MOCAP / "PlugInC3D.c3d"  # markers, and angles, forces, moments, powers as points


def fill_gaps(recording, out):
    r = subprocess.run([CLI, "fill-gaps", str(recording), "--method", "linear", "--out", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return out, json.loads((out / "report.json").read_text())


@pytest.fixture(scope="module")
def filled(tmp_path_factory):
    return fill_gaps(RECORDING, tmp_path_factory.mktemp("fill_gaps") / "vicon")


def write_csv(path, first, rate, labels, x):
    """A recording as moreau's CSV (frame numbers from `first`); NaN samples are missing."""
    rows = ["frame,time,marker,x,y,z"]
    for f in range(x.shape[0]):
        for m, label in enumerate(labels):
            xyz = "" if np.isnan(x[f, m, 0]) else ",".join(f"{v!r}" for v in x[f, m])
            rows.append(f"{first + f},{f / rate!r},{label},{xyz or ',,'}")
    path.write_text("\n".join(rows) + "\n")


# name → (first frame, rate, markers, frames); each has a 2-frame gap in marker 1, and "wide"
# has a marker that is never observed (it stays missing).
EDGES = {"wide": (101, 50.0, 300, 4), "long": (5, 1000.0, 2, 70000)}


@pytest.fixture(scope="module")
def edges(clients_venv, tmp_path_factory):
    """name → (output folder, report, input as a F×M×3 array with NaN where missing, labels)."""
    runs = {}
    for name, (first, rate, markers, frames) in EDGES.items():
        folder = tmp_path_factory.mktemp(name)
        f, m = np.meshgrid(np.arange(frames), np.arange(markers), indexing="ij")
        x = np.stack([m * 10.0 + 0.25, np.sin(f * 0.01 + m), f * 0.5 - 3.0], axis=2)
        x[1:3, 1] = np.nan
        if name == "wide":
            x[:, markers - 1] = np.nan
        labels = [f"{name}:M{k}" for k in range(markers)]
        write_csv(folder / "input.csv", first, rate, labels, x)
        runs[name] = fill_gaps(folder / "input.csv", folder / "out") + (x, labels)
    return runs


@pytest.fixture(scope="module")
def plug_in(clients_venv, tmp_path_factory):
    return fill_gaps(MODEL_OUTPUTS, tmp_path_factory.mktemp("fill_gaps") / "plug_in")


@pytest.fixture(scope="module")
def readers(clients_venv, filled, edges, plug_in, tmp_path_factory):
    """What ezc3d and Kinetics Toolkit read: "filled", "input" (Vicon.c3d), each of EDGES,
    "plug_in" (PlugInC3D.c3d filled) and "plug_in_input"."""
    files = {"filled": filled[0] / "filled.c3d", "input": RECORDING}
    files |= {name: out / "filled.c3d" for name, (out, *_) in edges.items()}
    files |= {"plug_in": plug_in[0] / "filled.c3d", "plug_in_input": MODEL_OUTPUTS}
    read = c3d_read(list(files.values()), tmp_path_factory.mktemp("c3d_read"))
    return dict(zip(files, read))


def read_csv(path):
    return np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")


def csv_points(table, frames, markers):
    xyz = np.stack([table["x"], table["y"], table["z"]], axis=1).astype(np.float64)
    return xyz.reshape(frames, markers, 3)


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
    table = read_csv(out / "filled.csv")
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
    table = read_csv(out / "filled.csv")
    csv_xyz = csv_points(table, report["frames"], report["markers"])
    np.testing.assert_allclose(points[:, :, :3], csv_xyz, rtol=1e-6, atol=1e-4)


def check_layout(c3d, labels, first, rate, frames, units):
    """Labels, units, rate, frame range as ezc3d and Kinetics Toolkit give them."""
    assert list(c3d["ezc3d_labels"]) == labels
    assert list(c3d["ktk_labels"]) == labels
    assert str(c3d["ezc3d_units"]) == units and str(c3d["ktk_unit"]) == units
    assert c3d["ezc3d_rate"] == rate
    assert c3d["ezc3d_first"] == first - 1  # ezc3d counts frames from 0, C3D from 1
    assert c3d["ezc3d_points"].shape == (frames, len(labels), 3)
    assert c3d["ezc3d_frames"] == frames  # ezc3d sets POINT:FRAMES to the frames it read
    assert list(c3d["ezc3d_trial_range"]) == [first, first + frames - 1]
    # Kinetics Toolkit's clock starts at the first frame: (first − 1) / rate.
    np.testing.assert_allclose(c3d["ktk_time"], (first - 1 + np.arange(frames)) / rate,
                               rtol=1e-12, atol=1e-12)
    # Kinetics Toolkit's points are ezc3d's, as homogeneous coordinates.
    assert np.array_equal(c3d["ktk_points"][..., :3], c3d["ezc3d_points"], equal_nan=True)
    observed = np.isfinite(c3d["ezc3d_points"][..., 0])
    assert (c3d["ktk_points"][..., 3][observed] == 1).all()


def test_ezc3d_and_ktk_read_labels_rate_and_frames(filled, readers):
    out, report = filled
    table = read_csv(out / "filled.csv")
    labels = [str(s) for s in table["marker"][: report["markers"]]]
    assert labels == list(readers["input"]["ezc3d_labels"])  # the recording's, in its order
    check_layout(readers["filled"], labels, int(table["frame"][0]), report["rate"],
                 report["frames"], report["units"])
    assert readers["filled"]["ezc3d_first"] == readers["input"]["ezc3d_first"]
    assert "ezc3d_ANGLES" not in readers["filled"]  # markers only: no POINT:ANGLES, …


def test_ezc3d_reads_the_filled_samples_as_the_csv_and_the_others_as_the_recording(filled,
                                                                                    readers):
    out, report = filled
    got = readers["filled"]["ezc3d_points"]
    table = read_csv(out / "filled.csv")
    csv_xyz = csv_points(table, report["frames"], report["markers"])
    assert np.isfinite(got).all()
    np.testing.assert_array_equal(got, csv_xyz.astype(np.float32))  # float32 of the CSV's doubles
    source = readers["input"]["ezc3d_points"]
    untouched = np.isfinite(source).all(axis=2) & (source != 0).any(axis=2)
    assert (~untouched).sum() == sum(g["last"] - g["first"] + 1 for g in report["gaps"]) > 0
    np.testing.assert_array_equal(got[untouched], source[untouched])


def test_residuals_are_zero_for_every_sample_holding_a_position(filled, readers):
    filled_c3d, source = readers["filled"], readers["input"]
    assert (filled_c3d["ezc3d_residuals"] == 0).all()
    assert not filled_c3d["ezc3d_camera_masks"].any()
    # The recording's gaps carry residual −1 there, and ezc3d reads them as NaN.
    assert (source["ezc3d_residuals"] < 0).any()
    missing = np.isnan(source["ezc3d_points"][..., 0])
    assert (source["ezc3d_residuals"][missing] < 0).all()


@pytest.mark.parametrize("name", sorted(EDGES))
def test_ezc3d_and_ktk_read_wide_long_and_late_recordings(name, edges, readers):
    out, report, x, labels = edges[name]
    first, rate, markers, frames = EDGES[name]
    c3d = readers[name]
    check_layout(c3d, labels, first, rate, frames, "mm")
    got = c3d["ezc3d_points"]
    observed = ~np.isnan(x[..., 0])
    np.testing.assert_array_equal(got[observed], x[observed].astype(np.float32))
    # The gap in marker 1 is filled (linearly, between frames 0 and 3) with residual 0.
    np.testing.assert_allclose(got[1:3, 1], x[0, 1] + np.outer([1, 2], x[3, 1] - x[0, 1]) / 3,
                               rtol=1e-6)
    never = np.isnan(x).all(axis=(0, 2))
    assert np.isnan(got[:, never]).all()  # residual −1 and coordinates 0: missing to ezc3d
    assert (c3d["ezc3d_residuals"][:, never] < 0).all()
    assert (c3d["ezc3d_residuals"][:, ~never] == 0).all()
    assert report["gaps_unfilled"] == int(never.sum())


def test_ezc3d_reads_the_model_outputs_types_as_the_recording_states_them(plug_in, readers):
    out, report = plug_in
    c3d, source = readers["plug_in"], readers["plug_in_input"]
    types = [f"ezc3d_{name}" for name in ("ANGLES", "FORCES", "MOMENTS", "POWERS")]
    for key in types:
        assert list(c3d[key]) == list(source[key])  # POINT:ANGLES, …: the labels of each type
    labels = list(source["ezc3d_labels"])
    check_layout(c3d, labels, int(source["ezc3d_first"]) + 1, report["rate"], report["frames"],
                 report["units"])
    # Model outputs are never filled: each sample is the recording's, or missing as there.
    outputs = np.isin(labels, np.concatenate([source[key] for key in types]))
    got, was = c3d["ezc3d_points"][:, outputs], source["ezc3d_points"][:, outputs]
    assert np.array_equal(np.isnan(got), np.isnan(was) | (was == 0).all(axis=2, keepdims=True))
    kept = ~np.isnan(got)
    np.testing.assert_allclose(got[kept], was[kept], rtol=1e-6)  # integer storage, scaled

"""moreau.mocap: recordings read and written, the positions view without a copy, gap filling
as `moreau fill-gaps` fills, errors naming the file."""
import numpy as np
import pytest

from moreau import mocap
from conftest import MOCAP


def test_read_write_round_trip_and_zero_copy_view(tmp_path):
    r, warnings = mocap.read_recording(MOCAP / "Vicon.c3d")
    x = r.positions
    assert x.shape == (r.frames, r.markers, 3) and not x.flags.writeable
    assert x.base is not None  # a view on the recording's storage
    assert np.array_equal(np.isfinite(x[:, :, 0]), r.observed)
    mocap.write_recording(r, tmp_path / "copy.c3d")
    again, _ = mocap.read_recording(tmp_path / "copy.c3d")
    assert again.labels == r.labels and again.rate == r.rate
    assert np.allclose(again.positions, x, equal_nan=True, rtol=0, atol=1e-3)


def test_point_types_descriptions_and_type_units():
    r, _ = mocap.read_recording(MOCAP / "PlugInC3D.c3d")
    types = r.point_types
    assert len(types) == r.markers == 86 and len(r.descriptions) == 86
    counts = {t: types.count(t) for t in set(types)}
    assert counts == {"marker": 54, "angle": 10, "force": 8, "moment": 8, "power": 6}
    assert all(t == "angle" for t, label in zip(types, r.labels) if "Angles" in label)
    assert r.type_units["angle"] == "deg" and "marker" not in r.type_units
    v, _ = mocap.read_recording(MOCAP / "Vicon.c3d")
    assert set(v.point_types) == {"marker"}
    x = mocap.Recording(["A"], np.zeros((2, 1, 3)), 100.0)
    assert x.point_types == ["marker"] and x.descriptions == [""]


def test_from_array_and_fill():
    t = np.linspace(0.0, 1.0, 101)
    x = np.zeros((101, 2, 3))
    x[:, 0, 0] = t**3  # a cubic: the spline fill reproduces it exactly
    x[:, 1, 1] = 1.0 + t
    truth = x.copy()
    x[40:50, 0, :] = np.nan
    r = mocap.Recording(["A", "B"], x, 100.0, "m")
    gaps = mocap.find_gaps(r)
    assert [(g.marker, g.first, g.last) for g in gaps] == [(0, 40, 49)]
    filled, summary = mocap.fill_gaps(r, method="spline")
    assert summary.ok and summary.gaps_filled == 1 and summary.samples_filled == 10
    assert np.allclose(filled.positions, truth, atol=1e-12)
    assert np.isnan(r.positions[45, 0, 0])  # the input is not modified


def test_errors_name_the_file_and_field(tmp_path):
    missing = tmp_path / "nothing.c3d"
    with pytest.raises(ValueError, match="nothing.c3d"):
        mocap.read_recording(missing)
    with pytest.raises(ValueError, match=r'^method: must be one of .*ocp \(got "magic"\)$'):
        mocap.FillOptions(method="magic")
    with pytest.raises(ValueError, match=r"^FillOptions: unknown option 'methd'$"):
        mocap.FillOptions(methd="pca")


def test_evaluate_small():
    t = np.linspace(0.0, 2.0, 201)
    x = np.stack([np.stack([np.sin(t + k), np.cos(t + k), t], axis=1) for k in range(4)], axis=1)
    r = mocap.Recording(["A", "B", "C", "D"], x * 100.0, 100.0, "mm")
    s = mocap.evaluate(r, methods=["linear", "spline"], gap_seconds=[0.1], trials=3, seed=2)
    d = s.to_dict()
    assert s.ok and d["settings"]["trials"] == 3
    two = mocap.evaluate(r, methods=["spline"], gap_seconds=[0.1], trials=2, markers_per_gap=2,
                         placement="any", filter_hz=5.0).to_dict()
    assert len(two["rows"]) == 4 and two["settings"]["placement"] == "any"
    assert two["statistics"][0]["gaps"] == 4
    assert "acceleration_error" in two["statistics"][0]["measures"]

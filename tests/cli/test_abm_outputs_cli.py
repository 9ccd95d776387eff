"""What an agent-based run writes for analysis (docs/abm.md, "What a run writes"): the agents'
arrays in trajectory.h5 (shapes, values against lineage.csv and a brute-force contact count),
the same arrays in the VTU frames, lineage.csv consistent with summary.json, geometry.vtp for a
room and for box walls, and plot_abm.py on an emptied room."""
import csv
import json
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from conftest import ROOT, run_cli

COLONY_FILE = ROOT / "tests/cli/abm_colony.toml"
COLONY = COLONY_FILE.read_text()

ARRAYS = {"type": (), "generation": (), "divisions": (), "mother": (), "display_id": (),
          "age": (), "polarity": (3,), "contacts": ()}


@pytest.fixture(scope="module")
def colony(tmp_path_factory):
    folder = tmp_path_factory.mktemp("colony")
    out = folder / "out"
    r = run_cli("run", COLONY_FILE, "--out", out)
    assert r.returncode == 0, r.stderr
    return out


def lineage_rows(out):
    return list(csv.DictReader(open(out / "lineage.csv")))


def test_hdf5_holds_every_agent_array_with_the_frames_shapes(colony):
    h5py = pytest.importorskip("h5py")  # installed by scripts/install-deps
    lineage = {int(r["id"]): r for r in lineage_rows(colony)}
    with h5py.File(colony / "trajectory.h5", "r") as f:
        assert [n.decode() for n in f.attrs["type_names"]] == ["normal", "tumour"]
        counts, ids = f["count"][:], f["ids"][:]
        frames, rows = ids.shape
        assert len(set(counts.tolist())) > 2 and frames > 3
        data = {name: f["point_data"][name][:] for name in ARRAYS}
        x, r = f["positions"][:], f["radii"][:]
    for name, tail in ARRAYS.items():
        assert data[name].shape == (frames, rows) + tail, name
    for fr, n in enumerate(counts):
        assert (data["mother"][fr, n:] == -1).all() and np.isnan(data["age"][fr, n:]).all()
        for i in range(n):
            row = lineage[int(ids[fr, i])]
            assert data["display_id"][fr, i] == int(row["display_id"])
            assert data["mother"][fr, i] == int(row["mother"])
            assert data["generation"][fr, i] >= int(row["generation"])
        assert set(data["type"][fr, :n].tolist()) <= {0, 1}
        assert (data["age"][fr, :n] >= 0).all()
        p = data["polarity"][fr, :n]
        np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 1.0, rtol=1e-12)
        assert (p[:, 2] == 0).all()
        # contacts: the agents j within 1.05 (r_i + r_j), counted by brute force
        d = np.linalg.norm(x[fr, :n, None, :] - x[fr, None, :n, :], axis=2)
        touching = d <= 1.05 * (r[fr, :n, None] + r[fr, None, :n])
        np.testing.assert_array_equal(data["contacts"][fr, :n], touching.sum(axis=1) - 1)
    assert data["generation"].max() >= 1 and data["contacts"].max() >= 1


def test_xdmf_and_vtu_name_the_arrays(colony):
    xdmf = (colony / "trajectory.xdmf").read_text()
    for name in ARRAYS:
        assert f'<Attribute Name="{name}"' in xdmf
    root = ET.parse(colony / "vtu" / "frame_000001.vtu").getroot()
    point_data = root.find("UnstructuredGrid/Piece/PointData")
    names = {a.get("Name"): a.get("NumberOfComponents") for a in point_data}
    assert names == {"radius": "1", "id": "1", "polarity": "3",
                     **{n: "1" for n in ARRAYS if n != "polarity"}}
    field = {a.get("Name") for a in root.find("UnstructuredGrid/FieldData")}
    assert "type_names" in field


def test_lineage_is_consistent_with_the_summary(colony):
    rows = lineage_rows(colony)
    summary = json.load(open(colony / "summary.json"))
    agents = list(csv.DictReader(open(colony / "agents.csv")))
    by_id = {r["id"]: r for r in rows}
    assert len(by_id) == len(rows)
    assert [int(r["display_id"]) for r in rows] == list(range(len(rows)))
    assert sum(r["mother"] == "-1" for r in rows) == 4
    born = [r for r in rows if r["mother"] != "-1"]
    assert len(born) == summary["births"] > 0
    for r in born:
        mother = by_id[r["mother"]]
        assert float(mother["birth_time"]) <= float(r["birth_time"])
        assert int(r["mother_display_id"]) == int(mother["display_id"])
        assert int(r["generation"]) >= 1
    fates = [r["fate"] for r in rows]
    assert fates.count("died") == summary["deaths"] > 0
    assert fates.count("removed") == summary["removals"] == 2
    alive = {r["id"] for r in rows if r["fate"] == "alive"}
    assert all(r["end_time"] == "" for r in rows if r["fate"] == "alive")
    assert all(float(r["end_time"]) >= float(r["birth_time"]) for r in rows if r["fate"] != "alive")
    assert alive == {a["id"] for a in agents} and len(alive) == summary["final_count"]


def vtp_cells(path):
    """(kind names, [(kind, points)]) of a geometry.vtp, read as XML."""
    piece = ET.parse(path).getroot().find("PolyData/Piece")

    def values(parent, name):
        array = next(a for a in parent.iter("DataArray") if a.get("Name") == name)
        return np.array(array.text.split(), dtype=float)
    points = values(piece.find("Points"), "Points").reshape(-1, 3)
    kinds = values(piece.find("CellData"), "kind").astype(int)
    cells = []
    for tag in ("Lines", "Polys"):
        connectivity = values(piece.find(tag), "connectivity").astype(int)
        start = 0
        for end in values(piece.find(tag), "offsets").astype(int):
            cells.append(points[connectivity[start:end]])
            start = end
    field = ET.parse(path).getroot().find("PolyData/FieldData/Array")
    codes = [int(c) for c in field.text.split()]
    names = bytes(codes).decode().split("\0")[:-1]
    return names, list(zip(kinds.tolist(), cells))


def test_room_geometry_has_the_walls_and_the_door(tmp_path):
    out = tmp_path / "crowd"
    r = run_cli("run", ROOT / "examples/abm/crowd_exit.toml", "--out", out, "--set",
                "problem.count=20", "--set", "problem.T=0.2")
    assert r.returncode == 0, r.stderr
    names, cells = vtp_cells(out / "geometry.vtp")
    assert names == ["wall", "segment", "sphere", "door"]
    assert sorted(names[k] for k, _ in cells) == ["door"] + ["segment"] * 5
    door = next(p for k, p in cells if names[k] == "door")
    np.testing.assert_allclose(door[:, :2], [[15.0, 6.9], [15.0, 8.1]])


def test_box_walls_are_drawn_in_their_planes_in_3d(tmp_path):
    out = tmp_path / "packing"
    r = run_cli("run", ROOT / "examples/packing3d.toml", "--out", out, "--set", "problem.T=0.02",
                "--set", "output.vtu=false")
    assert r.returncode == 0, r.stderr
    names, cells = vtp_cells(out / "geometry.vtp")
    walls = [p for k, p in cells if names[k] == "wall"]
    assert len(walls) == 2  # floor and ceiling: x and y are periodic
    for polygon, z in zip(walls, (0.0, 30.0)):
        assert len(polygon) == 4  # the plane crosses the (widened) box in a rectangle
        np.testing.assert_allclose(polygon[:, 2], z, atol=1e-12)
        assert np.ptp(polygon[:, 0]) > 20 and np.ptp(polygon[:, 1]) > 20


def test_plot_script_draws_an_emptied_room(tmp_path):
    out = tmp_path / "empty"
    scenario = tmp_path / "gone.toml"
    scenario.write_text(COLONY.replace("[-0.6, 0.0], [0.6, 0.0]", "[8.0, 0.0], [9.5, 0.0]"))
    r = run_cli("run", scenario, "--out", out)
    assert r.returncode == 0, r.stderr
    assert len(list(csv.DictReader(open(out / "agents.csv")))) == 0
    assert {row["fate"] for row in lineage_rows(out)} == {"removed"}
    script = ROOT / "examples/abm/plot_abm.py"
    for args in (["snapshot", tmp_path / "s.png", out / "agents.csv"],
                 ["count", tmp_path / "c.png", out / "population.csv"]):
        p = subprocess.run(["/usr/bin/python3", script, *map(str, args)], capture_output=True,
                           text=True, timeout=60)
        assert p.returncode == 0, p.stderr
        assert (args[1]).stat().st_size > 0

"""Shortened runs of the fields examples (docs/fields.md "A tumour spheroid", "Chemotactic
aggregation"), seeded, checking what the examples show: a spheroid's necrotic cells lie inside its
living ones and its oxygen is lowest at the centre; chemotactic cells end closer together than the
same cells without chemotaxis."""
import csv

import numpy as np
import pytest

from conftest import ROOT, run_cli

SPHEROID = ROOT / "examples/abm/spheroid_3d.toml"
CHEMOTAXIS = ROOT / "examples/abm/chemotaxis_2d.toml"


def agents(out):
    with open(out / "agents.csv") as f:
        rows = list(csv.DictReader(f))
    axes = [a for a in ("x", "y", "z") if a in rows[0]]
    return (np.array([[float(r[a]) for a in axes] for r in rows]),
            np.array([int(r["type"]) for r in rows]))


def test_a_short_spheroid_has_its_necrotic_core_inside_and_oxygen_lowest_at_the_centre(tmp_path):
    h5py = pytest.importorskip("h5py")
    out = tmp_path / "spheroid"
    # Strong uptake and high thresholds: a core by t = 12 (55 cells).
    r = run_cli("run", SPHEROID, "--out", out, "--set", "problem.T=12",
                "--set", "types.cell.oxygen.uptake_rate=600",
                "--set", "types.cell.oxygen.proliferation_above=0.5",
                "--set", "types.cell.oxygen.necrosis_below=0.35")
    assert r.returncode == 0, r.stderr
    x, types = agents(out)
    centre = x.mean(axis=0)
    d = np.linalg.norm(x - centre, axis=1)
    assert (types == 1).sum() >= 3 and (types == 0).sum() > (types == 1).sum()
    assert d[types == 1].mean() < d[types == 0].mean()
    with h5py.File(out / "fields.h5", "r") as f:
        c = f["fields/oxygen"][-1]  # (z, y, x)
        origin, h = f.attrs["origin"][:], float(f.attrs["spacing"])
    k, j, i = np.unravel_index(np.argmin(c), c.shape)
    lowest = origin + h * (np.array([i, j, k]) + 0.5)
    assert np.linalg.norm(lowest - centre) < 1.5  # within a few voxels of the colony's centre
    assert c.min() < 0.35 and c.max() > 0.99  # the medium near the faces stays oxygenated


def nearest_neighbour_distance(x, box):
    d = x[:, None, :] - x[None, :, :]
    d -= box * np.round(d / box)
    r = np.sqrt((d ** 2).sum(axis=2))
    np.fill_diagonal(r, np.inf)
    return r.min(axis=1).mean()


def test_chemotactic_cells_aggregate_more_than_without_chemotaxis(tmp_path):
    distances = []
    for chi in ("1.0", "0"):
        out = tmp_path / f"chi{chi}"
        r = run_cli("run", CHEMOTAXIS, "--out", out, "--set", "problem.T=20",
                    "--set", f"types.cell.signal.chemotaxis={chi}")
        assert r.returncode == 0, r.stderr
        x, _ = agents(out)
        assert len(x) == 300
        distances.append(nearest_neighbour_distance(x, 40.0))
    # A random gas of these disks has a mean nearest-neighbour distance of about 1.45.
    assert distances[0] < distances[1] - 0.15, distances

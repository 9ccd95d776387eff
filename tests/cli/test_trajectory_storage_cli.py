"""`[output]` precision and compression of trajectory.h5 (docs/io.md): single precision
stores the same run's positions rounded to float32, compression is lossless, the sidecar declares
the precision, the settings are echoed, and bad values are one line naming the key."""
import json

import numpy as np
import pytest

from conftest import rejected, run_cli
from test_abm_cli import COLONY
from test_particles_cli import SMALL

h5py = pytest.importorskip("h5py")  # installed by scripts/install-deps


def run(write_scenario, tmp_path, text, name, *settings):
    """Runs TEXT with `--set` SETTINGS into tmp_path/NAME; returns (arrays, sidecar, summary)."""
    out = tmp_path / name
    args = ["run", write_scenario(text, f"{name}.toml"), "--out", out]
    for setting in settings:
        args += ["--set", setting]
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr
    with h5py.File(out / "trajectory.h5", "r") as f:
        arrays = {key: f[key] for key in ("positions", "ids", "radii", "time", "count")}
        data = {key: d[()] for key, d in arrays.items()}
        data["filters"] = {key: (d.compression, d.compression_opts, d.shuffle)
                           for key, d in arrays.items()}
        data["view"] = f["xdmf/frame_000001/positions"][()]
    sidecar = (out / "trajectory.xdmf").read_text()
    return data, sidecar, json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("text", [SMALL, COLONY], ids=["particles", "agents"])
def test_single_precision_and_compression_keep_the_run_readable(tmp_path, write_scenario, text):
    double, double_xdmf, double_summary = run(write_scenario, tmp_path, text, "double")
    single, single_xdmf, summary = run(write_scenario, tmp_path, text, "single",
                                       'output.precision="single"', "output.compression=4")
    # The scenario as read: under "settings" for particles, "scenario" for agents.
    echoed = summary.get("scenario", summary["settings"])["output"]
    assert echoed["precision"] == "single" and echoed["compression"] == 4
    echoed = double_summary.get("scenario", double_summary["settings"])["output"]
    assert echoed["precision"] == "double" and echoed["compression"] == 0
    assert summary["positions_hash"] == double_summary["positions_hash"]  # the run is the same
    assert double["positions"].dtype == np.float64 and single["positions"].dtype == np.float32
    assert single["view"].dtype == np.float32
    # Rounded to the nearest float (padding NaN stays NaN), everything else bit for bit.
    np.testing.assert_array_equal(single["positions"], double["positions"].astype(np.float32))
    for key in ("ids", "radii", "time", "count"):
        assert single[key].dtype == double[key].dtype
        np.testing.assert_array_equal(single[key], double[key])
    for key, filters in single["filters"].items():
        assert filters == ("gzip", 4, True), key
        assert double["filters"][key] == (None, None, False), key
    assert single_xdmf.count('NumberType="Float" Precision="4"') == single_xdmf.count("positions<")
    assert 'Precision="4"' not in double_xdmf
    assert single_xdmf.replace('Precision="4"', 'Precision="8"') == double_xdmf


BAD = [
    ("output.compression=10", "output.compression", "10"),
    ("output.compression=-1", "output.compression", "-1"),
    ('output.precision="half"', "output.precision", "'half'"),
    ("output.precision=32", "output.precision", ""),
]


@pytest.mark.parametrize("setting,key,reason", BAD, ids=[b[0] for b in BAD])
def test_bad_storage_settings_are_one_line_and_write_nothing(tmp_path, write_scenario, setting,
                                                              key, reason):
    scenario = write_scenario(SMALL)
    out = tmp_path / "out"
    rejected(run_cli("run", scenario, "--out", out, "--set", setting), str(scenario), key, reason)
    assert not out.exists()

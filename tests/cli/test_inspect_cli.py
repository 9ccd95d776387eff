"""`moreau inspect`: the inventory of a recording, and exit code 2 with one line on bad input."""
import json

from conftest import ROOT, run_cli

DATA = ROOT.parent / "shared" / "data" / "mocap"


def test_inspect_json_lists_markers_frames_rate_and_gaps():
    r = run_cli("inspect", DATA / "Eb015pr.c3d", "--json")
    assert r.returncode == 0, r.stderr
    inv = json.loads(r.stdout)
    assert (inv["markers"], inv["frames"], inv["rate"], inv["units"]) == (26, 450, 50.0, "mm")
    assert inv["format"]["processor"] == "intel" and inv["format"]["storage"] == "float"
    gapped = {g["marker"] for g in inv["gaps"]}
    assert len(gapped) == 10
    assert inv["missing_samples"] == sum(g["length_frames"] for g in inv["gaps"])


def test_inspect_text_names_the_file_and_reports_warnings_on_stderr():
    r = run_cli("inspect", DATA / "standing_bts.c3d")
    assert r.returncode == 0, r.stderr
    assert "standing_bts.c3d" in r.stdout and "intel" in r.stdout
    assert "labels renamed" in r.stderr


def test_inspect_file_without_parameters_reads_the_header_and_warns():
    r = run_cli("inspect", DATA / "phasespace_sample.c3d", "--json")
    assert r.returncode == 0, r.stderr
    inv = json.loads(r.stdout)
    assert (inv["markers"], inv["frames"], inv["rate"], inv["units"]) == (40, 701, 30.0, "mm")
    assert inv["labels"][:2] == ["uname*1", "uname*2"] and len(set(inv["labels"])) == 40
    assert inv["missing_samples"] > 0
    warned = [w for w in inv["warnings"] if "no parameters" in w]
    assert len(warned) == 1 and "phasespace_sample.c3d" in warned[0], inv["warnings"]
    assert warned[0] in r.stderr


def test_inspect_truncated_file_exits_2_with_one_line_unless_allowed():
    r = run_cli("inspect", DATA / "Optotrak.c3d")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Optotrak.c3d" in lines[0] and "1149" in lines[0], r.stderr
    r = run_cli("inspect", DATA / "Optotrak.c3d", "--allow-truncated", "--json")
    assert r.returncode == 0 and json.loads(r.stdout)["frames"] == 29


def test_inspect_missing_file_and_wrong_extension_exit_2(tmp_path):
    for path in (tmp_path / "absent.c3d", tmp_path / "notes.txt"):
        if path.suffix == ".txt":
            path.write_text("hello")
        r = run_cli("inspect", path)
        assert r.returncode == 2, r.stderr
        assert str(path) in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_inspect_counts_model_outputs_apart_from_markers():
    r = run_cli("inspect", DATA / "PlugInC3D.c3d", "--json")
    assert r.returncode == 0, r.stderr
    inv = json.loads(r.stdout)
    assert inv["markers"] == 54 and len(inv["labels"]) == 54
    outputs = inv["model_outputs"]
    assert len(outputs) == 32
    types = inv["point_types"]
    assert types["marker"] == 54 and sum(types.values()) == 86
    for name in ("angle", "force", "moment", "power", "scalar", "reaction"):
        assert types[name] == sum(o["type"] == name for o in outputs)
    assert all(g["marker"] in inv["labels"] for g in inv["gaps"])
    text = run_cli("inspect", DATA / "PlugInC3D.c3d").stdout
    assert "  markers: 54\n" in text and f"  model outputs: 32 (angles {types['angle']}," in text

"""`moreau fill-gaps` and `moreau evaluate-gaps`: the files they write, and exit code 2 with one
line and nothing written on bad input."""
import collections
import csv
import json
import math
import os
import subprocess

import pytest

from conftest import CLI, ROOT, run_cli

DATA = (ROOT.parent / "shared" / "data" / "mocap").resolve()

EVALUATION_COLUMNS = ["method", "gap_frames", "trial", "marker", "first_frame", "mean_error",
                      "max_error"]


def read_csv_points(path):
    """(0-based frame, marker) -> (x, y, z) or None, from a file of rows frame,time,marker,x,y,z."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    first = min(int(r["frame"]) for r in rows)
    points = {}
    for r in rows:
        key = (int(r["frame"]) - first, r["marker"])
        assert key not in points
        points[key] = None if r["x"] == "" else (float(r["x"]), float(r["y"]), float(r["z"]))
    return points


def assert_rejected(args, out, *words):
    r = run_cli(*args, "--out", out)
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    for w in words:
        assert str(w) in lines[0], (w, lines[0])
    assert not out.exists() or not any(out.iterdir()), list(out.iterdir())


def fill_with_deletions(tmp_path, recording, rows, *args, name="out"):
    """`moreau fill-gaps RECORDING --gaps GAPS.csv ARGS --out tmp_path/NAME`, GAPS.csv holding
    ROWS; returns the finished run and the output folder."""
    gaps = tmp_path / f"{name}_gaps.csv"
    gaps.write_text(rows)
    out = tmp_path / name
    return run_cli("fill-gaps", recording, "--gaps", gaps, *args, "--out", out), out


def test_fill_gaps_deletes_listed_samples_and_fills_them(tmp_path):
    # Qualisys.c3d is complete: the only gaps are those GAPS.csv makes. Marker by label and by
    # index; linear fill is the straight line between the samples bounding the gap.
    inventory = json.loads(run_cli("inspect", DATA / "Qualisys.c3d", "--json").stdout)
    label = inventory["labels"][3]
    r, out = fill_with_deletions(
        tmp_path, DATA / "Qualisys.c3d",
        f"marker,first_frame,last_frame\n{label},100,119\n7,0,4\n# comment\n10,200,200\n",
        "--method", "linear")
    assert r.returncode == 0, r.stderr
    assert "3 gaps: 2 filled by linear, 1 unfillable (skipped_edge 1)" in r.stdout

    report = json.loads((out / "report.json").read_text())
    assert report["units"] == "mm" and report["samples_deleted"] == 20 + 5 + 1
    assert report["settings"]["fill"]["method"] == "linear"
    by_first = {g["first"]: g for g in report["gaps"]}
    assert set(by_first) == {0, 100, 200}
    assert (by_first[100]["label"], by_first[100]["last"]) == (label, 119)
    assert by_first[100]["status"] == "filled" and by_first[200]["status"] == "filled"
    assert by_first[0]["status"] == "skipped_edge" and by_first[0]["marker"] == 7
    for g in report["gaps"]:
        assert g["method"] == "linear" and g["seconds"] >= 0
    assert by_first[100]["mean_error"] > 0 and by_first[100]["max_error"] >= \
        by_first[100]["mean_error"]
    assert by_first[0]["mean_error"] is None

    points = read_csv_points(out / "filled.csv")
    labels = inventory["labels"]
    assert len(points) == inventory["frames"] * len(labels)
    assert all((f, m) in points for f in range(inventory["frames"]) for m in labels)
    before, after = points[(99, label)], points[(120, label)]
    for f in range(100, 120):
        s = (f - 99) / 21
        for c in range(3):
            expected = before[c] + s * (after[c] - before[c])
            assert math.isclose(points[(f, label)][c], expected, rel_tol=1e-12, abs_tol=1e-9)
    missing = {k for k, p in points.items() if p is None}
    assert missing == {(f, labels[7]) for f in range(5)}

    # The measures of evaluate-gaps where the truth is known: the velocity jump at each end is
    # the change of the one-sided velocity (filled.csv's samples, 200 Hz).
    def jump(a, b, c):
        return 200 * math.dist([2 * pb - pa - pc for pa, pb, pc in zip(a, b, c)], [0, 0, 0])

    g = by_first[100]
    p = {f: points[(f, label)] for f in range(97, 123)}
    assert math.isclose(g["velocity_jump_start"], jump(p[98], p[99], p[100]), rel_tol=1e-9)
    assert math.isclose(g["velocity_jump_end"], jump(p[119], p[120], p[121]), rel_tol=1e-9)
    assert g["max_error"] >= g["p90_error"] >= 0
    assert g["velocity_error"] > 0 and g["acceleration_error"] > 0
    assert g["distance_deviation"] > 0 and g["distance_z"] > 0
    assert by_first[0]["acceleration_error"] is None

    # filled.c3d holds the same recording: the unfilled gap is its only gap.
    c3d = json.loads(run_cli("inspect", out / "filled.c3d", "--json").stdout)
    assert (c3d["frames"], c3d["markers"], c3d["units"]) == (inventory["frames"], len(labels), "mm")
    assert [(g["marker"], g["first_frame"], g["last_frame"]) for g in c3d["gaps"]] == \
        [(labels[7], 0, 4)]
    assert (out / "gaps.png").stat().st_size > 0


def test_fill_gaps_fills_a_recording_with_gaps_and_echoes_settings(tmp_path):
    # Settings from a scenario file, then --set, then --method (the last word wins).
    scenario = tmp_path / "fill.toml"
    scenario.write_text('[fill]\nmethod = "pca"\nmax_gap_seconds = 2.0\n[rigid]\ndonors = 5\n')
    out = tmp_path / "out"
    r = run_cli("fill-gaps", DATA / "Eb015pr.c3d", "--scenario", scenario, "--method", "rigid",
                "--set", "rigid.donors=4", "--set", "fill.max_gap_seconds=0.5", "--out", out)
    assert r.returncode == 0, r.stderr
    report = json.loads((out / "report.json").read_text())
    settings = report["settings"]
    assert settings["fill"] == {"method": "rigid", "max_gap_seconds": 0.5}
    assert settings["rigid"]["donors"] == 4 and settings["pca"]["explained_fraction"] == 0.99
    assert report["gaps_filled"] + report["gaps_unfilled"] == len(report["gaps"]) == 12
    for g in report["gaps"]:
        if g["last"] - g["first"] + 1 > 0.5 * report["rate"]:
            assert g["status"] == "too_long"
    points = read_csv_points(out / "filled.csv")
    for g in report["gaps"]:
        values = [points[(f, g["label"])] for f in range(g["first"], g["last"] + 1)]
        if g["status"] == "filled":
            assert all(p is not None and all(map(math.isfinite, p)) for p in values)
        else:
            assert all(p is None for p in values)


def assert_outcomes_counted_from_the_gaps(report, stdout):
    """report.json's "outcomes" are the counts of the per-gap entries, and its message (the line
    printed) agrees with them."""
    gaps = report["gaps"]
    by_outcome = collections.Counter(g["outcome"] for g in gaps)
    by_reason = collections.Counter(g["prior_reason"] for g in gaps if g["outcome"] == "prior")
    by_status = collections.Counter(g["status"] for g in gaps if g["outcome"] == "unfillable")
    outcomes = report["outcomes"]
    assert outcomes["gaps"] == len(gaps)
    for name in ("optimal_control", "prior", "baseline", "unfillable"):
        assert outcomes[name] == by_outcome[name], name
    assert sum(by_outcome.values()) == len(gaps)
    assert outcomes["prior_by_reason"] == dict(by_reason)
    assert outcomes["unfillable_by_status"] == dict(by_status)
    assert report["gaps_unfilled"] == by_outcome["unfillable"]
    for g in gaps:
        assert (g["prior_reason"] is not None) == (g["outcome"] == "prior"), g
        assert (g["status"] == "filled") == (g["outcome"] != "unfillable"), g
        if g["outcome"] == "optimal_control":
            assert g["message"].startswith("optimal control:"), g
        if g["outcome"] == "prior":
            assert g["message"].startswith("prior"), g
    parts = [f"{len(gaps)} gaps"]
    words = {"optimal_control": "solved by the optimal control", "prior": "kept the prior",
             "unfillable": "unfillable"}
    for name, counts in (("optimal_control", None), ("prior", by_reason),
                         ("unfillable", by_status)):
        if by_outcome[name]:
            text = f"{by_outcome[name]} {words[name]}"
            if counts:
                text += " (" + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) + ")"
            parts.append(text)
    assert report["message"].startswith(parts[0] + ": " + ", ".join(parts[1:])), \
        (report["message"], parts)
    assert f"  {report['message']}; " in stdout


def test_fill_gaps_counts_gaps_by_outcome_prior_only(tmp_path):
    # Vicon.c3d's 34 real gaps with the optimal control off: every gap keeps the prior, and says
    # why.
    out = tmp_path / "out"
    r = run_cli("fill-gaps", DATA / "Vicon.c3d", "--set", "ocp.optimal_control=false",
                "--out", out)
    assert r.returncode == 0, r.stderr
    report = json.loads((out / "report.json").read_text())
    assert_outcomes_counted_from_the_gaps(report, r.stdout)
    assert report["outcomes"]["prior"] == 34
    assert report["outcomes"]["prior_by_reason"] == {"optimal_control_off": 34}
    assert report["message"] == "34 gaps: 34 kept the prior (optimal_control_off 34)"


def test_fill_gaps_counts_gaps_by_outcome_with_the_optimal_control(tmp_path):
    # One short deleted gap of the complete Qualisys recording, the optimal control on; plus a
    # gap at the start that only pca fills and a marker deleted in every frame (unfillable).
    r, out = fill_with_deletions(tmp_path, DATA / "Qualisys.c3d",
                                 "marker,first_frame,last_frame\n3,100,109\n7,0,339\n")
    assert r.returncode == 0, r.stderr
    report = json.loads((out / "report.json").read_text())
    assert_outcomes_counted_from_the_gaps(report, r.stdout)
    by_marker = {g["marker"]: g for g in report["gaps"]}
    assert by_marker[3]["outcome"] in ("optimal_control", "prior")
    assert by_marker[7]["outcome"] == "unfillable"
    assert by_marker[7]["status"] == "never_observed"


def test_fill_gaps_marker_never_observed_is_unfillable_exit_0_with_a_warning(tmp_path):
    # A C3D with one marker missing in every frame: written by fill-gaps itself (linear cannot
    # fill a gap that spans the recording), then filled again.
    inventory = json.loads(run_cli("inspect", DATA / "Qualisys.c3d", "--json").stdout)
    label = inventory["labels"][5]
    r, first = fill_with_deletions(tmp_path, DATA / "Qualisys.c3d",
                                   f"{label},0,{inventory['frames'] - 1}\n", "--method", "linear",
                                   name="first")
    assert r.returncode == 0, r.stderr
    source = first / "filled.c3d"
    c3d = json.loads(run_cli("inspect", source, "--json").stdout)
    assert [(g["marker"], g["first_frame"], g["last_frame"]) for g in c3d["gaps"]] == \
        [(label, 0, inventory["frames"] - 1)]
    for method in ("linear", "ocp"):
        out = tmp_path / method
        r = run_cli("fill-gaps", source, "--method", method, "--out", out)
        assert r.returncode == 0, r.stderr
        warnings = r.stderr.strip().splitlines()
        assert len(warnings) == 1, r.stderr
        assert label in warnings[0] and "missing in every frame" in warnings[0], warnings[0]
        report = json.loads((out / "report.json").read_text())
        assert_outcomes_counted_from_the_gaps(report, r.stdout)
        (gap,) = report["gaps"]
        assert (gap["label"], gap["status"], gap["outcome"]) == \
            (label, "never_observed", "unfillable")
        assert report["outcomes"]["unfillable_by_status"] == {"never_observed": 1}
        points = read_csv_points(out / "filled.csv")
        assert all(points[(f, label)] is None for f in range(inventory["frames"]))


def test_fill_gaps_failed_figure_is_one_warning_and_not_announced(tmp_path):
    # A matplotlib that cannot be imported, placed first on the figure script's path.
    fake = tmp_path / "fake" / "matplotlib"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text('raise ImportError("no matplotlib in this test")\n')
    out = tmp_path / "out"
    env = dict(os.environ, PYTHONPATH=str(fake.parent))
    r = subprocess.run([CLI, "fill-gaps", str(DATA / "Qualisys.c3d"), "--method", "linear",
                        "--out", str(out)], capture_output=True, text=True, env=env, timeout=600)
    assert r.returncode == 0, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "gaps.png not written" in lines[0] and "no matplotlib in this test" in lines[0], lines
    wrote = [x for x in r.stdout.splitlines() if x.startswith("wrote ")]
    assert wrote == [f"wrote {out}/filled.c3d, filled.csv, report.json"], r.stdout
    assert sorted(p.name for p in out.iterdir()) == ["filled.c3d", "filled.csv", "report.json"]


@pytest.mark.parametrize("rows,lines,words", [
    ("3,100,110\n4,100,110\n3,105,120\n", "lines 2 and 4", ["overlapping", "105 … 120"]),
    ("3,100,110\n3,111,120\n3,100,110\n", "lines 2 and 4", ["duplicate", "100 … 110"]),
    ("3,100,200\n3,120,130\n", "lines 2 and 3", ["overlapping", "120 … 130"]),
])
def test_fill_gaps_overlapping_or_duplicate_rows_exit_2_and_write_nothing(tmp_path, rows, lines,
                                                                          words):
    gaps = tmp_path / "gaps.csv"
    gaps.write_text("marker,first_frame,last_frame\n" + rows)
    assert_rejected(["fill-gaps", DATA / "Qualisys.c3d", "--gaps", gaps], tmp_path / "out", gaps,
                    lines, *words)


def test_evaluate_gaps_writes_rows_statistics_and_figure(tmp_path):
    out = tmp_path / "out"
    r = run_cli("evaluate-gaps", DATA / "Qualisys.c3d", "--gap-seconds", "0.1,0.25", "--trials", 3,
                "--seed", 7, "--methods", "linear,rigid", "--out", out)
    assert r.returncode == 0, r.stderr
    assert "linear" in r.stdout and "rigid" in r.stdout and "mean / p90" in r.stdout
    with open(out / "evaluation.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0].keys())[:len(EVALUATION_COLUMNS)] == EVALUATION_COLUMNS
    assert len(rows) == 2 * 3 * 2
    assert {(r["method"], int(r["gap_frames"])) for r in rows} == \
        {(m, n) for m in ("linear", "rigid") for n in (20, 50)}
    for row in rows:  # one marker and one position per trial, shared by the methods
        twin = [x for x in rows if x["trial"] == row["trial"] and x["gap_frames"] == row["gap_frames"]]
        assert {(x["marker"], x["first_frame"]) for x in twin} == {(row["marker"], row["first_frame"])}
        assert float(row["max_error"]) >= float(row["mean_error"]) >= 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["settings"]["evaluation"]["seed"] == 7 and summary["units"] == "mm"
    assert len(summary["statistics"]) == 4
    for s in summary["statistics"]:
        errors = sorted(float(r["mean_error"]) for r in rows
                        if r["method"] == s["method"] and int(r["gap_frames"]) == s["gap_frames"])
        assert math.isclose(s["mean_error"], sum(errors) / 3, rel_tol=1e-6)
        assert math.isclose(s["median_error"], errors[1], rel_tol=1e-6)
        assert math.isclose(s["p90_error"], errors[1] + 0.8 * (errors[2] - errors[1]), rel_tol=1e-6)
    assert (out / "errors.png").stat().st_size > 0


def test_evaluate_gaps_hides_a_segment_at_the_end_and_reports_every_measure(tmp_path):
    out = tmp_path / "out"
    r = run_cli("evaluate-gaps", DATA / "Qualisys.c3d", "--gap-seconds", "0.1", "--trials", 2,
                "--methods", "spline,pca", "--markers-per-gap", 3, "--placement", "end",
                "--set", "evaluation.filter_hz=8", "--out", out)
    assert r.returncode == 0, r.stderr
    assert "acc. / jump" in r.stdout
    with open(out / "evaluation.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0].keys()) == EVALUATION_COLUMNS + [
        "gap_seconds", "status", "p90_error", "velocity_error", "acceleration_error",
        "velocity_jump_start", "velocity_jump_end", "distance_deviation", "distance_z", "outcome",
        "prior_reason"]
    assert len(rows) == 2 * 2 * 3
    for trial in ("0", "1"):
        group = [x for x in rows if x["trial"] == trial]
        assert len({x["marker"] for x in group}) == 3
        assert {x["first_frame"] for x in group} == {str(340 - 20)}
    for row in rows:
        if row["method"] == "spline":  # no samples after the gap
            assert row["status"] == "skipped_edge" and row["acceleration_error"] == ""
            assert row["outcome"] == "unfillable"
        else:
            assert row["status"] == "filled" and row["velocity_jump_end"] == ""
            assert row["outcome"] == "baseline"
            assert float(row["max_error"]) >= float(row["p90_error"]) >= 0
            assert min(float(row[k]) for k in ("velocity_error", "acceleration_error",
                                               "velocity_jump_start", "distance_z")) > 0
    summary = json.loads((out / "summary.json").read_text())
    evaluation = summary["settings"]["evaluation"]
    assert (evaluation["markers_per_gap"], evaluation["placement"], evaluation["filter_hz"]) == \
        (3, "end", 8.0)
    pca = next(s for s in summary["statistics"] if s["method"] == "pca")
    assert (pca["trials"], pca["gaps"], pca["failed"]) == (2, 6, 0)
    values = [float(x["acceleration_error"]) for x in rows if x["method"] == "pca"]
    assert math.isclose(pca["measures"]["acceleration_error"]["mean"], sum(values) / 6,
                        rel_tol=1e-6)
    assert pca["measures"]["velocity_jump"]["p90"] > 0


def test_evaluate_gaps_same_seed_same_rows(tmp_path):
    def rows(seed, name):
        out = tmp_path / name
        r = run_cli("evaluate-gaps", DATA / "upper_body_25hz.c3d", "--gap-seconds", "0.2,0.4",
                    "--trials", 3, "--seed", seed, "--methods", "spline,pca", "--out", out)
        assert r.returncode == 0, r.stderr
        return (out / "evaluation.csv").read_text()
    first = rows(3, "a")
    assert rows(3, "b") == first
    assert rows(4, "c") != first


@pytest.mark.parametrize("case", ["missing", "unreadable", "method", "set_key", "out"])
def test_fill_gaps_bad_input_exits_2_and_writes_nothing(tmp_path, case):
    recording = DATA / "Eb015pr.c3d"
    args = ["fill-gaps", recording]
    out = tmp_path / "out"
    words = []
    if case == "missing":
        args[1] = tmp_path / "absent.c3d"
        words = [args[1]]
    elif case == "unreadable":
        args[1] = tmp_path / "noise.c3d"
        args[1].write_bytes(b"\x00\x01 not a c3d file" * 40)
        words = [args[1]]
    elif case == "method":
        args += ["--method", "cubic"]
        words = ["fill.method", "cubic"]
    elif case == "set_key":
        args += ["--set", "rigid.donor=4"]
        words = ["rigid.donor", "unknown key"]
    else:
        blocker = tmp_path / "file"
        blocker.write_text("a file, not a folder")
        out = blocker / "out"
        words = [out]
    assert_rejected(args, out, *words)


@pytest.mark.parametrize("line,words", [
    ("NOT_A_MARKER,10,20", ["line 2", "marker", "NOT_A_MARKER"]),
    ("26,10,20", ["line 2", "marker", "26"]),
    ("0,440,450", ["line 2", "last_frame", "450"]),
    ("0,-1,3", ["line 2", "first_frame"]),
    ("0,30,20", ["line 2", "last_frame", "before"]),
    ("0,30", ["line 2", "expected marker,first_frame,last_frame"]),
])
def test_fill_gaps_bad_gaps_file_exits_2_and_writes_nothing(tmp_path, line, words):
    gaps = tmp_path / "gaps.csv"
    gaps.write_text("marker,first_frame,last_frame\n" + line + "\n")
    assert_rejected(["fill-gaps", DATA / "Eb015pr.c3d", "--gaps", gaps], tmp_path / "out", gaps,
                    *words)


def test_fill_gaps_missing_gaps_file_exits_2(tmp_path):
    gaps = tmp_path / "absent.csv"
    assert_rejected(["fill-gaps", DATA / "Eb015pr.c3d", "--gaps", gaps], tmp_path / "out", gaps)


@pytest.mark.parametrize("extra,words", [
    (["--methods", "linear,cubic"], ["evaluation.methods", "cubic"]),
    (["--trials", "0"], ["evaluation.trials", "≥ 1"]),
    (["--placement", "middle"], ["evaluation.placement", "middle"]),
    (["--markers-per-gap", "56"], ["evaluation.markers_per_gap", "55 markers"]),
    (["--set", "evaluation.filter_hz=100"], ["evaluation.filter_hz", "Nyquist"]),
    (["--gap-seconds", "0.1,-0.2"], ["gap_seconds", "-0.2"]),
    (["--gap-seconds", "2"], ["gap_seconds", "does not fit"]),  # the recording lasts 1.7 s
])
def test_evaluate_gaps_bad_settings_exit_2_and_write_nothing(tmp_path, extra, words):
    assert_rejected(["evaluate-gaps", DATA / "Qualisys.c3d", *extra], tmp_path / "out", *words)


def test_evaluate_gaps_uses_the_complete_part_of_a_recording_with_holes(tmp_path):
    # Vicon.c3d has holes: the evaluation runs on its complete part and says which; refused when
    # evaluation.complete_part is false.
    out = tmp_path / "part"
    r = run_cli("evaluate-gaps", DATA / "Vicon.c3d", "--trials", 2, "--gap-seconds", "0.2",
                "--methods", "linear,rigid", "--out", out)
    assert r.returncode == 0, r.stderr
    assert "evaluated on the complete part: frames 0–579 of 580, 38 of 51 markers" in r.stdout
    summary = json.loads((out / "summary.json").read_text())
    part = summary["complete_part"]
    assert (part["first_frame"], part["frames"], len(part["markers"])) == (0, 580, 38)
    source = json.loads(run_cli("inspect", DATA / "Vicon.c3d", "--json").stdout)
    assert len(part["markers"]) + len(part["dropped"]) == source["markers"]
    assert set(part["markers"] + part["dropped"]) <= set(source["labels"])
    rows = (out / "evaluation.csv").read_text().splitlines()[1:]
    assert rows and all(row.split(",")[3] in part["markers"] for row in rows)
    assert set(summary["method_seconds"]) == {"linear", "rigid"}
    assert_rejected(["evaluate-gaps", DATA / "Vicon.c3d", "--trials", 2, "--set",
                     "evaluation.complete_part=false"], tmp_path / "out", "complete_part")


def test_fill_gaps_fills_markers_only_and_keeps_model_outputs(tmp_path):
    source = json.loads(run_cli("inspect", DATA / "PlugInC3D.c3d", "--json").stdout)
    out = tmp_path / "out"
    r = run_cli("fill-gaps", DATA / "PlugInC3D.c3d", "--method", "linear", "--out", out)
    assert r.returncode == 0, r.stderr
    report = json.loads((out / "report.json").read_text())
    assert report["markers"] == 54
    assert report["gaps"] and all(g["label"] in source["labels"] for g in report["gaps"])
    filled = json.loads(run_cli("inspect", out / "filled.c3d", "--json").stdout)
    assert filled["point_types"] == source["point_types"]
    assert filled["model_outputs"] == source["model_outputs"]
    points = read_csv_points(out / "filled.csv")
    for o in source["model_outputs"]:
        rows = [points[(f, o["label"])] for f in range(source["frames"])]
        assert sum(p is not None for p in rows) == o["observed_samples"]
    angle = next(o["label"] for o in source["model_outputs"] if o["type"] == "angle")
    gaps = tmp_path / "gaps.csv"
    gaps.write_text(f"marker,first_frame,last_frame\n{angle},10,12\n")
    assert_rejected(["fill-gaps", DATA / "PlugInC3D.c3d", "--gaps", gaps], tmp_path / "rejected",
                    "model output", "angle")

"""Every options type's field list against the tool, the Python package and the key reference.

For each field of each list: the key appears in `moreau keys` (and in docs/keys.md, which must be
what `moreau keys --markdown` writes), the tool accepts it (a bad value is rejected for its value,
never as an unknown key), and the tool and Python give the same reason for the same bad value.
A bad value is one below the field's range, or of the wrong type when any value of the type is
allowed."""
import re
import subprocess

import pytest

import moreau
from moreau import control, mocap, particles, pbd
from conftest import CLI, ROOT, MOCAP

SLIDING = ROOT / "examples/sliding.toml"
CROWD = ROOT / "examples/crowd.toml"
MONOLAYER = ROOT / "examples/abm/monolayer.toml"
OSCILLATOR = ROOT / "examples/control/oscillator_1d.toml"
VICON = MOCAP / "Vicon.c3d"
QUALISYS = MOCAP / "Qualisys.c3d"

# (options class, the tool's command line before --set, the scenario key of the list's key).
# A key a command sets from another one maps to None (the particle engine's seed is
# problem.seed).
MOUNTS = [
    (pbd.StepperOptions, ["run", SLIDING], lambda k: "solver." + k),
    (pbd.StepperOptions, ["run", SLIDING], lambda k: "reference." + k),
    (particles.EngineOptions, ["run", CROWD], lambda k: None if k == "seed" else "solver." + k),
    (particles.AgentType, ["run", MONOLAYER], lambda k: "types.cell." + k),
    (particles.PopulationRules, ["run", MONOLAYER],
     lambda k: None if k == "seed" else "population." + k),
    (control.ContinuationOptions, ["control", OSCILLATOR],
     lambda k: k if k.startswith(("newton.", "fixed_point.")) else "continuation." + k),
    (control.NewtonOptions, ["control", OSCILLATOR], lambda k: "newton." + k),
    (control.FixedPointOptions, ["control", OSCILLATOR], lambda k: "fixed_point." + k),
    (mocap.FillOptions, ["fill-gaps", VICON],
     lambda k: "fill." + k if k in ("method", "max_gap_seconds") else k),
    (mocap.ReadOptions, ["fill-gaps", VICON], lambda k: "read." + k),
    (mocap.EvaluationOptions, ["evaluate-gaps", QUALISYS],
     lambda k: None if k == "methods" else "evaluation." + k),
]


def bad_value(field):
    """A value the field must reject, as a TOML literal and as a Python value."""
    lower = re.match(r"(?:[>≥] |in [\[(])(-?[0-9.e+-]+)", field["range"])
    if field["type"] in ("number", "integer") and lower:
        value = float(lower.group(1)) - 1
        value = int(value) if field["type"] == "integer" or value.is_integer() else value
        return str(value), value
    if field["type"] in ("number", "integer", "boolean"):
        return '"x"', "x"
    return "3", 3  # strings, choices, lists of strings


def python_reason(cls, key, value):
    """The reason Python's set() gives for key = value (ValueError "KEY: REASON")."""
    with pytest.raises(ValueError) as e:
        cls().set(key, value)
    message = str(e.value)
    assert message.startswith(key + ": "), message
    return message[len(key) + 2:]


def test_every_key_is_accepted_and_checked_alike(tmp_path):
    checked = 0
    for cls, command, scenario_key in MOUNTS:
        for field in cls.fields():
            key = scenario_key(field["key"])
            if key is None or key == "types.cell.name":  # a type's name is its key
                continue
            literal, value = bad_value(field)
            reason = python_reason(cls, field["key"], value)
            r = subprocess.run([CLI, *map(str, command), "--set", f"{key}={literal}", "--out",
                                tmp_path / "out"], capture_output=True, text=True, timeout=60)
            assert r.returncode == 2, (key, r.stderr)
            assert r.stderr.count("\n") == 1, r.stderr  # one line
            assert f": {key}: {reason}\n" in r.stderr, (key, reason, r.stderr)
            checked += 1
    assert checked > 60


def test_every_key_is_in_the_reference():
    listed = subprocess.run([CLI, "keys"], capture_output=True, text=True, check=True).stdout
    keys = {line.split()[0] for line in listed.splitlines() if line.startswith("  ")}
    for cls, _, scenario_key in MOUNTS:
        for field in cls.fields():
            key = scenario_key(field["key"])
            if key is None:
                continue
            key = key.replace("types.cell.", "types.<name>.")
            assert key in keys, key


def test_docs_keys_md_is_what_the_tool_writes():
    written = subprocess.run([CLI, "keys", "--markdown"], capture_output=True, text=True,
                             check=True).stdout
    assert (ROOT / "docs/keys.md").read_text() == written, (
        "docs/keys.md is stale: regenerate it with `moreau keys --markdown > docs/keys.md`")


def test_python_keywords_are_the_field_list():
    o = particles.EngineOptions(h=0.01, skin_factor=0.5, order="lexicographic")
    assert (o.h, o.skin_factor, o.order) == (0.01, 0.5, "lexicographic")
    assert "skin_factor" in particles.EngineOptions.__doc__
    with pytest.raises(ValueError, match=r"^skin_factor: must be > 0 \(got -1\)$"):
        particles.EngineOptions(skin_factor=-1)
    with pytest.raises(ValueError, match=r"^order: must be one of"):
        o.order = "spiral"
    c = control.ContinuationOptions(**{"newton.armijo": 0.1})
    assert c.newton.armijo == 0.1 and c.get("newton.armijo") == 0.1
    with pytest.raises(ValueError, match=r"^newton\.armijo: must be in \(0, 0\.5\)"):
        c.set("newton.armijo", 0.7)

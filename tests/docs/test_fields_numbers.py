"""The numbers docs/fields.md quotes for its examples are those of the committed outputs.

docs/results/fields/ holds what scripts/fields_results.sh measured (make fields-results). Nothing
is rerun here: the bold numbers and the tables of docs/fields.md are compared with the CSVs.
"""
import csv
import os
import pathlib
import re

ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))
RESULTS = ROOT / "docs/results/fields"
DOC = (ROOT / "docs/fields.md").read_text()


def rows(name):
    with open(RESULTS / name) as f:
        return list(csv.DictReader(f))


def table_row(first_cell, prefix=False):
    """The cells of the docs/fields.md table row whose first cell is `first_cell` (or starts
    with it)."""
    for line in DOC.splitlines():
        cells = [c.strip().strip("*") for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and (cells[0].startswith(first_cell) if prefix
                                     else cells[0] == first_cell):
            return cells
    raise AssertionError(f"no row {first_cell!r} in docs/fields.md")


def number(text):
    return float(re.search(r"-?\d+(\.\d+)?", text).group())


def close(quoted, value):
    """A quoted number equals the value rounded to as many decimals as it is quoted with."""
    decimals = len(quoted.split(".")[1]) if "." in quoted else 0
    return round(float(value), decimals) == float(quoted)


def test_the_spheroid_numbers_are_the_committed_fits():
    fits = rows("spheroid_fits.csv")[0]
    for label, key in (("count's rate while fed", "rate_count"),
                       ("radius's rate while fed", "rate_radius"),
                       ("radius's speed once the core is necrotic", "speed"),
                       ("rim thickness W", "W_linear"), ("φ in the rim", "phi_linear")):
        cells = table_row(label, prefix=True)
        assert close(re.search(r"\d+\.\d+", cells[1]).group(), fits[key]), (label, cells[1])
    theory = table_row("radius's speed", prefix=True)[2]
    assert f"λ × shell(W) = {float(fits['speed_shell']):.3f}" in theory
    assert f"λ W = {float(fits['speed_thin']):.3f}" in theory
    assert f"{float(fits['rate_discrete']):.3f}" in DOC
    last = rows("spheroid_growth.csv")[-1]
    end = table_row("at the end (t = %g)" % float(last["t"]))[1]
    assert f"{last['count']} cells, {last['necrotic']} necrotic" in end
    assert f"R = {float(last['R']):.2f}" in end and f"W = {float(last['W']):.2f}" in end


def test_the_rim_table_is_the_committed_sweep():
    for row in rows("rim.csv"):
        cells = table_row(f"{float(row['uptake']):g}")
        for cell, key in zip(cells[1:], ("R", "c_surface", "phi", "L_eff", "L_fit", "W",
                                         "W_sphere", "W_thick")):
            assert close(cell, row[key]), (row["uptake"], key, cell, row[key])
    slope = float(rows("rim.csv")[0]["slope_W_L"])
    assert f"**{slope:.2f}**" in DOC


def test_the_chemotaxis_table_is_the_committed_run():
    section = DOC[DOC.index("## Chemotactic aggregation"):]
    quoted = {line.split("|")[1].strip(): [c.strip().strip("*") for c in line.split("|")[1:-1]]
              for line in section.splitlines() if re.match(r"\| \d+ \|", line)}
    assert set(quoted) == {"0", "20", "100"}
    for row in rows("chemotaxis.csv"):
        cells = quoted.get(f"{float(row['t']):g}")
        if cells is None:
            continue
        assert close(cells[1], row["nn_distance"]) and int(cells[2]) == int(row["clusters"])
        assert close(cells[3], row["control_nn_distance"])
        assert int(cells[4]) == int(row["control_clusters"])

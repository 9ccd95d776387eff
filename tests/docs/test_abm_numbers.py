"""The numbers docs/abm.md quotes from the agent-based examples are those of the committed outputs:
docs/results/abm/ (written by scripts/abm_results.sh), docs/results/cell_sorting.csv
(examples/abm/cell_sorting.py) and docs/results/crowd_flow.csv (examples/abm/crowd_flow.py).

Nothing is rerun here: each check formats numbers of a committed file as the page writes them and
looks for the phrase in the page (line breaks read as spaces). tests/cli/test_abm_results_cli.py
reruns the first time units of two examples against the committed files.
"""
import csv
import math
import os
import pathlib
import re

import pytest

ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))
RESULTS = ROOT / "docs/results"
ABM = RESULTS / "abm"


def page():
    """docs/abm.md with every run of whitespace as one space."""
    return re.sub(r"\s+", " ", (ROOT / "docs/abm.md").read_text())


def rows(path):
    """The rows of a CSV as dicts of floats (strings where a value is not a number)."""
    def number(v):
        try:
            return float(v)
        except ValueError:
            return v
    with open(path) as f:
        return [{k: number(v) for k, v in r.items()} for r in csv.DictReader(f)]


def summary(name):
    """docs/results/abm/NAME_summary.csv as a dict key → value (strings)."""
    with open(ABM / f"{name}_summary.csv") as f:
        return {r["key"]: r["value"] for r in csv.DictReader(f)}


def thousands(n):
    """1449 → '1449', 46157 → '46 000' (rounded to thousands above 10 000, as the page writes)."""
    n = int(n)
    return f"{round(n, -3):,}".replace(",", " ") if n >= 10000 else str(n)


def assert_quoted(*phrases):
    text = page()
    missing = [p for p in phrases if p not in text]
    assert not missing, f"docs/abm.md does not quote {missing}"


def test_the_monolayer_at_its_end():
    last = rows(ABM / "monolayer_population.csv")[-1]
    s = summary("monolayer")
    n = int(last["count"])
    assert last["t"] == 80 and int(s["final_count"]) == n
    assert_quoted(
        f"about {round(n, -2)} cells at t = 80",
        f"The monolayer at t = 80: {n} cells, {int(last['contacts'])} contacts, largest overlap "
        f"{last['overlap']:.3f} after the relaxation ({last['overlap_before']:.2f} right after the "
        f"last divisions, before it), colony radius {last['colony_radius']:.1f}",
        f"({thousands(s['relax_sweeps'])} relax sweeps for the {n} cells above)")


def test_the_invasion():
    front = rows(ABM / "invasion_front.csv")
    population = rows(ABM / "invasion_population.csv")
    first, last = front[0], front[-1]
    # the front table and population.csv are of the same run
    assert (last["t"], last["count_normal"], last["count_tumour"]) == (
        population[-1]["t"], population[-1]["count_normal"], population[-1]["count_tumour"])
    mid = next(r for r in front if r["t"] == 30)
    s = summary("invasion")
    inhibited = summary("invasion_inhibited")
    assert_quoted(
        f"{int(first['count_normal'])} normal cells",
        f"a clone of {int(first['count_tumour'])} tumour cells",
        f"At t = {last['t']:g} the clone has {int(last['count_tumour'])} cells against "
        f"{int(last['count_normal'])} normal ones",
        f"its area fraction went from {first['area_fraction_tumour']:.3f} to "
        f"{last['area_fraction_tumour']:.3f}",
        f"of all cells) from {first['front_tumour']:.1f} to {last['front_tumour']:.1f}",
        f"the tissue's edge from {first['edge']:.1f} to {last['edge']:.1f}",
        f"at t = 30 the front ({mid['front_tumour']:.1f}) is still inside the edge "
        f"({mid['edge']:.1f})",
        f"largest overlap {float(s['engine.max_overlap']):.3f}",
        f"; {thousands(s['relax_sweeps'])} relax sweeps)",
        f"{int(inhibited['births'])} births, {int(inhibited['final_count'])} cells at t = 45")
    assert int(inhibited["births"]) == 0


def test_the_cell_sorting_run_of_the_example_seed():
    sorting = rows(ABM / "cell_sorting_population.csv")
    equal = rows(ABM / "cell_sorting_equal_population.csv")
    overlap = max(r["overlap"] for r in sorting)
    assert_quoted(
        f"the index goes from {sorting[0]['segregation']:.2f} to {sorting[-1]['segregation']:.2f} "
        f"under differential adhesion and from {equal[0]['segregation']:.2f} to "
        f"{equal[-1]['segregation']:.2f} in the control",
        f"the largest pair overlap over the run is "
        f"{float(summary('cell_sorting')['engine.max_overlap']):.2f} ({overlap:.2f} at the "
        f"recorded times)")


def test_the_cell_sorting_table_and_ranges():
    table = rows(RESULTS / "cell_sorting.csv")
    at = {r["t"]: r for r in table}
    for seed in (1, 2, 3):
        cells = [at[t][f"{case}_seed{seed}"] for case, t in
                 (("sorting", 0), ("sorting", 1000), ("sorting", 2000), ("control", 1000),
                  ("control", 2000))]
        assert_quoted(f"| {seed} | " + " | ".join(f"{v:.3f}" for v in cells) + " |")
    early = [at[400][f"sorting_seed{s}"] for s in (1, 2, 3)]
    control = [r[f"control_seed{s}"] for r in table for s in (1, 2, 3)]
    assert_quoted(f"({min(early):.2f}–{max(early):.2f} at t = 400)",
                  f"({min(control):.2f}–{max(control):.2f} over the whole run)")


def flows(model, width=None, wide=False):
    table = rows(RESULTS / "crowd_flow.csv")
    return [r["specific_flow"] for r in table if r["model"] == model and
            (width is None or r["door_width"] == width) and (not wide or r["door_width"] >= 1.2)]


@pytest.mark.parametrize("width", [0.8, 1.0, 1.2, 1.6, 2.0, 2.4])
def test_the_crowd_flow_table(width):
    """A row of the table: the three seeds' J/b of each model, a cell may end in a remark."""
    cells = []
    for model in ("constant", "distribution", "weidmann"):
        values = flows(model, width)
        assert len(values) == 3
        if all(math.isnan(v) for v in values):
            cells.append(re.escape("clogged (3/3)"))
        else:
            cells.append(re.escape(", ".join(f"{v:.2f}" for v in values)) + r"(?: \([^)|]*\))?")
    row = re.escape(f"| {width:.1f} | ") + r" \| ".join(cells) + r" \|"
    assert re.search(row, page()), f"docs/abm.md has no row {row}"


def test_the_crowd_flow_ranges():
    fast = flows("constant", wide=True) + flows("distribution", wide=True)
    narrow = flows("constant", 1.0) + flows("distribution", 1.0)
    weidmann = [v for v in flows("weidmann") if not math.isnan(v)]
    assert_quoted(f"{min(fast):.1f}–{max(fast):.1f} persons/(m·s) from b = 1.2 m on",
                  f"at b = 1 m, {min(narrow):.1f}–{max(narrow):.1f} from seed to seed",
                  f"{min(weidmann):.2f}–{max(weidmann):.2f} persons/(m·s)")


def test_the_committed_results_are_small():
    for path in sorted(ABM.glob("*.csv")) + [RESULTS / "cell_sorting.csv",
                                               RESULTS / "crowd_flow.csv"]:
        assert path.stat().st_size < 50_000, path


def test_a_phrase_the_page_does_not_hold_fails():
    with pytest.raises(AssertionError, match="does not quote"):
        assert_quoted("The monolayer at t = 80: 1 cells")

"""The numbers docs/crowds.md quotes for the corridor, the bottleneck, the sensitivity study, the
time step and the comparison with JuPedSim are those of the committed CSVs.

docs/results/crowds/ holds what scripts/crowd_corridor.py, crowd_bottleneck.py,
crowd_sensitivity.py, crowd_time_step.py and crowd_jupedsim.py measured, and the experiments'
values. Nothing is rerun here: the tables of docs/crowds.md's sections "Corridor and bottleneck
against experiment", "The time step" and "Side by side with JuPedSim" are compared with the CSVs.
"""
import csv
import math
import os
import pathlib
import re

ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))
RESULTS = ROOT / "docs/results/crowds"
DOC = (ROOT / "docs/crowds.md").read_text()
START = DOC.index("## Corridor and bottleneck against experiment")
SECTION = DOC[START:DOC.index("\n## ", START)]
PROSE = " ".join(SECTION.split())  # line breaks as spaces


def rows(name):
    with open(RESULTS / name) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def tables(section=None):
    """The section's tables: lists of rows of cells (bold marks stripped), separators left out."""
    found, current = [], []
    for line in (section or SECTION).splitlines() + [""]:
        if line.startswith("|"):
            cells = [c.strip().strip("*") for c in line.strip().strip("|").split("|")]
            if not all(set(c) <= {"-"} for c in cells):
                current.append(cells)
        elif current:
            found.append(current)
            current = []
    return found


def table(first_cell, section=None):
    """The section's (default: SECTION) table whose first row starts with first_cell."""
    for t in tables(section):
        if t[0][0] == first_cell:
            return t
    raise AssertionError(f"no table starting with {first_cell!r} in docs/crowds.md")


def close(quoted, value):
    """A quoted number equals the value rounded to as many decimals as it is quoted with."""
    decimals = len(quoted.split(".")[1]) if "." in quoted else 0
    return round(float(value), decimals) == float(quoted)


def mean(values):
    values = list(values)
    return sum(values) / len(values)


def test_the_corridor_table_is_the_committed_sweep():
    t = table("ρ (persons/m²)")
    densities = [float(c) for c in t[0][1:]]
    model = next(r for r in t if r[0] == "model, simulated (m/s)")[1:]
    weidmann = next(r for r in t if r[0] == "Weidmann 1993, fit (m/s)")[1:]
    sim = rows("corridor_simulated.csv")
    for rho, m, w in zip(densities, model, weidmann, strict=True):
        mine = [r for r in sim if float(r["density_per_m2"]) == rho]
        assert len(mine) == 3, rho
        assert close(m, mean(float(r["simulated_speed_m_s"]) for r in mine)), (rho, m)
        assert close(w, mine[0]["weidmann_speed_m_s"]), (rho, w)


def test_the_zhang_table_is_the_committed_run_means():
    t = table("Zhang et al. 2011, run means")
    density = next(r for r in t if r[0] == "ρ (persons/m²)")[1:]
    speed = next(r for r in t if r[0] == "speed (m/s)")[1:]
    zhang = [r for r in rows("corridor_experiments.csv") if r["source"].startswith("Zhang")]
    assert len(zhang) == len(density) == len(speed)
    for r, rho, v in zip(zhang, density, speed):
        assert close(rho, r["density_per_m2"]) and close(v, r["speed_m_s"]), (rho, v)


def test_the_weidmann_rows_are_kladeks_formula():
    import math
    for r in rows("corridor_experiments.csv"):
        if r["source"].startswith("Weidmann"):
            rho = float(r["density_per_m2"])
            v = 1.34 * (1 - math.exp(-1.913 * (1 / rho - 1 / 5.4)))
            assert close(r["speed_m_s"], v), r


def test_the_bottleneck_table_is_the_committed_runs_and_experiments():
    t = table("b (m)")
    sim = rows("bottleneck_simulated.csv")
    exp = rows("bottleneck_experiments.csv")
    assert len(t) - 1 == len({r["door_width_m"] for r in sim})
    for cells in t[1:]:
        b = float(cells[0])
        mine = sorted((r for r in sim if float(r["door_width_m"]) == b), key=lambda r: r["seed"])
        quoted = [c.strip() for c in cells[1].split(",")]
        assert len(quoted) == len(mine) == 3, b
        for q, r in zip(quoted, mine):
            assert close(q, r["specific_flow_per_m_s"]), (b, q)
        assert close(cells[2], mean(float(r["specific_flow_per_m_s"]) for r in mine)), b
        for value, study, width in re.findall(r"(\d\.\d\d) \(([SKL])(?:, b = ([\d.]+) m)?\)",
                                              cells[3]):
            at = float(width) if width else b
            match = [r for r in exp if float(r["door_width_m"]) == at
                     and r["source"].startswith({"S": "Seyfried", "K": "Kretz",
                                                 "L": "Liddle"}[study])]
            assert len(match) == 1 and close(value, match[0]["specific_flow_per_m_s"]), cells


def test_the_experiments_flows_are_their_flows_over_the_width():
    # Both columns are rounded to 3 decimals: J/b of the rounded J is within 0.5e-3 / b of it.
    for r in rows("bottleneck_experiments.csv"):
        j, b = float(r["flow_per_s"]), float(r["door_width_m"])
        assert abs(float(r["specific_flow_per_m_s"]) - j / b) <= 0.5e-3 * (1 + 1 / b), r


def test_the_quoted_ranges_are_the_committed_ones():
    exp = [float(r["specific_flow_per_m_s"]) for r in rows("bottleneck_experiments.csv")
           if float(r["door_width_m"]) >= 0.8]
    assert f"({min(exp):.2f}–{max(exp):.2f} at b ≥ 0.8 m)" in PROSE
    means = {}
    for r in rows("bottleneck_simulated.csv"):
        means.setdefault(float(r["door_width_m"]), []).append(float(r["specific_flow_per_m_s"]))
    wide = [mean(v) for b, v in means.items() if b >= 1.0]
    assert f"({min(wide):.2f}–{max(wide):.2f} against" in PROSE


def test_the_sensitivity_table_is_the_committed_study():
    t = table("parameter")
    study = rows("sensitivity.csv")
    assert len(t) - 1 == len(study)
    for cells, r in zip(t[1:], study):
        assert float(cells[1]) == float(r["factor"]), cells
        for cell, key in zip(cells[2:], ("speed_rho1_m_s", "speed_rho2_m_s",
                                         "specific_flow_b1.2_per_m_s")):
            assert close(cell, r[key]), (cells, key)


def corridor_means():
    means = {}
    for r in rows("corridor_simulated.csv"):
        rho = float(r["density_per_m2"])
        means.setdefault(rho, [float(r["weidmann_speed_m_s"])]).append(
            float(r["simulated_speed_m_s"]))
    return {rho: (mean(v[1:]), v[0], max(v[1:]) - min(v[1:])) for rho, v in means.items()}


def signed(value, decimals=0):
    """A number with its sign written out, + or − (U+2212), as the prose quotes it."""
    text = f"{abs(value):.{decimals}f}"
    return ("−" if value < 0 and float(text) != 0 else "+") + text


def test_the_corridor_prose_is_the_committed_sweep():
    m = corridor_means()
    pct = {rho: round(100 * (v / w - 1)) for rho, (v, w, _) in m.items()}
    assert f"({signed(pct[2.0])} % at 2 /m²)" in PROSE
    assert f"({signed(pct[4.0])} % at 4 /m²)" in PROSE
    gaps = [v - w for rho, (v, w, _) in m.items() if 1.0 <= rho <= 3.0]
    assert f"{signed(min(gaps), 2)}…{signed(max(gaps), 2)} m/s" in PROSE
    spread = max(s for _, _, s in m.values())
    assert f"seeds differ by at most {spread:.2f} m/s" in PROSE
    assert all(abs(m[rho][0] - 1.34) < 0.005 for rho in m if rho <= 0.5)


def test_the_sensitivity_prose_is_the_committed_study():
    study = rows("sensitivity.csv")
    base = study[0]
    assert base["parameter"] == "default"

    def change(keys, column):
        ratios = [float(r[column]) / float(base[column]) - 1 for r in study
                  if r["parameter"] in keys and r["factor"] in ("0.7", "1.3")]
        return round(100 * min(ratios)), round(100 * max(ratios)), max(abs(x) for x in ratios)
    lo, hi, _ = change({"time_gap", "length"}, "speed_rho2_m_s")
    assert f"corridor speed at 2 /m² by −{-lo}…+{hi} %" in PROSE
    lo, hi, _ = change({"time_gap", "length"}, "specific_flow_b1.2_per_m_s")
    assert f"bottleneck flow by −{-lo}…+{hi} %" in PROSE
    worst = max(change({"repulsion", "repulsion_range", "wall_repulsion_range"}, c)[2]
                for c in ("speed_rho1_m_s", "speed_rho2_m_s", "specific_flow_b1.2_per_m_s"))
    assert f"less than {math.ceil(100 * worst)} %, and so does ±30 % on D_w" in PROSE


def test_the_wall_range_prose_is_the_committed_study():
    # The default D_w is the codes' 0.02 m; the variant 0.1 m is moreau's earlier default.
    study = rows("sensitivity.csv")
    base = study[0]
    assert "| `forces.collision_free.wall_repulsion_range` | number | 0.02 |" in (
        ROOT / "docs/keys.md").read_text()
    earlier = next(r for r in study
                   if r["parameter"] == "wall_repulsion_range" and float(r["value"]) == 0.1)
    assert (f"walks at {float(earlier['speed_rho2_m_s']):.2f} m/s instead of "
            f"{float(base['speed_rho2_m_s']):.2f}") in PROSE
    flow = f"{float(earlier['specific_flow_b1.2_per_m_s']):.2f}"
    assert f"at 1.2 m falls to {flow}" in PROSE and f"at 1.2 m it is {flow}" in PROSE


def test_the_projection_counts_are_the_committed_ones():
    door = [r for r in rows("bottleneck_simulated.csv")]
    counts = [int(r["projections"]) for r in door]
    assert f"{min(counts):,}–{max(counts):,} times per run".replace(",", " ") in PROSE
    narrowest = min(float(r["door_width_m"]) for r in door)
    assert max(counts) == max(int(r["projections"]) for r in door
                              if float(r["door_width_m"]) == narrowest)
    overlap = max(float(r["max_overlap_m"]) for r in door)
    assert f"overlaps of at most {overlap:.3f} m" in PROSE
    corridor = rows("corridor_simulated.csv")
    total = sum(int(r["projections"]) for r in corridor)
    said = {0: "nothing is ever projected", 1: "the projection acts once in all"}.get(
        total, f"the projection acts {total} times in all")
    assert f"In the {len(corridor)} corridor runs {said}" in PROSE


JUPEDSIM = DOC[DOC.index("## Side by side with JuPedSim"):]  # the last section


def jupedsim_table(first_cell):
    """A table of the section "Side by side with JuPedSim" by its first cell."""
    return table(first_cell, JUPEDSIM)


def by_case(name, scenario):
    """{(parameter, code): [rows of the seeds]} of a side-by-side CSV."""
    cases = {}
    for r in rows(name):
        if r["scenario"] == scenario:
            cases.setdefault((float(r["parameter"]), r["code"]), []).append(r)
    return cases


def finite_mean(values):
    """The mean over the values that are numbers (a clogged run's flow is NaN)."""
    return mean(v for v in map(float, values) if not math.isnan(v))


def test_the_jupedsim_bottleneck_table_is_the_committed_comparison():
    # "—" marks a run that clogged (NaN in the CSV); the means are over the runs that flowed.
    t = jupedsim_table("door b (m)")
    cases = by_case("jupedsim_side_by_side.csv", "bottleneck")
    assert len(t) - 1 == len(cases)
    columns = ("evac_first_s", "classic_density_per_m2", "voronoi_density_per_m2")
    for cells in t[1:]:
        mine = sorted(cases[(float(cells[0]), cells[1])], key=lambda r: int(r["seed"]))
        quoted = [c.strip() for c in cells[2].split(",")]
        assert len(quoted) == len(mine), cells
        for q, r in zip(quoted, mine):
            flow = float(r["specific_flow_per_m_s"])
            assert (q == "—" and math.isnan(flow)) or close(q, flow), (cells, q)
            assert int(r["passages"]) >= int(r["people"]) - 10 or math.isnan(flow), (cells, r)
        assert close(cells[3], finite_mean(r["specific_flow_per_m_s"] for r in mine)), cells
        for cell, column in zip(cells[4:], columns, strict=True):
            assert close(cell, finite_mean(r[column] for r in mine)), (cells, column)


def test_the_jupedsim_corridor_table_is_the_committed_comparison():
    t = jupedsim_table("corridor ρ₀ (persons/m²)")
    cases = by_case("jupedsim_side_by_side.csv", "corridor")
    assert len(t) - 1 == len(cases)
    for cells in t[1:]:
        mine = cases[(float(cells[0]), cells[1])]
        for cell, column in zip(cells[2:], ("classic_density_per_m2", "voronoi_density_per_m2",
                                            "mean_speed_m_s"), strict=True):
            assert close(cell, mean(float(r[column]) for r in mine)), (cells, column)


def test_the_speed_table_is_the_committed_timing():
    t = jupedsim_table("people")
    timing = rows("speed_vs_jupedsim.csv")
    sizes = sorted({int(r["people"]) for r in timing})
    assert [int(c[0].replace(" ", "")) for c in t[1:]] == sizes
    for cells, n in zip(t[1:], sizes):
        mine = [r for r in timing if int(r["people"]) == n]
        for cell, column in zip(cells[1:4], ("moreau_2threads_s", "moreau_1thread_s",
                                             "jupedsim_s")):
            assert [float(c) for c in cell.split(",")] == [
                round(float(r[column]), 2) for r in mine], (cells, column)
        for cell, column in zip(cells[4:6], ("moreau_2threads_s", "moreau_1thread_s"),
                                strict=True):
            ratios = sorted(float(r["jupedsim_s"]) / float(r[column]) for r in mine)
            assert close(cell, ratios[len(ratios) // 2]), (cells, column)


def time_step_section():
    start = DOC.index("### The time step")
    return DOC[start:DOC.index("\n## ", start)]


def test_the_time_step_table_is_the_committed_study():
    """Each row: the ring's largest change from h = 0.01 s, the corridor's mean speeds at 1, 2
    and 4 persons/m², the range of the bottleneck's per-width means, its mean at 1.2 m and its
    largest overlap, all from time_step.csv."""
    study = rows("time_step.csv")

    def of(name, step):
        return [r for r in study if r["study"] == name and float(r["step_s"]) == step]

    def at(name, step, x):
        return mean(float(r["value"]) for r in of(name, step) if float(r["x"]) == x)

    t = table("h (s)", time_step_section())
    steps = sorted({float(r["step_s"]) for r in study})
    assert [float(c[0]) for c in t[1:]] == steps
    ring0 = {r["x"]: float(r["value"]) for r in of("single_file", steps[0])}
    for cells, h in zip(t[1:], steps, strict=True):
        ring = max(abs(float(r["value"]) - ring0[r["x"]]) for r in of("single_file", h))
        assert close(cells[1], ring), cells
        for cell, rho in zip(cells[2].split(" / "), (1.0, 2.0, 4.0), strict=True):
            assert close(cell, at("corridor", h, rho)), (cells, rho)
        widths = sorted({float(r["x"]) for r in of("bottleneck", h)})
        flows = [at("bottleneck", h, b) for b in widths]
        low, high = cells[3].split("–")
        assert close(low, min(flows)) and close(high, max(flows)), cells
        assert close(cells[4], at("bottleneck", h, 1.2)), cells
        assert close(cells[5], max(float(r["max_overlap_m"]) for r in of("bottleneck", h))), cells
    prose = " ".join(time_step_section().split())
    exp = [float(r["specific_flow_per_m_s"]) for r in rows("bottleneck_experiments.csv")
           if float(r["door_width_m"]) >= 0.8]
    assert f"range is {min(exp):.2f}–{max(exp):.2f} persons/(m·s)" in prose
    drop = max(1 - at("bottleneck", steps[-1], b) / at("bottleneck", steps[0], b)
               for b in sorted({float(r["x"]) for r in of("bottleneck", steps[0])}))
    assert f"by up to {round(100 * drop)} % at h = {steps[-1]:g} s" in prose

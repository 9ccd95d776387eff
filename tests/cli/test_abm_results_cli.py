"""The committed outputs docs/abm.md quotes (docs/results/abm/, scripts/abm_results.sh) are those
of the examples as they are: the first time units of the monolayer and of the invasion, rerun,
give the committed rows of population.csv bit for bit (the runs are deterministic and a shorter
final time does not change the steps before it). tests/docs/test_abm_numbers.py compares the
page with the files."""
import subprocess
import sys

import pytest

from conftest import ROOT, run_cli

RESULTS = ROOT / "docs/results/abm"


@pytest.mark.parametrize("example, T", [("monolayer", 20), ("invasion", 10)])
def test_a_short_rerun_gives_the_committed_first_rows(tmp_path, example, T):
    out = tmp_path / example
    r = run_cli("run", ROOT / f"examples/abm/{example}.toml", "--set", f"problem.T={T}",
                "--out", out)
    assert r.returncode == 0, r.stderr
    rerun = (out / "population.csv").read_text().splitlines()
    committed = (RESULTS / f"{example}_population.csv").read_text().splitlines()
    assert rerun[0] == committed[0]
    assert rerun[-1].split(",")[1] == str(T)  # it reached T: rows up to t = T
    assert len(rerun) > 10 and rerun == committed[:len(rerun)]


def test_the_invasion_figure_and_its_first_front_rows(tmp_path):
    out = tmp_path / "invasion"
    r = run_cli("run", ROOT / "examples/abm/invasion.toml", "--set", "problem.T=5", "--out", out)
    assert r.returncode == 0, r.stderr
    front = tmp_path / "front.csv"
    p = subprocess.run([sys.executable, ROOT / "examples/abm/plot_abm.py", "invasion",
                        tmp_path / "invasion.png", out, front], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "invasion.png").stat().st_size > 0
    rows = front.read_text().splitlines()
    assert len(rows) == 4  # the header and t = 0, 2.5, 5
    assert rows == (RESULTS / "invasion_front.csv").read_text().splitlines()[:4]

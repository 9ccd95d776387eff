"""scripts/render_paraview.py (the docs/io.md figure) renders a frame of the crowd with pvbatch
under a virtual X display: a 1000×1000 picture with the particles drawn in it."""
import shutil
import subprocess

import matplotlib.image
import numpy as np

from conftest import ROOT, pvbatch


def test_render_script_draws_the_crowd(example_runs, tmp_path):
    name, out, summary = example_runs("crowd")
    xvfb_run = shutil.which("xvfb-run")
    assert xvfb_run, "xvfb-run not found: run scripts/install-deps (Debian packages xvfb, xauth)"
    png = tmp_path / "crowd.png"
    # -noreset: without it Xvfb resets when pvbatch's first X connection closes, and the next one
    # fails now and then ("bad X server connection", SIGABRT; 4 of 10 runs here).
    r = subprocess.run([xvfb_run, "-a", "-s", "-screen 0 1280x1024x24 -noreset", pvbatch(), str(ROOT / "scripts" / "render_paraview.py"),
                        str(png), str(out / "trajectory.xdmf"), "1"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    image = matplotlib.image.imread(png)
    assert image.shape[:2] == (1000, 1000)
    background = np.all(image[:, :, :3] > 0.99, axis=2)  # white
    assert 0.02 < 1.0 - background.mean() < 0.9  # the spheres cover part of the picture
    assert len(np.unique(image[~background][:, :3].round(2), axis=0)) > 20  # coloured by id

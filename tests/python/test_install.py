"""`pip install --no-build-isolation .` into a fresh virtual environment, offline, reusing the
build tree of this test run (MOREAU_BUILD_DIR): seconds, not a rebuild."""
import os
import subprocess
import sys

import pytest

from conftest import ROOT

BUILD = os.environ.get("MOREAU_BUILD_DIR")


@pytest.mark.skipif(not BUILD, reason="needs MOREAU_BUILD_DIR (set by ctest)")
def test_pip_install_into_a_venv_and_import(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)],
                   check=True)
    env = dict(os.environ, MOREAU_BUILD_DIR=BUILD, PIP_NO_INDEX="1", PYTHONPATH="")
    r = subprocess.run([str(venv / "bin/pip"), "install", "--no-build-isolation", "--no-deps",
                        "-q", str(ROOT)], env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout + r.stderr
    code = ("import moreau, moreau.particles; print(moreau.__file__); "
            "print(moreau.pbd.SlidingCase().radius)")
    r = subprocess.run([str(venv / "bin/python"), "-c", code], env=env, capture_output=True,
                       text=True, check=True, cwd=tmp_path)
    path, radius = r.stdout.split()
    assert path.startswith(str(venv)) and float(radius) == (1 + 10.0**2) ** 0.5

"""Builds moreau._moreau with CMake for `pip install .` (pyproject.toml has the metadata).

The extension is the CMake target moreau_python, built in MOREAU_BUILD_DIR (default:
build/release, the tree `make` uses, so an installed package costs a link when that tree is up
to date); the tree is configured only when it has no CMakeCache.txt yet. MOREAU_JOBS sets the
parallel jobs (default 2). CMake runs its tests and scripts with Debian's /usr/bin/python3
(MOREAU_PYTHON), whose ABI the virtual environment shares.
"""
import os
import pathlib
import shutil
import subprocess

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("MOREAU_BUILD_DIR", ROOT / "build" / "release"))
        if not (build / "CMakeCache.txt").exists():
            python = os.environ.get("MOREAU_PYTHON", "/usr/bin/python3")
            subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build),
                                   "-DCMAKE_BUILD_TYPE=Release", f"-DMOREAU_PYTHON={python}",
                                   "-DMOREAU_BUILD_PYTHON=ON"])
        subprocess.check_call(["cmake", "--build", str(build), "-j",
                               os.environ.get("MOREAU_JOBS", "2"), "--target", "moreau_python"])
        built = sorted((build / "python" / "moreau").glob("_moreau*.so"))
        if not built:
            raise RuntimeError(f"no _moreau*.so in {build}/python/moreau")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(ext_modules=[Extension("moreau._moreau", sources=[])], cmdclass={"build_ext": CMakeBuild})

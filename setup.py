"""Builds the Python module with the project's CMake build (docs/python.md).

`pip install --no-build-isolation .` (from the repository root) configures and builds the
target hribench_python in $HRIBENCH_BUILD_DIR (default build-python/; an already configured
build folder such as build/ is reused as it is) and installs build/python/hribench. Nothing is
downloaded: CMake, the compilers and the libraries are the Debian packages of
deps/debian-packages.txt.
"""

import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("HRIBENCH_BUILD_DIR", ROOT / "build-python")).resolve()
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja",
                            "-DCMAKE_BUILD_TYPE=Release", "-DHRIBENCH_BUILD_TESTS=OFF",
                            "-DHRIBENCH_BUILD_BENCH=OFF", f"-DPython3_EXECUTABLE={sys.executable}"],
                           check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "hribench_python",
                        "--parallel", str(os.cpu_count() or 1)], check=True)
        built = build / "python" / "hribench"
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).parent
        target.mkdir(parents=True, exist_ok=True)
        for item in built.iterdir():
            if item.is_file():
                shutil.copy2(item, target / item.name)


setup(
    packages=["hribench"],
    package_dir={"": "python"},
    ext_modules=[Extension("hribench._hribench", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build-setuptools"}},
    zip_safe=False,
)

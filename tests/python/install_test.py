"""`pip install --no-build-isolation` from the source tree into a virtual environment, with no
download (--no-index), then `import hribench` from elsewhere (setup.py, pyproject.toml). The
build folder is the one CTest runs from (HRIBENCH_BUILD_DIR), so nothing is recompiled; the
venv is made without its own pip and Debian's pip installs into it (--python), which saves
seeding pip into every test venv."""

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_pip_install_into_a_venv_without_downloads(tmp_path):
    build = os.environ.get("HRIBENCH_TEST_BUILD_DIR")
    if not build:
        pytest.fail("HRIBENCH_TEST_BUILD_DIR is not set (run the Python tests through CTest)")
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--without-pip", "--system-site-packages", str(venv)],
                   check=True)
    env = dict(os.environ, HRIBENCH_BUILD_DIR=build, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.pop("PYTHONPATH", None)
    install = subprocess.run(["/usr/bin/python3", "-m", "pip", "--python", str(venv / "bin" / "python"),
                              "install", "--no-build-isolation", "--no-index", "--no-deps", str(ROOT)],
                             env=env, cwd=tmp_path, capture_output=True, text=True)
    assert install.returncode == 0, install.stdout + install.stderr
    check = subprocess.run([str(venv / "bin" / "python"), "-c",
                            "import hribench; print(hribench.__file__); "
                            "env = hribench.make('I1', seed=0, horizon=0.1); print(env.reset()[0]['time'])"],
                           env=env, cwd=tmp_path, capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    location, time = check.stdout.split()
    assert pathlib.Path(location).is_relative_to(venv) and float(time) == 0.0

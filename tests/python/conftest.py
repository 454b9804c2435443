"""Shared fixtures of the Python tests (run by CTest from the repository root, with
PYTHONPATH=BUILD/python and HRIBENCH_BINARY=the built `hribench` command; see tests/CMakeLists.txt)."""

import os
import subprocess

import pytest


@pytest.fixture(scope="session")
def hribench_binary():
    binary = os.environ.get("HRIBENCH_BINARY")
    if not binary:
        pytest.fail("HRIBENCH_BINARY is not set (run the Python tests through CTest)")
    return binary


@pytest.fixture(scope="session")
def run_cli(hribench_binary):
    """Runs `hribench ARGS...`; returns the CompletedProcess (text, both streams)."""

    def run(*args):
        return subprocess.run([hribench_binary, *map(str, args)], capture_output=True, text=True)

    return run

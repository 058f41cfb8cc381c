"""Shared by the Python module's tests: the CLI to compare with, and a trace cache of the tests' own.

ctest sets OOVR_CLI (the oovr executable) and OOVR_CACHE_DIR (a folder in the build tree);
run.sh puts the module on PYTHONPATH.
"""

import json
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture(scope="session")
def cli():
    """Runs the oovr CLI; returns its standard output (fails the test on a non-zero exit)."""
    exe = os.environ.get("OOVR_CLI")
    if not exe or not os.path.exists(exe):
        pytest.fail("OOVR_CLI is not the oovr executable (ctest sets it)")

    def run(*args):
        p = subprocess.run([exe, *args], capture_output=True, text=True)
        assert p.returncode == 0, f"oovr {' '.join(args)}: {p.stderr}"
        return p.stdout

    return run


@pytest.fixture(scope="session")
def cli_json(cli, tmp_path_factory):
    """Runs an oovr command with --json and returns the document."""

    def run(*args):
        path = tmp_path_factory.mktemp("json") / "out.json"
        text = cli(*args, "--json", str(path))
        with open(path) as f:
            return text, json.load(f)

    return run

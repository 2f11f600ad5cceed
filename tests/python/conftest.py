"""Shared fixtures of the Python module's tests: the module built by CMake (PYTHONPATH), the CLI
binary ($SDFBRICK_CLI) to compare with, and one Context on the test device ($SDFBRICK_TEST_DEVICE,
default PoCL's "cpu") for the whole session."""
import json
import os
import pathlib
import subprocess

import pytest

import sdfbrick

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
DEVICE = os.environ.get("SDFBRICK_TEST_DEVICE") or "cpu"
CLI = os.environ.get("SDFBRICK_CLI")


@pytest.fixture(scope="session")
def ctx():
    with sdfbrick.Context(device=DEVICE) as c:
        yield c


@pytest.fixture(scope="session")
def spheres():
    return sdfbrick.Scene.load(str(SCENES / "spheres.json"))


def cli(*args, env=None, check=True, device=DEVICE):
    """Runs the CLI on the device; gives (exit status, stdout, stderr)."""
    if not CLI:
        pytest.skip("SDFBRICK_CLI is not set")
    run = subprocess.run([CLI, "--device", device, *map(str, args)], capture_output=True, text=True,
                         env={**os.environ, **(env or {})})
    if check and run.returncode != 0:
        raise AssertionError(f"sdfbrick {' '.join(map(str, args))}: exit {run.returncode}: {run.stderr}")
    return run.returncode, run.stdout, run.stderr


def cli_json(tmp_path, *args):
    """Runs the CLI with --json and reads the report back."""
    out = tmp_path / "report.json"
    cli(*args, "--json", out)
    return json.loads(out.read_text())


def keys(value):
    """The shape of a report: every dict's keys, recursively (lists element by element; kernel rows,
    which come sorted by their time, in the kernels' order)."""
    if isinstance(value, dict):
        return {k: keys(v) for k, v in value.items()}
    if isinstance(value, list):
        if all(isinstance(v, dict) and "kernel" in v for v in value):
            value = sorted(value, key=lambda v: v["kernel"])
        return [keys(v) for v in value]
    return None

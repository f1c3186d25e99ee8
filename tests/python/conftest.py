"""Shared fixtures of the Python tests: the module, the CLI, small scenes.

CTest (tests/python/CMakeLists.txt) sets PYTHONPATH to the build's python/ folder and
MGELASTIC_CLI to the built `mgelastic` executable."""
import copy
import os
import pathlib

import pytest

import mgelastic

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]

# A 1 m x 0.1 m x 0.1 m steel-like cantilever clamped at x = 0 under gravity, coarse lattice.
CANTILEVER = {
    "engine": "grid",
    "geometry": {"box": {"center": [0.5, 0, 0], "size": [1.0, 0.1, 0.1]}},
    "grid": {"resolution": 16},
    "material": {"youngs_modulus": 1e7, "poisson_ratio": 0.3, "density": 1000},
    "constraints": [{"region": {"box": {"center": [0, 0, 0], "size": [0.04, 0.2, 0.2]}}}],
    "loads": {"gravity": [0, -9.81, 0]},
    "solver": {"tolerance": 1e-8, "max_vcycles": 60, "precision": "double"},
    "output": {"dir": "out", "formats": ["obj"]},
}


@pytest.fixture
def cantilever():
    """A fresh copy of the cantilever document (tests may change it)."""
    return copy.deepcopy(CANTILEVER)


@pytest.fixture
def cli():
    """Path of the built CLI; skips the test when CTest did not provide it."""
    path = os.environ.get("MGELASTIC_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("MGELASTIC_CLI not set (the CLI is not built)")
    return path

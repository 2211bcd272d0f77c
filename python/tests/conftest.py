"""Shared fixtures: the module of this build (PYTHONPATH set by ctest), the CLI beside it, and a
small periodic test surface so that every test runs in well under a second or two."""
import os
import subprocess
import sys

import numpy as np
import pytest

import glintscope

SOURCE_DIR = os.environ.get("GLINTSCOPE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(scope="session")
def cli():
    exe = os.environ.get("GLINTSCOPE_EXE")
    if not exe or not os.path.exists(exe):
        pytest.fail("GLINTSCOPE_EXE must name the built glintscope executable (ctest sets it)")
    return exe


@pytest.fixture(scope="session")
def surface():
    """A 128 x 128 Gaussian random field at 1 um texels, 0.05 um rms height, 4 um correlation."""
    return glintscope.generate("gaussian", size=128, sigma_h=0.05, correlation_length_x=4, correlation_length_y=4)


def run_python(code):
    """Runs code in a fresh interpreter with this module; returns the completed process."""
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          env=dict(os.environ))


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)

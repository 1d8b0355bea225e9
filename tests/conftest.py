"""Shared helpers for the test suite (real numpy core; Blender where a test says so).

Tests live by layer: tests/core (the numpy core, recipes, benchmarks), tests/nodegraph (the
graph description, features, derived inputs), tests/blender (everything that imports bpy or
runs Blender: the add-on, renders, the command line's image files). Tests under
tests/blender are marked `blender`, so `pytest -m "not blender"` runs the rest in seconds.
With DYNPAINT_NO_BPY=1 importing bpy fails, which proves that they need no Blender.
"""
import os
import subprocess
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLENDER_TESTS = os.path.join(REPO, "tests", "blender")

if os.environ.get("DYNPAINT_NO_BPY"):
    sys.modules["bpy"] = None        # `import bpy` raises ImportError


def pytest_ignore_collect(collection_path, config):
    """`-m "not blender"`: do not even import the Blender tests (importing bpy takes seconds)."""
    if config.getoption("markexpr", "").replace(" ", "") == "notblender":
        return str(collection_path).startswith(BLENDER_TESTS) or None
    return None


def pytest_collection_modifyitems(config, items):
    for item in items:
        if str(item.path).startswith(BLENDER_TESTS + os.sep):
            item.add_marker(pytest.mark.blender)


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def flat_normals(h, w, dtype=np.float32):
    n = np.zeros((h, w, 3), dtype)
    n[..., 2] = 1
    return n


def run_cli(*args, cwd=None):
    """Run `python -m dynpaint_addon ARGS` in a fresh process → CompletedProcess (text)."""
    return subprocess.run([sys.executable, "-m", "dynpaint_addon", *map(str, args)],
                          cwd=cwd or REPO, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": REPO})


@pytest.fixture
def empty_scene():
    """An empty Blender scene with the add-on registered; the test must end without errors
    reported by the add-on's handlers."""
    import bpy
    from dynpaint_addon import blender
    from dynpaint_addon.blender import status
    bpy.ops.wm.read_homefile(use_empty=True)
    blender.register_once()
    status.LAST_ERRORS.clear()
    yield bpy.context.scene
    assert status.LAST_ERRORS == []


@pytest.fixture
def rng():
    return np.random.default_rng(1234)

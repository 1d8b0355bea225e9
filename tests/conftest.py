"""Shared helpers for the test suite (real numpy core; Blender where a test says so)."""
import os
import subprocess
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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

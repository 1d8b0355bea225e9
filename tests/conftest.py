"""Shared helpers for the test suite (real numpy core; Blender where a test says so).

Tests live by layer: tests/core (the numpy core, recipes, benchmarks), tests/nodegraph (the
graph description, features, derived inputs), tests/blender (everything that imports bpy or
runs Blender: the add-on, renders, the command line's image files). Tests under
tests/blender are marked `blender`, so `pytest -m "not blender"` runs the rest in seconds.
With DYNPAINT_NO_BPY=1 importing bpy fails, which proves that they need no Blender.
"""
import base64
import contextlib
import dataclasses
import io
import os
import signal
import subprocess
import sys

if os.environ.get("PYTEST_XDIST_WORKER"):
    # one BLAS thread a worker (before numpy is imported): the workers fill the cores already,
    # and OpenBLAS's idle threads spin — measured on the numpy tier, 2 workers on 2 cores:
    # 30 s of system time → 5 s, 106 s → 92 s
    for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from dynpaint_addon.core.either_relief import one_relief  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from testkit.chromium import Chromium, find_chromium  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLENDER_TESTS = os.path.join(REPO, "tests", "blender")
# Measured: EEVEE's blended transparency renders α ≥ 1 − 1/255 as fully opaque (254/255 → 1).
EEVEE_OPAQUE_SNAP = 1 - 1.5 / 255

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


def cli_in_process(*args, cwd=None):
    """Run the command line's main(ARGS) in this process → CompletedProcess (text), as
    run_cli would give it: for the numpy tier's commands that need no Blender (a fresh
    Python costs ~0.5 s of start-up per run; `python -m dynpaint_addon` itself is run in a
    fresh process by the Blender tests)."""
    from dynpaint_addon.cli import main       # (here: ~0.4 s that most workers never need)
    out, err, here = io.StringIO(), io.StringIO(), os.getcwd()
    args = list(map(str, args))
    try:
        os.chdir(cwd or REPO)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(args)
            except SystemExit as exc:          # argparse's own errors
                code = exc.code
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(["dynpaint", *args], code, out.getvalue(),
                                       err.getvalue())


def run_cli(*args, cwd=None, timeout=600):
    """Run `python -m dynpaint_addon ARGS` in a fresh process → CompletedProcess (text). A run
    past `timeout` seconds fails with where each of its threads was (faulthandler's dump on
    SIGABRT): a hang says where it hangs."""
    proc = subprocess.Popen([sys.executable, "-m", "dynpaint_addon", *map(str, args)],
                            cwd=cwd or REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env={**os.environ, "PYTHONPATH": REPO,
                                            "PYTHONFAULTHANDLER": "1"})
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGABRT)
        out, err = proc.communicate()
        raise AssertionError(f"`dynpaint {' '.join(map(str, args))}` ran past {timeout} s; "
                             f"its threads then:\n{err[-8000:]}") from None
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


@pytest.fixture
def empty_scene():
    """An empty Blender scene with the add-on registered; the test must end without errors
    reported by the add-on's handlers."""
    import bpy
    from dynpaint_addon import blender
    from dynpaint_addon.blender.state import status
    bpy.ops.wm.read_homefile(use_empty=True)
    blender.register_once()
    status.LAST_ERRORS.clear()
    yield bpy.context.scene
    assert status.LAST_ERRORS == []


@pytest.fixture
def rng():
    return np.random.default_rng(1234)


@pytest.fixture(scope="session")
def browser():
    """One headless Chromium for the session (testkit/chromium.py). The README's
    test command installs it where it runs as root; DYNPAINT_SKIP_BROWSER=1 skips these tests
    on a machine without one (say so when you report a run)."""
    if os.environ.get("DYNPAINT_SKIP_BROWSER"):
        pytest.skip("DYNPAINT_SKIP_BROWSER is set: web page tests skipped")
    if find_chromium() is None:
        pytest.fail("no Chromium: install Debian's `chromium` (scripts/bootstrap.sh does as "
                    "root), set DYNPAINT_CHROMIUM=/path/to/chrome, or DYNPAINT_SKIP_BROWSER=1")
    with Chromium() as b:
        yield b


def open_page(browser, path, width=900, height=700, scale=1.0, query=""):
    """Open an exported page and wait until it has drawn → Page (fails on the page's error)."""
    page = browser.open("file://" + os.path.abspath(path) + query, width, height, scale)
    page.evaluate("window.dynamicPainting.ready")
    error = page.evaluate("window.dynamicPainting.error")
    assert error is None, error
    return page


def shown(page, element_id):
    """Whether a viewer sees the page's element: it takes space on the page and is not made
    invisible (the `hidden` attribute alone says nothing: a stylesheet may override it)."""
    return page.evaluate(f"(() => {{ const e = document.getElementById('{element_id}'); "
                         f"return e.getClientRects().length > 0 && "
                         f"getComputedStyle(e).visibility !== 'hidden'; }})()")


def shot_pixels(page, path, width, height):
    """A screenshot of the page, its top-left `width` × `height` pixels as the page shows them
    (8-bit sRGB RGB, y up like the core's arrays)."""
    page.screenshot(str(path))
    return read_image(str(path)).pixels[-height:, :width, :3]


def page_pixels(page, width, height):
    """The page's premultiplied linear RGBA at the painting's size, y up (a float framebuffer)."""
    raw = base64.b64decode(page.evaluate("window.dynamicPainting.renderFloat()"))
    return np.frombuffer(raw, np.float32).reshape(height, width, 4)


def drawn_live(layers):
    """A scene's layers as the web page draws them (core/either_relief.one_relief: a normal
    map's one relief, where a final bake casts the shadow of either) — for the core picture a
    page's screenshot is checked against."""
    return [dataclasses.replace(layer, p=one_relief(
        layer.p, "shape" in layer.images and layer.images["shape"].has_alpha))
        for layer in layers]

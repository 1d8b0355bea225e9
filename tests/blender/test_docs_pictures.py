"""Pictures the docs show regenerate as committed (reading PNGs needs Blender's image I/O)."""
import os

import numpy as np
import pytest

from conftest import REPO
from doc_generators import load_generator
from dynpaint_addon.inputs.imageio import read_image


@pytest.mark.parametrize("generator, page, pictures", [
    ("make_real_paintings", "real-paintings.md", "real"),       # issue 15's before/after
    ("make_shape_pictures", "shape-from-painting.md", "shape"),  # issue 16's methods
    ("make_layer_pictures", "layers.md", "layers"),  # issue 30: layers that shadow each other
    ("make_frame_pictures", None, "frames"),    # issue 31: the animated sample (pictures only)
])
def test_page_and_pictures_are_current(generator, page, pictures, tmp_path):
    """The page (where one is generated) regenerates as committed, its pictures within
    ±2/255."""
    load_generator(generator).main(str(tmp_path))
    docs = os.path.join(REPO, "docs")
    assert page is None or (tmp_path / page).read_text(encoding="utf-8") == open(
        os.path.join(docs, page), encoding="utf-8").read(), \
        f"docs/{page} is stale: run docs/{generator}.py"
    for name in sorted(os.listdir(tmp_path / "img" / pictures)):
        new = read_image(str(tmp_path / "img" / pictures / name)).pixels
        old = read_image(os.path.join(docs, "img", pictures, name)).pixels
        assert new.shape == old.shape and float(np.abs(new - old).max()) <= 2 / 255, name


def test_walkthrough_page_and_pictures_are_current(browser, tmp_path):
    """docs/your-painting.md: its commands run as a user runs them (the page's picture is a
    headless Chromium screenshot, hence the browser)."""
    test_page_and_pictures_are_current("make_walkthrough", "your-painting.md", "walkthrough",
                                       tmp_path)

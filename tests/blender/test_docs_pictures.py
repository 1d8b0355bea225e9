"""Pictures the docs show regenerate as committed (reading PNGs needs Blender's image I/O)."""
import os

import numpy as np

from conftest import REPO
from doc_generators import load_generator
from dynpaint_addon.imageio import read_image


def test_real_paintings_page_and_pictures_are_current(tmp_path):
    """The before/after pictures of issue 15 regenerate as committed (±2/255)."""
    load_generator("make_real_paintings").main(str(tmp_path))
    docs = os.path.join(REPO, "docs")
    assert (tmp_path / "real-paintings.md").read_text(encoding="utf-8") == open(
        os.path.join(docs, "real-paintings.md"), encoding="utf-8").read(), \
        "docs/real-paintings.md is stale: run docs/make_real_paintings.py"
    for name in sorted(os.listdir(tmp_path / "img" / "real")):
        new = read_image(str(tmp_path / "img" / "real" / name)).pixels
        old = read_image(os.path.join(docs, "img", "real", name)).pixels
        assert new.shape == old.shape and float(np.abs(new - old).max()) <= 2 / 255, name


def test_shape_from_painting_page_and_pictures_are_current(tmp_path):
    """The make-shape page of issue 16 and its pictures regenerate as committed (±2/255)."""
    load_generator("make_shape_pictures").main(str(tmp_path))
    docs = os.path.join(REPO, "docs")
    assert (tmp_path / "shape-from-painting.md").read_text(encoding="utf-8") == open(
        os.path.join(docs, "shape-from-painting.md"), encoding="utf-8").read(), \
        "docs/shape-from-painting.md is stale: run docs/make_shape_pictures.py"
    for name in sorted(os.listdir(tmp_path / "img" / "shape")):
        new = read_image(str(tmp_path / "img" / "shape" / name)).pixels
        old = read_image(os.path.join(docs, "img", "shape", name)).pixels
        assert new.shape == old.shape and float(np.abs(new - old).max()) <= 2 / 255, name

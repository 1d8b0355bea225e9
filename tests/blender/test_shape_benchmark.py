"""benchmarks/shape_from_painting.py runs and measures what it says (small sizes): the Cycles
profiles of its scene give back its normals, integration and inflation meet their goals."""
import os
import sys
import tempfile

from conftest import REPO

sys.path.insert(0, os.path.join(REPO, "benchmarks"))

import shape_from_painting as sfp  # noqa: E402


def test_profiles_rendered_by_cycles_give_back_the_normals():
    rows = {count: mean for count, _, mean, _ in sfp.profile_errors(96, 45.0, tempfile.mkdtemp())}
    assert rows[5] < 5.0 and rows[4] < 6.0 and rows[2] > rows[4]


def test_integration_and_inflation_rows():
    rows, seconds = sfp.smooth_height_errors(size=512)
    assert all(err < sfp.GOALS["height_error"] for _, err, _ in rows) and seconds > 0
    seconds, peak, inner, rms = sfp.hemisphere(size=256)
    assert peak < 0.01 and inner < 0.01 and rms < 0.01


def test_the_bound_shows_suzannes_hidden_walls():
    """Cut at the walls the 3D scene knows, Suzanne's integrated normal map casts shadows much
    closer to the truth: what the default relief misses is those walls."""
    res = sfp.shadows_against_truth(sfp.SMOOTH["Suzanne"], 128, 0.01, 128, tempfile.mkdtemp(),
                                    {"default": sfp.default_relief,
                                     "bound": sfp.relief_with_true_walls})
    assert res["bound"][1] > res["default"][1] + 0.1
    assert res["bound"][0] < res["default"][0]

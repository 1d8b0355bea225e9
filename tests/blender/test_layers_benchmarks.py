"""benchmarks/ground_truth_layers.py and layers_speed.py run and measure what they say
(small sizes): the core's layered shadows against Cycles' 3D scene, and the report rows."""
import os
import sys

import numpy as np

from conftest import REPO

sys.path.insert(0, os.path.join(REPO, "benchmarks"))

import ground_truth_layers as gtl  # noqa: E402
import layers_speed  # noqa: E402


def test_the_layers_shadows_match_cycles_on_the_cards_and_the_ground():
    """At 160², d = 0.01: the shadows the layers cast on each other (ground and cards rows,
    where each has any) against the 3D render; the relief row is its own §6 term."""
    rows, seconds = gtl.evaluate(160, 0.01)
    assert len(rows) == 3 * len(gtl.LIGHTS) and all(s > 0 for s in seconds.values())
    ground = [(err, iou) for _, _, kind, err, iou in rows if kind == "ground"]
    assert all(err < 0.02 and iou > 0.9 for err, iou in ground), ground
    cards = [err for _, _, kind, err, _ in rows if kind == "cards"]
    assert max(cards) < 0.02


def test_every_scene_is_one_set_of_shapes_for_blender_and_the_core():
    """Each scene's layers: the ground first, depths rising, every card's box holding its
    shape (a card cut by its box would differ between the 3D truth and the core's alpha)."""
    for name, depths in gtl.SCENES.items():
        assert depths[0].kind == "ground" and not depths[0].cards, name
        assert all(a.depth < b.depth for a, b in zip(depths, depths[1:])), name
        for card in (c for layer in depths for c in layer.cards):
            x0, y0, x1, y1 = card.box
            x, y = np.meshgrid(np.linspace(-0.5, 0.5, 401), np.linspace(-0.5, 0.5, 401))
            outside = (x < x0 - 1e-9) | (x > x1 + 1e-9) | (y < y0 - 1e-9) | (y > y1 + 1e-9)
            assert not (card.inside(x, y) & outside).any(), (name, card.name)


def test_the_speed_report_puts_a_goal_beside_every_measured_row(capsys):
    m = layers_speed.main(["--size", "96", "--runs", "1"])
    out = capsys.readouterr().out
    assert out.count("≤ 1.5×") == 1 and out.count("≤ 50 ms") == 1 and out.count("≤ 2.0×") == 1
    assert all(np.isfinite(v) and v > 0 for v in m.values())

"""A hand's mask snapped onto the painting's outline (core/snap.py; issue 41's full-frame
paintings): the slip undone, nothing moved where the painting has no edge near, the image's
border no edge."""
import numpy as np

from dynpaint_addon.core.snap import (resnapped, signed_edge_distance, snap_margin_px,
                                      snap_to_edges, snapped)


def centred(size=96):
    y, x = np.mgrid[0:size, 0:size] + 0.5
    return x - size / 2, y - size / 2


def front_lit(figure, z):
    """A figure's picture lit from the front (its luminance n_z, the ground white)."""
    gy, gx = np.gradient(z)
    return np.where(figure, 1 / np.sqrt(1 + gx * gx + gy * gy), 1.0)


def test_a_slipped_mask_comes_back_onto_a_disc_and_a_ring():
    x, y = centred()
    r = np.hypot(x, y)
    for figure, z in (((r < 30), np.sqrt(np.clip(30 ** 2 - r * r, 0, None))),
                      ((r > 14) & (r < 34), np.sqrt(np.clip(10 ** 2 - (r - 24) ** 2, 0, None)))):
        painting = front_lit(figure, z)
        slipped = np.roll(np.roll(figure, 2, axis=1), -1, axis=0)
        wrong = (slipped != figure).sum()
        assert (snap_to_edges(slipped, painting, 3) != figure).sum() < 0.2 * wrong


def test_no_edge_near_leaves_the_mask_as_it_is():
    x, y = centred()
    mask = np.hypot(x, y) < 25
    assert np.array_equal(snap_to_edges(mask, np.full(mask.shape, 0.4), 3), mask)
    far = np.hypot(x, y) < 33                                    # its edge 8 px out: beyond 3
    assert np.array_equal(snap_to_edges(mask, np.where(far, 0.2, 1.0), 3), mask)
    assert np.array_equal(snapped(mask, np.where(far, 0.2, 1.0), 0.0), mask)
    assert np.array_equal(snapped(mask, None, 0.05), mask)


def test_the_images_border_is_no_edge():
    """A figure the frame cuts: the rows at the border keep their pixels, its one edge
    inside the image snaps."""
    x, y = centred()
    figure, mask = x < 0, x < 2                                  # painted 2 px too far
    got = snap_to_edges(mask, np.where(figure, 0.3, 0.9), 3)
    assert np.array_equal(got, figure)
    s = signed_edge_distance(mask, 5)
    assert s[0, 10] == s[48, 10] == 5.0 and s[48, 49] == 0.5 and s[48, 50] == -0.5


def test_a_stroke_resnapped_around_its_box_is_the_whole_masks_snap_bit_for_bit():
    """Paint Shape's figure mask, Snap on: 60 random dabs (painted and erased, some at the
    image's border, some two at once far apart), each snapped again around its box alone
    — bit for bit the whole mask's snap; and no dab changes the snap beyond the margin."""
    rng = np.random.default_rng(4)
    x, y = centred(160)
    r = np.hypot(x + 10, y)
    figure = (r < 40) | ((np.abs(y + 20) < 6) & (x > 0))            # a disc and a limb
    painting = front_lit(figure, np.sqrt(np.clip(40 ** 2 - r * r, 0, None))) \
        + 0.05 * rng.random(figure.shape)                           # and the canvas's grain
    reach = 6.0
    margin = snap_margin_px(reach)
    mask = np.roll(figure, 2, axis=1)
    snapped_mask = snap_to_edges(mask, painting, reach)
    for i in range(60):
        before, after = mask, mask.copy()
        for _ in range(1 + (i % 7 == 0)):
            cx, cy = rng.integers(-5, 165, 2)
            after[np.hypot(x + 80 - cx, y + 80 - cy) < rng.uniform(1, 9)] = bool(i % 2)
        whole = snap_to_edges(after, painting, reach)
        got = resnapped(before, snapped_mask, after, painting, reach)
        assert np.array_equal(got, whole), i
        moved = np.argwhere(whole != snapped_mask)
        if len(moved):
            changed = np.argwhere(before != after)
            far = np.abs(moved[:, None, :] - changed[None, :, :]).max(-1).min(1)
            assert far.max() <= margin, i
        mask, snapped_mask = after, got

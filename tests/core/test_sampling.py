"""core/sampling.py's resampling: its fast passes give the general gather's values bit for bit."""
import numpy as np

from dynpaint_addon.core.sampling import resample_separable


def test_an_image_enlarged_a_power_of_two_times_equals_the_general_gather_bit_for_bit():
    """Enlarging rows a power of two times writes each period of rows from one difference
    (_rows_enlarged); asking for the whole image as a box takes the general gather. Both must
    give the same bits — for float32 and float64, channels, edges, non-finite values, and
    sizes where the fast pass does not apply (other factors, one row)."""
    rng = np.random.default_rng(3)
    cases = [((2, 3), (4, 6)), ((5, 7), (40, 56)), ((16, 16), (128, 128)), ((17, 9), (34, 40)),
             ((9, 4, 4), (72, 32)), ((3, 5, 3), (48, 5)), ((8, 8), (64, 8)),
             ((6, 5), (18, 10)), ((1, 4), (8, 8)), ((12, 12), (6, 24))]
    for small, big in cases:
        for dtype in (np.float32, np.float64):
            img = (rng.random(small) * 3 - 1).astype(dtype)
            img.flat[::7] = rng.choice([np.inf, -np.inf, np.nan, 1e30], img.flat[::7].shape)
            with np.errstate(invalid="ignore", over="ignore"):
                fast = resample_separable(img, *big)
                general = resample_separable(img, *big, (0, big[0], 0, big[1]))
            assert fast.dtype == general.dtype == dtype and fast.shape == general.shape
            assert np.array_equal(fast, general, equal_nan=True), (small, big, dtype)


def test_an_enlarged_image_keeps_the_values_at_the_input_pixel_centres():
    """Bilinear at the new pixel centres: where a new pixel's centre falls between two old
    ones it is their mix by distance; beyond the first and last centres, the edge's value."""
    img = np.array([[0.0], [1.0], [3.0]], np.float32)
    out = resample_separable(img, 12, 1)[:, 0]
    assert out[:2].tolist() == [0.0, 0.0] and out[-2:].tolist() == [3.0, 3.0]
    # output row 2 is at input 0.125 (between rows 0 and 1): 0.125; row 6 at 1.125: 1.25
    assert out[2] == 0.125 and out[6] == 1.25

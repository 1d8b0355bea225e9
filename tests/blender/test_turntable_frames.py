"""A turntable's frames as files, and a farm's chunks of them (issue 64): `turntable --out
frames/####.png` writes each frame as a 16-bit PNG, and `--only FIRST-LAST` renders a chunk
in a fresh process as a render farm's worker would — the chunks' frames are the whole
turntable's, bit for bit."""
import os

import numpy as np
import pytest

from dynpaint_addon.inputs.imageio import read_image

from conftest import run_cli

FRAMES = 6


@pytest.fixture(scope="module")
def painting(tmp_path_factory):
    folder = tmp_path_factory.mktemp("farm") / "painting"
    assert run_cli("make-test-painting", "--size", "48", folder).returncode == 0
    return folder


def frames(folder):
    return {name: read_image(os.path.join(folder, name)) for name in sorted(os.listdir(folder))}


def test_chunks_rendered_apart_are_the_whole_turntables_frames(painting, tmp_path):
    whole = run_cli("turntable", painting, "--frames", FRAMES, "--out",
                    tmp_path / "whole" / "####.png")
    assert whole.returncode == 0, whole.stderr
    for chunk in ("1-2", "3-5", "6"):                        # as three workers' tasks
        r = run_cli("turntable", painting, "--frames", FRAMES, "--only", chunk, "--out",
                    tmp_path / "farm" / "frame_##.png")
        assert r.returncode == 0, r.stderr
        assert f"of {FRAMES}" in r.stdout
    want, got = frames(tmp_path / "whole"), frames(tmp_path / "farm")
    assert list(want) == [f"{f:04d}.png" for f in range(1, FRAMES + 1)]   # nothing hidden left
    assert list(got) == [f"frame_{f:02d}.png" for f in range(1, FRAMES + 1)]
    for (name, a), b in zip(want.items(), got.values()):
        assert a.bits == 16 and a.pixels.shape == (48, 48, 3)
        np.testing.assert_array_equal(a.pixels, b.pixels, err_msg=name)
    # the light turns: each frame differs from the one before
    pixels = [a.pixels for a in want.values()]
    assert all(np.abs(p - q).max() > 0.01 for p, q in zip(pixels, pixels[1:]))


@pytest.mark.parametrize("args, message", [
    (["--only", "5-9", "--out", "f/####.png"], "--only 5-9: frames between 1 and 6"),
    (["--only", "4-2", "--out", "f/####.png"], "the first frame after the last"),
    (["--only", "a-b", "--out", "f/####.png"], "frames as FIRST-LAST"),
    (["--only", "1-2", "--out", "v.mp4"], "--out names their files"),
    (["--out", "f/####.exr"], "frames are written as PNG files"),
])
def test_a_chunk_that_cannot_be_rendered_is_refused_before_blender_starts(painting, tmp_path,
                                                                          args, message):
    r = run_cli("turntable", painting, "--frames", FRAMES, *args, cwd=tmp_path)
    assert r.returncode != 0 and message in r.stderr and "Traceback" not in r.stderr
    assert not os.path.exists(tmp_path / "f")

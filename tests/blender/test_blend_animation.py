"""A .blend file's animation from the command line (issue 64: the job a render farm runs for
a .blend): `dynpaint animation FILE.blend` renders the file as saved, each frame baking its
dynamic paintings' shadows — a turntable saved from Blender gives the frames `dynpaint
turntable` gives of its recipe, bit for bit; a chunk rendered apart gives the same frames; the
file is only read."""
import hashlib
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.farm.blend_files import pack, scene_frames  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from testkit.turntable_blend import save_turntable_blend  # noqa: E402

from conftest import run_cli  # noqa: E402

pytestmark = pytest.mark.every_blender

FRAMES = 6


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """(the painting's folder, a .blend of its turntable saved beside it)."""
    folder = tmp_path_factory.mktemp("blend")
    assert run_cli("make-test-painting", "--size", "48", folder / "painting").returncode == 0
    save_turntable_blend(folder / "painting", folder / "turntable.blend", FRAMES)
    return folder / "painting", folder / "turntable.blend"


def frames(folder):
    return {name: read_image(os.path.join(folder, name)).pixels
            for name in sorted(os.listdir(folder))}


def digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def test_a_saved_turntable_renders_the_recipes_turntable_frames(saved, tmp_path):
    painting, blend = saved
    before = digest(blend)
    r = run_cli("animation", blend, "--out", tmp_path / "blend" / "####.png")
    assert r.returncode == 0, r.stderr
    assert f"frames 1–{FRAMES} (1 dynamic painting)" in r.stdout
    r = run_cli("turntable", painting, "--frames", FRAMES, "--out",
                tmp_path / "recipe" / "####.png")
    assert r.returncode == 0, r.stderr
    got, want = frames(tmp_path / "blend"), frames(tmp_path / "recipe")
    assert list(got) == [f"{f:04d}.png" for f in range(1, FRAMES + 1)]
    for name in want:
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)
    pixels = list(got.values())           # the light turns, the shadows with it
    assert all(np.abs(p - q).max() > 0.01 for p, q in zip(pixels, pixels[1:]))
    assert digest(blend) == before        # the artist's file is only read


def test_a_chunk_rendered_apart_gives_the_same_frames(saved, tmp_path):
    _, blend = saved
    assert run_cli("animation", blend, "--out", tmp_path / "all" / "f_##.png").returncode == 0
    r = run_cli("animation", blend, "--only", "3-4", "--out", tmp_path / "chunk" / "f_##.png")
    assert r.returncode == 0 and "frames 3–4" in r.stdout, r.stderr
    whole, chunk = frames(tmp_path / "all"), frames(tmp_path / "chunk")
    assert list(chunk) == ["f_03.png", "f_04.png"]
    for name, pixels in chunk.items():
        np.testing.assert_array_equal(pixels, whole[name], err_msg=name)


def test_a_video_of_the_animation(saved, tmp_path):
    _, blend = saved
    r = run_cli("animation", blend, "--out", tmp_path / "turntable.mp4")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "turntable.mp4").stat().st_size > 1000


@pytest.mark.parametrize("args, message", [
    (["--only", "5-9", "--out", "f/####.png"], "the scene 'Scene' has frames 1-6"),
    (["--only", "4-2", "--out", "f/####.png"], "the first frame after the last"),
    (["--only", "1-2", "--out", "v.mp4"], "--out names their files"),
    (["--out", "f/####.exr"], "frames are written as PNG files"),
    (["--out", "f.png"], "an animation is a video"),
])
def test_what_cannot_be_rendered_is_refused_in_one_line(saved, tmp_path, args, message):
    _, blend = saved
    r = run_cli("animation", blend, *args, cwd=tmp_path)
    assert r.returncode == 1 and message in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert not os.path.exists(tmp_path / "f")


def test_a_file_that_is_not_a_blend_or_has_no_camera_is_refused(saved, tmp_path):
    painting, _ = saved
    r = run_cli("animation", painting / "painting.toml", "--out", tmp_path / "v.mp4")
    assert r.returncode == 1 and "not a .blend file" in r.stderr
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "empty.blend"))
    r = run_cli("animation", tmp_path / "empty.blend", "--out", tmp_path / "v.mp4")
    assert r.returncode == 1 and "has no camera to render from" in r.stderr
    assert "Traceback" not in r.stderr and not os.path.exists(tmp_path / "v.mp4")


def test_a_packed_copy_renders_the_same_frames_even_from_a_compressed_file(saved, tmp_path):
    """What `farm submit FILE.blend` sends (blender-asset-tracer's pack of a file saved
    compressed, moved away from the artist's folder) renders the artist's frames."""
    _, blend = saved
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    zipped = blend.parent / "zipped.blend"           # beside the original: the same images
    bpy.ops.wm.save_as_mainfile(filepath=str(zipped), compress=True, copy=True)
    assert open(zipped, "rb").read(4) == b"\x28\xb5\x2f\xfd"     # zstandard's magic
    assert scene_frames(zipped) == (1, FRAMES, 24.0)
    packed = pack(zipped, tmp_path / "farm" / "input")
    assert sorted(os.listdir(tmp_path / "farm" / "input" / "painting")) == \
        sorted(n for n in os.listdir(blend.parent / "painting") if n.endswith(".png"))
    for source in (blend, packed):
        r = run_cli("animation", source, "--only", "2-3", "--out",
                    tmp_path / os.path.basename(os.path.dirname(source)) / "##.png")
        assert r.returncode == 0, r.stderr
    a, b = frames(tmp_path / blend.parent.name), frames(tmp_path / "input")
    assert list(a) == ["02.png", "03.png"]
    for name in a:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)

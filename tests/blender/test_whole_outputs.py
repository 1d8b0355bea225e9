"""Nothing lost (issue 60): no command writes over the painting it reads or over a painting's
files without --force; a render killed while writing and two turntables writing one file
leave whole files; one recipe string cannot blank the exported page."""
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

pytest.importorskip("bpy")

from conftest import REPO, open_page, run_cli  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_exr  # noqa: E402


@pytest.fixture
def painting(tmp_path):
    folder = tmp_path / "pt"
    assert run_cli("make-test-painting", folder, "--size", "48").returncode == 0
    return folder


@pytest.mark.parametrize("command, target, extra", [
    ("render", "dark.png", []),
    ("render", "dark.png", ["--engine", "cycles"]),
    ("render", "painting.toml", []),
    ("turntable", "dark.png", ["--frames", "2"]),
    ("export-web", "dark.png", []),
    ("bake-shadow", "height.png", ["--kind", "height", "--light", "0", "0", "1"]),
    ("make-shape", "height.png", []),
])
def test_no_command_writes_over_the_painting_it_reads(painting, command, target, extra):
    """Each command's --out onto one of the files it reads (the recipe, an image the recipe
    names, the image given): refused before any work, the file untouched."""
    path = painting / target
    before = path.read_bytes()
    if command == "bake-shadow":
        args = [command, painting / "height.png", *extra]
    elif command == "make-shape":
        args = [command, "inflate", painting / "height.png"]
    else:
        args = [command, painting, *extra]
    r = run_cli(*args, "--out", path)
    assert r.returncode == 1 and "writing there would replace it" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and path.read_bytes() == before


def test_make_test_painting_keeps_a_painting_unless_forced(painting):
    before = (painting / "painting.toml").read_text() + "# mine\n"
    (painting / "painting.toml").write_text(before)
    r = run_cli("make-test-painting", painting)
    assert r.returncode == 1 and "--force" in r.stderr
    assert (painting / "painting.toml").read_text() == before
    r = run_cli("make-test-painting", painting, "--force", "--size", "32")
    assert r.returncode == 0 and "replaced painting.toml" in r.stdout


def test_a_read_only_output_is_refused_before_the_work(painting, tmp_path):
    out = tmp_path / "kept.png"
    out.write_bytes(b"mine")
    out.chmod(0o444)
    start = time.perf_counter()
    r = run_cli("render", painting, "--out", out, "--engine", "cycles")
    assert r.returncode == 1 and "read-only" in r.stderr and out.read_bytes() == b"mine"
    assert "rendered" not in r.stdout and time.perf_counter() - start < 20


def test_a_render_killed_while_writing_leaves_a_whole_picture(tmp_path):
    """A 1024² render killed the moment its output appears beside `--out` (SIGKILL: nothing
    cleans up): the picture at `--out` is the old one or the new one whole, never cut."""
    folder = tmp_path / "big"
    assert run_cli("make-test-painting", folder, "--size", "1024").returncode == 0
    out = tmp_path / "render.png"
    out.write_bytes(b"the old picture")
    proc = subprocess.Popen([sys.executable, "-m", "dynpaint_addon", "render", str(folder),
                             "--out", str(out)], cwd=REPO, env={**os.environ,
                                                                "PYTHONPATH": REPO},
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 300
    while time.time() < deadline and proc.poll() is None and \
            not any(n.startswith(".render.png.") for n in os.listdir(tmp_path)):
        time.sleep(0.001)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    data = out.read_bytes()
    assert data == b"the old picture" or read_image(str(out)).pixels.shape == (1024, 1024, 4)


def test_two_turntables_of_one_file_leave_one_whole_video(painting, tmp_path):
    out = tmp_path / "clip.mp4"
    runs = [subprocess.Popen([sys.executable, "-m", "dynpaint_addon", "turntable", str(painting),
                              "--out", str(out), "--frames", str(frames)], cwd=REPO,
                             env={**os.environ, "PYTHONPATH": REPO},
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            for frames in (6, 9)]
    assert [r.wait() for r in runs] == [0, 0]
    data = out.read_bytes()
    assert data.count(b"moov") == 1                          # one video, not two run together
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".")]


def test_no_recipe_string_blanks_the_page(painting, tmp_path, browser):
    """`<!--<script>` (and `</script>`) in the name, the credits and a light's name: the page
    still draws and shows the strings as written."""
    evil = "<!--<script></script>&amp;"
    text = (painting / "painting.toml").read_text()
    (painting / "painting.toml").write_text(text.replace('"Built-in test painting"', f'"{evil}"')
                                            .replace('name = "Key"', f'name = "{evil}"'))
    out = tmp_path / "page.html"
    r = run_cli("export-web", painting, "--out", out, "--credits", evil)
    assert r.returncode == 0, r.stderr
    page = open_page(browser, out)
    assert page.evaluate("document.title") == evil
    assert page.evaluate("document.getElementById('credits').textContent") == evil


def test_ctrl_c_stops_a_turntable_and_keeps_the_old_video(painting, tmp_path):
    """Blender's render loop swallows the KeyboardInterrupt a handler raises (Ctrl-C, even
    twice, was ignored): now the turntable stops within a frame, exit status 130, the
    video at --out as it was and no hidden half video left beside it."""
    out = tmp_path / "clip.mp4"
    out.write_bytes(b"the old video")
    proc = subprocess.Popen([sys.executable, "-m", "dynpaint_addon", "turntable", str(painting),
                             "--out", str(out), "--frames", "2000"], cwd=REPO,
                            env={**os.environ, "PYTHONPATH": REPO}, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:             # its progress lines: it is rendering frames
        if line.startswith("frame 3/"):
            break
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "interrupted" in err and "Traceback" not in err
    assert out.read_bytes() == b"the old video"
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".")]


def test_a_file_named_blend_that_is_not_one_gets_one_line(tmp_path, painting):
    fake = tmp_path / "fake.blend"
    fake.write_bytes((painting / "dark.png").read_bytes())
    r = run_cli("render", fake, "--grease-pencil", "Stroke", "--out", tmp_path / "x.png")
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert "Blender cannot open it" in r.stderr.splitlines()[-1]


def test_a_pipe_named_as_an_image_is_said_not_waited_for(painting, tmp_path):
    dark = painting / "dark.png"
    dark.unlink()
    os.mkfifo(dark)
    r = run_cli("render", painting, "--out", tmp_path / "x.png")
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert "dark.png" in r.stderr


def test_an_all_nan_height_is_refused_by_bake_shadow(tmp_path):
    """It gave rc 0 and a constant 0.8137 with no word (issue 60): refused as render refuses
    it."""
    write_exr(str(tmp_path / "nan.exr"), np.full((16, 16), np.nan, np.float32))
    r = run_cli("bake-shadow", tmp_path / "nan.exr", "--kind", "height", "--light", "0", "0.5",
                "0.8", "--out", tmp_path / "t.exr")
    assert r.returncode == 1 and "no finite pixel" in r.stderr
    assert not (tmp_path / "t.exr").exists()


def test_a_video_larger_than_ffmpeg_takes_is_refused_before_the_work(tmp_path):
    """`turntable --size 16384 16384` ended in `RuntimeError: Picture size … is invalid` after
    building the scene (issue 60): one line, at once."""
    r = run_cli("turntable", "portrait", "--size", "16384", "16384", "--out", tmp_path / "x.mp4")
    assert r.returncode == 1 and "16254 × 16254 at most" in r.stderr and "Traceback" not in r.stderr

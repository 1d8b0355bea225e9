"""A turntable on a Flamenco render farm (issue 64), with the real thing: a Manager and two
Workers built from ../shared/flamenco and started on loopback (testkit/flamenco.py), the job
type farm/dynamic_painting.js installed beside the Manager as a studio installs it. Skipped,
saying why, where Flamenco's source or Go is missing."""
import os
import re
import subprocess
import sys

import hashlib
import shutil

import imageio_ffmpeg
import numpy as np
import pytest

from dynpaint_addon.farm.flamenco import ANIMATION, PLATFORM, TURNTABLE, FarmError, api, submit
from dynpaint_addon.inputs.imageio import read_image
from dynpaint_addon.inputs.recipe import load_recipe
from testkit import flamenco
from testkit.turntable_blend import save_turntable_blend

from conftest import REPO, run_cli

sys.path.insert(0, os.path.join(REPO, "benchmarks"))
import farm as farm_benchmark  # noqa: E402

FRAMES = 24
SIZE = 48


@pytest.fixture(scope="module")
def farm(tmp_path_factory):
    why = flamenco.unavailable()
    if why:
        pytest.skip(f"no Flamenco farm here: {why}")
    with flamenco.Farm(tmp_path_factory.mktemp("farm"), workers=2) as running:
        yield running


@pytest.fixture(scope="module")
def painting(tmp_path_factory):
    folder = tmp_path_factory.mktemp("painting") / "painting"
    assert run_cli("make-test-painting", "--size", SIZE, folder).returncode == 0
    return folder


def submitted(farm, *args):
    """`dynpaint farm submit …` → (job id, its output folder)."""
    # (seconds here; once a submit hung 10 min before it reached the Manager, and the farm's
    # idle workers timed out under the tests after it: failed at 3 min, it says where)
    r = run_cli("farm", "submit", *args, "--manager", farm.url, timeout=180)
    assert r.returncode == 0, r.stderr
    job = re.search(r"job ([0-9a-f-]{36})", r.stdout).group(1)
    output = re.search(r"its frames and video go to (.+)", r.stdout).group(1).strip()
    return job, output


def frame_pixels(folder):
    names = sorted(n for n in os.listdir(folder) if n.endswith(".png"))
    return names, [read_image(os.path.join(folder, n)).pixels for n in names]


def video_frames(path):
    """How many frames ffmpeg decodes from a video."""
    r = subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-i", path, "-f", "null", "-"],
                       capture_output=True, text=True, timeout=120)
    return int(re.findall(r"frame=\s*(\d+)", r.stderr)[-1])


def test_two_workers_render_the_local_turntables_frames_and_join_them(farm, painting, tmp_path):
    local = run_cli("turntable", painting, "--frames", FRAMES, "--out",
                    tmp_path / "local" / "####.png")
    assert local.returncode == 0, local.stderr
    job, output = submitted(farm, painting, "--frames", FRAMES, "--chunk-size", 4,
                            "--name", "two workers")
    assert farm.wait_job(job)["status"] == "completed"
    tasks = [api(farm.url, "GET", f"/api/v3/tasks/{t['id']}") for t in farm.tasks(job)]
    renders = [t for t in tasks if t["name"].startswith("render-")]
    assert len(renders) == FRAMES // 4 and {t["name"] for t in tasks} >= {"video"}
    assert {t["worker"]["name"] for t in renders} == {"worker0", "worker1"}   # both took some
    names, got = frame_pixels(output)
    assert names == [f"frame_{f:06d}.png" for f in range(1, FRAMES + 1)]
    _, want = frame_pixels(tmp_path / "local")
    for name, a, b in zip(names, want, got):
        np.testing.assert_array_equal(a, b, err_msg=name)             # bit for bit
    assert video_frames(os.path.join(output, "painting.mp4")) == FRAMES
    status = run_cli("farm", "status", job, "--manager", farm.url)
    assert status.returncode == 0 and "is completed" in status.stdout
    assert f"{FRAMES // 4 + 1} completed" in status.stdout


@pytest.fixture(scope="module")
def blend(tmp_path_factory):
    """A .blend of a turntable saved in a project folder beside its painting's images."""
    project = tmp_path_factory.mktemp("project")
    assert run_cli("make-test-painting", "--size", SIZE, project / "painting").returncode == 0
    save_turntable_blend(project / "painting", project / "portrait.blend", 6)
    return project / "portrait.blend"


def digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def test_a_blend_files_animation_packed_and_rendered_by_two_workers(farm, blend, tmp_path):
    """`farm submit FILE.blend`: the file packed with its images onto the shared storage (the
    artist's file only read), its animation rendered in chunks by both workers, the frames
    a local `dynpaint animation`'s bit for bit, joined into a video."""
    before = digest(blend)
    local = run_cli("animation", blend, "--out", tmp_path / "local" / "####.png")
    assert local.returncode == 0, local.stderr
    job, output = submitted(farm, blend, "--chunk-size", 2, "--name", "a blend")
    assert farm.wait_job(job)["status"] == "completed"
    settings = api(farm.url, "GET", f"/api/v3/jobs/{job}")["settings"]
    staged = os.path.dirname(settings["blendfile"])
    assert os.path.basename(settings["blendfile"]) == "portrait.blend"
    assert sorted(os.listdir(os.path.join(staged, "painting"))) == \
        sorted(n for n in os.listdir(blend.parent / "painting") if n.endswith(".png"))
    assert settings["frames"] == "1-6" and settings["fps"] == 24
    tasks = [api(farm.url, "GET", f"/api/v3/tasks/{t['id']}") for t in farm.tasks(job)]
    renders = [t for t in tasks if t["name"].startswith("render-")]
    assert sorted(t["name"] for t in renders) == ["render-1-2", "render-3-4", "render-5-6"]
    names, got = frame_pixels(output)
    assert names == [f"frame_{f:06d}.png" for f in range(1, 7)]
    _, want = frame_pixels(tmp_path / "local")
    for name, a, b in zip(names, want, got):
        np.testing.assert_array_equal(a, b, err_msg=name)
    assert video_frames(os.path.join(output, "portrait.mp4")) == 6
    assert digest(blend) == before


def test_the_animation_job_type_is_one_flamencos_add_on_fills_in(farm):
    """Flamenco's Blender add-on lists the Manager's job types and, for one with a `blendfile`
    string setting of subtype file_path, packs the open file and fills it in; the frame range
    and rate are evaluated in Blender from its settings' `eval`."""
    types = {t["name"]: t for t in api(farm.url, "GET", "/api/v3/jobs/types")["job_types"]}
    settings = {s["key"]: s for s in types[ANIMATION]["settings"]}
    assert (settings["blendfile"]["type"], settings["blendfile"]["subtype"]) == \
        ("string", "file_path")
    assert "C.scene.frame_start" in settings["frames"]["eval"]
    assert "C.scene.render.fps" in settings["fps"]["eval"]
    assert types[ANIMATION]["label"] == "Dynamic Painting animation"
    assert types[TURNTABLE]["label"] == "Dynamic Painting turntable"


def test_a_blend_is_refused_with_a_turntables_options_or_missing_images(farm, blend, tmp_path):
    r = run_cli("farm", "submit", blend, "--manager", farm.url, "--frames", 24)
    assert r.returncode == 1 and "--frames are a recipe's turntable's options" in r.stderr
    moved = tmp_path / "moved.blend"            # saved elsewhere: its images left behind
    shutil.copy(blend, moved)
    jobs = os.path.join(farm.shared, "dynpaint-jobs")
    before = set(os.listdir(jobs)) if os.path.isdir(jobs) else set()
    r = run_cli("farm", "submit", moved, "--manager", farm.url, "--name", "moved")
    assert r.returncode == 1 and "uses files that are not there" in r.stderr, r.stderr
    assert "bright.png" in r.stderr and "Traceback" not in r.stderr
    assert (set(os.listdir(jobs)) if os.path.isdir(jobs) else set()) == before


def test_a_bad_recipe_fails_the_job_with_the_projects_message(farm):
    """A recipe that cannot be read on the workers (here: not there at all) fails its tasks
    with the project's one-line error in their logs, and the job fails."""
    job = api(farm.url, "POST", "/api/v3/jobs", {
        "name": "bad recipe", "type": TURNTABLE, "priority": 50,
        "submitter_platform": PLATFORM,
        "settings": {"recipe": os.path.join(farm.shared, "nowhere", "painting.toml"),
                     "frames": 4, "chunk_size": 4, "engine": "cycles", "size": "",
                     "elevation": "", "light": "", "clockwise": False, "samples": 0,
                     "fps": 24, "render_output_path": os.path.join(farm.shared, "bad")}})
    assert farm.wait_job(job["id"], timeout=300)["status"] == "failed"
    render = next(t for t in farm.tasks(job["id"]) if t["name"].startswith("render-"))
    log = farm.task_log(render["id"])
    assert "error:" in log and "painting.toml" in log and "Traceback" not in log, log


def test_refused_before_anything_is_sent(farm, painting, tmp_path):
    """Options no render takes, a Manager that does not answer, or one without the job type:
    one line, nothing staged on the shared storage."""
    r = run_cli("farm", "submit", painting, "--manager", farm.url, "--frames", 1)
    assert r.returncode == 1 and "--frames must be at least 2" in r.stderr
    r = run_cli("farm", "submit", painting, "--manager", f"http://127.0.0.1:{flamenco.free_port()}/")
    assert r.returncode == 1 and "no Flamenco Manager answers" in r.stderr
    assert "Traceback" not in r.stderr
    jobs = os.path.join(farm.shared, "dynpaint-jobs")
    os.makedirs(os.path.join(jobs, "taken"), exist_ok=True)          # a job's folder
    before = set(os.listdir(jobs))
    r = run_cli("farm", "submit", painting, "--manager", farm.url, "--name", "taken")
    assert r.returncode == 1 and "exists already" in r.stderr
    assert set(os.listdir(jobs)) == before
    # a job the Manager refuses (its job type's own check) leaves nothing staged behind
    with pytest.raises(FarmError, match="refused"):
        submit(farm.url, load_recipe(str(painting)), {"frames": 1, "chunk_size": 1},
               name="refused")
    assert set(os.listdir(jobs)) == before


def test_a_worker_killed_mid_task_has_its_task_requeued_and_the_job_completes(farm, painting):
    """A worker's machine dies mid-task (killed with its render) and its service starts it
    again: the Manager hands it the task it held, which it renders from its start; the job
    completes with every frame whole. (A worker gone for good has its task requeued to
    another by the Manager's timeout check, 5 minutes after the Manager starts and then once a
    minute: measured 3 min 47 s after such a kill — docs/farm.md.)"""
    job, output = submitted(farm, painting, "--frames", 8, "--chunk-size", 4,
                            "--name", "killed worker")
    active = flamenco._wait("a render task active", lambda: next(
        (api(farm.url, "GET", f"/api/v3/tasks/{t['id']}") for t in farm.tasks(job)
         if t["status"] == "active"), None), 120)
    victim = int(active["worker"]["name"].removeprefix("worker"))
    farm.kill_worker(victim)
    farm.start_worker(victim)
    assert farm.wait_job(job, timeout=600)["status"] == "completed"
    log = farm.task_log(active["id"])
    assert log.count("Task assigned to worker") == 2 and "active -> completed" in log, log
    names, _ = frame_pixels(output)
    assert names == [f"frame_{f:06d}.png" for f in range(1, 9)]
    assert not [n for n in os.listdir(output) if n.startswith(".")]   # no cut frame left


def test_a_worker_gone_for_good_has_its_task_requeued_to_another(farm, painting):
    """A worker's machine dies and does not come back: removed from the farm (Flamenco's web
    interface, Workers › Delete: the API call below), its task is requeued and another worker
    renders it; the job completes with every frame whole. (Left alone, the Manager's timeout
    check requeues it too, minutes later: docs/farm.md.) Last of the module's farm tests:
    the farm has one worker after it."""
    job, output = submitted(farm, painting, "--frames", 8, "--chunk-size", 4,
                            "--name", "worker gone")
    active = flamenco._wait("a render task active", lambda: next(
        (api(farm.url, "GET", f"/api/v3/tasks/{t['id']}") for t in farm.tasks(job)
         if t["status"] == "active"), None), 120)
    gone = active["worker"]
    farm.kill_worker(int(gone["name"].removeprefix("worker")))
    api(farm.url, "DELETE", f"/api/v3/worker-mgt/workers/{gone['id']}")
    assert farm.wait_job(job, timeout=600)["status"] == "completed"
    task = api(farm.url, "GET", f"/api/v3/tasks/{active['id']}")
    assert task["worker"]["name"] != gone["name"]                  # rendered by another
    log = farm.task_log(active["id"])
    assert "queued by Manager because worker is being deleted" in log and \
        f"Task assigned to worker {task['worker']['name']}" in log, log
    names, _ = frame_pixels(output)
    assert names == [f"frame_{f:06d}.png" for f in range(1, 9)]
    assert not [n for n in os.listdir(output) if n.startswith(".")]   # no cut frame left


def test_the_benchmark_times_one_and_two_workers_against_no_farm(tmp_path):
    """benchmarks/farm.py at a tiny size (numbers, not speed): every row measured, the farms'
    frames the whole turntable's."""
    if flamenco.unavailable():
        pytest.skip(f"no Flamenco farm here: {flamenco.unavailable()}")
    m = farm_benchmark.main(["--painting-size", "32", "--frames", "4", "--chunk-size", "2",
                             "--out", str(tmp_path / "farm.md"),
                             "--picture", str(tmp_path / "frames.png")])
    assert m["same"] and all(m[k] > 0 for k in ("whole", "apart", "one", "two"))
    text = (tmp_path / "farm.md").read_text()
    assert "| farm, 2 workers |" in text and "bit for bit: yes" in text
    sheet = read_image(str(tmp_path / "frames.png")).pixels    # 4 frames in a row, 4 px apart
    assert sheet.shape[:2] == (2 * 4 + 32, 2 * 4 + 4 * 32 + 3 * 4)


def test_job_type_says_where_the_job_types_are_and_installs_both(tmp_path):
    r = run_cli("farm", "job-type")
    assert r.returncode == 0
    assert [os.path.basename(p) for p in r.stdout.split()] == \
        ["dynamic_painting.js", "dynamic_painting_animation.js"]
    r = run_cli("farm", "job-type", "--install", tmp_path)
    assert r.returncode == 0 and "restart the Manager" in r.stdout
    assert sorted(os.listdir(tmp_path / "scripts")) == \
        ["dynamic_painting.js", "dynamic_painting_animation.js"]
    r = run_cli("farm", "job-type", "--install", tmp_path / "nowhere")
    assert r.returncode == 1 and "not a folder" in r.stderr

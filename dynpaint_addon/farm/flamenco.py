"""A turntable rendered by a Flamenco render farm (issue 64): the job type, and a Manager's
REST API as `dynpaint farm` uses it. No bpy.

Flamenco (Blender's own farm) runs a Manager that splits a job into tasks and Workers that run
them, with storage they all share. The job types are the .js files beside this one:
`dynamic_painting.js`, a recipe's turntable's frames in chunks (`dynpaint turntable … --only
FIRST-LAST`: each worker bakes its frames' shadows; chunks give a whole turntable's frames bit
for bit), and `dynamic_painting_animation.js`, a .blend file's animation (`dynpaint animation`),
each then `frames-to-video`. `submit` copies the painting — a recipe and every file it reads, or
a .blend packed with its images (blend_files.py) — onto the shared storage, where the workers
read it, and submits the job; `job_status` reads it back.
"""
import datetime
from collections import Counter
import json
import os
import shutil
import sys
import urllib.error
import urllib.request

from ..errors import UserError
from ..inputs.recipe import image_files
from .blend_files import is_blend, pack

HERE = os.path.dirname(os.path.abspath(__file__))
TURNTABLE = "dynamic-painting"             # a recipe's turntable (its `recipe` setting)
ANIMATION = "dynamic-painting-animation"   # a .blend's animation (its `blendfile` setting)


def job_type_file(job_type):
    """The file of a job type shipped here (Flamenco names a job type after its file, _ → -)."""
    return os.path.join(HERE, job_type.replace("-", "_") + ".js")


JOB_TYPE_FILES = tuple(job_type_file(t) for t in (TURNTABLE, ANIMATION))
STAGING = "dynpaint-jobs"              # the folder on the shared storage the jobs' files go to
PLATFORM = {"linux": "linux", "darwin": "darwin", "win32": "windows"}.get(sys.platform,
                                                                          sys.platform)


class FarmError(UserError):
    """A problem with the farm: the Manager, the job type, the shared storage."""


def api(manager, method, path, body=None, timeout=30.0):
    """One call of the Manager's REST API (/api/v3/…) → its JSON answer (None when empty; the
    text of a text answer, as a task's log)."""
    url = manager.rstrip("/") + path
    data = None if body is None else json.dumps(body).encode("utf-8")
    request = urllib.request.Request(url, data=data, method=method,
                                     headers={"Content-Type": "application/json",
                                              "Accept": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=timeout) as reply:
            text, kind = reply.read(), reply.headers.get_content_type()
    except urllib.error.HTTPError as exc:
        detail = exc.read().decode("utf-8", "replace")
        try:
            detail = json.loads(detail).get("message", detail)
        except ValueError:
            pass
        raise FarmError(f"the Flamenco Manager at {manager} refused {method} {path}: "
                        f"{exc.code} {detail.strip()}") from None
    except (urllib.error.URLError, OSError) as exc:
        raise FarmError(f"no Flamenco Manager answers at {manager} ({exc}): is it running, "
                        f"and is that its address (its web page's)?") from None
    if not text.strip():
        return None
    return json.loads(text) if kind.endswith("json") else text.decode("utf-8", "replace")


def shared_storage(manager):
    """The farm's shared storage as this machine sees it (the Manager's two-way variables)."""
    found = api(manager, "GET", f"/api/v3/configuration/shared-storage/users/{PLATFORM}")
    location = found.get("location", "")
    if not location or not os.path.isdir(location):
        raise FarmError(f"the Manager's shared storage {location or '(not set)'} is not a "
                        f"folder on this machine: mount it here (or map it with a two-way "
                        f"variable) to submit from here")
    return location


def check_job_type(manager, job_type):
    """Refuse early where the Manager lacks the job type (it was never installed there)."""
    types = api(manager, "GET", "/api/v3/jobs/types").get("job_types", [])
    if not any(t.get("name") == job_type for t in types):
        raise FarmError(f"the Manager at {manager} has no '{job_type}' job type: copy "
                        f"{job_type_file(job_type)} into the scripts/ folder beside its "
                        f"flamenco-manager (`dynpaint farm job-type --install FOLDER`) and "
                        f"restart it")


def stage(recipe, folder):
    """Copy a recipe (core Recipe, loaded) and every file it reads — images, every frame of a
    sequence, its layers' recipes — into `folder`, keeping their places relative to the
    recipe's folder → the copied recipe's path. Files outside the recipe's folder are refused
    (the farm would need them at the same absolute place)."""
    paths = {recipe.path} | {lay.recipe.path for lay in recipe.layers if lay.recipe.path} | \
        image_files(recipe)
    root = os.path.abspath(recipe.folder)
    outside = sorted(p for p in paths if os.path.commonpath([root, os.path.abspath(p)]) != root)
    if outside:
        raise FarmError(f"{recipe.path} reads files outside its folder {root}: "
                        f"{', '.join(outside)}; put them beside it to render it on a farm")
    for path in sorted(paths):
        target = os.path.join(folder, os.path.relpath(os.path.abspath(path), root))
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copy2(path, target)
    return os.path.join(folder, os.path.relpath(os.path.abspath(recipe.path), root))


def stage_layered(path, folder):
    """Copy a layered file (an .ora file, or a folder of layer images) into `folder` → the
    copy's path."""
    target = os.path.join(folder, os.path.basename(os.path.abspath(path).rstrip(os.sep)))
    if os.path.isdir(path):
        shutil.copytree(path, target)
    else:
        os.makedirs(folder, exist_ok=True)
        shutil.copy2(path, target)
    return target


def job_name(recipe_path, now=None):
    """'portrait 2026-11-29 18.40.02': the recipe's folder or file name and the time (no ':',
    which some file systems refuse in the job's folder name)."""
    stem = os.path.splitext(os.path.basename(recipe_path))[0]
    if stem == "painting":                   # every recipe's file is painting.toml
        stem = os.path.basename(os.path.dirname(os.path.abspath(recipe_path))) or stem
    return f"{stem} {(now or datetime.datetime.now()).strftime('%Y-%m-%d %H.%M.%S')}"


def submit(manager, source, settings, name=None, priority=50):
    """Stage a painting on the shared storage and submit its job → (job, the folder its frames
    and video are written to). source: a loaded Recipe or the path of a layered file (.ora, a
    folder of layers), for a turntable; or a .blend file's path, for its animation. settings:
    the job type's without its input (`recipe` or `blendfile`) and `render_output_path`,
    which this fills in."""
    blend = isinstance(source, str) and is_blend(source)
    job_type, key = (ANIMATION, "blendfile") if blend else (TURNTABLE, "recipe")
    check_job_type(manager, job_type)
    shared = shared_storage(manager)
    path = source if isinstance(source, str) else source.path
    name = name or job_name(path)
    folder = os.path.join(shared, STAGING, name.replace("/", "_"))
    if os.path.exists(folder):
        raise FarmError(f"{folder} exists already: give the job another --name")
    output = os.path.join(folder, "output")
    try:
        staging = os.path.join(folder, "input")
        staged = pack(source, staging) if blend else stage_layered(source, staging) \
            if isinstance(source, str) else stage(source, staging)
        os.makedirs(output)
        job = api(manager, "POST", "/api/v3/jobs", {
            "name": name, "type": job_type, "priority": int(priority),
            "submitter_platform": PLATFORM,
            "settings": {**settings, key: staged, "render_output_path": output},
            "metadata": {"dynpaint.recipe": os.path.abspath(path)}})
    except BaseException:       # a job the Manager refused leaves nothing on the storage
        shutil.rmtree(folder, ignore_errors=True)
        raise
    return job, output


def job_status(manager, job_id):
    """(the job, {task status: count}) as the Manager has them now."""
    job = api(manager, "GET", f"/api/v3/jobs/{job_id}")
    tasks = api(manager, "GET", f"/api/v3/jobs/{job_id}/tasks").get("tasks", [])
    return job, dict(Counter(task["status"] for task in tasks))

"""A Flamenco render farm on loopback, for the farm's tests and benchmark (issue 64).

Its Manager and Workers are built from Flamenco's source in ../shared/flamenco (its build.sh,
Go and the Go module proxy; ~2 minutes the first time) into build/flamenco, then each process
runs in a folder of its own under the test's: the Manager (a copy of its binary, with the job
type in the scripts/ folder beside it, as a studio installs it) on 127.0.0.1 at a free port,
with its shared storage; each Worker with its own configuration and credentials
(FLAMENCO_HOME), an ffmpeg on its PATH (imageio-ffmpeg's, for `frames-to-video`). Each is
stopped by its process id.
"""
import os
import shutil
import signal
import socket
import subprocess
import time

import imageio_ffmpeg

from dynpaint_addon.farm.flamenco import JOB_TYPE_FILES, api

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCE = os.path.normpath(os.path.join(REPO, "..", "shared", "flamenco"))
BUILT = os.path.join(REPO, "build", "flamenco")
DYNPAINT = os.path.join(REPO, ".venv", "bin", "dynpaint")
WORKER_TIMEOUT = "8s"           # a Worker silent this long is lost: its task goes to another


def unavailable():
    """Why no farm can be built here (a sentence), or None."""
    if not os.path.isfile(os.path.join(SOURCE, "build.sh")):
        return f"Flamenco's source is not at {SOURCE} (../shared/flamenco)"
    if shutil.which("go") is None and not os.path.exists(os.path.join(BUILT, "flamenco-worker")):
        return "Go is not installed: Flamenco's Manager and Worker cannot be built"
    return None


def build():
    """Build (once) Flamenco's Manager and Worker → the folder holding them."""
    done = subprocess.run(["bash", os.path.join(SOURCE, "build.sh"), BUILT],
                          capture_output=True, text=True, timeout=1200)
    if done.returncode:
        raise RuntimeError(f"building Flamenco from {SOURCE} failed (exit {done.returncode}):\n"
                           + (done.stdout + done.stderr)[-3000:])
    return BUILT


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait(what, check, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        found = check()
        if found:
            return found
        time.sleep(0.2)
    raise TimeoutError(f"the farm: {what} within {timeout} s")


class Farm:
    """A Manager and `workers` Workers in `folder` (start(), stop(); a `with` block too)."""

    def __init__(self, folder, workers=2, program=DYNPAINT):
        self.folder, self.count, self.program = str(folder), workers, program
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}/"
        self.shared = os.path.join(self.folder, "shared")
        self.manager, self.workers = None, {}

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()

    def _spawn(self, exe, where, env=None):
        log = open(os.path.join(where, "log.txt"), "ab")
        return subprocess.Popen([exe], cwd=where, stdout=log, stderr=subprocess.STDOUT,
                                env={**os.environ, **(env or {})}, start_new_session=True)

    def start(self):
        built = build()
        where = os.path.join(self.folder, "manager")
        os.makedirs(os.path.join(where, "scripts"), exist_ok=True)
        os.makedirs(self.shared, exist_ok=True)
        exe = shutil.copy(os.path.join(built, "flamenco-manager"), where)
        for file in JOB_TYPE_FILES:
            shutil.copy(file, os.path.join(where, "scripts"))
        with open(os.path.join(where, "flamenco-manager.yaml"), "w") as fh:
            fh.write(f"_meta:\n  version: 3\nmanager_name: dynpaint tests\n"
                     f"database: flamenco-manager.sqlite\nlisten: 127.0.0.1:{self.port}\n"
                     f"autodiscoverable: false\nlocal_manager_storage_path: ./storage\n"
                     f"shared_storage_path: {self.shared}\nshaman:\n  enabled: false\n"
                     f"task_timeout: 10m\nworker_timeout: {WORKER_TIMEOUT}\n"
                     f"blocklist_threshold: 3\ntask_fail_after_softfail_count: 3\n"
                     f"variables:\n  dynpaint:\n    values:\n      - platform: all\n"
                     f"        value: {self.program}\n")
        self.manager = self._spawn(exe, where)
        _wait("the Manager answers", self._answers, 60)
        for i in range(self.count):
            self.start_worker(i)
        _wait(f"{self.count} Workers awake", lambda: len(self.awake()) >= self.count, 60)

    def _answers(self):
        try:
            return api(self.url, "GET", "/api/v3/version", timeout=2)
        except Exception:
            return None

    def start_worker(self, i):
        where = os.path.join(self.folder, f"worker{i}")
        os.makedirs(where, exist_ok=True)
        tools = os.path.join(where, "bin")
        os.makedirs(tools, exist_ok=True)
        if not os.path.exists(os.path.join(tools, "ffmpeg")):
            os.symlink(imageio_ffmpeg.get_ffmpeg_exe(), os.path.join(tools, "ffmpeg"))
        with open(os.path.join(where, "flamenco-worker.yaml"), "w") as fh:
            fh.write(f"manager_url: {self.url}\nworker_name: worker{i}\n"
                     f"task_types: [misc, ffmpeg, file-management]\n")
        self.workers[i] = self._spawn(os.path.join(BUILT, "flamenco-worker"), where,
                                      {"FLAMENCO_HOME": where,
                                       "PATH": tools + os.pathsep + os.environ["PATH"]})

    def awake(self):
        """The names of the Workers the Manager has awake."""
        found = api(self.url, "GET", "/api/v3/worker-mgt/workers").get("workers", [])
        return {w["name"] for w in found if w["status"] == "awake"}

    def kill_worker(self, i):
        """Kill Worker i and what it runs, at once (a machine that dies mid-task)."""
        os.killpg(self.workers[i].pid, signal.SIGKILL)
        self.workers.pop(i).wait()

    def wait_job(self, job_id, timeout=600, until=("completed", "failed", "canceled")):
        """The job once its status is one of `until` → its data."""
        def ended():
            job = api(self.url, "GET", f"/api/v3/jobs/{job_id}")
            return job if job["status"] in until else None
        return _wait(f"job {job_id} {'/'.join(until)}", ended, timeout)

    def tasks(self, job_id):
        return api(self.url, "GET", f"/api/v3/jobs/{job_id}/tasks").get("tasks", [])

    def task_log(self, task_id):
        return api(self.url, "GET", f"/api/v3/tasks/{task_id}/logtail") or ""

    def stop(self):
        for proc in list(self.workers.values()) + [self.manager]:
            if proc is not None and proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
                try:
                    proc.wait(10)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait()
        self.workers.clear()

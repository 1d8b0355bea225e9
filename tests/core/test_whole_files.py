"""Outputs appear whole or not at all (issue 60; inputs/whole_files.py), without Blender: a
failed or interrupted write leaves the old file, a killed process leaves no half file at the
path, two writers of one path leave one whole file; a folder, a read-only file or an input is
refused as an output before any work."""
import os
import signal
import subprocess
import sys

import pytest

from conftest import REPO
from dynpaint_addon.inputs.whole_files import (OutputError, refuse_inputs, writable_here,
                                               write_text_whole, written_whole)


def test_a_failed_write_keeps_the_old_file(tmp_path):
    path = tmp_path / "render.png"
    path.write_bytes(b"the old picture")
    for interrupt in (RuntimeError("disk full"), KeyboardInterrupt()):
        with pytest.raises(type(interrupt)):
            with written_whole(path) as part:
                open(part, "wb").write(b"half a pic")
                raise interrupt
        assert path.read_bytes() == b"the old picture"
        assert os.listdir(tmp_path) == ["render.png"]          # no half file left about
    write_text_whole(path, "new")
    assert path.read_text() == "new" and os.listdir(tmp_path) == ["render.png"]


# A writer killed outright (SIGKILL: no handler runs) half way through a slow write
KILLED = """
import os, signal, sys
sys.path.insert(0, sys.argv[1])
from dynpaint_addon.inputs.whole_files import written_whole
with written_whole(sys.argv[2]) as part:
    with open(part, "wb") as fh:
        fh.write(b"x" * 1000)
        fh.flush()
        os.kill(os.getpid(), signal.SIGKILL)
"""


def test_a_killed_writer_leaves_the_old_file_whole(tmp_path):
    path = tmp_path / "turntable.mp4"
    path.write_bytes(b"the old video" * 1000)
    res = subprocess.run([sys.executable, "-c", KILLED, REPO, str(path)])
    assert res.returncode == -signal.SIGKILL
    assert path.read_bytes() == b"the old video" * 1000
    hidden = [n for n in os.listdir(tmp_path) if n != "turntable.mp4"]
    assert len(hidden) == 1 and hidden[0].startswith(".turntable.mp4.")   # only the hidden part


# Two writers of one path at once, each writing its own byte slowly
WRITER = """
import sys, time
sys.path.insert(0, sys.argv[1])
from dynpaint_addon.inputs.whole_files import written_whole
with written_whole(sys.argv[2]) as part:
    with open(part, "wb") as fh:
        for _ in range(40):
            fh.write(sys.argv[3].encode() * 5000)
            fh.flush()
            time.sleep(0.005)
"""


def test_two_writers_of_one_path_leave_one_whole_file(tmp_path):
    path = tmp_path / "out.mp4"
    runs = [subprocess.Popen([sys.executable, "-c", WRITER, REPO, str(path), mark])
            for mark in "ab"]
    assert [r.wait() for r in runs] == [0, 0]
    data = path.read_bytes()
    assert data in (b"a" * 200000, b"b" * 200000)
    assert os.listdir(tmp_path) == ["out.mp4"]


def test_an_output_that_cannot_or_must_not_be_written_is_refused(tmp_path):
    dark = tmp_path / "dark.png"
    dark.write_bytes(b"painted")
    link = tmp_path / "link.png"
    link.symlink_to(dark)
    with pytest.raises(OutputError, match="is the dark image"):
        refuse_inputs(str(link), {str(dark): "the dark image"})
    refuse_inputs(str(tmp_path / "other.png"), {str(dark): "the dark image"})
    with pytest.raises(OutputError, match="is a folder"):
        writable_here(str(tmp_path))
    dark.chmod(0o444)
    with pytest.raises(OutputError, match="read-only"):
        writable_here(str(dark))
    writable_here(str(tmp_path / "new" / "deeper" / "x.png"))     # folders made as needed


# A process under `ulimit -v` (3 GB) on a machine with more free: what it may be given
ULIMITED = """
import resource, sys
sys.path.insert(0, sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
from dynpaint_addon.inputs import memory
print(memory.available_bytes() / 2**30)
"""


def test_the_memory_check_sees_a_limit_on_the_process():
    """The machine's MemAvailable is not all a limited process may use (issue 60: a 12000²
    read under a 3 GB limit raised MemoryError without numbers)."""
    out = subprocess.run([sys.executable, "-c", ULIMITED, REPO], capture_output=True,
                         text=True, check=True).stdout
    assert float(out) < 3.0

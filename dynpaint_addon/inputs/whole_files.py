"""Outputs that never destroy an artist's files (issue 60; no bpy): every file a command writes
appears whole or not at all, and no command writes over an input of the painting it reads.

- `written_whole(path)`: the file is written under a hidden name beside `path` (same folder,
  same extension: every writer, Blender's movie writer included, picks its format by it) and
  renamed onto `path` only when it is complete (`os.replace`, atomic on one file system). An
  error or Ctrl-C removes the half file; a process killed outright leaves only the hidden one,
  never a truncated `path`. Two writers of one path each rename a whole file: the last wins.
- `refuse_inputs(out, inputs)`: an output that is one of the painting's own files (the same
  file by any path or link) is refused before any work, with the option that names it.
- `writable_here(out)`: an output that cannot be written (a read-only file, a folder where a
  file should be) is refused before the work, not after.

    >>> import tempfile, os
    >>> folder = tempfile.mkdtemp()
    >>> with written_whole(os.path.join(folder, "a.png")) as part:
    ...     _ = open(part, "w").write("whole")
    ...     os.path.basename(part).startswith(".a.png.")
    True
    >>> open(os.path.join(folder, "a.png")).read(), os.listdir(folder)
    ('whole', ['a.png'])
"""
import os
import secrets
from contextlib import contextmanager

from ..errors import UserError


class OutputError(UserError):
    """An output that would destroy a file, or that cannot be written; said before the work."""


_WRITING = set()         # the hidden files being written now (abandon_writing's)


def abandon_writing():
    """Remove every hidden file being written now: for a process about to end at once (a
    Ctrl-C that Blender's render loop would otherwise swallow), which leaves each `path` as
    it was."""
    for part in list(_WRITING):
        if os.path.exists(part):
            os.remove(part)
        _WRITING.discard(part)


@contextmanager
def written_whole(path):
    """Yield the hidden path to write `path`'s content to; renamed onto `path` when the block
    ends, removed if it raises (see the module)."""
    path = os.path.abspath(os.fspath(path))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    part = _new_hidden_file(path)
    _WRITING.add(part)
    try:
        yield part
        if os.path.exists(path):            # keep the old file's permissions, as an editor does
            os.chmod(part, os.stat(path).st_mode & 0o7777)
        os.replace(part, path)
    except BaseException:
        if os.path.exists(part):
            os.remove(part)
        raise
    finally:
        _WRITING.discard(part)


def write_text_whole(path, text):
    """A text file (UTF-8) written whole or not at all."""
    with written_whole(path) as part:
        with open(part, "w", encoding="utf-8") as fh:
            fh.write(text)


def _new_hidden_file(path):
    """A new empty file beside `path`, hidden, of its extension, created with the permissions
    a new `path` would get (0o666 less the umask: mkstemp's are 0o600)."""
    folder, name = os.path.split(path)
    for _ in range(100):
        part = os.path.join(folder, f".{name}.{secrets.token_hex(4)}{os.path.splitext(name)[1]}")
        try:
            os.close(os.open(part, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666))
            return part
        except FileExistsError:
            continue
    raise FileExistsError(f"{folder}: no free name for a hidden file beside {name}")


def same_file(a, b):
    """Whether two paths name one file (links and relative paths followed); False when
    either does not exist."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def refuse_inputs(out, inputs, option="--out"):
    """OutputError when `out` is one of `inputs` ({path: what it is}: 'the dark image', …):
    the output would replace the painting's own file."""
    for path, what in inputs.items():
        if path and same_file(out, path):
            raise OutputError(f"{option} {out} is {what} ({path}): writing there would "
                              f"replace it; choose another name")


def writable_here(out, option="--out"):
    """OutputError when `out` cannot be written: an existing folder, a read-only file, or a
    folder that cannot take a new file."""
    out = os.path.abspath(os.fspath(out))
    if os.path.isdir(out):
        raise OutputError(f"{option} {out} is a folder: give a file name")
    if os.path.exists(out) and (not os.access(out, os.W_OK) or
                                not os.stat(out).st_mode & 0o222):   # read-only, root or not
        raise OutputError(f"{option} {out} is read-only: choose another name, or make it "
                          f"writable")
    folder = os.path.dirname(out)
    while not os.path.exists(folder):
        folder = os.path.dirname(folder)
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{option} {out}: {folder} cannot take a new file (no write "
                          f"permission)")

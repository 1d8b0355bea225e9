"""Layout promises: extension manifest, zip contents, CI = README's test command (the folder
rule for bpy is tests/core/test_import_graph.py's)."""
import glob
import os
import re
import subprocess
import sys
import zipfile

import bpy
import pytest

from conftest import REPO

BLENDER_EXT = os.path.join(bpy.utils.system_resource("SCRIPTS"), "addons_core", "bl_pkg", "cli",
                           "blender_ext.py")


@pytest.mark.every_blender
def test_manifest_validates():
    res = subprocess.run([sys.executable, BLENDER_EXT, "validate", REPO], capture_output=True, text=True)
    assert res.returncode == 0 and "Success" in res.stdout, res.stdout + res.stderr


def test_built_zip_excludes_dev_files(tmp_path):
    res = subprocess.run([sys.executable, BLENDER_EXT, "build", "--source-dir", REPO,
                          "--output-dir", str(tmp_path)], capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    names = zipfile.ZipFile(glob.glob(str(tmp_path / "*.zip"))[0]).namelist()
    assert "blender_manifest.toml" in names and "__init__.py" in names
    assert "dynpaint_addon/core/shadow.py" in names
    for asset in ("viewer.html", "viewer.js", "viewer.css"):   # the web page's, read at export
        assert f"dynpaint_addon/web/{asset}" in names
    snippets = os.path.join(REPO, "dynpaint_addon", "nodegraph", "snippets")
    for language in ("shared", "osl", "glsl"):         # the generators' hand-written sources
        for name in os.listdir(os.path.join(snippets, language)):
            assert f"dynpaint_addon/nodegraph/snippets/{language}/{name}" in names
    for sample in ("portrait", "glass", "impossible"):      # samples ship, their generator not
        assert f"sample_scenes/{sample}/painting.toml" in names
        assert f"sample_scenes/{sample}/thumbnail.png" in names
    assert "sample_scenes/make_samples.py" not in names
    assert not [n for n in names if n.endswith(".oso")]       # compiled where needed
    for dev in ("tests/", "testkit/", ".ci/", "scripts/", "benchmarks/", "docs/", ".venv/",
                ".venv-newest/",
                "requirements-dev.txt",
                "pytest.ini", "__pycache__"):
        assert not any(n.startswith(dev) or f"/{dev}" in n for n in names), dev


INSTALL_AND_ADD = """
import os, sys, glob, tempfile
os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp()
import bpy
bpy.ops.extensions.package_install_files(filepath=sys.argv[1], repo="user_default",
                                         enable_on_install=True)
bpy.ops.wm.read_homefile(use_empty=True)
folder = sys.argv[2]
bpy.ops.dynpaint.add(directory=folder, files=[{"name": n} for n in
                     ("normal.png", "dark.png", "bright.png")])
mat = bpy.context.object.active_material
print("ADDED", bpy.context.object.name, mat.dynamic_painting.is_painting, len(mat.node_tree.nodes))
assert bpy.ops.dynpaint.add_sample(sample="portrait") == {"FINISHED"}
mat = bpy.context.object.active_material
print("SAMPLE", mat.name, mat.dynamic_painting.is_painting, len(mat.dynamic_painting.lights),
      mat.dynamic_painting.image_shape.filepath)
print("MODULE", [m for m in sys.modules if m.endswith("dynamic_painting")])
prefs = bpy.context.preferences.addons["bl_ext.user_default.dynamic_painting"].preferences
prefs.frame_cache_mb = 300                   # the preference the frame cache is bounded by
from bl_ext.user_default.dynamic_painting.dynpaint_addon.blender.state.frames import cache_mb
print("FRAME CACHE", cache_mb())
assert bpy.ops.dynpaint.add_sample(sample="blink") == {"FINISHED"}
print("BLINK", bpy.context.scene.frame_end)
"""


@pytest.mark.every_blender
def test_built_zip_installs_headless_and_adds_a_painting(tmp_path):
    """The extension as artists get it: install the zip, enable it, Add › Dynamic Painting."""
    from parity_recipes import write_images
    subprocess.run([sys.executable, BLENDER_EXT, "build", "--source-dir", REPO,
                    "--output-dir", str(tmp_path)], check=True, capture_output=True)
    write_images(str(tmp_path / "images"))
    res = subprocess.run([sys.executable, "-c", INSTALL_AND_ADD,
                          glob.glob(str(tmp_path / "*.zip"))[0], str(tmp_path / "images")],
                         cwd=str(tmp_path), capture_output=True, text=True,
                         env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert "ADDED" in res.stdout and " True " in res.stdout, res.stdout + res.stderr
    assert "bl_ext.user_default.dynamic_painting" in res.stdout
    # the sample comes from the installed extension's own folder, not from this repository
    # its own two lights: the Sun the first painting added lights that one only (issue 60)
    assert "SAMPLE Portrait (Suzanne) True 2 " in res.stdout, res.stdout + res.stderr
    sample_line = next(ln for ln in res.stdout.splitlines() if ln.startswith("SAMPLE"))
    assert REPO not in sample_line and "extensions" in sample_line
    # the animated sample plays from the installed copy; its frames kept as the preference says
    assert "FRAME CACHE 300" in res.stdout and "BLINK 48" in res.stdout, res.stdout + res.stderr


TOGGLE = """
import os, sys, tempfile
os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp()
import bpy
bpy.ops.extensions.package_install_files(filepath=sys.argv[1], repo="user_default",
                                         enable_on_install=True)
bpy.ops.wm.read_homefile(use_empty=True)
MOD = "bl_ext.user_default.dynamic_painting"
HANDLERS = ("depsgraph_update_post", "frame_change_post", "load_post", "render_pre",
            "undo_post", "redo_post")

def ours():
    return {h: sum(getattr(f, "__module__", "").startswith(MOD)
                   for f in getattr(bpy.app.handlers, h)) for h in HANDLERS}

assert bpy.ops.dynpaint.add_sample(sample="impossible") == {"FINISHED"}
mat = bpy.context.object.active_material
drivers = len(mat.node_tree.animation_data.drivers)
namespace = set(bpy.app.driver_namespace)
print("ENABLED", ours())
for i in range(3):
    bpy.ops.preferences.addon_disable(module=MOD)
    print("DISABLED", ours(), hasattr(bpy.types.Material, "dynamic_painting"),
          hasattr(bpy.types, "DYNPAINT_OT_add"), hasattr(bpy.types, "VIEW3D_MT_dynpaint_add"))
    bpy.ops.preferences.addon_enable(module=MOD)
print("AFTER", ours(), len(mat.node_tree.animation_data.drivers) == drivers,
      set(bpy.app.driver_namespace) == namespace, mat.dynamic_painting.is_painting,
      all(d.is_valid for d in mat.node_tree.animation_data.drivers))
bpy.context.scene.frame_set(5)
print("ERRORS", [e for e in sys.modules[MOD + ".dynpaint_addon.blender.state.status"].LAST_ERRORS])
"""


@pytest.mark.every_blender
def test_enabling_and_disabling_the_extension_leaves_nothing_behind(tmp_path):
    """Disable/enable the installed extension three times: no handler left while disabled,
    exactly one of each after, the painting's drivers neither lost nor duplicated."""
    subprocess.run([sys.executable, BLENDER_EXT, "build", "--source-dir", REPO,
                    "--output-dir", str(tmp_path)], check=True, capture_output=True)
    res = subprocess.run([sys.executable, "-c", TOGGLE, glob.glob(str(tmp_path / "*.zip"))[0]],
                         cwd=str(tmp_path), capture_output=True, text=True,
                         env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    one = ("{'depsgraph_update_post': 1, 'frame_change_post': 1, 'load_post': 1, "
           "'render_pre': 1, 'undo_post': 1, 'redo_post': 1}")
    none = one.replace("1", "0")
    lines = res.stdout.splitlines()
    assert f"ENABLED {one}" in lines, res.stdout + res.stderr
    disabled = [ln for ln in lines if ln.startswith("DISABLED")]
    assert len(disabled) == 3 and all(ln == f"DISABLED {none} False False False" for ln in disabled), \
        res.stdout
    assert f"AFTER {one} True True True True" in lines, res.stdout + res.stderr
    assert "ERRORS []" in lines, res.stdout + res.stderr


def readme_commands():
    text = open(os.path.join(REPO, "README.md")).read()
    return re.findall(r"```sh\n(.*?)\n```", text, re.S)


def test_ci_runs_the_readme_test_command_exactly():
    commands = readme_commands()
    tests_cmd = [c for c in commands if "pytest" in c]
    assert len(tests_cmd) == 1
    ci = open(os.path.join(REPO, ".ci", "run")).read()
    assert tests_cmd[0].strip() in [ln.strip() for ln in ci.splitlines()]
    # both ends of the Blender versions the manifest claims (README.md, "Tested Blender versions")
    spread = "-n auto --maxprocesses 4 --dist loadfile"     # (memory: ~5 GB a worker at most)
    assert f".venv/bin/python -m pytest -q {spread} tests" in tests_cmd[0]
    assert f".venv-newest/bin/python -m pytest -q {spread} -m every_blender tests" in tests_cmd[0]
    # the suite spread over the machine's cores: its tool comes with the set-up
    assert "pytest-xdist" in open(os.path.join(REPO, "requirements-dev.txt")).read()
    assert any(".venv/bin/dynpaint turntable" in c for c in commands)      # the main job


def test_no_compiled_shader_is_committed():
    """A compiled .oso embeds one machine's paths: compiled where needed, never committed."""
    res = subprocess.run(["git", "ls-files", "*.oso"], cwd=REPO, capture_output=True, text=True)
    if res.returncode != 0:
        pytest.skip("not a git checkout")
    assert res.stdout.strip() == ""
    assert "*.oso" in open(os.path.join(REPO, ".gitignore")).read().split()


def test_venv_is_ignored():
    ignored = open(os.path.join(REPO, ".gitignore")).read().split()
    assert ".venv/" in ignored and ".venv-newest/" in ignored

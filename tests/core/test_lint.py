"""The code lints clean (scripts/lint.py: pyflakes, Blender's property idiom aside)."""
import importlib.util
import os

from conftest import REPO


def _lint_module():
    spec = importlib.util.spec_from_file_location("lint", os.path.join(REPO, "scripts",
                                                                        "lint.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_code_lints_clean_and_the_linter_finds_what_it_should(tmp_path):
    lint = _lint_module()
    assert lint.lint() == []
    # the idiom it leaves out is a Blender property's declaration, nothing else
    probe = tmp_path / "probe.py"
    probe.write_text("from bpy.props import IntProperty\n\n\nclass A:\n"
                     "    size: IntProperty(name=\"Frame Cache\",\n"
                     "                      description=\"Megabytes kept\")\n\n\n"
                     "def f():\n    return missing\n")
    found = lint.lint([str(probe)])
    assert len(found) == 1 and "undefined name 'missing'" in found[0]

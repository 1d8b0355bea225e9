"""Every runnable example in the package's docstrings runs and gives what it shows (issue 28,
point 7: nine modules' examples were never run). Modules without bpy only, so this runs in the
core suite; a module that gains an example is found by its `>>>`."""
import doctest
import importlib
import os

import pytest

from conftest import REPO

# the package, and what the tests and benchmarks share beside it
FOLDERS = [os.path.join(REPO, name) for name in ("dynpaint_addon", "testkit")]


def modules_with_examples():
    found = []
    for folder, _, files in (entry for top in FOLDERS for entry in os.walk(top)):
        for name in sorted(files):
            path = os.path.join(folder, name)
            if name.endswith(".py") and ">>>" in open(path, encoding="utf-8").read():
                rel = os.path.relpath(path, REPO)[:-3].replace(os.sep, ".")
                found.append(rel.removesuffix(".__init__"))
    return sorted(found)


def test_the_examples_are_found():
    assert {"dynpaint_addon.core.integrate", "dynpaint_addon.core.shape",
            "dynpaint_addon.inputs.channel_names"} <= set(modules_with_examples())


@pytest.mark.parametrize("name", modules_with_examples())
def test_docstring_examples_run(name):
    result = doctest.testmod(importlib.import_module(name),
                             optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0, result

"""The package's imports run one way (issue 14), and bpy lives in one folder (issue 28): read
from the source, no Blender needed.

    command line, add-on glue (blender/)  →  nodegraph/  →  core/
    params, recipe, imageio, … sit beside: the core imports none of them, they import the core

Only blender/ imports bpy; nothing under core/, nodegraph/, web/ or cli/ does, even inside a
function; a module beside them may reach Blender on first use only (imageio's image loader).

Every import of a dynpaint_addon module counts, also one inside a function: a cycle kept alive
by a late import is still a cycle.
"""
import ast
import os
import subprocess
import sys

from conftest import REPO

PACKAGE = os.path.join(REPO, "dynpaint_addon")
# Imports inside a function that are allowed: what is optional or heavy for some callers
# (the command line runs without Blender until a command asks for it).
LAZY = {("dynpaint_addon.cli.render", "dynpaint_addon.blender.headless"),
        ("dynpaint_addon.cli.turntable", "dynpaint_addon.blender.headless")}
LAZY_EXTERNAL = {"bpy", "OpenEXR", "cycles"}


def modules():
    """{module name: path} of every module of the package."""
    found = {}
    for folder, _, files in os.walk(PACKAGE):
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, REPO)[:-3].replace(os.sep, ".")
                found[rel.removesuffix(".__init__")] = path
    return found


def parsed(path):
    """(syntax tree, ids of the nodes inside a function) of a module."""
    tree = ast.parse(open(path, encoding="utf-8").read())
    in_function = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            in_function |= {id(n) for n in ast.walk(node) if n is not node}
    return tree, in_function


def imports(name, path, known):
    """[(imported module, inside a function, line)] of one module's own-package imports."""
    is_package = path.endswith("__init__.py")
    tree, in_function = parsed(path)
    out = []
    for node in ast.walk(tree):
        targets = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_package else name.split(".")[:-1]
                base = base[:len(base) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            # `from . import x` imports the submodule x where there is one
            targets = [f"{module}.{a.name}" if f"{module}.{a.name}" in known else module
                       for a in node.names]
        for target in targets:
            out.append((target, id(node) in in_function, node.lineno))
    return out


def graph():
    known = modules()
    edges = {}
    for name, path in known.items():
        edges[name] = [(t, lazy, line) for t, lazy, line in imports(name, path, known)
                       if t.split(".")[0] == "dynpaint_addon" and t in known]
    return known, edges


def test_no_import_cycle():
    known, edges = graph()
    state, stack = {}, []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for target, _, _ in edges[m]:
            if state.get(target) == "open":
                cycle = stack[stack.index(target):] + [target]
                raise AssertionError("import cycle: " + " → ".join(cycle))
            if target not in state:
                visit(target)
        stack.pop()
        state[m] = "done"
    for m in sorted(known):
        if m not in state:
            visit(m)


def test_no_import_inside_a_function_but_optional_ones():
    known, edges = graph()
    late = [f"{m}:{line} imports {t}" for m, targets in edges.items()
            for t, lazy, line in targets if lazy and (m, t) not in LAZY]
    assert late == []
    for name, path in known.items():
        for target, lazy, line in imports(name, path, known):
            if lazy and target.split(".")[0] != "dynpaint_addon":
                assert target.split(".")[0] in LAZY_EXTERNAL, f"{name}:{line} imports {target}"


FOLDERS = ("core", "nodegraph", "blender", "web", "cli")


def layer(module):
    """The folder a module sits in under the package ("core", "blender", …), or "top"."""
    parts = module.split(".")
    if len(parts) > 2 or (len(parts) == 2 and parts[1] in FOLDERS):
        return parts[1]
    return "top"


def test_layers_import_downward_only():
    """core imports only core; nodegraph never the glue; nothing but the glue (and the command
    line's Blender commands) imports the glue."""
    _, edges = graph()
    wrong = []
    for m, targets in edges.items():
        for t, lazy, line in targets:
            src, dst = layer(m), layer(t)
            if src == "core" and dst != "core":
                wrong.append(f"{m}:{line} → {t}")
            if src == "nodegraph" and dst == "blender":
                wrong.append(f"{m}:{line} → {t}")
            if dst == "blender" and src != "blender" and (m, t) not in LAZY:
                wrong.append(f"{m}:{line} → {t}")
    assert wrong == []


def test_no_single_letter_module_aliases():
    known = modules()
    short = []
    for name, path in known.items():
        for node in ast.walk(ast.parse(open(path, encoding="utf-8").read())):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                short += [f"{name}:{node.lineno} {a.name} as {a.asname}" for a in node.names
                          if a.asname and len(a.asname) == 1]
    assert short == []


BPY_FREE_FOLDERS = ("core", "nodegraph", "web", "cli")


def bpy_imports(path):
    """[(line, inside a function)] of a module's imports of bpy (or its submodules)."""
    tree, in_function = parsed(path)
    found = []
    for node in ast.walk(tree):
        names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                 [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
        if any(n.split(".")[0] == "bpy" for n in names):
            found.append((node.lineno, id(node) in in_function))
    return found


def test_bpy_lives_in_blender_only():
    """The folder rule: core/, nodegraph/, web/ and cli/ never import bpy; the modules beside them
    only inside a function (on first use); blender/ is the glue."""
    wrong = []
    for name, path in modules().items():
        folder = layer(name)
        for line, lazy in bpy_imports(path):
            if folder in BPY_FREE_FOLDERS or (folder == "top" and not lazy):
                wrong.append(f"{name}:{line}")
    assert wrong == []
    # the rule holds at run time too: every module outside blender/ imports with bpy absent
    outside = sorted(m for m in modules() if layer(m) != "blender" and m != "dynpaint_addon.__main__")
    code = ("import sys, importlib; sys.modules['bpy'] = None\n"
            f"for m in {outside!r}: importlib.import_module(m)\n"
            "from dynpaint_addon.core import pipeline\n"
            "from dynpaint_addon.testpainting import builtin_images, builtin_recipe\n"
            "r = builtin_recipe(); print(pipeline.render(builtin_images(16), r.lights, r.params).rgba.shape)")
    res = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": REPO})
    assert res.returncode == 0 and "(16, 16, 4)" in res.stdout, res.stderr
    assert len(outside) > 40

"""The package's imports run one way (issue 14), its top shows its parts (issue 40), and bpy
lives in one folder (issue 28): read from the source, no Blender needed.

    cli/ → blender/ (grouped by job) → farm/ → web/ → inputs/ → shapes/ → nodegraph/ → the
    tables → core/

Only blender/ imports bpy; nothing under core/, nodegraph/, shapes/, web/, farm/ or cli/ does, even
inside a function; inputs/ may reach Blender on first use only (imageio's image loader).

Every import of a dynpaint_addon module counts, also one inside a function: a cycle kept alive
by a late import is still a cycle.
"""
import ast
import functools
import os
import subprocess
import sys

from conftest import REPO

PACKAGE = os.path.join(REPO, "dynpaint_addon")
# Imports inside a function that are allowed: what is optional or heavy for some callers
# (the command line runs without Blender until a command asks for it).
LAZY = {(f"dynpaint_addon.cli.{command}", "dynpaint_addon.blender.headless")
        for command in ("render", "turntable", "animation", "export_web")}
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


@functools.lru_cache(maxsize=None)
def import_nodes(path):
    """[(import statement, inside a function)] of a module, found in one walk of its tree
    (once for every test: they only read them)."""
    found = []

    def visit(node, in_function):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                found.append((child, in_function))
            visit(child, in_function or isinstance(child, (ast.FunctionDef,
                                                           ast.AsyncFunctionDef)))
    visit(ast.parse(open(path, encoding="utf-8").read()), False)
    return found


def imports(name, path, known):
    """[(imported module, inside a function, line)] of one module's own-package imports."""
    is_package = path.endswith("__init__.py")
    out = []
    for node, in_function in import_nodes(path):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        else:
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
            out.append((target, in_function, node.lineno))
    return out


@functools.lru_cache(maxsize=None)
def graph():
    """(modules(), {module: [(imported module of the package, inside a function, line)]}),
    made once for every test (they only read it)."""
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


# The package's parts, lowest first: a module imports from its own part and the parts below it
# only. The tables sit at the top of the package beside the parts; blender/ is grouped by job,
# and its own modules (what Blender calls: properties, panels, handlers; headless, the command
# line's way in) sit above its groups.
ORDER = ("core", "tables", "nodegraph", "shapes", "inputs", "web", "farm",
         "blender.nodes", "blender.state", "blender.bake", "blender.material", "blender.scenes",
         "blender.operators", "blender", "cli", "entry")
TABLES = ("params", "looks", "errors")
ENTRIES = ("__init__", "__main__")


def part(module):
    """The part of the package a module belongs to: a folder ("core", "inputs", …), a group of
    blender/ ("blender.bake", …), "blender" for blender/'s own modules, "tables", "entry"."""
    parts = module.split(".")[1:]
    if not parts or parts == ["__main__"]:
        return "entry"
    if len(parts) == 1:
        return "tables" if parts[0] in TABLES else parts[0]
    if parts[0] == "blender" and len(parts) > 2:
        return f"blender.{parts[1]}"
    return parts[0]


def test_the_top_lists_the_parts_and_the_tables_only():
    """Every entry at the package's top is a part in ORDER, a table, or the package's entry."""
    top = sorted(e for e in os.listdir(PACKAGE) if e != "__pycache__")
    folders = {p for p in ORDER if "." not in p} - {"tables", "entry"}
    expected = sorted(folders | {t + ".py" for t in TABLES} | {e + ".py" for e in ENTRIES})
    assert top == expected
    groups = {p.split(".")[1] for p in ORDER if p.startswith("blender.")}
    blender = os.path.join(PACKAGE, "blender")
    assert {e for e in os.listdir(blender) if os.path.isdir(os.path.join(blender, e))
            and e != "__pycache__"} == groups


def test_parts_import_downward_only():
    """A module imports its own part and those below it in ORDER; the glue is imported by
    nothing outside blender/ but the command line's Blender commands, on first use."""
    known, edges = graph()
    assert {part(m) for m in known} == set(ORDER)
    wrong = []
    for m, targets in edges.items():
        for t, lazy, line in targets:
            src, dst = ORDER.index(part(m)), ORDER.index(part(t))
            if dst > src:
                wrong.append(f"{m}:{line} → {t} ({part(m)} is below {part(t)})")
            if part(t).startswith("blender") and not part(m).startswith("blender") \
                    and (m, t) not in LAZY:
                wrong.append(f"{m}:{line} → {t}")
    assert wrong == []


def test_no_single_letter_module_aliases():
    known = modules()
    short = []
    for name, path in known.items():
        for node, _ in import_nodes(path):
            short += [f"{name}:{node.lineno} {a.name} as {a.asname}" for a in node.names
                      if a.asname and len(a.asname) == 1]
    assert short == []


BPY_FREE = ("core", "tables", "nodegraph", "shapes", "web", "farm", "cli", "entry")


def bpy_imports(path):
    """[(line, inside a function)] of a module's imports of bpy (or its submodules)."""
    found = []
    for node, in_function in import_nodes(path):
        names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                 [node.module or ""] if not node.level else [])
        if any(n.split(".")[0] == "bpy" for n in names):
            found.append((node.lineno, in_function))
    return found


def test_bpy_lives_in_blender_only():
    """The folder rule: core/, nodegraph/, shapes/, web/, farm/, cli/ and the tables never import bpy;
    inputs/ only inside a function (on first use); blender/ is the glue."""
    wrong = []
    for name, path in modules().items():
        for line, lazy in bpy_imports(path):
            if part(name) in BPY_FREE or (part(name) == "inputs" and not lazy):
                wrong.append(f"{name}:{line}")
    assert wrong == []
    # the rule holds at run time too: every module outside blender/ imports with bpy absent
    outside = sorted(m for m in modules() if not part(m).startswith("blender")
                     and m != "dynpaint_addon.__main__")
    code = ("import sys, importlib; sys.modules['bpy'] = None\n"
            f"for m in {outside!r}: importlib.import_module(m)\n"
            "from dynpaint_addon.core import pipeline\n"
            "from dynpaint_addon.inputs.testpainting import builtin_images, builtin_recipe\n"
            "r = builtin_recipe(); print(pipeline.render(builtin_images(16), r.lights, r.params).rgba.shape)")
    res = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": REPO})
    assert res.returncode == 0 and "(16, 16, 4)" in res.stdout, res.stderr
    assert len(outside) > 40

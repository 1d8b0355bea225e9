"""The package's imports run one way (issue 14): read from the source, no Blender needed.

    command line, add-on glue (blender/)  →  nodegraph/  →  core/
    params, recipe, imageio, … sit beside: the core imports none of them, they import the core

Every import of a dynpaint_addon module counts, also one inside a function: a cycle kept alive
by a late import is still a cycle.
"""
import ast
import os

from conftest import REPO

PACKAGE = os.path.join(REPO, "dynpaint_addon")
# Imports inside a function that are allowed: what is optional or heavy for some callers
# (the command line runs without Blender until a command asks for it).
LAZY = {("dynpaint_addon.cli", "dynpaint_addon.blender.headless")}
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


def imports(name, path, known):
    """[(imported module, inside a function, line)] of one module's own-package imports."""
    is_package = path.endswith("__init__.py")
    tree = ast.parse(open(path, encoding="utf-8").read())
    in_function = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            in_function |= {id(n) for n in ast.walk(node) if n is not node}
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


def layer(module):
    parts = module.split(".")
    return parts[1] if len(parts) > 2 or parts[1] in ("core", "nodegraph", "blender") else "top"


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

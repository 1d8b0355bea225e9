"""Lint the code with pyflakes (requirements-dev.txt; scripts/bootstrap.sh installs it):
unused imports and names, undefined names. Run: `.venv/bin/python scripts/lint.py`; exit
status 1 when anything is found (tests/core/test_lint.py runs it).

Blender declares properties as annotations (`size: IntProperty(name="Frame Cache")`), whose
string arguments pyflakes reads as forward annotations ("syntax error in forward annotation",
"undefined name 'Light'"): those two messages on the lines of a Blender property's
declaration are left out, every other one is reported.
"""
import ast
import functools
import os
import sys

from pyflakes import api, messages, reporter

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDERS = ("dynpaint_addon", "testkit", "tests", "benchmarks", "docs", "sample_scenes",
           "scripts")
ANNOTATION_MESSAGES = (messages.ForwardAnnotationSyntaxError, messages.UndefinedName)


class _Collect(reporter.Reporter):
    def __init__(self):
        super().__init__(sys.stdout, sys.stderr)
        self.found = []

    def flake(self, message):
        if not (isinstance(message, ANNOTATION_MESSAGES)
                and message.lineno in _property_lines(message.filename)):
            self.found.append(str(message))

    def syntaxError(self, filename, msg, lineno, offset, text):
        self.found.append(f"{filename}:{lineno}: {msg}")

    def unexpectedError(self, filename, msg):
        self.found.append(f"{filename}: {msg}")


@functools.lru_cache(maxsize=None)
def _property_lines(path):
    """The lines of a module's annotations that declare a Blender property (`x: …Property(…)`,
    however many lines the call takes)."""
    with open(path, encoding="utf-8") as f:
        tree = ast.parse(f.read())
    lines = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.AnnAssign) and isinstance(node.annotation, ast.Call):
            func = node.annotation.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name.endswith("Property"):
                lines |= set(range(node.lineno, node.end_lineno + 1))
    return lines


def lint(paths=None):
    """The messages pyflakes gives on `paths` (default: the repository's code), Blender's
    property idiom aside."""
    collect = _Collect()
    api.checkRecursive(paths or [os.path.join(ROOT, f) for f in FOLDERS], collect)
    return collect.found


if __name__ == "__main__":
    os.chdir(ROOT)
    found = lint()
    print("\n".join(found) if found else "lint: clean")
    sys.exit(1 if found else 0)

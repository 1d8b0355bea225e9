"""The docs' generators (docs/make_*.py, scripts outside the package) loaded as modules."""
import importlib.util
import os

from conftest import REPO


def load_generator(name):
    """docs/<name>.py as a module, e.g. load_generator("make_docs")."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(REPO, "docs", name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

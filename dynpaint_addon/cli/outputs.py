"""Before a command works, its output (issue 60): `--out` can be written and is none of the
files the command reads — the images and recipe it was given, and every image a recipe it was
given names (each frame of a sequence, each layer's). Said in one `error:` line before any
work (with --force, where a command has it, said in a note and done); the files themselves
are written whole by inputs/whole_files.py."""
import os

from ..errors import UserError
from ..inputs.layered_files import is_layered_file
from ..inputs.painting_folder import recipe_in
from ..inputs.recipe import load_recipe
from ..inputs.whole_files import refuse_inputs, same_file, writable_here
from .notes import print_notes

# options whose value is a file a command writes, not one it reads
OUTPUT_OPTIONS = ("out", "residual")


def guard_outputs(args):
    """OutputError (a UserError) when an output option of `args` (argparse's namespace) can
    not be written or names a file the command reads."""
    # a folder output (make-shape export-maps, bake-shadow --layers) is its command's to check
    outputs = {option: getattr(args, option, None) for option in OUTPUT_OPTIONS}
    outputs = {option: out for option, out in outputs.items() if isinstance(out, str) and out
               and not (os.path.isdir(out) and not os.path.splitext(out)[1])}
    inputs = read_files(args) if outputs else {}
    for option, out in outputs.items():
        flag = f"--{option}"
        writable_here(out, flag)
        if getattr(args, "force", False):     # asked for: said (`new --force` rewrites a recipe)
            print_notes([f"--force: {flag} {out} replaces {what}" for path, what in
                         inputs.items() if same_file(out, path)])
        else:
            refuse_inputs(out, inputs, flag)


def read_files(args):
    """{path: what it is} of the files a command reads: every existing path its arguments
    name but the outputs, and a recipe's images."""
    found = {}
    for key, value in vars(args).items():
        if key in OUTPUT_OPTIONS or key == "func":
            continue
        for path in value if isinstance(value, list) else [value]:
            if isinstance(path, str) and os.path.exists(path):
                found.update(_files_of(path, key))
    return found


def _files_of(path, key):
    """A path an argument names → {file: what it is} it stands for (a recipe: itself and
    its images; a folder: its recipe's; an image: itself)."""
    recipe = recipe_in(path) if os.path.isdir(path) else \
        path if path.lower().endswith(".toml") else ""
    if not recipe:
        return {} if os.path.isdir(path) or is_layered_file(path) else \
            {path: f"the {key.replace('_', ' ')} file"}
    try:
        loaded = load_recipe(recipe)
    except UserError:
        return {recipe: "the recipe"}      # the command says what is wrong with it
    found = {recipe: "the recipe"}
    for layer in loaded.layers or [None]:
        part = layer.recipe if layer else loaded
        for channel, slot in part.slots().items():
            for file in slot.files():
                found[file] = f"the painting's {channel} image"
    return found

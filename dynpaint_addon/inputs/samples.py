"""The sample paintings shipped in `sample_scenes/` (one folder per sample with painting.toml,
its images and thumbnail.png). No bpy here: the add-on's menus and the command line share it.
"""
import os
import tomllib
from dataclasses import dataclass

# The extension root holds both dynpaint_addon/ and sample_scenes/ (in the repo and in the zip);
# this file is dynpaint_addon/inputs/samples.py.
EXTENSION_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SAMPLES_DIR = os.path.join(EXTENSION_ROOT, "sample_scenes")


@dataclass(frozen=True)
class Sample:
    id: str            # the folder name: "portrait"
    name: str
    description: str
    recipe: str        # absolute path of painting.toml
    thumbnail: str     # absolute path of thumbnail.png ("" if missing)


def list_samples(folder=SAMPLES_DIR):
    """Every sample folder with a painting.toml, sorted by folder name (unreadable ones are
    skipped: a menu must not fail because one sample is broken)."""
    if not os.path.isdir(folder):
        return []
    found = []
    for entry in sorted(os.listdir(folder)):
        recipe = os.path.join(folder, entry, "painting.toml")
        if not os.path.isfile(recipe):
            continue
        try:
            with open(recipe, "rb") as fh:
                data = tomllib.load(fh)
        except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
            continue
        thumb = os.path.join(folder, entry, "thumbnail.png")
        found.append(Sample(entry, str(data.get("name", entry)), str(data.get("description", "")),
                            recipe, thumb if os.path.isfile(thumb) else ""))
    return found


def recipe_path(name_or_path):
    """A recipe file path, or the name of a sample ("portrait") → the recipe's path."""
    if os.path.exists(name_or_path) or os.sep in name_or_path or name_or_path.endswith(".toml"):
        return name_or_path
    for sample in list_samples():
        if sample.id == name_or_path:
            return sample.recipe
    return name_or_path     # load_recipe reports it as not found


def recipe_help():
    """The command line's help for a RECIPE argument, naming the samples there are."""
    return f"painting.toml, or a sample's name ({', '.join(s.id for s in list_samples())})"

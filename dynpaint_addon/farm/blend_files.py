"""A .blend file for a render farm (issue 64), read and packed by blender-asset-tracer (BAT, the
packer Flamenco's own add-on uses) without starting Blender. No bpy.

`pack` copies the file and every file it uses (images, image sequences, linked libraries) into
a folder, rewriting the copy's paths to their new places; the artist's file is only read.
`scene_frames` reads the frame range and rate of the scene the file opens with.
"""
import pathlib

try:
    from blender_asset_tracer import blendfile
    from blender_asset_tracer.pack import Packer
except ImportError:          # an optional dependency: only `farm submit FILE.blend` needs it
    blendfile = Packer = None

from ..errors import UserError

NEEDS_BAT = ("a .blend file is packed for the farm by blender-asset-tracer: "
             "`pip install blender-asset-tracer` (requirements-dev.txt pins it)")


def is_blend(path):
    return str(path).lower().endswith(".blend")


def _check_bat():
    if Packer is None:
        raise UserError(NEEDS_BAT)


def scene_frames(path):
    """The frame range and frame rate of the scene a .blend opens with → (first, last, fps)."""
    _check_bat()
    try:
        bfile = blendfile.open_cached(pathlib.Path(path))
        scene = bfile.find_blocks_from_code(b"GLOB")[0].get_pointer(b"curscene")
        first, last = scene.get((b"r", b"sfra")), scene.get((b"r", b"efra"))
        fps = scene.get((b"r", b"frs_sec")) / (scene.get((b"r", b"frs_sec_base")) or 1.0)
    except Exception as exc:     # BAT's errors for damaged, compressed or foreign files
        raise UserError(f"{path}: not a .blend file BAT can read ({exc})") from None
    finally:
        blendfile.close_all_cached()
    return first, last, fps


def pack(path, folder):
    """Copy the .blend at `path` and every file it uses into `folder` (files outside its own
    folder go to `folder/_outside_project`, as BAT places them) → the packed copy's path.
    Refused, naming them, when files it uses are missing: the farm would render without them."""
    _check_bat()
    source = pathlib.Path(path).absolute()
    with Packer(source, source.parent, str(folder)) as packer:
        packer.strategise()
        if packer.missing_files:
            missing = ", ".join(sorted(str(p) for p in packer.missing_files))
            raise UserError(f"{path} uses files that are not there: {missing}; find them "
                            f"(File › External Data › Find Missing Files) and save it again")
        packer.execute()
        return str(packer.output_path)

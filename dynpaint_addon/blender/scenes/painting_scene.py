"""Putting a painting into a scene: the plane, its material, lights, camera and render setup.

The plane's mesh is measured in image widths (x ∈ [−½, ½], y ∈ [−½·H/W, ½·H/W]) so its
object space *is* the painting frame of pipeline.md §0; the object's uniform scale sets its
size in the scene. A Copy Rotation constraint keeps it facing the scene camera (the same
choice as Blender's Image as Planes).
"""
import os
from collections.abc import Mapping
from contextlib import contextmanager
from dataclasses import replace

import bpy
from mathutils import Matrix, Vector

from ... import params
from ...core.frames import is_pattern
from ...core.input_rules import input_notes
from ...core.lights import default_sun as new_default_sun  # create_painting has a flag so named
from ...inputs import memory
from ...inputs.imageio import file_channels, file_header, image_data_from_blender
from ..material.sync import batch, update
from ..state.frames import frames_of, painting_size
from ..state.images import downsampled, load_image, prepare_channel_image, remove_images
from ..state.lights import add_light, linked_lights
from ..state.settings import frames_to_settings, params_to_settings

FACE_CAMERA = "Dynamic Painting: face camera"


def _corners(width_px, height_px):
    """A quad's corners one image width wide, the image's aspect high (§0)."""
    ar = height_px / width_px
    return [(-0.5, -0.5 * ar, 0), (0.5, -0.5 * ar, 0), (0.5, 0.5 * ar, 0), (-0.5, 0.5 * ar, 0)]


def plane_mesh(name, width_px, height_px):
    """A quad one image width wide with UVs spanning [0, 1]² (pixel centres line up)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(_corners(width_px, height_px), [], [(0, 1, 2, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    for loop, (u, v) in zip(uv.data, ((0, 0), (1, 0), (1, 1), (0, 1))):
        loop.uv = (u, v)
    mesh.update()
    return mesh


def reshape_plane(mesh, width_px, height_px):
    """plane_mesh's quad given another image size's aspect, in place (its UVs as they are)."""
    mesh.vertices.foreach_set("co", [v for corner in _corners(width_px, height_px)
                                     for v in corner])
    mesh.update()


@contextmanager
def unchanged_images_on_failure():
    """Images loaded inside the block are removed again if it raises: a failed Add leaves the
    file as it was."""
    known = set(bpy.data.images)
    try:
        yield
    except Exception:
        remove_images([i for i in bpy.data.images if i not in known])
        raise


class _ImagesRead(Mapping):
    """{channel: ImageData} of Blender images, each read on first use (input_notes reads
    the pixels of the shape and the masks only); of a moving slot, its first frame (§16)."""

    def __init__(self, loaded, frames=None):
        self.loaded, self.read, self.frames = loaded, {}, frames

    def __getitem__(self, channel):
        if channel not in self.read:
            img = self.loaded[channel]
            name = os.path.basename(bpy.path.abspath(img.filepath)) or img.name
            moving = self.frames is not None and self.frames.slots[channel].kind != "still"
            data = self.frames.image(channel, self.frames.start) if moving else \
                image_data_from_blender(img)
            self.read[channel] = replace(data, name=name)
        return self.read[channel]

    def __iter__(self):
        return iter(self.loaded)

    def __len__(self):
        return len(self.loaded)


def check_images(loaded, p, frames=None):
    """core.input_rules.input_notes on the painting's Blender images (a moving slot's first
    frame: `frames`, a PaintingFrames) → notes; raises ValueError (one line) for a shape image
    that cannot be what the settings `p` say."""
    return input_notes(_ImagesRead(loaded, frames), p)


def face_camera(obj, camera):
    """Keep `obj` facing `camera` (Copy Rotation), replacing an earlier such constraint."""
    con = obj.constraints.get(FACE_CAMERA) or obj.constraints.new("COPY_ROTATION")
    con.name = FACE_CAMERA
    con.target = camera


def check_add_memory(images, p, lights, max_size=0):
    """Refuse an Add that would not fit in memory (memory.py) before any image is loaded:
    Blender going out of memory takes the artist's unsaved work with it. max_size: Add's
    Max Size (the painting is worked at that size; each image is still read whole)."""
    headers = {}
    for channel, src in images.items():
        if isinstance(src, bpy.types.Image):
            headers[channel] = (*src.size, file_channels(src), 4 if src.is_float else 1, False)
        elif not is_pattern(os.path.basename(os.fspath(src))) and os.path.isfile(src):
            headers[channel] = file_header(src)
    if headers.get("shape") is None:
        return
    headers = {c: h for c, h in headers.items() if h is not None}
    w, h = headers["shape"][:2]
    width = round(w * max_size / max(w, h)) if max_size and max(w, h) > max_size else None
    memory.check(memory.add_bytes(headers, p, lights, width), f"adding a {w}×{h} painting",
                 "set a Max Size in Add's options (the painting is worked at that size), "
                 "scale its images down, or turn Shadows off before adding")


NO_CAMERA = "no camera in the scene"


def face_scene_camera(obj, scene, otherwise):
    """Keep `obj` facing the scene's camera → [], or, without a camera, [what to say]."""
    if scene.camera is None:
        return [f"{NO_CAMERA}: {otherwise}"]
    face_camera(obj, scene.camera)
    return []


def create_painting(context, images, p=None, lights=None, name="Dynamic Painting", size=1.0,
                    location=(0.0, 0.0, 0.0), rotation=None, default_sun=True, progress=None,
                    frames=None, max_size=0):
    """Create the plane, its material and (optionally) lights → (plane, material, messages).

    images: {channel: file path or bpy Image}; p: a params namespace (defaults if None);
    lights: core Lights in the painting frame to create; with none given, a Sun is added if
    the scene has no light (unless default_sun is False). size: the plane's width in scene
    units. frames: a recipe's frames table (§16: sequences and sprite sheets). max_size: the
    longest side, in pixels, a still image keeps (larger ones are downsampled copies, packed;
    0 keeps every image as it is).
    The scene is left as it was if anything fails.
    """
    with unchanged_images_on_failure():
        return _create_painting(context, images, p, lights, name, size, location, rotation,
                                default_sun, progress, frames or {}, max_size)


LARGE_PX = 4096 * 4096     # from here on, say what a painting costs


def _create_painting(context, images, p, lights, name, size, location, rotation, default_sun,
                     progress, frames, max_size):
    scene = context.scene
    p = p or params.defaults()
    messages = []
    check_add_memory(images, p, lights or [new_default_sun()], max_size)
    loaded = {}
    for channel, src in images.items():
        loaded[channel] = load_image(src, channel) if isinstance(src, (str, os.PathLike)) else src
        if isinstance(src, bpy.types.Image):
            prepare_channel_image(src, channel)
        loaded[channel], note = downsampled(loaded[channel], max_size)
        messages += [note] if note else []
    if "shape" not in loaded:
        raise ValueError("a painting needs a shape image (normal or height map)")
    if "dark" not in loaded and "bright" not in loaded:
        raise ValueError("a painting needs a dark or a bright image (one may serve both)")
    moving = frames_of(loaded, frames)
    if not moving.animated:
        moving = None
    messages += check_images(loaded, p, moving)
    w, h = loaded["shape"].size if moving is None else \
        moving.image("shape", moving.start).size         # a sheet's cell
    messages += moving.notes if moving is not None else []
    if w * h >= LARGE_PX:
        messages.append(f"large painting: {w}×{h} ({w * h / 1e6:.0f} Mpx); its numpy images "
                        f"take ≈{w * h * 16 / 2**30:.1f} GiB each, shadow bakes take a while "
                        "(preview quality is 4× faster)")
    created = []
    try:
        mesh = plane_mesh(name, w, h)
        created.append(mesh)
        obj = bpy.data.objects.new(name, mesh)
        created.append(obj)
        context.collection.objects.link(obj)
        obj.location = location
        obj.scale = (size, size, size)
        if rotation is not None:
            obj.rotation_euler = rotation
        mat = bpy.data.materials.new(name)
        created.append(mat)
        mesh.materials.append(mat)
        s = mat.dynamic_painting
        with batch():
            params_to_settings(p, s)
            frames_to_settings(frames, s)
            for channel, img in loaded.items():
                setattr(s, f"image_{channel}", img)
            s.plane = obj
        messages += face_scene_camera(obj, scene, "the painting faces the view; add a camera "
                                                  "and use 'Face Camera' to keep it facing it")
        context.view_layer.update()
        if lights:          # a recipe's lights light its painting, as the recipe shows it
            own = bpy.data.collections.new(f"{name} Lights")
            created.append(own)
            context.collection.children.link(own)
            for light in lights:
                created.append(add_light(scene, light, obj.matrix_world, own))
            others = [o for o in scene.objects if o.type == "LIGHT" and o.name not in
                      own.all_objects]
            s.light_collection = own
            if others:          # said only where it changes what lights the painting
                messages.append(f"lit by its recipe's lights only (collection '{own.name}', "
                                f"its Lights field), not by the scene's {len(others)} other "
                                f"light(s): empty the field to light it with every light")
        elif default_sun and not linked_lights(mat, scene):
            created.append(add_light(scene, new_default_sun(), obj.matrix_world, context.collection))
            messages.append("the scene had no light: added a Sun")
        context.view_layer.update()
        # force: a painting of an earlier file may have had this name (cached shapes)
        messages += update(mat, scene, progress=progress, force=True)
        s.is_painting = True       # from here on, handlers and setting changes keep it current
    except Exception:
        _remove(created)
        raise
    return obj, mat, messages


def _remove(blocks):
    for block in reversed(blocks):
        for coll in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.lights,
                     bpy.data.collections):
            if isinstance(block, bpy.types.ID) and block.name in coll and coll[block.name] == block:
                coll.remove(block)
                break


# -- exact-pixel rendering (parity tests, the `render` command) -------------------------------
def exact_camera(scene, plane):
    """An orthographic camera looking at the plane along its normal (down −Z for a plane
    lying flat) that frames it pixel for pixel (the plane faces it, so its pixels line up
    with the painting's)."""
    mat = plane.active_material
    w, h = painting_size(mat)
    cam_data = bpy.data.cameras.new("Dynamic Painting camera")
    cam_data.type = "ORTHO"
    cam = bpy.data.objects.new(cam_data.name, cam_data)
    scene.collection.objects.link(cam)
    size = plane.matrix_world.to_scale()[0]          # (a layer's: its parent's scale too)
    cam_data.ortho_scale = size * max(1.0, h / w)
    cam_data.clip_end = 100.0 * size
    facing = plane.matrix_world.to_3x3().normalized()
    cam.matrix_world = Matrix.Translation(plane.matrix_world.translation +
                                          facing @ Vector((0.0, 0.0, 5.0 * size))) @ \
        facing.to_4x4()
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    face_camera(plane, cam)
    return cam


# Measured (bpy 5.0.1): with 1 sample and the narrowest box filter (0.01 px, the minimum),
# Cycles shades every pixel at its centre + 1/2048 px in x and y, at any resolution. On a
# cliff of a height map (slope 30) that shift alone moves the gradient taps enough to cost
# 2e-3; the exact camera cancels it with a lens shift. EEVEE samples the centre exactly.
CYCLES_SAMPLE_OFFSET_PX = 1.0 / 2048.0


def exact_render_settings(scene, engine):
    """1 sample, no denoising, box filter of ~0: pixels are the shader's values (notes)."""
    r = scene.render
    cam = scene.camera
    if cam is not None and cam.data.type == "ORTHO":
        shift = CYCLES_SAMPLE_OFFSET_PX / max(r.resolution_x, r.resolution_y) \
            if engine == "cycles" else 0.0
        cam.data.shift_x = cam.data.shift_y = -shift
    r.engine = {"cycles": "CYCLES", "eevee": "BLENDER_EEVEE"}[engine]
    r.film_transparent = True
    r.use_persistent_data = False   # it would keep showing an old shadow image
    r.use_lock_interface = True
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.filter_width = 0.01
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.device = "CPU"
    scene.eevee.taa_render_samples = 1
    r.filter_size = 0.0          # EEVEE's film filter (1.5 px by default) spreads pixels
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    r.dither_intensity = 0.0
    # Anisotropic filtering (2× by default) decides EEVEE's texel values: under llvmpipe it
    # blurs even 1:1 lookups (a checkerboard comes out 0.33/0.54). Blender 5.0 reads it from
    # the user preferences, 5.3 from the scene (the preference is still there, unused by
    # renders: blender-notes.md). Only the command line and tests set it; the add-on never
    # touches preferences.
    if bpy.app.background:
        bpy.context.preferences.system.anisotropic_filter = "FILTER_0"
    if hasattr(r, "anisotropic_filter"):
        r.anisotropic_filter = "FILTER_0"


def output_settings(scene, path):
    ext = os.path.splitext(path)[1].lower()
    s = scene.render.image_settings
    s.media_type = "IMAGE"      # Blender 5.0: a scene set up for video offers only FFMPEG
    if ext == ".exr":
        s.file_format, s.color_depth, s.exr_codec = "OPEN_EXR", "32", "ZIP"
    elif ext == ".png":
        s.file_format, s.color_depth = "PNG", "8"
    else:
        raise ValueError(f"{path}: unsupported output format '{ext}' (use .png or .exr)")
    s.color_mode = "RGBA"
    scene.render.filepath = os.path.abspath(path)


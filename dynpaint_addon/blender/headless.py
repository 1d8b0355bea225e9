"""Render a recipe with EEVEE or Cycles in background Blender (the `render` command).

The scene is built exactly as the add-on's Add › Dynamic Painting builds it, then framed by an
orthographic camera pixel for pixel, so the result can be compared with the numpy core.
"""
import math
import os
import signal
import sys
import time

import bpy
import gpu

from . import register_once
from ..core.layers import render_scene
from ..core.frames import expand_pattern
from ..core.lights import default_sun
from ..inputs import memory
from ..inputs.imageio import quiet_native, write_render
from ..inputs.whole_files import abandon_writing, written_whole
from .bake.layers import group_layers, group_materials
from .handlers import paintings
from .scenes import turntable
from .scenes.grease_pencil.lit_copy import light_recipe_drawing
from .scenes.layered_build import add_layered
from .scenes.painting_scene import (NO_CAMERA, create_painting, exact_camera, exact_render_settings,
                    output_settings)
from .scenes.web_page import painting_page
from .state.frames import painting_size
from .state.lights import linked_lights, painting_frame_light


def build_recipe_scene(recipe, size=1.0, notes=None, drawing_width=None):
    """Empty scene → the recipe's painting, lights and an exact camera → (plane, material).
    A layered source (a layered recipe, or an .ora file or folder given as its path) is
    built as Add › Layered… builds it, a drawing's recipe as From Grease Pencil lights it,
    the camera framing its back layer (its layers drawn `drawing_width` pixels across, when
    given). notes: called with what Add says about the painting (a list of lines), if given."""
    bpy.ops.wm.read_homefile(use_empty=True)
    register_once()
    context = bpy.context
    if not isinstance(recipe, str) and recipe.drawing:      # a Grease Pencil drawing, lit
        parent, messages = light_recipe_drawing(context, recipe, width=drawing_width)
        mat = group_materials(parent)[0]
        plane = mat.dynamic_painting.plane
    elif isinstance(recipe, str) or recipe.layered:
        parent, messages = add_layered(context, recipe if isinstance(recipe, str) else
                                       recipe.path, size=size, lights="all")
        mat = group_materials(parent)[0]
        plane = mat.dynamic_painting.plane
    else:
        plane, mat, messages = create_painting(context, recipe.images, recipe.params,
                                               recipe.lights, name=recipe.name or
                                               "Dynamic Painting", size=size, default_sun=False,
                                               frames=recipe.frames)
    if notes is not None:        # the exact camera comes next, and the painting faces it
        notes([m for m in messages if not m.startswith(NO_CAMERA)])
    exact_camera(context.scene, plane)
    context.view_layer.update()
    return plane, mat


def render_recipe(recipe, engine, out, frame=None, notes=None, drawing_width=None):
    """Render the recipe's painting to `out` (.exr linear float or .png) → seconds rendering.
    notes, drawing_width (a drawing's recipe: its layers drawn that many pixels across): as
    for build_recipe_scene."""
    plane, mat = build_recipe_scene(recipe, notes=notes, drawing_width=drawing_width)
    scene = bpy.context.scene
    exact_render_settings(scene, engine)
    if frame is not None:
        scene.frame_set(frame)
    t = time.perf_counter()
    with written_whole(out) as part:        # whole or not at all (issue 60)
        output_settings(scene, part)
        bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t


SOFTWARE_RENDERERS = ("llvmpipe", "softpipe")      # Mesa's OpenGL drawn on the CPU


def software_renderer(name):
    """Whether OpenGL's renderer `name` draws on the CPU (SOFTWARE_RENDERERS): EEVEE and
    Blender's Grease Pencil renderer are slow there, and it filters textures in floats."""
    return any(s in name.lower() for s in SOFTWARE_RENDERERS)


def drawn_on(engine):
    """What drew this process's EEVEE renders, as OpenGL names it (a GPU's name, or a software
    renderer's such as llvmpipe: EEVEE is slow there), for a command's last line; '' for
    Cycles (the CPU) or where nothing was drawn yet."""
    if engine != "eevee":
        return ""
    try:
        return gpu.platform.renderer_get()
    except (SystemError, RuntimeError):   # (background Blender before its first drawing)
        return ""


def open_blend(path):
    """Open a .blend file here, the add-on registered first (its load handler remakes the
    images numpy made, which a file keeps no pixels of). ValueError names what is wrong."""
    if not os.path.isfile(path) or not path.lower().endswith(".blend"):
        raise ValueError(f"{path}: not a .blend file")
    register_once()
    try:
        with quiet_native():
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path))
    except RuntimeError as exc:     # a damaged file, or another file named .blend
        raise ValueError(f"{path}: Blender cannot open it "
                         f"({str(exc).removeprefix('Error: ').strip()})") from None


def build_grease_pencil_scene(path, object_name, width=None, frame=None):
    """A .blend file's Grease Pencil drawing lit as *From Grease Pencil* lights it (its
    animation where it has one), every other object hidden from renders, an exact camera on
    its back layer → (parent, back layer's material). ValueError names what is
    wrong (no such file or object, not a drawing)."""
    open_blend(path)
    context = bpy.context
    obj = bpy.data.objects.get(object_name)
    drawings = [o.name for o in bpy.data.objects if o.type == "GREASEPENCIL"]
    if obj is None or obj.type != "GREASEPENCIL":
        raise ValueError(f"{object_name}: no Grease Pencil object of that name in {path} "
                         f"(its drawings: {', '.join(drawings) or 'none'})")
    scene = context.scene
    if frame is not None:
        scene.frame_set(frame)
    for other in context.view_layer.objects:
        other.select_set(False)
    obj.hide_set(False)
    context.view_layer.objects.active = obj
    kwargs = {"resolution": width} if width else {}
    with context.temp_override(object=obj, active_object=obj):
        try:
            done = bpy.ops.dynpaint.add_grease_pencil(**kwargs)
        except RuntimeError as exc:      # (background Blender raises an operator's error report)
            raise ValueError(str(exc).removeprefix("Error: ").strip()) from None
        if done != {"FINISHED"}:
            raise ValueError(f"{object_name}: could not be lit (see the messages above)")
    parent = context.object
    mats = group_materials(parent)
    shown = {parent, *(m.dynamic_painting.plane for m in mats),
             *linked_lights(mats[0], scene)}
    for other in scene.objects:          # the lit drawing alone (its lights stay)
        if other not in shown:
            other.hide_render = True
    exact_camera(scene, mats[0].dynamic_painting.plane)
    if frame is not None:
        scene.frame_set(frame)
    context.view_layer.update()
    return parent, mats[0]


def render_grease_pencil(path, object_name, engine, out, frame=None, width=None):
    """Render a .blend's Grease Pencil drawing, lit (`render FILE.blend --grease-pencil`):
    with the numpy core (its layers' images and the scene's lights at `frame`, §15) or
    Cycles / EEVEE framed on its back layer → seconds rendering."""
    parent, mat = build_grease_pencil_scene(path, object_name, width, frame)
    scene = bpy.context.scene
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    t = time.perf_counter()
    if engine == "numpy":
        mats = group_materials(parent)
        back = mats[0].dynamic_painting.plane
        lights = [painting_frame_light(o, back.matrix_world) for o in linked_lights(mat, scene)]
        write_render(out, render_scene(group_layers(mats), lights).rgba)
    else:
        exact_render_settings(scene, engine)
        with written_whole(out) as part:
            output_settings(scene, part)
            bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t


def grease_pencil_page(source, object_name=None, width=None, **page):
    """A Grease Pencil drawing lit as *From Grease Pencil* lights it, each layer drawn
    `width` pixels across (default: its default) — a .blend file's (`source` its path, with
    the drawing's `object_name`) or a drawing's recipe (`source` the Recipe) — as the web
    page's data (`export-web`): its layers' frames over the scene's range, its lights and
    their animation → (data, warnings). page: painting_page's title, credits, steps,
    max_size."""
    if object_name is None:
        mat = build_recipe_scene(source, drawing_width=width)[1]
    else:
        mat = build_grease_pencil_scene(source, object_name, width)[1]
    return painting_page(mat, bpy.context.scene, **page)


def fit_camera(scene, plane, width, height):
    """Render at width × height with the whole plane in view (letterboxed if the aspects
    differ); the exact camera's pixel-for-pixel framing is kept when the size is the image's."""
    w, h = painting_size(plane.active_material)
    cam = scene.camera.data
    size = plane.scale[0]
    pw, ph = size, size * h / w
    if width >= height:     # ortho_scale spans the longer side of the render
        cam.ortho_scale = max(pw, ph * width / height)
    else:
        cam.ortho_scale = max(ph, pw * height / width)
    scene.render.resolution_x, scene.render.resolution_y = width, height


ANTIALIAS_SAMPLES = 16     # a video whose pixels are not the painting's: enough to hide jaggies


def video_render_settings(scene, engine, samples=None, exact=False):
    """Opaque frames for a video. `exact` (framed pixel for pixel): one sample at each pixel's
    centre is the exact image, the settings of exact_render_settings (the parity tests'); else
    `samples` (ANTIALIAS_SAMPLES by default) with a normal 1.5 px pixel filter. → samples."""
    exact_render_settings(scene, engine)
    scene.render.film_transparent = False
    if exact and samples in (None, 1):
        return 1
    samples = samples or ANTIALIAS_SAMPLES
    scene.cycles.samples = samples
    scene.cycles.filter_width = 1.5
    scene.cycles.pixel_filter_type = "BLACKMAN_HARRIS"
    scene.eevee.taa_render_samples = samples
    scene.render.filter_size = 1.5
    if scene.camera is not None:
        scene.camera.data.shift_x = scene.camera.data.shift_y = 0.0
    return samples


def turntable_light(lights, mat, scene, name=None):
    """The light a turntable orbits: the named one, else the first Sun of `lights` (the
    recipe's), else its first light → (object or None, elevation, azimuth, radius) from
    where the recipe puts it."""
    by_name = {o.name: o for o in linked_lights(mat, scene)}
    chosen = None
    if name is not None:
        if name not in by_name:
            raise ValueError(f"--light {name}: no such light (the recipe's lights: "
                             f"{', '.join(by_name) or 'none'})")
        chosen = next((lt for lt in lights if lt.name == name), None)
        obj = by_name[name]
    else:
        chosen = next((lt for lt in lights if lt.kind == "sun"), None) or \
            (lights[0] if lights else None)
        obj = by_name.get(chosen.name or ("Sun" if chosen.kind == "sun" else "Point")) \
            if chosen is not None else None
    if chosen is None:
        return obj, math.radians(35), math.radians(135), 1.0
    x, y, z = chosen.vector
    r = math.sqrt(x * x + y * y + z * z)
    return obj, math.asin(max(-1.0, min(1.0, z / r))), math.atan2(y, x), \
        (r if chosen.kind == "point" else 1.0)


VIDEO_MIN_PX = 16      # H.264 (the command line's --size asks for as much)


def video_size(width, height, notes=None):
    """The size a video of a width × height painting is rendered at: its own where H.264
    encodes it (even, at least VIDEO_MIN_PX each way), else the nearest larger that is, the
    painting letterboxed in it and said through `notes` (as for build_recipe_scene)."""
    w, h = (max(VIDEO_MIN_PX, n + n % 2) for n in (width, height))
    if (w, h) != (width, height) and notes is not None:
        notes([f"the video is {w}×{h}: H.264 needs even sizes of at least {VIDEO_MIN_PX} px, "
               f"and the painting is {width}×{height} (letterboxed, antialiased)"])
    return w, h


def render_turntable(recipe, out, frames=48, engine="cycles", size=None, elevation=None,
                     light_name=None, clockwise=False, samples=None, fps=24, progress=print,
                     notes=None, grease_pencil=None, only=None):
    """Render a light turntable of the recipe's painting to a video file → (seconds, samples
    per pixel): build_turntable_scene's scene, rendered. Blender's own render log is kept off
    the terminal: `progress` gets a line a frame. only: (first, last) frames of the orbit,
    `out` then a frame-numbered pattern of PNG files (a farm's chunk: each frame rendered
    and written whole, as a whole turntable renders it).
    """
    scene, samples = build_turntable_scene(recipe, frames, engine, size, elevation, light_name,
                                           clockwise, samples, fps, notes, grease_pencil)
    return _render_frames(scene, out, only, progress), samples


def build_turntable_scene(recipe, frames=48, engine="cycles", size=None, elevation=None,
                          light_name=None, clockwise=False, samples=None, fps=24, notes=None,
                          grease_pencil=None):
    """Empty scene → a light turntable of the recipe's painting, ready to render (or to save:
    a .blend as Add Light Turntable leaves it) → (scene, samples per pixel).

    The recipe's first Sun (or the named light) orbits the painting once over `frames` frames,
    starting where the recipe puts it; every frame bakes its shadows at final quality. At the
    shape image's size (the default) the video frames the painting pixel for pixel and one
    sample is the exact image; `samples` (default ANTIALIAS_SAMPLES at other sizes) adds
    antialiasing. notes: as for build_recipe_scene. grease_pencil: a drawing's name, `recipe`
    then the .blend file holding it (build_grease_pencil_scene: lit by the file's lights; an
    animated drawing plays while the light turns).
    """
    if grease_pencil is not None:
        _, mat = build_grease_pencil_scene(recipe, grease_pencil,
                                           width=size[0] if size else None)
        plane = mat.dynamic_painting.plane
    else:
        plane, mat = build_recipe_scene(recipe, notes=notes)
    scene = bpy.context.scene
    image_size = painting_size(mat)
    w, h = size or video_size(*image_size, notes)
    memory.check_video(w, h)            # (the painting is built: its memory is taken)
    fit_camera(scene, plane, w, h)
    samples = video_render_settings(scene, engine, samples, exact=(w, h) == image_size)
    # a layered file (.ora, a folder of layers) names no light: the default sun lights it;
    # a drawing's are its file's
    lights = [painting_frame_light(o, plane.matrix_world) for o in linked_lights(mat, scene)] \
        if grease_pencil is not None else \
        [default_sun()] if isinstance(recipe, str) else recipe.lights
    light, elev, azimuth, radius = turntable_light(lights, mat, scene, light_name)
    if elevation is not None:
        elev = math.radians(elevation)
    kind = "SUN" if light is None or light.data.type == "SUN" else "POINT"
    turntable.add_light_turntable(bpy.context, mat, light, kind, 1, frames, elev, radius, azimuth,
                          clockwise)
    scene.render.fps = fps
    return scene, samples


def render_animation(path, out, only=None, as_frames=False, progress=print):
    """Render a .blend file's animation as it was saved — its scene, camera, frame range and
    render settings — each frame baking its paintings' shadows (the add-on's frame handler, as
    in Blender) → (seconds, (first, last) frames rendered, paintings in the scene). `out`: a
    video, or `as_frames` a frame-numbered pattern of PNG files, of frames `only` (first,
    last: a farm's chunk) or all.
    ValueError names what is wrong (no file, no camera, frames outside the scene's range)."""
    open_blend(path)
    scene = bpy.context.scene
    if scene.camera is None:
        raise ValueError(f"{path}: its scene '{scene.name}' has no camera to render from")
    first, last = only or (scene.frame_start, scene.frame_end)
    if not scene.frame_start <= first <= last <= scene.frame_end:
        raise ValueError(f"--only {first}-{last}: the scene '{scene.name}' has frames "
                         f"{scene.frame_start}-{scene.frame_end}")
    return _render_frames(scene, out, (first, last) if as_frames else None, progress), \
        (first, last), len(paintings(scene))


def _render_frames(scene, out, only, progress):
    """The scene's animation into the video `out`, or frames only = (first, last) into the
    PNG pattern `out`; a line to `progress` a frame; Ctrl-C ends it cleanly → seconds."""
    start = time.perf_counter()
    count = scene.frame_end - scene.frame_start + 1

    def report(scene, *_):
        done = scene.frame_current - scene.frame_start + 1
        progress(f"frame {done}/{count}  {time.perf_counter() - start:6.1f} s")

    bpy.app.handlers.render_post.append(report)
    previous = signal.signal(signal.SIGINT, _stop_rendering)
    try:
        if only is not None:
            _render_frame_files(scene, out, *only)
            return time.perf_counter() - start
        # the video appears whole when the last frame is in (issue 60): an interrupted or a
        # second render never leaves a cut or interleaved file at `out`
        with written_whole(out) as part, quiet_native(1):   # "Video append frame N" lines
            turntable.video_output(scene, part)
            bpy.ops.render.render(animation=True)
    finally:
        signal.signal(signal.SIGINT, previous)
        bpy.app.handlers.render_post.remove(report)
    return time.perf_counter() - start


def _render_frame_files(scene, pattern, first, last):
    """Frames first … last of the scene's animation, each a 16-bit PNG at `pattern` with its
    number (core/frames.expand_pattern), written whole: a farm's task that dies leaves no
    cut frame for the video to take."""
    turntable.frames_output(scene)
    for f in range(first, last + 1):
        scene.frame_set(f)             # (frame_change_post bakes this frame's shadows)
        with written_whole(expand_pattern(os.path.abspath(pattern), f)) as part, \
                quiet_native(1):                  # (Blender's "Saved: …" lines)
            scene.render.filepath = part
            bpy.ops.render.render(write_still=True)


def _stop_rendering(*_):
    """Ctrl-C during a turntable: Blender's render loop swallows the KeyboardInterrupt its
    handlers raise, so the process ends here, at the frame being finished, the video being
    written removed (`--out` stays as it was) — said, exit status 130 as the shell's."""
    abandon_writing()
    print("\ninterrupted: the video at --out was left as it was", file=sys.stderr, flush=True)
    os._exit(130)

"""Light turntables: a light orbiting a painting in a seamless loop, and video output.

The orbit lives in the painting frame (§0): an Empty "pivot" is parented to the painting's
plane and spins about the plane's normal; the light is parented to the pivot at the chosen
elevation, radius and start angle. The pivot's Z rotation is keyed at the first frame and one
frame past the last with linear interpolation and a Cycles modifier, so the loop is seamless
(frame_end + 1 would repeat frame_start) and keeps going beyond the range. The plane may
face the camera (or be moved) and the orbit follows it. The shader's drivers and the per-frame
bake read the light's world transform, so nothing else needs to know about the pivot.
"""
import math
import os

import bpy
from mathutils import Vector

from ..material.sync import update
from ..state.animation import fcurves
from ..state.lights import aim, linked_lights, painting_frame_light

PIVOT_NAME = "Turntable"


def turn_first_sun(context, mat, frame_start, frame_end):
    """The painting's first Sun turned once over the frames, from where it is now (a light
    turntable at its own elevation) → report lines (none without a Sun)."""
    suns = [o for o in linked_lights(mat, context.scene) if o.data.type == "SUN"]
    if not suns:
        return []
    x, y, z = painting_frame_light(suns[0], mat.dynamic_painting.plane.matrix_world).vector
    add_light_turntable(context, mat, suns[0], "SUN", frame_start, frame_end,
                        math.asin(max(-1, min(1, z))), 1.0, math.atan2(y, x))
    return [f"{suns[0].name} turns once over frames {frame_start}–{frame_end}"]


def orbit_position(elevation, azimuth, radius=1.0):
    """Painting-frame position of a light at `elevation` above the plane and `azimuth` from +x
    (radians; counter-clockwise seen from the viewer) → (x, y, z)."""
    ce = math.cos(elevation)
    return (radius * ce * math.cos(azimuth), radius * ce * math.sin(azimuth),
            radius * math.sin(elevation))


def _clear_transform_animation(obj):
    """Drop the light's own location/rotation keys (the orbit replaces them) → count dropped."""
    ad = obj.animation_data
    if ad is None or ad.action is None:
        return 0
    curves = fcurves(obj)
    dropped = [fc for fc in curves if fc.data_path.startswith(("location", "rotation"))]
    for fc in dropped:
        curves.remove(fc)
    return len(dropped)


def add_light_turntable(context, mat, light=None, kind="SUN", frame_start=1, frame_end=96,
                        elevation=math.radians(35), radius=1.0, start_angle=math.radians(135),
                        clockwise=False):
    """Make `light` (a light object, or a new Sun/Point if None) orbit the painting of `mat`
    → (pivot, light, messages). Lengths in image widths; angles in radians."""
    if frame_end < frame_start:
        raise ValueError(f"the last frame ({frame_end}) comes before the first ({frame_start})")
    if not -math.pi / 2 <= elevation <= math.pi / 2:
        raise ValueError("elevation must be between −90° and 90°")
    if radius <= 0:
        raise ValueError("radius must be positive")
    plane = mat.dynamic_painting.plane
    if plane is None:
        raise ValueError(f"{mat.name}: the painting has no plane")
    scene = context.scene
    messages = []
    collection = context.collection
    pivot = bpy.data.objects.new(PIVOT_NAME, None)
    pivot.empty_display_type = "CIRCLE"
    pivot.empty_display_size = radius * math.cos(elevation) if elevation < 1.5 else 0.1
    collection.objects.link(pivot)
    pivot.parent = plane                       # the painting frame: follows the plane
    pivot.rotation_mode = "XYZ"
    if light is None:
        data = bpy.data.lights.new("Turntable " + kind.title(), kind)
        if kind == "SUN":
            data.angle = 0.0
        else:
            data.energy = 1000.0 * 0.5          # k = ½ (a point light's Power / 1000 W, §5)
        light = bpy.data.objects.new(data.name, data)
        # in the painting's own lights where it has them, or it would light nothing
        (mat.dynamic_painting.light_collection or collection).objects.link(light)
        messages.append(f"added a {kind.title()} light '{light.name}'")
    elif light.type != "LIGHT":
        raise ValueError(f"{light.name} is not a light")
    if _clear_transform_animation(light):
        messages.append(f"{light.name}: its own location/rotation keys were replaced by the orbit")
    light.parent = pivot
    light.matrix_parent_inverse.identity()
    pos = Vector(orbit_position(elevation, start_angle, radius))
    light.location = pos
    aim(light, pos.normalized().to_track_quat("Z", "Y"))    # +Z toward the light, in its mode
    sign = -1.0 if clockwise else 1.0
    for frame, angle in ((frame_start, 0.0), (frame_end + 1, sign * 2 * math.pi)):
        pivot.rotation_euler.z = angle
        pivot.keyframe_insert("rotation_euler", index=2, frame=frame)
    fc = next(f for f in fcurves(pivot)
              if f.data_path == "rotation_euler" and f.array_index == 2)
    for key in fc.keyframe_points:
        key.interpolation = "LINEAR"
    fc.modifiers.new("CYCLES")
    scene.frame_start, scene.frame_end = frame_start, frame_end
    if light not in linked_lights(mat, scene):
        messages.append(f"{light.name} is not in the painting's light collection: it will not "
                        "light the painting")
    scene.frame_set(scene.frame_current)
    update(mat, scene)    # a new light joins the tree's drivers; a moved or new one bakes
    return pivot, light, messages


def frames_output(scene):
    """Write stills as 16-bit RGB PNG files at exactly scene.render.filepath (a turntable's
    frames, for a farm: ffmpeg joins them)."""
    s = scene.render.image_settings
    s.media_type = "IMAGE"
    s.file_format, s.color_mode, s.color_depth = "PNG", "RGB", "16"
    scene.render.use_file_extension = False


def video_output(scene, path):
    """Write animations as an H.264 MP4 at `path` (exactly that name)."""
    s = scene.render.image_settings
    s.media_type = "VIDEO"      # Blender 5.0: FFMPEG is only offered for the video media type
    s.file_format = "FFMPEG"
    ff = scene.render.ffmpeg
    ff.format, ff.codec = "MPEG4", "H264"
    ff.constant_rate_factor = "HIGH"
    ff.gopsize = max(1, min(ff.gopsize, scene.frame_end - scene.frame_start + 1))
    scene.render.use_file_extension = False
    scene.render.filepath = path if path.startswith("//") else os.path.abspath(path)

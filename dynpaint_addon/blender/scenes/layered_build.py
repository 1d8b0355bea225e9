"""Build a layered painting in the scene (pipeline.md §15, issue 30): one plane per layer
under one parent Empty, each at its depth with today's material; what Add › Layered…, the
headless render and the turntable of a layered recipe share."""
import math
import os

import bpy
from mathutils import Matrix, Vector

from ...core.inputs import about
from ...inputs.layered_files import DEFAULT_SHADE, DEFAULT_SPACING, is_layered_file, load_scene
from ...inputs.recipe import DEFAULT_SUN_NOTE, hidden_notes, load_recipe
from ..bake.layers import LAYERED, bake_group_live, forget_group, group_materials
from ..material.sync import batch, update
from ..state.images import packed_image, remove_images
from ..state.lights import add_light, linked_lights
from ..state.settings import channel_images
from .painting_scene import FACE_CAMERA, create_painting, face_scene_camera
from .turntable import turn_first_sun


def scene_layers(path, spacing, shade):
    """The layers of `path` → ([(name, depth, offset, scale, thickness, images, p)], lights,
    notes): images as file paths (a recipe) or bpy images packed from the file's layers."""
    if is_layered_file(path):
        layers, lights, notes = load_scene(path, spacing, shade)
        return [(lay.name, lay.depth, lay.offset, lay.scale, lay.thickness,
                 {c: packed_image(f"{lay.name} {c}", img, c) for c, img in lay.images.items()},
                 lay.p) for lay in layers], lights, notes
    recipe = load_recipe(path)
    if not recipe.layered:
        raise ValueError(f"{path}: a one-painting recipe: use From Images or Recipe…")
    return [(lay.name, lay.depth, lay.offset, lay.scale, lay.thickness, lay.recipe.images,
             lay.recipe.params) for lay in recipe.layers if lay.visible], recipe.lights, \
        [n for n in recipe.notes if n != DEFAULT_SUN_NOTE] + hidden_notes(recipe)


def add_layered(context, path, spacing=DEFAULT_SPACING, shade=DEFAULT_SHADE, size=1.0,
                parallax=True, rotation=None, progress=None, lights=True):
    """Build a layered painting → (parent Empty, messages). The parent faces the camera at
    the 3D cursor; each layer's plane is its child at (offset, depth) × size, scaled by its
    scale (and by (D − z)/D about the camera's axis with `parallax` and a perspective
    camera; rotation: the parent's when there is no camera to face); the source's lights are
    added in the back layer's frame when the scene has none (always with `lights` 'all')."""
    layers, source_lights, messages = scene_layers(path, spacing, shade)
    stem = os.path.splitext(os.path.basename(path.rstrip(os.sep)))[0]
    return build_layered(context, stem, layers, source_lights, messages, size, parallax,
                         rotation, progress, lights)


def build_layered(context, stem, layers, lights, messages, size=1.0, parallax=True,
                  rotation=None, progress=None, add_lights=True, frames=None, place=None,
                  bake="now", name=None):
    """add_layered's build, of `layers` as scene_layers gives them → (parent, messages);
    frames: {layer name: its [frames] table} for layers that move (§16: sheets, sequences);
    place: the parent's world matrix (else at the 3D cursor, facing the camera); bake: the
    group's shadows baked 'now', or 'live' (beside the UI, as for a dragged light: a draft
    now, the final in a worker thread, bake_group_live); name: the parent's (default: stem),
    given before the bake (a final bake due finds its group by it)."""
    scene = context.scene
    parent = bpy.data.objects.new(name or stem, None)
    parent.empty_display_type = "PLAIN_AXES"
    parent.empty_display_size = 0.25 * size
    parent[LAYERED] = 1
    context.collection.objects.link(parent)
    if place is not None:        # placed before the bake: its lights are where they will be
        parent.matrix_world = place
    else:
        parent.location = scene.cursor.location
        if rotation is not None:
            parent.rotation_euler = rotation
        messages += face_scene_camera(parent, scene, "the layers face the view (give the "
                                                     "parent a Copy Rotation constraint to a "
                                                     "camera to keep them facing it)")
    context.view_layer.update()
    camera = _camera_in(parent, scene.camera) if parallax else None
    planes, shadows = [], []
    try:
        for i, (name, depth, offset, scale, thickness, images, p) in enumerate(layers):
            shadows.append(p.shadows.enabled)
            p.shadows.enabled = False         # the group bakes once, when all are placed
            plane, mat, notes = create_painting(context, images, p, None, f"{stem} {name}",
                                                size, default_sun=False,
                                                frames=(frames or {}).get(name))
            planes.append(plane)
            messages += about(name, [n for n in notes if "no camera" not in n])
            if FACE_CAMERA in plane.constraints:      # the parent faces the camera instead
                plane.constraints.remove(plane.constraints[FACE_CAMERA])
            plane.parent = parent
            plane.matrix_parent_inverse = Matrix.Identity(4)
            plane.rotation_euler = (0.0, 0.0, 0.0)
            plane.location, plane.scale = layer_place(depth, offset, scale, size, camera)
            with batch():
                mat.dynamic_painting.layer_thickness = thickness or 0.0
            if progress is not None:
                progress((i + 1) / (len(layers) + 1))
        context.view_layer.update()
        if add_lights == "all" or (add_lights and
                                   not linked_lights(planes[0].active_material, scene)):
            back = planes[0].matrix_world
            for light in lights:
                add_light(scene, light, back, context.collection)
            named = ", ".join(light.name or light.kind for light in lights)
            messages.append(f"added its lights: {named}" if add_lights == "all"
                            else f"the scene had no light: added its lights ({named})")
            context.view_layer.update()
        with batch():        # shadows on, all at once: a partial group would bake
            for plane, on in zip(planes, shadows):
                plane.active_material.dynamic_painting.shadows.enabled = on
        if bake == "live":    # beside the UI: the group's draft now, its final in a worker
            bake_group_live(parent)
        for plane in planes:  # the first bakes the whole group, the others find it baked
            messages += update(plane.active_material, scene,
                               bake="none" if bake == "live" else bake)
    except Exception:
        remove_objects(planes + [parent])
        raise
    return parent, messages


def layer_place(depth, offset, scale, size, camera=None):
    """A layer's plane under its parent → (location, scale): at its depth and offset (§15,
    image widths of a `size` wide scene), and — with `camera`, where it lies in the parent's
    space — moved and scaled toward it so the composition holds from there (parallax)."""
    x, y, z = offset[0] * size, offset[1] * size, depth * size
    k = 1.0
    if camera is not None and camera[2] > z:       # keep the composition (§15)
        k = (camera[2] - z) / camera[2]
        x, y = camera[0] + (x - camera[0]) * k, camera[1] + (y - camera[1]) * k
    return (x, y, z), (size * scale * k,) * 3


def remove_objects(objects, images=False):
    """Objects gone with their meshes and materials (a layered build that failed, a lit copy
    made anew); `images`: the materials' paintings' images too (images the build made:
    remove_images)."""
    for obj in objects:
        mesh = obj.data
        mats = list(mesh.materials) if mesh is not None else []
        if images:
            remove_images({img for mat in mats
                           for img in channel_images(mat.dynamic_painting).values()})
        if obj.get(LAYERED):
            forget_group(obj.name)
        bpy.data.objects.remove(obj)
        if mesh is not None:
            bpy.data.meshes.remove(mesh)
        for mat in mats:
            bpy.data.materials.remove(mat)


def _camera_in(parent, camera):
    """A perspective camera's position in the parent's frame (None: none, or orthographic)."""
    if camera is None or camera.data.type != "PERSP":
        return None
    return tuple(parent.matrix_world.inverted() @ Vector(camera.matrix_world.translation))




def add_camera(context, distance=2.2):
    """A perspective camera `distance` in front of the 3D cursor, looking at it along +Y
    (Blender's front view), as the scene's camera → the camera."""
    scene = context.scene
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    context.collection.objects.link(cam)
    cam.location = Vector(scene.cursor.location) + Vector((0.0, -distance, 0.0))
    cam.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.camera = cam
    context.view_layer.update()
    return cam


def animate_scene(context, parent, truck=0.3):
    """A layered scene's showpiece over the scene's frame range: the camera trucks across it
    (its layers move at their depths: parallax) and the key light turns once (a light
    turntable of its first Sun) → report lines."""
    scene = context.scene
    lines = []
    fs, fe = scene.frame_start, scene.frame_end
    cam = scene.camera
    if cam is not None and cam.data.type == "PERSP":
        base = Vector(cam.location)
        right = cam.matrix_world.to_3x3() @ Vector((1.0, 0.0, 0.0))
        for frame, side in ((fs, -1.0), (fe, 1.0)):
            cam.location = base + right * (side * truck)
            cam.keyframe_insert("location", frame=frame)
        lines.append(f"the camera trucks across the layers over frames {fs}–{fe}")
    mats = group_materials(parent)
    if mats:
        lines += turn_first_sun(context, mats[0], fs, fe)
    scene.frame_set(fs)
    return lines

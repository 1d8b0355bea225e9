"""The material flavour of the graph's backend-specific nodes (graph.py), with drivers.

Parameters and lights reach the material through drivers that Blender evaluates natively
(no Python auto-run, blender-notes.md): SINGLE_PROP drivers read the material's own
Dynamic Painting settings, TRANSFORMS drivers read each light's world transform, and a sun's
direction is the −Z axis of its world rotation written as a "simple expression" over the
quaternion. A Vector Transform node then brings world vectors into the painting frame (the
plane's object space, whose unit is one image width, §0).
"""
import bpy

from ... import params
from .build import link_or_set

SETTINGS = "dynamic_painting"     # Material.dynamic_painting (blender/properties.py)

# +Z axis of a rotation quaternion (w, x, y, z). A sun shines along its local −Z, so +Z is
# the direction toward the light, L of §0.
SUN_AXIS_EXPRESSIONS = ("2*(x*z+w*y)", "2*(y*z-w*x)", "1-2*(x*x+y*y)")
POINT_POWER_UNIT = 1000.0   # a 1000 W point light (Blender's default) has strength k = 1
IMAGE_SIZE_NODES = ("Image width", "Image height")     # the Values of dp.size, by name


def _driver(socket, index=-1):
    fc = socket.driver_add("default_value", index) if index >= 0 else socket.driver_add("default_value")
    return fc.driver


def drive_property(socket, id_type, id_block, data_path, index=-1, expression=None):
    """socket.default_value[index] ← id_block.data_path (optionally through `expression` of v)."""
    d = _driver(socket, index)
    d.type = "SCRIPTED" if expression else "AVERAGE"
    var = d.variables.new()
    var.name = "v"
    var.type = "SINGLE_PROP"
    var.targets[0].id_type = id_type
    var.targets[0].id = id_block
    var.targets[0].data_path = data_path
    if expression:
        d.expression = expression
    return d


def drive_sun_direction(combine, light):
    """CombineXYZ inputs ← the sun's direction toward the light in world space."""
    for axis, expression in enumerate(SUN_AXIS_EXPRESSIONS):
        d = _driver(combine.inputs[axis])
        d.type = "SCRIPTED"
        for name, channel in zip("wxyz", ("ROT_W", "ROT_X", "ROT_Y", "ROT_Z")):
            var = d.variables.new()
            var.name = name
            var.type = "TRANSFORMS"
            t = var.targets[0]
            t.id = light
            t.transform_type = channel
            t.transform_space = "WORLD_SPACE"
            t.rotation_mode = "QUATERNION"   # whatever the light's own rotation mode
        d.expression = expression


def drive_location(combine, obj):
    for axis, channel in enumerate(("LOC_X", "LOC_Y", "LOC_Z")):
        d = _driver(combine.inputs[axis])
        d.type = "SUM"
        var = d.variables.new()
        var.type = "TRANSFORMS"
        var.targets[0].id = obj
        var.targets[0].transform_type = channel
        var.targets[0].transform_space = "WORLD_SPACE"


def set_image_size(tree, size):
    """A built tree's image size (ShaderBackend.size) set to (width, height) → whether the tree
    has it (one built before it did not)."""
    values = [tree.nodes.get(name) for name in IMAGE_SIZE_NODES]
    if None in values:
        return False
    for value, number in zip(values, size):
        if value.outputs[0].default_value != number:        # (a write updates the material)
            value.outputs[0].default_value = float(number)
    return True


def light_strength_expression(kind):
    """k_i of §5 from the Blender light's power: a sun's strength as is, a point light's watts
    over 1000 (its default), so both default lights give k = 1."""
    return "v" if kind == "sun" else f"v/{POINT_POWER_UNIT:g}"


class ShaderBackend:
    """Builds the pseudo nodes into a material's node tree."""
    prefix = ""

    def __init__(self, material, images, lights, size=(1, 1)):
        self.material = material
        self.images = images      # channel → bpy Image
        self.lights = lights      # light objects, in the order of Features.lights
        self.image_size = size    # the shape image's (width, height)

    def uv(self, tree, node, inputs):
        tc = tree.nodes.new("ShaderNodeTexCoord")
        return [tc], {0: tc.outputs["UV"]}

    def size(self, tree, node, inputs):
        """The image's width and height as two Values named IMAGE_SIZE_NODES (set_image_size
        sets them when the painting is framed anew)."""
        values = []
        for name, number in zip(IMAGE_SIZE_NODES, self.image_size):
            value = tree.nodes.new("ShaderNodeValue")
            value.name = value.label = name
            value.outputs[0].default_value = float(number)
            values.append(value)
        return values, {"width": values[0].outputs[0], "height": values[1].outputs[0]}

    def sample(self, tree, node, inputs):
        channel = node.props["channel"]
        image = self.images.get(channel)
        if image is None:
            raise KeyError(f"no image for the '{channel}' channel")
        tex = tree.nodes.new("ShaderNodeTexImage")
        tex.image = image
        tex.interpolation = node.props.get("interpolation", "Linear")
        tex.extension = node.props["extension"]
        if "uv" in inputs:   # unlinked, Image Texture reads the default UV map (the pixel's own)
            tree.links.new(inputs["uv"], tex.inputs["Vector"])
        return [tex], {"color": tex.outputs["Color"], "alpha": tex.outputs["Alpha"]}

    def param(self, tree, node, inputs):
        value = tree.nodes.new("ShaderNodeValue")
        value.outputs[0].default_value = 0.0
        setting = params.BY_PATH[node.props["path"]].setting(node.props.get("index"))
        drive_property(value.outputs[0], "MATERIAL", self.material, f"{SETTINGS}.{setting}")
        return [value], {0: value.outputs[0]}

    def light(self, tree, node, inputs):
        obj = self.lights[node.props["index"]]
        kind = node.props["kind"]
        where = tree.nodes.new("ShaderNodeCombineXYZ")
        where.label = f"{obj.name} {'direction' if kind == 'sun' else 'position'} (world)"
        if kind == "sun":
            drive_sun_direction(where, obj)
        else:
            drive_location(where, obj)
        to_painting = tree.nodes.new("ShaderNodeVectorTransform")
        to_painting.vector_type = "VECTOR" if kind == "sun" else "POINT"
        to_painting.convert_from, to_painting.convert_to = "WORLD", "OBJECT"
        tree.links.new(where.outputs[0], to_painting.inputs["Vector"])
        colour = tree.nodes.new("ShaderNodeCombineXYZ")
        colour.label = f"{obj.name} colour"
        for i in range(3):
            drive_property(colour.inputs[i], "LIGHT", obj.data, f"color[{i}]")
        weight = tree.nodes.new("ShaderNodeVectorMath")
        weight.operation = "SCALE"
        weight.label = f"{obj.name} k·c"
        tree.links.new(colour.outputs[0], weight.inputs[0])
        drive_property(weight.inputs["Scale"], "LIGHT", obj.data, "energy",
                       expression=light_strength_expression(kind))
        return ([where, colour, weight, to_painting],
                {"vector": to_painting.outputs[0], "weight": weight.outputs[0]})

    def output(self, tree, node, inputs):
        rgb, alpha = inputs["rgb"], inputs["alpha"]
        emission = tree.nodes.new("ShaderNodeEmission")
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        made = [emission]
        if isinstance(alpha, bpy.types.NodeSocket):
            # premultiplied (rgb, α) → Emission(rgb) + Transparent of colour 1 − α: coverage α
            # and colour rgb exactly, also where α = 0 and rgb is not (a highlight on clear
            # glass with nothing behind it adds light, §11), with no division by α
            clear_rgb = tree.nodes.new("ShaderNodeCombineXYZ")
            see_through = tree.nodes.new("ShaderNodeMath")
            see_through.operation = "SUBTRACT"
            see_through.inputs[0].default_value = 1.0
            tree.links.new(alpha, see_through.inputs[1])
            for i in range(3):
                tree.links.new(see_through.outputs[0], clear_rgb.inputs[i])
            link_or_set(tree, rgb, emission.inputs["Color"])
            clear = tree.nodes.new("ShaderNodeBsdfTransparent")
            tree.links.new(clear_rgb.outputs[0], clear.inputs["Color"])
            add = tree.nodes.new("ShaderNodeAddShader")
            tree.links.new(clear.outputs[0], add.inputs[0])
            tree.links.new(emission.outputs[0], add.inputs[1])
            tree.links.new(add.outputs[0], out.inputs["Surface"])
            made = [see_through, clear_rgb, emission, clear, add]
        else:
            link_or_set(tree, rgb, emission.inputs["Color"])
            tree.links.new(emission.outputs[0], out.inputs["Surface"])
        return made + [out], {}


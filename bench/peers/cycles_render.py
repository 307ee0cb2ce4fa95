# Renders a scene exported by tessera-bench (bench/converge/scene_export.cpp, JSON) with
# Blender Cycles, once per sample count, in one Blender process so start-up is paid once.
#
#   blender -b --factory-startup --python bench/peers/cycles_render.py -- \
#       --scene SCENE.json --out DIR --spp 1,2,4,...,256 --reference-spp 4096 --threads 2
#
# Writes DIR/cycles_<spp>.exr (linear RGBA, 32-bit float) and prints, per render,
#   TESSERA_PEER spp=<n> wall=<s> sync=<s> exr=<path>
# and, with --reference-spp, one line more with reference=1 for DIR/cycles_reference_<n>.exr,
# rendered with another seed: with the same seed, the n-spp render would be the first n
# samples of the reference and its error would look smaller than it is.
# which tessera-bench parses. wall is the time around bpy.ops.render.render (Blender's
# start, the scene build in Python and the EXR write are outside it); sync is the part of
# it Cycles reports as synchronisation (scene export to Cycles, BVH build, shader and kernel
# setup; "cycles.<layer>.synchronization_time" in the EXR header, 10 ms resolution).
# tessera-bench times Cycles as wall - sync, since Tessera does not time scene preparation.
# Persistent data would keep the BVH between renders, but Blender 3.4 in background mode
# then ignores the new sample count (every render comes out at the first one's), so each
# render syncs afresh.
#
# How Tessera's model maps onto Cycles (and where it only approximately does) is in
# bench/peers/README.md.
import argparse
import json
import math
import os
import re
import sys
import time

import bmesh
import bpy
from mathutils import Matrix, Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cycles_render.py")
    p.add_argument("--scene", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--spp", required=True, help="comma-separated sample counts")
    p.add_argument("--reference-spp", type=int, default=0,
                   help="also render the reference at this spp, with another seed")
    p.add_argument("--threads", type=int, default=0, help="0: all")
    p.add_argument("--sphere-segments", type=int, default=128)
    p.add_argument("--disk-segments", type=int, default=128)
    return p.parse_args(argv)


def warn(message):
    print("cycles_render.py: warning: " + message, flush=True)


def clear_scene():
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials,
                       bpy.data.cameras, bpy.data.lights, bpy.data.worlds):
        for block in list(collection):
            collection.remove(block)


def configure(scene, data, args):
    r = data["render"]
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    scene.render.threads_mode = "FIXED" if args.threads > 0 else "AUTO"
    if args.threads > 0:
        scene.render.threads = args.threads
    scene.render.resolution_x = r["width"]
    scene.render.resolution_y = r["height"]
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.use_motion_blur = False
    scene.render.film_transparent = False
    scene.render.use_persistent_data = False  # see the top of this file
    scene.render.dither_intensity = 0.0

    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    # Cycles skips lights whose estimated contribution is below this; Tessera never does.
    c.light_sampling_threshold = 0.0
    c.seed = 0
    c.use_animated_seed = False
    # Tessera's max_depth counts path segments and its last vertex takes no light sample:
    # max_depth M gives at most M - 1 scattering vertices. Cycles' bounces count the
    # vertices after the first (0 bounces = direct light only), so bounces = M - 2.
    bounces = max(r["max_depth"] - 2, 0)
    c.max_bounces = bounces
    c.diffuse_bounces = bounces
    c.glossy_bounces = bounces
    c.transmission_bounces = bounces
    c.transparent_max_bounces = bounces
    c.volume_bounces = 0
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    # Caustics stay: Tessera neither blurs glossy bounces nor drops caustic paths.
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.use_fast_gi = False
    # Tessera jitters each sample uniformly inside its pixel: a 1-pixel box filter.
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.use_auto_tile = True
    c.tile_size = 2048

    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    scene.display_settings.display_device = "sRGB"
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    return bounces


def add_camera(scene, cam):
    position = Vector(cam["position"])
    forward = (Vector(cam["look_at"]) - position).normalized()
    right = forward.cross(Vector(cam["up"])).normalized()
    up = right.cross(forward)
    data = bpy.data.cameras.new("camera")
    # Tessera's fov is vertical whatever the aspect ratio.
    data.sensor_fit = "VERTICAL"
    data.sensor_height = 24.0
    data.lens = 0.5 * data.sensor_height / math.tan(math.radians(cam["fov_degrees"]) * 0.5)
    data.clip_start = 1e-4
    data.clip_end = 1e7
    data.dof.use_dof = False
    obj = bpy.data.objects.new("camera", data)
    # Blender cameras look down -Z with +Y up.
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = right[i], up[i], -forward[i], position[i]
    obj.matrix_world = m
    scene.collection.objects.link(obj)
    scene.camera = obj


def add_world(scene, data, scene_path):
    # What escaping rays see. Tessera's y is up (Blender's z), so the world shader reads
    # the direction itself (Texture Coordinate "Generated" in a world shader) rather than
    # letting Blender orient the sky.
    env = data.get("environment") or dict(type="constant", **data["background"])
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    background.inputs["Strength"].default_value = env["intensity"]
    kind = env["type"]
    if kind == "constant":
        background.inputs["Color"].default_value = (*env["color"], 1.0)
    elif kind in ("gradient", "image"):
        direction = nodes.new("ShaderNodeSeparateXYZ")
        links.new(nodes.new("ShaderNodeTexCoord").outputs["Generated"], direction.inputs[0])
        if kind == "gradient":
            # RayON's sky: t = (y + 1) / 2 of the unit direction, white below to
            # (0.5, 0.7, 1.0) above, times the intensity (the colour is not used).
            t = nodes.new("ShaderNodeMath")
            t.operation = "MULTIPLY_ADD"
            t.inputs[1].default_value = 0.5
            t.inputs[2].default_value = 0.5
            links.new(direction.outputs["Y"], t.inputs[0])
            mix = nodes.new("ShaderNodeMixRGB")
            mix.inputs["Color1"].default_value = (1.0, 1.0, 1.0, 1.0)
            mix.inputs["Color2"].default_value = (0.5, 0.7, 1.0, 1.0)
            links.new(t.outputs[0], mix.inputs["Fac"])
            links.new(mix.outputs[0], background.inputs["Color"])
        else:
            # Tessera's image: rows from +y down, column u = (atan2(-z, x) + pi) / 2 pi of
            # the direction turned by the rotation about +y. Blender's equirectangular map
            # of (a, b, c) has u = (pi - atan2(b, a)) / 2 pi and the top row at c = 1, so
            # (a, b, c) = (x', z', y') of the turned direction (x', y', z').
            r = math.radians(env["rotation_degrees"])
            c, sn = math.cos(r), math.sin(r)

            def mixed(a, b, wa, wb):  # wa * a + wb * b
                scaled = nodes.new("ShaderNodeMath")
                scaled.operation = "MULTIPLY"
                scaled.inputs[1].default_value = wb
                links.new(b, scaled.inputs[0])
                out = nodes.new("ShaderNodeMath")
                out.operation = "MULTIPLY_ADD"
                out.inputs[1].default_value = wa
                links.new(a, out.inputs[0])
                links.new(scaled.outputs[0], out.inputs[2])
                return out.outputs[0]

            vector = nodes.new("ShaderNodeCombineXYZ")
            x, z = direction.outputs["X"], direction.outputs["Z"]
            links.new(mixed(x, z, c, -sn), vector.inputs["X"])
            links.new(mixed(x, z, sn, c), vector.inputs["Y"])
            links.new(direction.outputs["Y"], vector.inputs["Z"])
            texture = nodes.new("ShaderNodeTexEnvironment")
            texture.image = bpy.data.images.load(os.path.join(os.path.dirname(scene_path),
                                                              env["image"]))
            texture.image.colorspace_settings.name = "Non-Color"  # linear, as exported
            texture.interpolation = "Closest"  # Tessera reads the pixel a direction falls in
            texture.projection = "EQUIRECTANGULAR"
            links.new(vector.outputs[0], texture.inputs["Vector"])
            tint = nodes.new("ShaderNodeMixRGB")
            tint.blend_type = "MULTIPLY"
            tint.inputs["Fac"].default_value = 1.0
            tint.inputs["Color2"].default_value = (*env["color"], 1.0)
            links.new(texture.outputs["Color"], tint.inputs["Color1"])
            links.new(tint.outputs[0], background.inputs["Color"])
    else:
        warn(f"environment {kind!r} not drawn: black")
        background.inputs["Strength"].default_value = 0.0
    scene.world = world


def undo_spot_cosine(lamp, forward):
    # Cycles 3.4's spot attenuation (its kernel's spot_attenuation) is the cosine to the axis
    # times the smoothstep; Tessera's spot has the smoothstep alone. The light's node tree divides its strength by that cosine: a lamp's
    # Incoming is the direction from the lamp to the point it lights, so the cosine is its
    # dot product with the axis (measured: a spot on a white floor, means +10.8% apart
    # before, see bench/peers/README.md).
    lamp.use_nodes = True
    tree = lamp.node_tree
    emission = next(n for n in tree.nodes if n.type == "EMISSION")
    incoming = tree.nodes.new("ShaderNodeNewGeometry").outputs["Incoming"]
    cosine = tree.nodes.new("ShaderNodeVectorMath")
    cosine.operation = "DOT_PRODUCT"
    cosine.inputs[1].default_value = forward
    tree.links.new(incoming, cosine.inputs[0])
    inverse = math_node(tree.nodes, tree.links, "DIVIDE", 1.0,
                        math_node(tree.nodes, tree.links, "MAXIMUM", cosine.outputs["Value"], 1e-4))
    tree.links.new(inverse, emission.inputs["Strength"])


def add_lights(scene, data):
    # Blender's lights take a power P in watts and a colour in [0, 1]: a point or spot light
    # of radiant intensity I is P = 4 pi I (measured: radiance I / pi on a white Lambertian
    # square 1 m below it), a sun's strength is its irradiance. Radius 0: Tessera's are
    # deltas, or a sun's cone of the given angular radius (Blender takes the diameter).
    for i, light in enumerate(data.get("lights", [])):
        kind = light["type"]
        colour = light["color"]
        peak = max(colour)
        if peak <= 0.0:
            continue
        if kind == "directional":
            lamp = bpy.data.lights.new(f"light{i}", "SUN")
            lamp.energy = light["irradiance"] * peak
            lamp.angle = math.radians(2.0 * light["angular_radius_degrees"])
            forward = Vector(light["direction"]).normalized()  # where the light travels
            position = Vector((0.0, 0.0, 0.0))
        else:
            lamp = bpy.data.lights.new(f"light{i}", "SPOT" if kind == "spot" else "POINT")
            lamp.energy = 4.0 * math.pi * light["intensity"] * peak
            lamp.shadow_soft_size = 0.0
            forward = Vector(light["direction"]).normalized()
            position = Vector(light["position"])
            if kind == "spot":
                outer = math.radians(light["cone_angle_degrees"])
                inner = math.radians(max(0.0, light["cone_angle_degrees"] -
                                         light["cone_falloff_degrees"]))
                lamp.spot_size = 2.0 * outer
                # Cycles' smoothstep runs over (1 - cos outer) * blend of the cosine.
                lamp.spot_blend = (math.cos(inner) - math.cos(outer)) / (1.0 - math.cos(outer))
                undo_spot_cosine(lamp, forward)
        lamp.color = [c / peak for c in colour]
        obj = bpy.data.objects.new(f"light{i}", lamp)
        # Blender lights shine down their local -Z.
        obj.matrix_world = Matrix.Translation(position) @ \
            forward.to_track_quat("-Z", "Y").to_matrix().to_4x4()
        scene.collection.objects.link(obj)


def emission_node(nodes, emission):
    # Cycles' Emission shader at strength s and colour c gives radiance s * c, which is
    # what a camera ray returns from it: the pixel value Tessera writes for an emitter seen
    # directly (its emission). Colour in [0, 1], the scale in the strength.
    strength = max(emission)
    node = nodes.new("ShaderNodeEmission")
    node.inputs["Color"].default_value = (*[e / strength for e in emission], 1.0)
    node.inputs["Strength"].default_value = strength
    return node


# Dots drawn as node-graph tests (two nodes each); a pattern with more is left plain.
MAX_PEER_DOTS = 256


def direction_from_centre(nodes, links, frame):
    # The unit direction from a shape's centre to the shaded point, in the frame Tessera
    # measures patterns and a sphere's uv in: `frame` is the centre in world space and the
    # rows of the inverse linear map into the shape's own space (None: the world's axes).
    centre, inverse = frame
    offset = nodes.new("ShaderNodeVectorMath")
    offset.operation = "SUBTRACT"
    links.new(nodes.new("ShaderNodeNewGeometry").outputs["Position"], offset.inputs[0])
    offset.inputs[1].default_value = centre
    direction = offset.outputs["Vector"]
    if inverse is not None:
        combine = nodes.new("ShaderNodeCombineXYZ")
        for axis, row in zip("XYZ", inverse):
            component = nodes.new("ShaderNodeVectorMath")
            component.operation = "DOT_PRODUCT"
            links.new(direction, component.inputs[0])
            component.inputs[1].default_value = row
            links.new(component.outputs["Value"], combine.inputs[axis])
        direction = combine.outputs["Vector"]
    unit = nodes.new("ShaderNodeVectorMath")
    unit.operation = "NORMALIZE"
    links.new(direction, unit.inputs[0])
    return unit.outputs["Vector"]


def operation_node(nodes, links, node_type, operation, a, b=None):
    # A Math or Vector Math node of `operation` on its first two inputs, each a socket (linked)
    # or a constant (a number, or an (x, y, z) tuple).
    node = nodes.new(node_type)
    node.operation = operation
    for index, value in ((0, a), (1, b)):
        if value is None:
            continue
        if isinstance(value, (int, float, tuple)):
            node.inputs[index].default_value = value
        else:
            links.new(value, node.inputs[index])
    return node


def math_node(nodes, links, operation, a, b=None):
    return operation_node(nodes, links, "ShaderNodeMath", operation, a, b).outputs[0]


def vector_math_node(nodes, links, operation, a, b=None, scale=None):
    # Vector Math has two outputs (Vector, Value): the node is returned. `scale` for SCALE.
    node = operation_node(nodes, links, "ShaderNodeVectorMath", operation, a, b)
    if scale is not None:
        links.new(scale, node.inputs["Scale"])
    return node


def sphere_uv(nodes, links, frame):
    # Tessera's sphere uv (geometry/sphere.hpp): u = (atan2(-z, x) + pi) / 2 pi, v = acos(-y) / pi
    # of the outward direction.
    xyz = nodes.new("ShaderNodeSeparateXYZ")
    links.new(direction_from_centre(nodes, links, frame), xyz.inputs[0])
    x, y, z = xyz.outputs["X"], xyz.outputs["Y"], xyz.outputs["Z"]
    phi = math_node(nodes, links, "ARCTAN2", math_node(nodes, links, "MULTIPLY", z, -1.0), x)
    u = math_node(nodes, links, "DIVIDE", math_node(nodes, links, "ADD", phi, math.pi),
                  2.0 * math.pi)
    theta = math_node(nodes, links, "ARCCOSINE", math_node(nodes, links, "MULTIPLY", y, -1.0))
    v = math_node(nodes, links, "DIVIDE", theta, math.pi)
    uv = nodes.new("ShaderNodeCombineXYZ")
    links.new(u, uv.inputs["X"])
    links.new(v, uv.inputs["Y"])
    return uv.outputs["Vector"]


def texture_colour(nodes, links, texture, uv, scene_dir):
    # Tessera's texture at `uv` (render/texture.hpp). Its checker is colour_a where
    # floor(u s) + floor(v s) is even; Cycles' Checker gives Color1 where it is odd. Images:
    # the decoded linear pixels Tessera read, bilinear (Tessera's trilinear mipmaps agree where
    # a texel is no smaller than a pixel's footprint), wrapped the same way.
    if texture["type"] == "checker":
        node = nodes.new("ShaderNodeTexChecker")
        node.inputs["Scale"].default_value = texture["scale"]
        node.inputs["Color1"].default_value = (*texture["color_b"], 1.0)
        node.inputs["Color2"].default_value = (*texture["color_a"], 1.0)
        links.new(uv, node.inputs["Vector"])
        return node.outputs["Color"]
    scaled = nodes.new("ShaderNodeVectorMath")
    scaled.operation = "SCALE"
    links.new(uv, scaled.inputs[0])
    scaled.inputs["Scale"].default_value = texture["scale"]
    node = nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.load(os.path.join(scene_dir, texture["image"]))
    node.image.colorspace_settings.name = "Non-Color"  # linear, as exported
    node.interpolation = "Closest" if texture["filter"] == "nearest" else "Linear"
    extension = {"repeat": "REPEAT", "clamp": "EXTEND", "mirror": "MIRROR"}[texture["wrap"]]
    try:
        node.extension = extension
    except TypeError:  # Blender 3.4 has no MIRROR
        warn(f"texture {texture['name']}: wrap {texture['wrap']} drawn as repeat by this Blender")
        node.extension = "REPEAT"
    links.new(scaled.outputs["Vector"], node.inputs["Vector"])
    return node.outputs["Color"]


def fibonacci_dots(nodes, links, m, colour, frame):
    # RayON's fibonacci_dots as Tessera draws it (render/pattern.hpp): the pattern's colour
    # where the unit direction from the shape's centre lies within the dot radius of one of
    # dot_count points of a spherical Fibonacci spiral, `colour` elsewhere. `frame`: the
    # centre in world space and the rows of the inverse linear map into the shape's own space
    # (None: the world's axes, as for baked spheres and every other shape).
    unit = direction_from_centre(nodes, links, frame)
    count = m["pattern_dot_count"]
    inside = None
    for i in range(count):
        k = i + 0.5
        z = 1.0 - 2.0 * k / count
        r = math.sqrt(max(0.0, 1.0 - z * z))
        longitude = 2.39996323 * k
        cosine = nodes.new("ShaderNodeVectorMath")
        cosine.operation = "DOT_PRODUCT"
        links.new(unit, cosine.inputs[0])
        cosine.inputs[1].default_value = (math.cos(longitude) * r, math.sin(longitude) * r, z)
        test = math_node(nodes, links, "GREATER_THAN", cosine.outputs["Value"],
                         m["pattern_cos_dot_radius"])
        inside = test if inside is None else math_node(nodes, links, "MAXIMUM", inside, test)
    mix = nodes.new("ShaderNodeMixRGB")
    links.new(inside, mix.inputs["Fac"])
    mix.inputs["Color1"].default_value = colour
    mix.inputs["Color2"].default_value = (*m["pattern_color"], 1.0)
    return mix.outputs["Color"]


def conductor_fresnel(nodes, links, eta, k, albedo):
    # The unpolarised Fresnel reflectance of a conductor of index eta + i k (per RGB channel)
    # at cos = N . I, as Tessera's conductor_fresnel computes it, times the albedo.
    geometry = nodes.new("ShaderNodeNewGeometry")
    cos = nodes.new("ShaderNodeVectorMath")
    cos.operation = "DOT_PRODUCT"
    links.new(geometry.outputs["Normal"], cos.inputs[0])
    links.new(geometry.outputs["Incoming"], cos.inputs[1])
    c = math_node(nodes, links, "MINIMUM",
                  math_node(nodes, links, "MAXIMUM", cos.outputs["Value"], 0.0), 1.0)
    cos2 = math_node(nodes, links, "MULTIPLY", c, c)
    sin2 = math_node(nodes, links, "SUBTRACT", 1.0, cos2)
    channels = []
    for e, kk in zip(eta, k):
        # t0 = e^2 - k^2 - sin^2; a2b2 = sqrt(t0^2 + 4 e^2 k^2); a = sqrt((a2b2 + t0) / 2)
        t0 = math_node(nodes, links, "SUBTRACT", e * e - kk * kk, sin2)
        a2b2 = math_node(nodes, links, "SQRT", math_node(
            nodes, links, "ADD", math_node(nodes, links, "MULTIPLY", t0, t0), 4.0 * e * e * kk * kk))
        a = math_node(nodes, links, "SQRT", math_node(
            nodes, links, "MULTIPLY", math_node(nodes, links, "ADD", a2b2, t0), 0.5))
        t1 = math_node(nodes, links, "ADD", a2b2, cos2)
        t2 = math_node(nodes, links, "MULTIPLY", math_node(nodes, links, "MULTIPLY", a, c), 2.0)
        rs = math_node(nodes, links, "DIVIDE", math_node(nodes, links, "SUBTRACT", t1, t2),
                       math_node(nodes, links, "ADD", t1, t2))
        t3 = math_node(nodes, links, "ADD", math_node(nodes, links, "MULTIPLY", cos2, a2b2),
                       math_node(nodes, links, "MULTIPLY", sin2, sin2))
        t4 = math_node(nodes, links, "MULTIPLY", t2, sin2)
        rp = math_node(nodes, links, "MULTIPLY", rs, math_node(
            nodes, links, "DIVIDE", math_node(nodes, links, "SUBTRACT", t3, t4),
            math_node(nodes, links, "ADD", t3, t4)))
        channels.append(math_node(nodes, links, "MULTIPLY",
                                  math_node(nodes, links, "ADD", rs, rp), 0.5))
    rgb = nodes.new("ShaderNodeCombineRGB")
    for name, channel in zip("RGB", channels):
        links.new(channel, rgb.inputs[name])
    tint = nodes.new("ShaderNodeMixRGB")
    tint.blend_type = "MULTIPLY"
    tint.inputs["Fac"].default_value = 1.0
    links.new(rgb.outputs["Image"], tint.inputs["Color1"])
    tint.inputs["Color2"].default_value = albedo
    return tint.outputs["Color"]


def make_material(m, context=None):
    # `context`: None for the materials list, or (pattern frame, uv source, textures by name,
    # the scene's folder) for one shape's copy of a dotted or textured material, uv source
    # "sphere", "uvmap" (the mesh's UV layer) or None (a shape whose uv the peer lacks).
    pattern_frame = context[0] if context else None
    mat = bpy.data.materials.new(m["name"] or "material")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    albedo = (*m["albedo"], 1.0)
    bsdf = m["bsdf"]
    emitting = max(m["emission"]) > 0.0
    # Not drawn: said, so a difference between the two images has a named cause.
    rough_textured = bool(m.get("roughness_texture")) and context is not None
    if rough_textured and (context[1] is None or m["roughness_mapping"] == "none"):
        warn(f"material {m['name']}: roughness_texture {m['roughness_texture']!r} not drawn on "
             "this shape (the plain roughness instead)")
        rough_textured = False
    textured = bool(m.get("albedo_texture")) and context is not None
    if textured and (context[1] is None or bsdf not in ("diffuse", "coated", "conductor") or
                     m["complex_fresnel"]):
        warn(f"material {m['name']}: albedo_texture {m['albedo_texture']!r} not drawn on this "
             "shape (the plain albedo instead)")
        textured = False
    # RayON's checkerboard and stripes draw the plain albedo in RayON and Tessera alike.
    # The materials list is built without a frame; each shape of a dotted material gets a
    # copy with its own (shape_material).
    dots = m.get("pattern") == "fibonacci_dots" and pattern_frame is not None
    if dots and (bsdf not in ("diffuse", "coated", "conductor") or m["complex_fresnel"] or
                 m["pattern_dot_count"] > MAX_PEER_DOTS):
        warn(f"material {m['name']}: fibonacci_dots not drawn here (the plain albedo instead)")
        dots = False

    def shape_uv():
        return (sphere_uv(nodes, links, pattern_frame) if context[1] == "sphere" else
                nodes.new("ShaderNodeUVMap").outputs["UV"])

    def set_roughness(node):
        # A roughness texture as Tessera reads it (Material::set_roughness): the mean of the
        # texel's RGB, clamped to [0, 1], mapped to GGX alpha (r / 2 or r^2); Blender's
        # roughness is sqrt(alpha) (anisotropy keeps sqrt(alpha_x alpha_y) = alpha).
        if not rough_textured:
            return
        colour = texture_colour(nodes, links, context[2][m["roughness_texture"]], shape_uv(),
                                context[3])
        rgb = nodes.new("ShaderNodeSeparateRGB")
        links.new(colour, rgb.inputs[0])
        total = math_node(nodes, links, "ADD", math_node(nodes, links, "ADD", rgb.outputs["R"],
                                                         rgb.outputs["G"]), rgb.outputs["B"])
        mean = math_node(nodes, links, "DIVIDE", total, 3.0)
        r = math_node(nodes, links, "MINIMUM", math_node(nodes, links, "MAXIMUM", mean, 0.0), 1.0)
        alpha = (math_node(nodes, links, "MULTIPLY", r, 0.5) if m["roughness_mapping"] == "half"
                 else math_node(nodes, links, "MULTIPLY", r, r))
        node.distribution = "GGX"
        links.new(math_node(nodes, links, "SQRT", alpha), node.inputs["Roughness"])

    def set_albedo(socket, colour=albedo):
        # The albedo: a texture's where there is one (it wins over a pattern, as in Tessera),
        # RayON's dots over it on a shape with a pattern frame, else the plain colour.
        if textured:
            links.new(texture_colour(nodes, links, context[2][m["albedo_texture"]], shape_uv(),
                                     context[3]), socket)
        elif dots:
            links.new(fibonacci_dots(nodes, links, m, colour, pattern_frame), socket)
        else:
            socket.default_value = colour

    surface = None
    if bsdf == "emitter":
        surface = emission_node(nodes, m["emission"]) if emitting else None
        emitting = False
    elif bsdf == "diffuse":
        surface = nodes.new("ShaderNodeBsdfDiffuse")
        set_albedo(surface.inputs["Color"])
        surface.inputs["Roughness"].default_value = 0.0
    elif bsdf == "conductor":
        # Tessera: GGX (single scattering) with alpha_x, alpha_y; Fresnel = albedo, or
        # albedo times the exact conductor term of eta + i k. Cycles: Metallic BSDF with the
        # physical-conductor Fresnel, or Glossy BSDF (colour = albedo, no Fresnel); Blender
        # roughness is sqrt(alpha).
        alpha_x, alpha_y = m["alpha_x"], m["alpha_y"]
        smooth = max(alpha_x, alpha_y) < 1e-3
        if m["complex_fresnel"] and not hasattr(bpy.types, "ShaderNodeBsdfMetallic"):
            # Blender before 4.0 has no conductor Fresnel: the exact term of eta + i k per
            # channel in the node graph, at the angle between the view and the shading normal
            # (Tessera takes it at each microfacet's, so rough metals differ a little at
            # grazing angles), times the albedo, as a Glossy BSDF's colour.
            warn(f"material {m['name']}: this Blender has no Metallic BSDF; the conductor "
                 "Fresnel at the shading normal's angle, not the microfacet's")
            surface = nodes.new("ShaderNodeBsdfGlossy")
            links.new(conductor_fresnel(nodes, links, m["eta"], m["k"], albedo),
                      surface.inputs["Color"])
        elif m["complex_fresnel"]:
            surface = nodes.new("ShaderNodeBsdfMetallic")
            surface.fresnel_type = "PHYSICAL_CONDUCTOR"
            surface.inputs["IOR"].default_value = m["eta"]
            surface.inputs["Extinction"].default_value = m["k"]
            if min(m["albedo"]) < 1.0:
                warn(f"material {m['name']}: albedo tint of a measured metal not exported")
        else:
            surface = nodes.new("ShaderNodeBsdfGlossy")
            set_albedo(surface.inputs["Color"])
        surface.distribution = "GGX"
        surface.inputs["Roughness"].default_value = 0.0 if smooth else math.sqrt(
            math.sqrt(alpha_x * alpha_y))
        if abs(alpha_x - alpha_y) > 1e-6:
            ratio = min(alpha_x, alpha_y) / max(alpha_x, alpha_y)
            if "Anisotropy" in surface.inputs:
                # Blender 4's Glossy BSDF stretches as Tessera does (Disney's): alpha / aspect
                # along the tangent, alpha * aspect across, aspect = sqrt(1 - 0.9 anisotropy);
                # a wider lobe across the tangent is the same lobe turned a quarter. (Not
                # run here: Debian's Blender is 3.4.)
                surface.inputs["Anisotropy"].default_value = (1.0 - ratio) / 0.9
                if alpha_y > alpha_x:
                    surface.inputs["Rotation"].default_value = 0.25
            else:
                # Before Blender 4.0 the Glossy BSDF is isotropic; anisotropy is a node of
                # its own, with the same colour and roughness, whose positive anisotropy A
                # narrows the lobe along the tangent: alpha (1 - A) along, alpha / (1 - A)
                # across. So A = 1 - sqrt(ratio), turned a quarter when Tessera's wider
                # alpha is the tangent's (measured on RayON's 05_material_laboratory, whose
                # three brushed metals were +11% apart with Disney's mapping and the other
                # turn, +0.28% with this).
                glossy = surface
                surface = nodes.new("ShaderNodeBsdfAnisotropic")
                surface.distribution = "GGX"
                for name in ("Color", "Roughness"):
                    source = glossy.inputs[name]
                    if source.is_linked:  # a Fresnel, texture or pattern graph
                        links.new(source.links[0].from_socket, surface.inputs[name])
                    else:
                        surface.inputs[name].default_value = source.default_value
                nodes.remove(glossy)
                surface.inputs["Anisotropy"].default_value = 1.0 - math.sqrt(ratio)
                if alpha_x > alpha_y:
                    surface.inputs["Rotation"].default_value = 0.25
            # Tessera's tangent (anisotropy_tangent in render/bsdf.hpp) is cross(+y, n) in
            # world space, the latitude circles of a sphere whose pole is +y; Cycles' default
            # is the object's radial tangent, so it is given Tessera's.
            # Where the normal is +-y (a cap, a sphere's pole) the cross product vanishes and
            # Tessera takes +x; so does this graph: cross + x * (|cross|^2 < 1e-8).
            normal = nodes.new("ShaderNodeNewGeometry").outputs["Normal"]
            cross = vector_math_node(nodes, links, "CROSS_PRODUCT", (0.0, 1.0, 0.0),
                                     normal).outputs["Vector"]
            length2 = vector_math_node(nodes, links, "DOT_PRODUCT", cross, cross).outputs["Value"]
            degenerate = math_node(nodes, links, "LESS_THAN", length2, 1e-8)
            fallback = vector_math_node(nodes, links, "SCALE", (1.0, 0.0, 0.0), scale=degenerate)
            chosen = vector_math_node(nodes, links, "ADD", cross, fallback.outputs["Vector"])
            unit = vector_math_node(nodes, links, "NORMALIZE", chosen.outputs["Vector"])
            links.new(unit.outputs["Vector"], surface.inputs["Tangent"])
        set_roughness(surface)
    elif bsdf == "dielectric":
        # Tessera: exact Fresnel, smooth or GGX (Walter et al. 2007) with alpha = roughness^2;
        # the albedo tints light entering the glass (Cycles tints every transmission).
        surface = nodes.new("ShaderNodeBsdfGlass")
        alpha = m["alpha_x"]
        surface.distribution = "GGX" if alpha >= 1e-3 else "SHARP"
        surface.inputs["Roughness"].default_value = math.sqrt(alpha) if alpha >= 1e-3 else 0.0
        surface.inputs["Color"].default_value = albedo
        surface.inputs["IOR"].default_value = m["ior"]
        set_roughness(surface)
    elif bsdf == "coated":
        # Tessera: an exact-Fresnel choice between a white GGX lobe and the diffuse base.
        # Cycles: the same mix by its Fresnel node (which uses the shading normal's angle).
        warn(f"material {m['name']}: clear coat approximated (Fresnel mix of glossy and diffuse)")
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        set_albedo(diffuse.inputs["Color"])
        glossy = nodes.new("ShaderNodeBsdfGlossy")
        alpha = m["alpha_x"]
        glossy.distribution = "GGX" if alpha >= 1e-3 else "SHARP"
        glossy.inputs["Roughness"].default_value = math.sqrt(alpha) if alpha >= 1e-3 else 0.0
        set_roughness(glossy)
        fresnel = nodes.new("ShaderNodeFresnel")
        fresnel.inputs["IOR"].default_value = m["ior"]
        surface = nodes.new("ShaderNodeMixShader")
        links.new(fresnel.outputs["Fac"], surface.inputs["Fac"])
        links.new(diffuse.outputs["BSDF"], surface.inputs[1])
        links.new(glossy.outputs["BSDF"], surface.inputs[2])
    elif bsdf == "thin_dielectric":
        # Cycles has no thin-film interference. The nearest it draws: a mirror and a
        # transparent lobe mixed by the film's reflectance averaged over its phase (the
        # incoherent sum of the two faces, 2F / (1 + F), which Tessera's Airy sum averages
        # to), with air on both sides. Cycles' Fresnel node inverts the IOR on back faces (a
        # ray leaving a solid), which inside a bubble gave total internal reflection a film
        # does not have (rayon 11_soap_bubbles: its floor 20% darker than Tessera's): the
        # node is given 1/ior there, so it sees ior from both sides.
        warn(f"material {m['name']}: thin film approximated (mirror and transparent mixed by "
             "the film's phase-averaged reflectance; no interference colours)")
        glossy = nodes.new("ShaderNodeBsdfGlossy")
        glossy.distribution = "SHARP"
        transparent = nodes.new("ShaderNodeBsdfTransparent")
        fresnel = nodes.new("ShaderNodeFresnel")
        backfacing = nodes.new("ShaderNodeNewGeometry").outputs["Backfacing"]
        ior = m["ior"]
        facing_ior = math_node(nodes, links, "ADD",  # ior + backfacing * (1/ior - ior)
                               math_node(nodes, links, "MULTIPLY", backfacing, 1.0 / ior - ior), ior)
        links.new(facing_ior, fresnel.inputs["IOR"])
        face = fresnel.outputs["Fac"]
        film = math_node(nodes, links, "DIVIDE", math_node(nodes, links, "MULTIPLY", face, 2.0),
                         math_node(nodes, links, "ADD", face, 1.0))
        surface = nodes.new("ShaderNodeMixShader")
        links.new(film, surface.inputs["Fac"])
        links.new(transparent.outputs["BSDF"], surface.inputs[1])
        links.new(glossy.outputs["BSDF"], surface.inputs[2])
    else:
        warn(f"material {m['name']}: unknown bsdf {bsdf!r}, drawn diffuse")
        surface = nodes.new("ShaderNodeBsdfDiffuse")
        surface.inputs["Color"].default_value = albedo
    if emitting:
        # Tessera adds a non-emitter material's emission to its scattering.
        add = nodes.new("ShaderNodeAddShader")
        links.new(emission_node(nodes, m["emission"]).outputs[0], add.inputs[0])
        links.new(surface.outputs[0], add.inputs[1])
        surface = add
    if surface is not None:
        links.new(surface.outputs[0], output.inputs["Surface"])
    return mat


def frame_of(normal):
    n = Vector(normal).normalized()
    helper = Vector((1.0, 0.0, 0.0)) if abs(n.x) < 0.9 else Vector((0.0, 1.0, 0.0))
    t = helper.cross(n).normalized()
    return t, n.cross(t), n


def mesh_from_lists(name, vertices, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    return mesh


def build_sphere(s, args):
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=args.sphere_segments,
                              v_segments=args.sphere_segments // 2, radius=s["radius"])
    bmesh.ops.translate(bm, vec=Vector(s["center"]), verts=bm.verts)
    mesh = bpy.data.meshes.new("sphere")
    bm.to_mesh(mesh)
    bm.free()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    return mesh


def similarity_scale(rows):
    # The uniform scale of a row-major 4 x 4 similarity (rotation, uniform scale,
    # translation), or None when the matrix is not one.
    if rows is None:
        return 1.0
    m = Matrix([rows[0:4], rows[4:8], rows[8:12], rows[12:16]])
    columns = [m.col[i].to_3d() for i in range(3)]
    scale = columns[0].length
    for i in range(3):
        if abs(columns[i].length - scale) > 1e-9 * max(scale, 1.0):
            return None
        for j in range(i + 1, 3):
            if abs(columns[i].dot(columns[j])) > 1e-9 * max(scale * scale, 1.0):
                return None
    return scale


def sphere_points(s, material):
    # An exact sphere: Cycles draws a point-cloud point as one (Geometry Nodes' Mesh to
    # Points), where a UV sphere's facets sink a large sphere's top by R (1 - cos(pi / 64)):
    # RayON's ground, a 1000 m sphere, came out 1.2 m low. Centre and radius are placed in
    # world space here, so the object carries no transform.
    rows = s["matrix"]
    scale = similarity_scale(rows)
    centre = Vector(s["center"])
    if rows is not None:
        centre = Matrix([rows[0:4], rows[4:8], rows[8:12], rows[12:16]]) @ centre
    mesh = mesh_from_lists("sphere", [centre], [])
    obj = bpy.data.objects.new("sphere", mesh)
    group = bpy.data.node_groups.new("sphere", "GeometryNodeTree")
    group.inputs.new("NodeSocketGeometry", "Geometry")
    group.outputs.new("NodeSocketGeometry", "Geometry")
    points = group.nodes.new("GeometryNodeMeshToPoints")
    points.inputs["Radius"].default_value = s["radius"] * scale
    assign = group.nodes.new("GeometryNodeSetMaterial")
    assign.inputs["Material"].default_value = material
    group.links.new(group.nodes.new("NodeGroupInput").outputs[0], points.inputs["Mesh"])
    group.links.new(points.outputs[0], assign.inputs["Geometry"])
    group.links.new(assign.outputs[0], group.nodes.new("NodeGroupOutput").inputs[0])
    obj.modifiers.new("points", "NODES").node_group = group
    return obj


def build_revolved(base, axis, profile, segments, caps):
    # A surface of revolution about `axis` through `base`: `profile` lists (radius, height)
    # along it; caps close its first and last ring with flat discs of their own vertices
    # (so the side's smooth normals do not bend towards them).
    t, b, n = frame_of(axis)
    base = Vector(base)

    def ring(radius, height):
        return [base + height * n + radius * (math.cos(2 * math.pi * i / segments) * t +
                                              math.sin(2 * math.pi * i / segments) * b)
                for i in range(segments)]

    vertices, faces, smooth = [], [], []
    for k in range(len(profile) - 1):
        (r0, h0), (r1, h1) = profile[k], profile[k + 1]
        start = len(vertices)
        vertices += ring(r0, h0) + ring(r1, h1)
        for i in range(segments):
            j = (i + 1) % segments
            faces.append((start + i, start + j, start + segments + j, start + segments + i))
            smooth.append(True)
    if caps:
        # Faces face outwards: the last ring's cap along +axis, the first ring's along
        # -axis. Glass needs it (Cycles tells entering from leaving by the face's side); the
        # bottom cap once faced inwards, which only opaque cylinders and cones had hidden.
        for (radius, height), outward in ((profile[0], False), (profile[-1], True)):
            if radius <= 0.0:
                continue
            start = len(vertices)
            vertices += ring(radius, height) + [base + height * n]
            for i in range(segments):
                here, after = start + i, start + (i + 1) % segments
                faces.append((start + segments, here, after) if outward else
                             (start + segments, after, here))
                smooth.append(False)
    mesh = mesh_from_lists("revolved", vertices, faces)
    mesh.polygons.foreach_set("use_smooth", smooth)
    return mesh


def build_cylinder(c, args):
    return build_revolved(c["base"], c["axis"], [(c["radius"], 0.0), (c["radius"], c["height"])],
                          args.sphere_segments, c["caps"])


def build_cone(c, args):
    # Rings along the side so a pointed cone's normals stay those of its side up to the tip.
    rings = 32
    profile = [(c["base_radius"] + (c["top_radius"] - c["base_radius"]) * k / rings,
                c["height"] * k / rings) for k in range(rings + 1)]
    return build_revolved(c["base"], c["axis"], profile, args.sphere_segments, c["caps"])


def build_torus(t, args):
    if t["minor_radius"] >= t["major_radius"]:
        warn("a horn or spindle torus is drawn as its whole tube; Tessera shows its outer surface")
    u_segments, v_segments = args.sphere_segments, args.sphere_segments // 2
    tangent, bitangent, n = frame_of(t["axis"])
    centre, major, minor = Vector(t["center"]), t["major_radius"], t["minor_radius"]
    vertices = []
    for i in range(u_segments):
        u = 2 * math.pi * i / u_segments
        radial = math.cos(u) * tangent + math.sin(u) * bitangent
        for j in range(v_segments):
            v = 2 * math.pi * j / v_segments
            vertices.append(centre + (major + minor * math.cos(v)) * radial + minor * math.sin(v) * n)
    faces = [(i * v_segments + j, ((i + 1) % u_segments) * v_segments + j,
              ((i + 1) % u_segments) * v_segments + (j + 1) % v_segments,
              i * v_segments + (j + 1) % v_segments)
             for i in range(u_segments) for j in range(v_segments)]
    mesh = mesh_from_lists("torus", vertices, faces)
    mesh.polygons.foreach_set("use_smooth", [True] * len(faces))
    return mesh


def build_quad(q):
    c, u, v = Vector(q["corner"]), Vector(q["u"]), Vector(q["v"])
    mesh = mesh_from_lists("quad", [c, c + u, c + u + v, c + v], [(0, 1, 2, 3)])
    # Tessera's quad uv: the corner's parameters along u and v.
    layer = mesh.uv_layers.new(name="UVMap")
    for loop, uv in zip(mesh.loops, [(0, 0), (1, 0), (1, 1), (0, 1)]):
        layer.data[loop.index].uv = uv
    return mesh


def build_disk(d, args):
    t, b, n = frame_of(d["normal"])
    center, r, ri = Vector(d["center"]), d["radius"], d["inner_radius"]
    k = args.disk_segments
    ring = [center + r * (math.cos(2 * math.pi * i / k) * t + math.sin(2 * math.pi * i / k) * b)
            for i in range(k)]
    if ri > 0.0:
        inner = [center + ri * (math.cos(2 * math.pi * i / k) * t +
                                math.sin(2 * math.pi * i / k) * b) for i in range(k)]
        faces = [(i, (i + 1) % k, k + (i + 1) % k, k + i) for i in range(k)]
        return mesh_from_lists("annulus", ring + inner, faces)
    faces = [(k, i, (i + 1) % k) for i in range(k)]
    return mesh_from_lists("disk", ring + [center], faces)


def build_plane(p):
    # An infinite plane has no mesh; a square far larger than any suite scene stands in.
    warn("plane drawn as a 2000 x 2000 square")
    t, b, _ = frame_of(p["normal"])
    c, h = Vector(p["point"]), 1000.0
    return mesh_from_lists("plane", [c - h * t - h * b, c + h * t - h * b, c + h * t + h * b,
                                     c - h * t + h * b], [(0, 1, 2, 3)])


def build_mesh(m):
    positions, indices, normals = m["positions"], m["indices"], m["normals"]
    nv, nt = len(positions) // 3, len(indices) // 3
    mesh = bpy.data.meshes.new("mesh")
    mesh.vertices.add(nv)
    mesh.vertices.foreach_set("co", positions)
    mesh.loops.add(3 * nt)
    mesh.loops.foreach_set("vertex_index", indices)
    mesh.polygons.add(nt)
    mesh.polygons.foreach_set("loop_start", list(range(0, 3 * nt, 3)))
    mesh.polygons.foreach_set("loop_total", [3] * nt)
    mesh.update(calc_edges=True)
    uvs = m.get("uvs")
    if uvs:
        # The file's per-vertex uv, per loop as Blender keeps them.
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", [c for i in indices for c in uvs[2 * i:2 * i + 2]])
    if normals:
        # Tessera interpolates the file's vertex normals; custom split normals do the same.
        mesh.polygons.foreach_set("use_smooth", [True] * nt)
        mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(
            [tuple(normals[3 * i:3 * i + 3]) for i in range(nv)])
    return mesh


def pattern_frame(s):
    # Where Tessera measures a pattern's direction from (render/surface_textures.hpp): a
    # sphere's centre, in world space when its transform is baked (none, or a similarity),
    # in its own space when it is instanced (the inverse of the linear part, as rows);
    # the world origin for every other shape. Hashable: materials are copied per frame.
    if s["type"] != "sphere":
        return ((0.0, 0.0, 0.0), None)
    rows = s["matrix"]
    centre = Vector(s["center"])
    if rows is None:
        return (tuple(centre), None)
    m = Matrix([rows[0:4], rows[4:8], rows[8:12], rows[12:16]])
    world_centre = tuple(m @ centre)
    if similarity_scale(rows) is not None:
        return (world_centre, None)
    inverse = m.to_3x3().inverted()
    return (world_centre, tuple(tuple(inverse[r]) for r in range(3)))


def add_shapes(scene, data, materials, args, scene_dir):
    counts = {}
    copies = {}  # (material, frame, uv source) -> its copy for such shapes
    textures = {t["name"]: t for t in data.get("textures", [])}
    for s in data["shapes"]:
        kind = s["type"]
        material = data["materials"][s["material"]]
        shape_material = materials[s["material"]]
        if (material.get("pattern") == "fibonacci_dots" or material.get("albedo_texture") or
                material.get("roughness_texture")):
            uv = ("sphere" if kind == "sphere" else
                  "uvmap" if kind == "quad" or (kind == "mesh" and s.get("uvs")) else None)
            key = (s["material"], pattern_frame(s), uv)
            if key not in copies:
                copies[key] = make_material(material, (key[1], uv, textures, scene_dir))
            shape_material = copies[key]
        if s.get("dimples"):
            warn(f"shape {s['source_index']}: golf-ball dimples not drawn (a plain sphere)")
        # Opaque, non-emitting spheres become exact point spheres. Emitters stay meshes:
        # Cycles 3.4 samples emitting triangles as lights, not points. Glass stays a mesh
        # too (the point primitive's rays from inside were not checked), and so do
        # anisotropic metals (a point has no tangent: Cycles drew them black).
        exact = (kind == "sphere" and max(material["emission"]) <= 0.0 and
                 material["bsdf"] in ("diffuse", "conductor", "coated") and
                 abs(material["alpha_x"] - material["alpha_y"]) <= 1e-6 and
                 similarity_scale(s["matrix"]) is not None)
        if exact:
            obj = sphere_points(s, shape_material)
            counts["point sphere"] = counts.get("point sphere", 0) + 1
            if not s["visible"]:
                obj.visible_camera = False
            scene.collection.objects.link(obj)
            continue
        if kind == "sphere":
            mesh = build_sphere(s, args)
        elif kind == "cylinder":
            mesh = build_cylinder(s, args)
        elif kind == "cone":
            mesh = build_cone(s, args)
        elif kind == "torus":
            mesh = build_torus(s, args)
        elif kind == "quad":
            mesh = build_quad(s)
        elif kind == "disk":
            mesh = build_disk(s, args)
        elif kind == "plane":
            mesh = build_plane(s)
        elif kind == "mesh":
            mesh = build_mesh(s)
        else:
            warn(f"geometry[{s['source_index']}]: {s.get('kind', kind)} not drawn by the Cycles peer")
            continue
        counts[kind] = counts.get(kind, 0) + 1
        mesh.materials.append(shape_material)
        obj = bpy.data.objects.new(kind, mesh)
        if s["matrix"] is not None:
            rows = s["matrix"]
            obj.matrix_world = Matrix([rows[0:4], rows[4:8], rows[8:12], rows[12:16]])
        if not s["visible"]:
            # Hidden from camera rays only, as in Tessera (and RayON): reflections, bounces
            # and shadow rays still meet the shape.
            obj.visible_camera = False
        scene.collection.objects.link(obj)
    return counts


def synchronization_seconds(exr_path):
    # The EXR header holds Cycles' stamp fields as OpenEXR string attributes:
    # name NUL "string" NUL, a 32-bit little-endian length, the text ("MM:SS.hh").
    with open(exr_path, "rb") as f:
        header = f.read(1 << 16)
    match = re.search(rb"cycles\.[^\x00]*\.synchronization_time\x00string\x00", header)
    if not match:
        return 0.0
    length = int.from_bytes(header[match.end():match.end() + 4], "little")
    text = header[match.end() + 4:match.end() + 4 + length].decode()
    seconds = 0.0
    for part in text.split(":"):
        seconds = seconds * 60.0 + float(part)
    return seconds


def main():
    args = parse_args()
    with open(args.scene) as f:
        data = json.load(f)
    if data.get("format") != "tessera-scene-export" or data.get("version") != 1:
        sys.exit("cycles_render.py: not a tessera-scene-export version 1 file")
    if data["render"]["integrator"] != "path":
        warn(f"integrator {data['render']['integrator']}: Cycles renders the path tracer's image")
    clear_scene()
    scene = bpy.context.scene
    bounces = configure(scene, data, args)
    add_camera(scene, data["camera"])
    add_world(scene, data, args.scene)
    add_lights(scene, data)
    materials = [make_material(m) for m in data["materials"]]
    counts = add_shapes(scene, data, materials, args, os.path.dirname(args.scene))
    print(f"cycles_render.py: Blender {bpy.app.version_string}, {scene.render.resolution_x}x"
          f"{scene.render.resolution_y}, bounces {bounces}, threads "
          f"{args.threads or 'all'}, shapes {counts}", flush=True)

    spp_list = [int(x) for x in args.spp.split(",") if x]
    scene.cycles.samples = 1
    bpy.ops.render.render()  # warm-up: the first render also loads kernels
    for spp in spp_list:
        scene.cycles.samples = spp
        start = time.perf_counter()
        bpy.ops.render.render()
        wall = time.perf_counter() - start
        path = f"{args.out}/cycles_{spp}.exr"
        bpy.data.images["Render Result"].save_render(path, scene=scene)
        sync = synchronization_seconds(path)
        print(f"TESSERA_PEER spp={spp} wall={wall:.6f} sync={sync:.3f} exr={path}", flush=True)
    if args.reference_spp > 0:
        scene.cycles.samples = args.reference_spp
        scene.cycles.seed = 1
        start = time.perf_counter()
        bpy.ops.render.render()
        wall = time.perf_counter() - start
        path = f"{args.out}/cycles_reference_{args.reference_spp}.exr"
        bpy.data.images["Render Result"].save_render(path, scene=scene)
        sync = synchronization_seconds(path)
        print(f"TESSERA_PEER reference=1 spp={args.reference_spp} wall={wall:.6f} sync={sync:.3f} "
              f"exr={path}", flush=True)


main()

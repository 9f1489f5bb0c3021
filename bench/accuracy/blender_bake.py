# Blender's Cycles baker, the anchor of table 13 (docs/accuracy-cost.md;
# bench/accuracy/table_bake.cpp runs it): HIGH baked onto LOW's UV layout the
# way a Blender user bakes a sculpt onto a triangle mesh ("Selected to
# Active": rays start at LOW pushed out by the cage extrusion along its
# interpolated normal and go inwards up to the maximum ray distance; the
# first hit wins).
#
#   blender --background --factory-startup --python blender_bake.py -- \
#       LOW.obj HIGH.obj OUT_PREFIX SIZE EXTRUSION MAX_RAY_DISTANCE MARGIN
#
# Writes four files OUT_PREFIX.<pass>.f32, each SIZE x SIZE RGBA texels as
# Blender holds them (row 0 at v = 0, which is also the order of the
# project's grids), little-endian float32; table_bake.cpp turns them into
# maps (blender_anchor.cpp):
#  - normal: the Cycles "Normal" pass in tangent space (LOW's MikkTSpace
#    frames, +x along +u, +y along +v: OpenGL green), as 0.5 n + 0.5;
#  - high_position, low_position, low_normal: Cycles has no displacement
#    pass for "Selected to Active", so the height is made as Blender users
#    make it: HIGH's position baked through an emission shader (an "Emit"
#    bake, selected to active; positions + POSITION_OFFSET), LOW's own
#    position likewise and its object-space normal (0.5 n + 0.5), and
#    height = dot(P_high - P_low, normalize(N_low)).
# Prints one line "BLENDER_BAKE {json}" with the seconds of each bake call
# (BVH build and shading included, file reading and start-up excluded).
#
# Settings that matter: denoising off (Debian's Blender is built without
# OpenImageDenoise and a bake with denoising on returns zeros), one sample
# (sample 0 is the texel centre: a normal or position bake needs no more),
# both OBJ files read with the same axes (+Y forward, +Z up: no rotation), so
# object space is the file's space.
import array
import json
import sys
import time

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
if len(args) != 7:
    sys.exit("blender_bake.py: expected LOW HIGH OUT_PREFIX SIZE EXTRUSION MAX_RAY MARGIN")
low_path, high_path, out_prefix = args[0], args[1], args[2]
size, extrusion, max_ray, margin = int(args[3]), float(args[4]), float(args[5]), int(args[6])

# Emission is a radiance: keep positions positive so no renderer-side rule
# about negative light can touch them (Spot lies within [-1, 1]).
POSITION_OFFSET = 4.0

bpy.ops.wm.read_factory_settings(use_empty=True)


def load(path):
    bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    obj = bpy.context.selected_objects[0]
    for poly in obj.data.polygons:
        poly.use_smooth = True
    return obj


t_load = time.perf_counter()
low = load(low_path)
high = load(high_path)
# LOW's normals are Blender's own smooth vertex normals, as on a mesh a user
# subdivides in Blender: with the OBJ's normals kept as custom normals,
# Blender 3.4's tangent-space bake disagrees with its own frames (Spot L3 at
# 256^2: 2.7 degrees median from the project's refined-surface bake of the
# same triangles, 0.14 without; HIGH's custom normals change nothing).
low.data.use_auto_smooth = False
t_load = time.perf_counter() - t_load

scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 1
scene.cycles.use_denoising = False
scene.render.threads_mode = "AUTO"


def emit_position_material(name, target=None):
    """A material whose emission is the world position + POSITION_OFFSET;
    with `target`, also the active image node the bake writes to."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    geometry = nodes.new("ShaderNodeNewGeometry")
    add = nodes.new("ShaderNodeVectorMath")
    add.operation = "ADD"
    add.inputs[1].default_value = (POSITION_OFFSET,) * 3
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(geometry.outputs["Position"], add.inputs[0])
    links.new(add.outputs["Vector"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], out.inputs["Surface"])
    if target is not None:
        node = nodes.new("ShaderNodeTexImage")
        node.image = target
        nodes.active = node
    return m


image = bpy.data.images.new("bake", size, size, float_buffer=True, alpha=True)
image.colorspace_settings.name = "Non-Color"
for obj, material in ((low, emit_position_material("low", image)),
                      (high, emit_position_material("high"))):
    obj.data.materials.clear()
    obj.data.materials.append(material)


def save_pixels(name):
    a = array.array("f", bytes(4 * size * size * 4))
    image.pixels.foreach_get(a)
    if sys.byteorder != "little":
        a.byteswap()
    with open(out_prefix + "." + name + ".f32", "wb") as f:
        a.tofile(f)


def bake(name, selected_to_active, **kw):
    bpy.ops.object.select_all(action="DESELECT")
    low.select_set(True)
    high.select_set(selected_to_active)
    bpy.context.view_layer.objects.active = low
    t0 = time.perf_counter()
    bpy.ops.object.bake(use_selected_to_active=selected_to_active, cage_extrusion=extrusion,
                        max_ray_distance=max_ray, margin=margin, margin_type="EXTEND", **kw)
    seconds[name] = time.perf_counter() - t0
    save_pixels(name)


seconds = {"load": t_load}
bake("normal", True, type="NORMAL", normal_space="TANGENT", normal_r="POS_X", normal_g="POS_Y",
     normal_b="POS_Z")
bake("high_position", True, type="EMIT")
bake("low_position", False, type="EMIT")
bake("low_normal", False, type="NORMAL", normal_space="OBJECT", normal_r="POS_X",
     normal_g="POS_Y", normal_b="POS_Z")
print("BLENDER_BAKE " + json.dumps({"seconds": seconds, "position_offset": POSITION_OFFSET,
                                    "version": bpy.app.version_string}))

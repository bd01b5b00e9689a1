# Blender's side of test_blender (docs/groundtruth.md): renders a glTF scene
# lit by its sun with Cycles, direct light only, on white diffuse surfaces,
# twice (as it is, and with the node named "plate" hidden), and writes the
# ratio lit / unshadowed per pixel: Cycles' V_gt_weighted. Blender reads
# KHR_lights_punctual but not the angle in the light's extras, so the
# angle comes on the command line. Python only because Blender is driven in
# Python; it runs inside Blender, nowhere else.
# Usage: blender -b --factory-startup --python-exit-code 1 -P blender_sun.py --
#        SCENE.gltf ANGULAR_DIAMETER_DEG WIDTH HEIGHT SAMPLES OUT.f32
import array
import math
import os
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 glTF importer still uses numpy.bool, which the
# numpy 1.24 Debian ships it with has removed: the alias, put back.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

scene_path, degrees, width, height, samples, out_path = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=scene_path)
scene = bpy.context.scene
suns = [o for o in scene.objects if o.type == "LIGHT" and o.data.type == "SUN"]
cameras = [o for o in scene.objects if o.type == "CAMERA"]
plates = [o for o in scene.objects if o.name.startswith("plate")]
if len(suns) != 1 or len(cameras) != 1 or len(plates) != 1:
    sys.exit("blender_sun.py: want one sun, one camera and one node named plate in %s" % scene_path)
suns[0].data.angle = math.radians(float(degrees))
suns[0].data.energy = 1.0
scene.camera = cameras[0]
white = bpy.data.materials.new("white")  # Lambert, albedo 1
white.use_nodes = True
nodes = white.node_tree.nodes
nodes.remove(nodes["Principled BSDF"])
diffuse = nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (1, 1, 1, 1)
white.node_tree.links.new(diffuse.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
for o in scene.objects:
    if o.type == "MESH":
        o.data.materials.clear()
        o.data.materials.append(white)
world = bpy.data.worlds.new("black")
world.color = (0, 0, 0)
scene.world = world
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = int(samples)
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.max_bounces = 0  # direct light only: the ground truth models the light's shadowing alone
scene.cycles.pixel_filter_type = "BOX"
scene.cycles.filter_width = 0.01  # a pixel's centre, as the ground truth's primary rays
scene.render.resolution_x, scene.render.resolution_y = int(width), int(height)
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.view_settings.view_transform = "Standard"


def render(name):
    path = os.path.join(os.path.dirname(out_path), name + ".exr")
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = array.array("f", image.pixels[:])  # RGBA, bottom row first
    return pixels


lit = render("lit")
plates[0].hide_render = True
unlit = render("unlit")
w, h = int(width), int(height)
ratio = array.array("f", [0.0] * (w * h))
for y in range(h):
    for x in range(w):
        i = ((h - 1 - y) * w + x) * 4  # top row first, as shadowbench's images
        ratio[y * w + x] = lit[i] / unlit[i] if unlit[i] > 0 else -1.0
with open(out_path, "wb") as f:
    ratio.tofile(f)

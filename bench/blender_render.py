# Renders a rigsim dataset's views with Blender Cycles on the CPU, for a side-by-side speed
# comparison with `rigsim render` (bench/blender_bench.sh, BENCHMARKS.md). Not part of rigsim.
#
#   blender -b --factory-startup -P bench/blender_render.py -- SCENE.glb RIG.json FRAMES.json SPP OUT_DIR [FRAME_INDEX]
#
# The same glTF, the same cameras (every camera of rig.json at frame FRAME_INDEX of frames.json:
# cam_from_world = cam_from_rig * rig_from_world, OpenCV axes, glTF world), the same image size;
# PINHOLE intrinsics from fx, cx, cy (Cycles has no OpenCV lens distortion: a distorted camera is
# rendered without it). One bounce (Cycles' max_bounces = 1: direct light and shadows, as rigsim),
# a sun in rigsim's default direction and a uniform sky, SPP samples (no adaptive sampling, no
# denoising), the combined image with the object-index and depth passes, written as one
# multilayer EXR per camera. Prints the seconds of each render (render and write) and their sum.
import json
import math
import os
import sys
import time

import numpy

# Debian 12's Blender 3.4 glTF importer still uses numpy.bool, which its numpy 1.24 removed.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

import bpy
from mathutils import Matrix, Quaternion, Vector

args = sys.argv[sys.argv.index("--") + 1:]
scene_path, rig_path, frames_path, spp, out_dir = args[0], args[1], args[2], int(args[3]), args[4]
frame_index = int(args[5]) if len(args) > 5 else 0

# An empty scene, then the glTF.
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj, do_unlink=True)
start = time.time()
bpy.ops.import_scene.gltf(filepath=scene_path)
print(f"blender: imported {scene_path} in {time.time() - start:.2f} s", flush=True)
for i, obj in enumerate(o for o in bpy.data.objects if o.type == "MESH"):
    obj.pass_index = i + 1

scene = bpy.context.scene
scene.render.engine = "CYCLES"
cycles = scene.cycles
cycles.device = "CPU"
cycles.samples = spp
cycles.use_adaptive_sampling = False
cycles.use_denoising = False
cycles.max_bounces = 1
cycles.diffuse_bounces = 1
cycles.glossy_bounces = 1
cycles.transmission_bounces = 1
cycles.transparent_max_bounces = 1
cycles.volume_bounces = 0
scene.render.threads_mode = "AUTO"
view_layer = scene.view_layers[0]
view_layer.use_pass_object_index = True
view_layer.use_pass_z = True
scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
scene.render.image_settings.color_depth = "32"

# Light: rigsim's default sun (towards (0.4, 0.8, 0.3) in glTF's +Y-up world) and a uniform sky.
gl_to_blender = Matrix(((1, 0, 0), (0, 0, -1), (0, 1, 0)))  # glTF (x, y, z) -> Blender (x, -z, y)
sun_dir = gl_to_blender @ Vector((0.4, 0.8, 0.3)).normalized()
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", type="SUN"))
sun.data.energy = 3.0
sun.rotation_euler = Vector((0, 0, 1)).rotation_difference(sun_dir).to_euler()
scene.collection.objects.link(sun)
world = scene.world or bpy.data.worlds.new("world")
scene.world = world
world.use_nodes = True
world.node_tree.nodes["Background"].inputs[0].default_value = (0.6, 0.7, 0.9, 1.0)

rig = json.load(open(rig_path))
frame = json.load(open(frames_path))["frames"][frame_index]


def rigid(pose):
    w, x, y, z = pose["rotation_wxyz"]
    m = Quaternion((w, x, y, z)).to_matrix().to_4x4()
    m.translation = Vector(pose["translation"])
    return m


rig_from_world = rigid(frame["rig_from_world"])
cv_from_blender_cam = Matrix(((1, 0, 0, 0), (0, -1, 0, 0), (0, 0, -1, 0), (0, 0, 0, 1)))
total = 0.0
for cam in rig["cameras"]:
    w, h = cam["width"], cam["height"]
    fx, fy, cx, cy = cam["params"][:4]
    world_from_cam = (rigid(cam["cam_from_rig"]) @ rig_from_world).inverted()
    data = bpy.data.cameras.new(cam["name"])
    data.sensor_fit = "HORIZONTAL"
    data.sensor_width = 36.0
    data.lens = fx * 36.0 / w
    data.shift_x = -(cx - (w - 1) / 2) / w
    data.shift_y = (cy - (h - 1) / 2) / w
    obj = bpy.data.objects.new(cam["name"], data)
    obj.matrix_world = gl_to_blender.to_4x4() @ world_from_cam @ cv_from_blender_cam
    scene.collection.objects.link(obj)
    scene.camera = obj
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = 1.0
    scene.render.pixel_aspect_y = fx / fy
    scene.render.filepath = os.path.join(out_dir, cam["name"] + ".exr")
    start = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - start
    total += seconds
    print(f"blender: {cam['name']} {w}x{h} {spp} spp rendered and written in {seconds:.2f} s", flush=True)
print(f"blender: {len(rig['cameras'])} views rendered in {total:.2f} s", flush=True)

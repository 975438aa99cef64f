# The peer of `candela render SCENE --raytrace path --spp N --size WxH`: Blender Cycles,
# CPU, the same glTF scene, camera, sample count and size, no denoiser, a box pixel filter (what
# the tracer averages) and no bounce cap but Russian roulette (Candela's path default), to PNG.
#
#   blender -b --factory-startup -noaudio -P tests/bench/cycles_cornell.py -- \
#       samples/scenes/cornell_box.gltf out.png [SPP] [WxH]
#
# Prints "cycles: render N spp WxH in S s" (the render alone, from bpy.ops.render.render to the
# written file); time the whole process from outside (docs/raytracing.md, "Path tracing speed").
import json
import sys
import time

import bpy
import numpy

# Debian's blender 3.4 glTF importer uses numpy.bool, which Debian 12's numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
scene_path = argv[0] if len(argv) > 0 else "samples/scenes/cornell_box.gltf"
out_path = argv[1] if len(argv) > 1 else "cycles_cornell.png"
spp = int(argv[2]) if len(argv) > 2 else 64
width, height = (int(v) for v in (argv[3] if len(argv) > 3 else "256x256").split("x"))

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=scene_path)
scene = bpy.context.scene
cameras = [o for o in scene.objects if o.type == "CAMERA"]
if not cameras:
    sys.exit("no camera in " + scene_path)
scene.camera = cameras[0]
# The glTF's vertical field of view, as Candela uses it (the importer may fit the sensor otherwise).
if scene_path.endswith(".gltf"):
    with open(scene_path) as f:
        gltf_cameras = json.load(f).get("cameras", [])
    if gltf_cameras and gltf_cameras[0].get("type") == "perspective":
        scene.camera.data.sensor_fit = "VERTICAL"
        scene.camera.data.angle_y = gltf_cameras[0]["perspective"]["yfov"]

# No environment light: Candela's scene has none (`candela info`: environment: none).
world = bpy.data.worlds.new("black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
scene.world = world

scene.render.engine = "CYCLES"
c = scene.cycles
c.device = "CPU"
c.samples = spp
c.use_adaptive_sampling = False
c.use_denoising = False
c.use_preview_denoising = False
c.pixel_filter_type = "BOX"
scene.render.filter_size = 1.0
# Candela's path mode: no depth cap, Russian roulette ends paths. Cycles' roulette is always on;
# 1024 is its largest bounce count, far beyond what the roulette lets through.
c.max_bounces = 1024
c.diffuse_bounces = 1024
c.glossy_bounces = 1024
c.transmission_bounces = 1024
c.transparent_max_bounces = 1024
c.volume_bounces = 0
c.caustics_reflective = True
c.caustics_refractive = True
c.sample_clamp_direct = 0.0
c.sample_clamp_indirect = 0.0
c.seed = 1
scene.render.threads_mode = "AUTO"
scene.render.resolution_x = width
scene.render.resolution_y = height
scene.render.resolution_percentage = 100
scene.render.use_persistent_data = False
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGBA"
scene.render.filepath = out_path

t0 = time.perf_counter()
bpy.ops.render.render(write_still=True)
print("cycles: render %d spp %dx%d in %.3f s" % (spp, width, height, time.perf_counter() - t0), flush=True)

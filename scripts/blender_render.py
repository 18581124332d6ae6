# Renders a drape .glb as Blender imports and plays it: frames at the given times, side by side
# in one PNG (Eevee, headless). Used by scripts/pictures.sh for the README's picture:
#   blender -b --python scripts/blender_render.py -- RUN.glb OUT.png 0.3 0.8 3.0
import math
import sys

import numpy

# Debian 12's Blender 3.4 glTF importer still calls numpy.bool, which NumPy 1.24 removed.
if "bool" not in vars(numpy):
    numpy.bool = bool

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
glb, out, times = args[0], args[1], [float(t) for t in args[2:]]

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=glb)

camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.location = (2.6, -3.4, 1.9)
camera.rotation_euler = (Vector((0.1, 0.0, 0.35)) - camera.location).to_track_quat("-Z", "Y").to_euler()
camera.data.lens = 40
scene.camera = camera
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 4.0
sun.data.angle = math.radians(8)
sun.rotation_euler = (math.radians(35), math.radians(15), math.radians(40))
scene.collection.objects.link(sun)
scene.world = bpy.data.worlds.new("sky")
scene.world.use_nodes = True
background = scene.world.node_tree.nodes["Background"]
background.inputs[0].default_value = (0.75, 0.8, 0.88, 1.0)
background.inputs[1].default_value = 0.5

scene.render.engine = "BLENDER_EEVEE"
scene.eevee.use_soft_shadows = True
scene.eevee.use_gtao = True
scene.render.resolution_x, scene.render.resolution_y = 480, 360
scene.render.film_transparent = False

# Each time as the frame Blender placed it at (the importer maps seconds to its frame rate).
tiles = []
for i, t in enumerate(times):
    scene.frame_set(round(t * scene.render.fps / scene.render.fps_base))
    scene.render.filepath = f"{out}.{i}.png"
    bpy.ops.render.render(write_still=True)
    tiles.append(bpy.data.images.load(scene.render.filepath))

w, h = scene.render.resolution_x, scene.render.resolution_y
strip = numpy.zeros((h, w * len(tiles), 4), dtype=numpy.float32)
for i, image in enumerate(tiles):
    strip[:, i * w:(i + 1) * w, :] = numpy.array(image.pixels[:], dtype=numpy.float32).reshape(h, w, 4)
result = bpy.data.images.new("strip", w * len(tiles), h)
result.pixels = strip.ravel()
result.filepath_raw = out
result.file_format = "PNG"
result.save()
print(f"blender_render: {out}: {len(tiles)} frames at {times} s")

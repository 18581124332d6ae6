# Inside Blender (blender -b --python-exit-code 1 --python check_caches.py -- DIR): imports
# DIR/run.glb and checks its animation against the same run's OBJ frames in DIR/frames/, then
# imports the rest mesh DIR/run.obj, plays DIR/run.pc2 on it through a Mesh Cache modifier with
# its default settings and checks that too. The run: scenes/hang.json, 1 s, every 5th frame.
import sys

import numpy

# Debian 12's Blender 3.4 glTF importer still calls numpy.bool, which NumPy 1.24 removed.
if "bool" not in vars(numpy):
    numpy.bool = bool

import bpy  # noqa: E402

folder = sys.argv[sys.argv.index("--") + 1]
tolerance = 1e-6  # m: float storage of coordinates near 1 m, and Blender's own floats


def obj_positions(path):
    with open(path) as f:
        return numpy.array([[float(t) for t in line.split()[1:4]] for line in f if line.startswith("v ")])


def blender_axes(p):
    """drape's y-up (x, y, z) as Blender's z-up world: (x, -z, y)."""
    return numpy.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


def world_positions(ob):
    evaluated = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    xyz = numpy.array([(ob.matrix_world @ v.co)[:] for v in mesh.vertices])
    evaluated.to_mesh_clear()
    return xyz


def check(what, ob, drape_frame):
    want = blender_axes(obj_positions(f"{folder}/frames/frame_{drape_frame:05d}.obj"))
    error = numpy.abs(world_positions(ob) - want).max()
    print(f"check_caches: {what}, frame {drape_frame}: largest difference {error:.2e} m")
    if not error < tolerance:
        raise SystemExit(f"check_caches: {what} differs from the run's frame {drape_frame}")


# glTF: the mesh with one shape key per kept frame, played by an action. Blender places a time of
# t s at frame t·fps.
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=f"{folder}/run.glb")
cloth = bpy.data.objects["hang"]
keys = cloth.data.shape_keys
print(f"check_caches: run.glb: {len(cloth.data.vertices)} vertices, {len(keys.key_blocks) - 1} "
      f"shape keys, action {keys.animation_data.action.name}")
assert len(cloth.data.vertices) == 1024 and len(keys.key_blocks) == 1 + 12
for drape_frame in (0, 30, 60):
    scene.frame_set(round(drape_frame / 60 * scene.render.fps))
    check("run.glb", cloth, drape_frame)

# PC2 on the rest mesh, as an artist sets it up: import the OBJ, add a Mesh Cache modifier. At
# scene frame f it shows the cache's frame f, i.e. the run's frame 5f.
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
bpy.ops.wm.obj_import(filepath=f"{folder}/run.obj")
rest = bpy.context.selected_objects[0]
cache = rest.modifiers.new("drape", "MESH_CACHE")
cache.cache_format = "PC2"
cache.filepath = f"{folder}/run.pc2"
for drape_frame in (0, 30, 60):
    scene.frame_set(drape_frame // 5)
    check("run.pc2 on run.obj", rest, drape_frame)

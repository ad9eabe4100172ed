# SPDX-License-Identifier: Apache-2.0
# Imports a 3D Tiles leaf GLB written with export.3dtiles compression: none into Blender 3.4 headless
# and prints its faces, images and textured materials (docs/benchmarks/tiles3d.md):
#   blender --background --factory-startup --python-exit-code 1 --python scripts/blender_check_glb.py -- OUT/3dtiles/tile.glb
import sys, bpy, numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Blender 3.4's glTF importer uses the removed numpy.bool
path = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
faces = sum(len(o.data.polygons) for o in bpy.data.objects if o.type == "MESH")
images = [(i.name, tuple(i.size)) for i in bpy.data.images]
textured = sum(1 for m in bpy.data.materials if m.use_nodes and any(n.type == "TEX_IMAGE" for n in m.node_tree.nodes))
print("GLB_CHECK faces=%d images=%s textured_materials=%d" % (faces, images, textured))

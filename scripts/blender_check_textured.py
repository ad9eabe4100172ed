# SPDX-License-Identifier: Apache-2.0
"""Imports a textured OBJ written by texture.mrf into Blender (3.4, headless) and checks that
every material has an image texture that Blender loaded, and that the mesh has UVs.

    blender --background --factory-startup --python scripts/blender_check_textured.py -- \
        OUT/textured/mesh.obj

Exit code 0 when the check passes, 1 otherwise (with the reason on stderr).
"""
import os
import sys

import bpy


def fail(message):
    print("blender_check_textured: FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        fail("usage: blender --background --python blender_check_textured.py -- mesh.obj")
    path = os.path.abspath(argv[0])
    if not os.path.isfile(path):
        fail("no such file: " + path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if hasattr(bpy.ops.wm, "obj_import"):
        bpy.ops.wm.obj_import(filepath=path)
    else:
        bpy.ops.import_scene.obj(filepath=path)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if not meshes:
        fail("no mesh object imported from " + path)
    textures = 0
    faces = 0
    for obj in meshes:
        mesh = obj.data
        faces += len(mesh.polygons)
        if not mesh.uv_layers:
            fail("object %s has no UV layer" % obj.name)
        if not obj.material_slots:
            fail("object %s has no material" % obj.name)
        for slot in obj.material_slots:
            material = slot.material
            if material is None or not material.use_nodes:
                fail("object %s has a material without nodes" % obj.name)
            images = [n.image for n in material.node_tree.nodes
                      if n.type == "TEX_IMAGE" and n.image is not None]
            if not images:
                fail("material %s has no image texture" % material.name)
            for image in images:
                image_path = bpy.path.abspath(image.filepath)
                if not os.path.isfile(image_path):
                    fail("material %s: texture file missing: %s" % (material.name, image_path))
                width, height = image.size
                if width == 0 or height == 0:
                    fail("material %s: Blender could not load %s" % (material.name, image_path))
                if width > 8192 or height > 8192:
                    fail("material %s: texture %dx%d exceeds 8192" % (material.name, width, height))
                textures += 1
    print("blender_check_textured: OK: %d object(s), %d faces, %d image texture(s) in %s"
          % (len(meshes), faces, textures, path))


main()

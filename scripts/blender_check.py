# SPDX-License-Identifier: Apache-2.0
"""Checks that Blender 3.4 (headless) imports vdbmap's outputs: map.vdb as a volume with the
"surface" grid, and mesh.ply as a mesh with faces.

    blender --background --factory-startup --python-exit-code 1 \
        --python scripts/blender_check.py -- OUT/map.vdb OUT/mesh.ply

Prints one line per file and exits 0 when both import, 1 otherwise (reason on stderr).
"""
import os
import sys

import bpy


def fail(message):
    print("blender_check: FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def check_vdb(path):
    bpy.ops.object.volume_import(filepath=path, files=[{"name": os.path.basename(path)}],
                                 directory=os.path.dirname(path) + os.sep)
    volumes = [o for o in bpy.context.scene.objects if o.type == "VOLUME"]
    if not volumes:
        fail("no volume object imported from " + path)
    volume = volumes[-1].data
    if not volume.grids.load():
        fail("Blender could not load the grids of " + path + ": " + str(volume.grids.error_message))
    names = [g.name for g in volume.grids]
    if "surface" not in names:
        fail(path + " has no 'surface' grid; grids: " + ", ".join(names))
    print("blender_check: OK volume %s grids=[%s] frame_filepath=%s" %
          (path, ", ".join(names), volume.grids.frame_filepath))


def check_ply(path):
    bpy.ops.import_mesh.ply(filepath=path)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if not meshes:
        fail("no mesh object imported from " + path)
    mesh = meshes[-1].data
    if len(mesh.polygons) == 0:
        fail(path + " imported with no faces")
    print("blender_check: OK mesh %s vertices=%d faces=%d" %
          (path, len(mesh.vertices), len(mesh.polygons)))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 2:
        fail("usage: blender --background --python blender_check.py -- map.vdb mesh.ply")
    vdb, ply = (os.path.abspath(a) for a in argv)
    for p in (vdb, ply):
        if not os.path.isfile(p):
            fail("no such file: " + p)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    check_vdb(vdb)
    check_ply(ply)


main()

# SPDX-License-Identifier: Apache-2.0
# Renders an OBJ (textured or semantic) seen from straight above with Blender's Cycles on the
# CPU, without denoising (Debian's Blender 3.4 has no OpenImageDenoise):
#   blender --background --factory-startup --python-exit-code 1 \
#       --python scripts/blender_render_topdown.py -- MESH.obj OUT.png \
#       [--target X Y Z] [--up X Y Z] [--scale M] [--size W H] [--samples N]
# Coordinates are the OBJ's own (imported without axis conversion): vdbmap's world is KITTI
# camera 0 at frame 0, so up is -y and the car drives along +z.
import argparse
import os
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_render_setup import render_png  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
p = argparse.ArgumentParser()
p.add_argument("mesh")
p.add_argument("out")
p.add_argument("--target", type=float, nargs=3, default=[0.0, 1.7, -2.0])
p.add_argument("--up", type=float, nargs=3, default=[0.0, -1.0, 0.0])
p.add_argument("--scale", type=float, default=24.0, help="orthographic view width, m")
p.add_argument("--size", type=int, nargs=2, default=[960, 640])
p.add_argument("--samples", type=int, default=16)
a = p.parse_args(argv)

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.obj(filepath=a.mesh, axis_forward="Y", axis_up="Z")
scene = bpy.context.scene
target = Vector(a.target)
up = Vector(a.up).normalized()

cam_data = bpy.data.cameras.new("top")
cam_data.type = "ORTHO"
cam_data.ortho_scale = a.scale
cam_data.clip_end = 500.0
cam = bpy.data.objects.new("top", cam_data)
scene.collection.objects.link(cam)
cam.location = target + up * 40.0
# The camera looks along its -Z, down -up; its +Y (the top of the image) is the driving
# direction, +z of the OBJ.
forward = Vector((0.0, 0.0, 1.0))
z_cam = up
y_cam = (forward - forward.dot(z_cam) * z_cam).normalized()
x_cam = y_cam.cross(z_cam)
cam.matrix_world = Matrix((
    (x_cam.x, y_cam.x, z_cam.x, cam.location.x),
    (x_cam.y, y_cam.y, z_cam.y, cam.location.y),
    (x_cam.z, y_cam.z, z_cam.z, cam.location.z),
    (0.0, 0.0, 0.0, 1.0)))
scene.camera = cam

render_png(scene, a.out, a.size, a.samples)
print("blender_render_topdown: wrote", a.out)

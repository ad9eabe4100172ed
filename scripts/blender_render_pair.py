# SPDX-License-Identifier: Apache-2.0
# Renders two OBJs (e.g. a run's textured/mesh.obj and semantic/mesh.obj) from the same
# perspective camera with Blender's Cycles on the CPU, without denoising (Debian's Blender 3.4
# has no OpenImageDenoise), and writes them side by side into one image (README's picture):
#   blender --background --factory-startup --python-exit-code 1 \
#       --python scripts/blender_render_pair.py -- LEFT.obj RIGHT.obj OUT.jpg \
#       [--eye X Y Z] [--target X Y Z] [--up X Y Z] [--lens MM] [--size W H] [--samples N]
# Coordinates are the OBJ's own (imported without axis conversion): vdbmap's world is KITTI
# camera 0 at frame 0, so up is -y and the car drives along +z.
import argparse
import os
import sys
import tempfile

import bpy
import numpy as np
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_render_setup import render_png  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
p = argparse.ArgumentParser()
p.add_argument("left")
p.add_argument("right")
p.add_argument("out")
p.add_argument("--eye", type=float, nargs=3, default=[5.0, -8.0, -5.0])
p.add_argument("--target", type=float, nargs=3, default=[-1.0, 2.5, 14.0])
p.add_argument("--up", type=float, nargs=3, default=[0.0, -1.0, 0.0])
p.add_argument("--lens", type=float, default=22.0, help="focal length, mm (36 mm sensor)")
p.add_argument("--size", type=int, nargs=2, default=[640, 400], help="of each half, px")
p.add_argument("--samples", type=int, default=48)
p.add_argument("--gap", type=int, default=8, help="white pixels between the halves")
a = p.parse_args(argv)


def look_at(eye, target, up):
    """World matrix of a Blender camera (looking down its -Z, +Y up) at eye towards target."""
    z_cam = (eye - target).normalized()
    x_cam = up.cross(z_cam).normalized()
    y_cam = z_cam.cross(x_cam)
    return Matrix(((x_cam.x, y_cam.x, z_cam.x, eye.x),
                   (x_cam.y, y_cam.y, z_cam.y, eye.y),
                   (x_cam.z, y_cam.z, z_cam.z, eye.z),
                   (0.0, 0.0, 0.0, 1.0)))


def render(mesh, path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.obj(filepath=mesh, axis_forward="Y", axis_up="Z")
    for material in bpy.data.materials:  # the albedo as it is: no specular highlights
        bsdf = material.node_tree.nodes.get("Principled BSDF") if material.use_nodes else None
        if bsdf is not None:
            bsdf.inputs["Specular"].default_value = 0.0
            bsdf.inputs["Roughness"].default_value = 1.0
    scene = bpy.context.scene
    cam_data = bpy.data.cameras.new("view")
    cam_data.lens = a.lens
    cam_data.clip_end = 1000.0
    cam = bpy.data.objects.new("view", cam_data)
    scene.collection.objects.link(cam)
    cam.matrix_world = look_at(Vector(a.eye), Vector(a.target), Vector(a.up).normalized())
    scene.camera = cam
    scene.view_settings.view_transform = "Standard"  # colours as they are, not Filmic's
    render_png(scene, path, a.size, a.samples)


with tempfile.TemporaryDirectory() as tmp:
    halves = []
    for i, mesh in enumerate((a.left, a.right)):
        path = os.path.join(tmp, "half%d.png" % i)
        render(mesh, path)
        image = bpy.data.images.load(path)
        pixels = np.array(image.pixels[:], dtype=np.float32).reshape(a.size[1], a.size[0], 4)
        halves.append(pixels)
    gap = np.ones((a.size[1], a.gap, 4), dtype=np.float32)
    both = np.concatenate([halves[0], gap, halves[1]], axis=1)
    out = bpy.data.images.new("pair", width=both.shape[1], height=both.shape[0])
    out.pixels = both.ravel()
    scene = bpy.context.scene
    jpeg = a.out.lower().endswith((".jpg", ".jpeg"))
    scene.render.image_settings.file_format = "JPEG" if jpeg else "PNG"
    scene.render.image_settings.quality = 88
    out.save_render(a.out, scene=scene)
print("blender_render_pair: wrote", a.out)

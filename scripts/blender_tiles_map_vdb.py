# SPDX-License-Identifier: Apache-2.0
# Imports tiles' own map.vdb files (tiling.map_vdb: per_tile) side by side in Blender, each
# meshed by a Volume to Mesh modifier over its observed voxels (grid "weight" above 0.05) in a
# colour of its own, and renders the place where they meet with Cycles on the CPU (no
# denoising: Debian's Blender 3.4 has no OpenImageDenoise). Shows that the tiles' files meet
# without gap or overlap (docs/tiling.md, "A map.vdb per tile"):
#   blender --background --factory-startup --python-exit-code 1 \
#       --python scripts/blender_tiles_map_vdb.py -- OUT.png X,Z TILE.vdb [TILE.vdb ...]
# X,Z: the ground point looked at (KITTI's W, camera 0: up is -y), e.g. the corner tiles share.
import math
import os
import sys

import bpy
from mathutils import Vector

COLOURS = [(0.85, 0.35, 0.2, 1), (0.2, 0.5, 0.85, 1), (0.3, 0.75, 0.3, 1), (0.8, 0.75, 0.2, 1)]


def tile_object(index, path, scene):
    """The tile's volume (not rendered) and a mesh object holding its Volume to Mesh."""
    bpy.ops.object.volume_import(filepath=path, files=[{"name": os.path.basename(path)}],
                                 directory=os.path.dirname(path) + "/")
    volume = bpy.context.active_object
    volume.hide_render = True
    holder = bpy.data.objects.new("tile%d" % index, bpy.data.meshes.new("tile%d" % index))
    scene.collection.objects.link(holder)
    modifier = holder.modifiers.new("mesh", "VOLUME_TO_MESH")
    modifier.object = volume
    modifier.grid_name = "weight"
    modifier.threshold = 0.05
    modifier.resolution_mode = "GRID"
    material = bpy.data.materials.new("tile%d" % index)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    for node in list(nodes):
        nodes.remove(node)
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = COLOURS[index % len(COLOURS)]
    links.new(diffuse.outputs["BSDF"], nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    holder.data.materials.append(material)
    return volume


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    out_png, focus_xz, files = args[0], [float(v) for v in args[1].split(",")], args[2:]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    heights = []
    for i, path in enumerate(files):
        volume = tile_object(i, path, scene)
        heights += [(volume.matrix_world @ Vector(c)).y for c in volume.bound_box]
    focus = Vector((focus_xz[0], sum(heights) / len(heights), focus_xz[1]))
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    camera.location = focus + Vector((25.0, -45.0, -30.0))  # above (-y), back along the drive
    camera.rotation_euler = (focus - camera.location).to_track_quat("-Z", "Y").to_euler()
    camera.data.lens = 30
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 4
    sun.rotation_euler = (math.radians(200), math.radians(20), 0)
    scene.collection.objects.link(sun)
    scene.world = bpy.data.worlds.new("world")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = 960, 600
    scene.render.filepath = out_png
    bpy.ops.render.render(write_still=True)


main()

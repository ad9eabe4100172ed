# SPDX-License-Identifier: Apache-2.0
# The set-up our headless Blender renders share (scripts/blender_render_topdown.py,
# scripts/blender_render_pair.py): a white world light, Cycles on the CPU without denoising
# (Debian's Blender 3.4 has no OpenImageDenoise), one PNG still.
import bpy


def render_png(scene, path, size, samples):
    """Lights `scene` by a uniform white world and renders its camera's view to the PNG `path`,
    `size` = (width, height) pixels, `samples` Cycles samples per pixel."""
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.filepath = path
    scene.render.image_settings.file_format = "PNG"
    bpy.ops.render.render(write_still=True)

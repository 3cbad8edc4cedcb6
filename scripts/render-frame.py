#!/usr/bin/env python3
"""Render one frame written by tear (PLY or OBJ, Y up, metres) to a PNG, without a display.

Uses Blender's Python module (`pip install bpy`, Python 3.11) or Blender itself:

    python scripts/render-frame.py out/pull.0048.ply docs/images/demo-pull.png --view front
    blender -b -P scripts/render-frame.py -- out/pull.0048.ply pull.png --view front

The mesh is split into its pieces (connected parts), each drawn in its own colour (the largest first) with the
Workbench engine, under a camera that frames the mesh (its pieces of at least 2 % of the faces;
shreds a tear throws off may lie outside the picture) from --view: `front` (from +z, the side
a sheet of tear's xy plane faces), `top` (from above, at an angle), or a direction X,Y,Z in tear's
coordinates. --sphere X,Y,Z,R adds a sphere (a collider's, in tear's coordinates) to the picture;
--body FILE.obj adds a mesh (a mesh collider where it is at that frame).
"""

import argparse
import math
import sys

import bpy
from mathutils import Vector


def tear_to_blender(v):
    """tear's Y-up coordinates to Blender's Z-up ones, as the importers below convert the mesh."""
    return Vector((v[0], -v[2], v[1]))


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description="Render a tear frame (PLY or OBJ) to PNG, headless.")
    parser.add_argument("frame", help="a frame written by tear: .ply or .obj")
    parser.add_argument("png", help="the picture to write")
    parser.add_argument("--view", default="front", help="front, top, or a direction X,Y,Z (tear's coordinates)")
    parser.add_argument("--size", default="800x600", help="WIDTHxHEIGHT in pixels (default 800x600)")
    parser.add_argument("--sphere", default=None, help="X,Y,Z,R: a sphere to draw (tear's coordinates)")
    parser.add_argument("--body", default=None, help="an OBJ to draw in grey (a mesh collider, tear's coordinates)")
    parser.add_argument("--engine", default="workbench", choices=["workbench", "eevee"])
    return parser.parse_args(argv)


def import_frame(path):
    before = set(bpy.data.objects)
    if path.lower().endswith(".ply"):
        bpy.ops.wm.ply_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    elif path.lower().endswith(".obj"):
        bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    else:
        sys.exit("render-frame: expected a .ply or .obj frame, got " + path)
    imported = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if not imported:
        sys.exit("render-frame: no mesh in " + path)
    return imported


def split_pieces(objects):
    """One object per connected part, so that each piece can have its own colour."""
    bpy.ops.object.select_all(action="DESELECT")
    for o in objects:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.separate(type="LOOSE")
    bpy.ops.object.mode_set(mode="OBJECT")
    return [o for o in bpy.data.objects if o.type == "MESH"]


def main():
    args = parse_args()
    width, height = (int(s) for s in args.size.lower().split("x"))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    pieces = split_pieces(import_frame(args.frame))
    palette = [(0.45, 0.55, 0.85), (0.90, 0.55, 0.35), (0.45, 0.75, 0.50), (0.85, 0.45, 0.65), (0.60, 0.50, 0.85),
               (0.85, 0.75, 0.35)]
    pieces.sort(key=lambda o: -len(o.data.polygons))
    for i, o in enumerate(pieces):
        o.color = palette[i % len(palette)] + (1.0,)
        o.data.materials.clear()
        for polygon in o.data.polygons:
            polygon.use_smooth = False
    print("render-frame: %d piece(s)" % len(pieces))

    # The camera frames the pieces of at least 2 % of the faces: small shreds a tear throws off
    # are drawn, but may fly off the picture.
    faces = sum(len(o.data.polygons) for o in pieces)
    framed = [o for o in pieces if len(o.data.polygons) >= 0.02 * faces] or pieces
    corners = [o.matrix_world @ Vector(c) for o in framed for c in o.bound_box]
    if args.sphere:
        x, y, z, r = (float(s) for s in args.sphere.split(","))
        bpy.ops.mesh.primitive_uv_sphere_add(radius=r, location=tear_to_blender((x, y, z)), segments=48,
                                             ring_count=24)
        sphere = bpy.context.active_object
        bpy.ops.object.shade_smooth()
        sphere.color = (0.75, 0.75, 0.75, 1.0)
    if args.body:
        for o in import_frame(args.body):
            o.color = (0.75, 0.75, 0.75, 1.0)
    lo = Vector((min(c[i] for c in corners) for i in range(3)))
    hi = Vector((max(c[i] for c in corners) for i in range(3)))
    centre = (lo + hi) / 2
    radius = max((hi - lo).length / 2, 1e-3)

    views = {"front": (0.25, 0.3, 1.0), "top": (0.35, 1.0, 0.9)}
    direction = views.get(args.view) or tuple(float(s) for s in args.view.split(","))
    direction = tear_to_blender(direction).normalized()
    camera_data = bpy.data.cameras.new("camera")
    camera_data.lens = 50
    camera = bpy.data.objects.new("camera", camera_data)
    scene.collection.objects.link(camera)
    fov = min(camera_data.angle_x, camera_data.angle_x * height / width)
    camera.location = centre + direction * (radius / math.sin(fov / 2) * 1.05)
    camera.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
    camera_data.clip_end = 1000
    scene.camera = camera

    light_data = bpy.data.lights.new("sun", type="SUN")
    light_data.energy = 3
    light = bpy.data.objects.new("sun", light_data)
    light.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
    scene.collection.objects.link(light)

    world = bpy.data.worlds.new("world")
    world.color = (1.0, 1.0, 1.0)
    scene.world = world
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 100
    scene.render.filepath = args.png
    if args.engine == "workbench":
        scene.render.engine = "BLENDER_WORKBENCH"
        shading = scene.display.shading
        shading.light = "STUDIO"
        shading.color_type = "OBJECT"
        shading.show_backface_culling = False
        shading.show_object_outline = True
        shading.show_cavity = False
        scene.display.render_aa = "8"
    else:
        scene.render.engine = "BLENDER_EEVEE_NEXT" if hasattr(bpy.types, "EEVEE_NEXT") else "BLENDER_EEVEE"
    scene.view_settings.view_transform = "Standard"
    bpy.ops.render.render(write_still=True)
    print("render-frame: wrote " + args.png)


if __name__ == "__main__":
    main()

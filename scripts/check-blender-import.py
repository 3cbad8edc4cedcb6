#!/usr/bin/env python3
"""Imports a USD layer written by tear into Blender (its Python module, `pip install bpy`) and
prints what Blender made of it: the objects, their modifiers, the scene's frame range and rate, and
per frame the evaluated mesh's counts and attributes. docs/cli.md (USD output) records a run.

    python check-blender-import.py shot.usda
"""
import sys

import bpy

path = sys.argv[-1]
bpy.ops.wm.read_factory_settings(use_empty=True)
print("import:", bpy.ops.wm.usd_import(filepath=path))
scene = bpy.context.scene
print("scene: frames %d..%d at %g fps" % (scene.frame_start, scene.frame_end, scene.render.fps / scene.render.fps_base))
print("objects:", [(o.name, o.type, o.parent.name if o.parent else None) for o in bpy.data.objects])
for o in bpy.data.objects:
    if o.type != "MESH":
        continue
    for m in o.modifiers:
        print("modifier:", m.name, m.type,
              "reads %s from %s" % (m.object_path, m.cache_file.filepath) if m.type == "MESH_SEQUENCE_CACHE" else "")
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        evaluated = o.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = evaluated.to_mesh()
        tear_edge = mesh.attributes.get("tear_edge")
        velocity = mesh.attributes.get("velocity")
        print("frame %d: %d vertices, %d faces, UV maps %s, %s corners on a tear, largest |velocity| %s, attributes %s"
              % (frame, len(mesh.vertices), len(mesh.polygons), [uv.name for uv in mesh.uv_layers],
                 sum(1 for v in tear_edge.data if v.value) if tear_edge else "no",
                 "%.3f" % max(abs(c) for v in velocity.data for c in v.vector) if velocity else "none",
                 sorted("%s (%s)" % (a.name, a.domain.lower()) for a in mesh.attributes if not a.name.startswith("."))))
        evaluated.to_mesh_clear()

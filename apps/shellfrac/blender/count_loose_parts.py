"""Counts the loose parts of a shellfrac frame as Blender sees them: a real-client check of our counts.

    blender -b --factory-startup -noaudio --python-exit-code 1 -P count_loose_parts.py -- FRAME [--join]
        [--weld-distance D]

Imports FRAME with Blender's importer for its format (bpy.ops.wm.obj_import for OBJ, Blender 3.4's C++
importer), counts loose parts of every imported mesh object with bmesh, and prints one JSON line
starting with "loose-parts: ":
    {"file": ..., "objects": {name: parts, ...}, "total": sum over objects, "welded": parts over all
     objects once patches are joined along their seams, "vertices": n, "faces": n}
--join first joins all objects into one (bpy.ops.object.join, which welds nothing), so "total" is then
counted on the joined object. "welded" also joins two patches' parts where a boundary vertex of one lies
within --weld-distance (default 1e-4 m, Blender's "Merge by Distance" default) of the other's faces: the
seams, which is how a multi-patch garment falls into pieces. Patches are objects, or in an OBJ frame (one
object in Blender 3.4) the shells' groups, kept as vertex groups. For one patch it equals "total".
"""
import argparse
import json
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import shellfrac_mesh as mesh  # noqa: E402  (the helpers `shellfrac preview` uses too)


def main():
    ap = argparse.ArgumentParser(prog="count_loose_parts.py")
    ap.add_argument("frame")
    ap.add_argument("--join", action="store_true", help="join all imported objects first")
    ap.add_argument("--weld-distance", type=float, default=mesh.WELD_DISTANCE)
    args = ap.parse_args(mesh.script_arguments())
    mesh.empty_scene()
    objects = mesh.import_frame(args.frame)
    _, _, _, welded = mesh.welded_parts(objects, args.weld_distance)
    vertices = sum(len(o.data.vertices) for o in objects)
    faces = sum(len(o.data.polygons) for o in objects)
    names = [o.name for o in objects]
    if args.join and len(objects) > 1:
        bpy.ops.object.select_all(action="DESELECT")
        for o in objects:
            o.select_set(True)
        bpy.context.view_layer.objects.active = objects[0]
        bpy.ops.object.join()
        objects = [bpy.context.view_layer.objects.active]
    per_object = {o.name: mesh.loose_parts(o)[1] for o in objects}
    record = {
        "file": args.frame, "imported_objects": names, "objects": per_object, "joined": bool(args.join),
        "total": sum(per_object.values()), "welded": welded, "weld_distance": args.weld_distance,
        "vertices": vertices, "faces": faces, "blender": bpy.app.version_string,
    }
    print("loose-parts: " + json.dumps(record), flush=True)


if __name__ == "__main__":
    main()

"""Renders one brittle fracture event (OUT/brittle/<solid>_event_0_*.obj) to a PNG with Blender's
Workbench engine, to look at the fragments: every fragment in its own colour, pulled apart from the
solid's centre by a fraction of its size so that the cracks show; the crack surface in red beside them
(or alone when the solid stayed in one piece).

    blender -b --python scripts/render_fracture_event.py -- OUT/brittle/slab_event_0_fragments.obj out.png [--explode 0.15]
        [--size 800x600] [--direction 0.55,-1.0,0.8]
"""
import argparse
import colorsys
import os
import sys

import bpy
from mathutils import Vector


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("fragments")
    p.add_argument("png")
    p.add_argument("--explode", type=float, default=0.15, help="fragments move this fraction of the solid's size")
    p.add_argument("--size", default="800x600")
    p.add_argument("--direction", default="0.55,-1.0,0.8", help="from the scene's centre towards the camera, x,y,z")
    return p.parse_args(argv)


def import_obj(path):
    before = set(bpy.data.objects)
    bpy.ops.import_scene.obj(filepath=path, split_mode="ON", axis_forward="Y", axis_up="Z")
    return [o for o in bpy.data.objects if o not in before and o.type == "MESH"]


def world_box(objects):
    lo = Vector((1e30, 1e30, 1e30))
    hi = -lo
    for o in objects:
        for c in o.bound_box:
            w = o.matrix_world @ Vector(c)
            lo = Vector(map(min, lo, w))
            hi = Vector(map(max, hi, w))
    return lo, hi


def main():
    a = arguments()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    fragments = import_obj(a.fragments)
    crack_path = a.fragments.replace("_fragments.obj", "_crack.obj")
    # (A rigid frame has no crack file; its name has no "_fragments.obj" to replace.)
    cracks = import_obj(crack_path) if crack_path != a.fragments and os.path.exists(crack_path) else []
    lo, hi = world_box(fragments)
    centre, size = (lo + hi) / 2, (hi - lo).length
    for k, o in enumerate(fragments):
        # Centroid of the vertices: good enough to pull the pieces apart.
        c = sum((o.matrix_world @ v.co for v in o.data.vertices), Vector()) / max(1, len(o.data.vertices))
        d = c - centre
        if d.length > 0:
            o.location += d.normalized() * a.explode * size
        o.color = (*colorsys.hsv_to_rgb((0.61803 * k) % 1.0, 0.55, 0.95), 1.0)
    # The crack surface beside the solid (shifted by 1.2 sizes along x), in red.
    for o in cracks:
        o.location.x += 1.2 * size
        o.color = (0.9, 0.1, 0.1, 1.0)
    everything = fragments + cracks
    bpy.context.view_layer.update()  # matrix_world after the moves
    lo, hi = world_box(everything)
    target, extent = (lo + hi) / 2, (hi - lo).length
    cam_data = bpy.data.cameras.new("camera")
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    direction = Vector(tuple(float(x) for x in a.direction.split(","))).normalized()
    cam.location = target + direction * extent * 1.6
    cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
    cam_data.lens = 40
    scene = bpy.context.scene
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "OBJECT"
    scene.display.shading.show_cavity = True
    w, h = (int(x) for x in a.size.split("x"))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.filepath = os.path.abspath(a.png)
    bpy.ops.render.render(write_still=True)
    print(f"rendered {len(fragments)} fragment object(s) and {len(cracks)} crack object(s) to {a.png}")


main()

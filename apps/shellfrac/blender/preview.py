"""Blender-side half of `shellfrac preview`: renders frames of a shellfrac run to PNG, plus a contact sheet.

Run by the shellfrac binary (which embeds this file and shellfrac_mesh.py) as
    blender -b --factory-startup -noaudio --python-exit-code 1 -P preview.py -- \
        --out PNG_DIR [--staging DIR] --size W H --samples N [--threads N] [--rest FRAME0] \
        [--sliver-area A] --frame NUMBER PATH [--frame NUMBER PATH ...]
Lines starting with "shellfrac-preview: " are progress for the user; PNG_DIR/preview.json records the
numbers. Every file is written into the staging folder (default PNG_DIR; shellfrac passes a private one
inside PNG_DIR and removes it afterwards) and moved into PNG_DIR only when complete, so an interrupted
or failed render leaves no partial image under a final name. Importing, loose parts and edge stretch live in shellfrac_mesh.py, shared with count_loose_parts.py.

What the picture shows, and why:
  * colour = one loose part (after welding patches along their seams), largest part first, so a tear
    that came apart shows two colours and a sheet still held by strands shows one;
  * red = faces with an edge stretched more than STRAND_STRETCH times its rest length (strands, needles);
  * yellow markers = parts smaller than the sliver area (one simulation cell), too small to see;
  * back faces are drawn darker than front faces, and a faint wireframe shows the render mesh;
  * the camera frames the bounding box of all chosen frames and does not move between them.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shellfrac_mesh import (  # noqa: E402  (next to this file, in the repository and when embedded)
    edge_stretch, empty_scene, face_area_by_class, import_frame, remove_objects, rest_shapes, script_arguments,
    welded_parts, WELD_DISTANCE)

PREFIX = "shellfrac-preview: "
STRAND_STRETCH = 3.0  # strand threshold: a render edge over 3x its rest length


def say(message):
    print(PREFIX + message, flush=True)


PNG_END = b"IEND\xae\x42\x60\x82"  # the last chunk of every complete PNG


def publish(staged, final):
    """Moves a finished file from the staging folder to its final name, after checking that a PNG is
    complete (Blender does not fail a render whose image could not be written whole) and syncing it."""
    with open(staged, "rb") as f:
        if staged.endswith(".png"):
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - len(PNG_END)))
            if size < 16 or f.read() != PNG_END:
                raise RuntimeError("cannot write %s: the image is incomplete (%d bytes; is the disk full?)" % (final, size))
        os.fsync(f.fileno())
    os.replace(staged, final)


# ---------------------------------------------------------------------------------------------------
# Scene: camera, light, material


def bounding_box(objects):
    lo = Vector((math.inf,) * 3)
    hi = Vector((-math.inf,) * 3)
    for o in objects:
        for v in o.data.vertices:
            lo = Vector(map(min, lo, v.co))
            hi = Vector(map(max, hi, v.co))
    return lo, hi


def view_direction(lo, hi):
    """Unit vector from the target towards the camera: a thin box (a sheet) is seen nearly face-on, tilted
    so that folds read; a bulky one from a three-quarter view."""
    ext = hi - lo
    thin = min(range(3), key=lambda i: ext[i])
    if ext[thin] > 0.5 * max(ext):
        return Vector((0.55, -0.75, 0.45)).normalized()
    tilt, turn = math.radians(20.0), math.radians(15.0)
    if thin == 2:  # lying flat: from above, a little from the front
        d = Vector((math.sin(turn) * math.sin(tilt * 1.5), -math.cos(turn) * math.sin(tilt * 1.5), math.cos(tilt * 1.5)))
    elif thin == 1:  # upright, facing -Y (Blender's front view)
        d = Vector((math.sin(turn), -math.cos(turn), math.tan(tilt)))
    else:  # upright, facing +X
        d = Vector((math.cos(turn), math.sin(turn), math.tan(tilt)))
    return d.normalized()


def place_camera(lo, hi, width, height):
    cam_data = bpy.data.cameras.new("preview")
    cam_data.lens, cam_data.sensor_width, cam_data.sensor_fit = 50.0, 36.0, "HORIZONTAL"
    cam = bpy.data.objects.new("preview camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    back = view_direction(lo, hi)
    cam.rotation_euler = (-back).to_track_quat("-Z", "Y").to_euler()
    rot = cam.rotation_euler.to_matrix()
    right, up = rot.col[0], rot.col[1]
    tan_x = math.tan(math.atan(18.0 / 50.0)) * 0.9  # 10% margin
    tan_y = tan_x * height / width
    centre = (lo + hi) / 2
    distance = 1e-3
    for i in range(8):
        corner = Vector((hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2]))
        q = corner - centre
        z = q.dot(back)
        distance = max(distance, z + abs(q.dot(right)) / tan_x, z + abs(q.dot(up)) / tan_y)
    cam.location = centre + back * distance
    diagonal = max((hi - lo).length, 1e-6)
    cam_data.clip_start = max(distance - diagonal, distance * 1e-3, 1e-6) * 0.5
    cam_data.clip_end = (distance + diagonal) * 2
    bpy.context.scene.camera = cam
    return cam, back, right, up, diagonal


def add_lights_and_world(back, right, up):
    # A key sun from the camera's upper left and an even grey sky: neither assumes a ground plane.
    sun_data = bpy.data.lights.new("key", "SUN")
    sun_data.energy, sun_data.angle = 3.0, math.radians(12.0)
    sun = bpy.data.objects.new("key light", sun_data)
    bpy.context.scene.collection.objects.link(sun)
    towards_light = (back * 0.8 + up * 0.7 - right * 0.5).normalized()
    sun.rotation_euler = (-towards_light).to_track_quat("-Z", "Y").to_euler()

    world = bpy.data.worlds.new("preview")
    bpy.context.scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    sky = nodes.new("ShaderNodeBackground")
    sky.inputs["Color"].default_value = (0.62, 0.64, 0.68, 1)
    sky.inputs["Strength"].default_value = 0.9
    backdrop = nodes.new("ShaderNodeBackground")  # what the camera sees behind the meshes
    backdrop.inputs["Color"].default_value = (0.035, 0.04, 0.05, 1)
    path = nodes.new("ShaderNodeLightPath")
    mix = nodes.new("ShaderNodeMixShader")
    out = nodes.new("ShaderNodeOutputWorld")
    links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    links.new(sky.outputs["Background"], mix.inputs[1])
    links.new(backdrop.outputs["Background"], mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])


def part_material():
    """Colour from the "preview" corner attribute; back faces darker; a faint wireframe."""
    mat = bpy.data.materials.new("shellfrac preview")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    attr = nodes.new("ShaderNodeAttribute")
    attr.attribute_name = "preview"
    geometry = nodes.new("ShaderNodeNewGeometry")
    darker = nodes.new("ShaderNodeMixRGB")
    darker.blend_type = "MULTIPLY"
    darker.inputs["Color2"].default_value = (0.45, 0.45, 0.5, 1)
    links.new(geometry.outputs["Backfacing"], darker.inputs["Fac"])
    links.new(attr.outputs["Color"], darker.inputs["Color1"])
    wire = nodes.new("ShaderNodeWireframe")
    wire.use_pixel_size = True
    wire.inputs["Size"].default_value = 1.0
    wire_strength = nodes.new("ShaderNodeMath")
    wire_strength.operation = "MULTIPLY"
    wire_strength.inputs[1].default_value = 0.18
    links.new(wire.outputs["Fac"], wire_strength.inputs[0])
    lines = nodes.new("ShaderNodeMixRGB")
    lines.inputs["Color2"].default_value = (0, 0, 0, 1)
    links.new(wire_strength.outputs["Value"], lines.inputs["Fac"])
    links.new(darker.outputs["Color"], lines.inputs["Color1"])
    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Roughness"].default_value = 0.65
    bsdf.inputs["Specular"].default_value = 0.25
    links.new(lines.outputs["Color"], bsdf.inputs["Base Color"])
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def marker_material():
    mat = bpy.data.materials.new("sliver marker")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    emit = nodes.new("ShaderNodeEmission")
    emit.inputs["Color"].default_value = (1.0, 0.85, 0.05, 1)
    emit.inputs["Strength"].default_value = 2.0
    out = nodes.new("ShaderNodeOutputMaterial")
    mat.node_tree.links.new(emit.outputs["Emission"], out.inputs["Surface"])
    return mat


def palette(i):
    """Distinct, fairly light colours by golden-ratio hue steps; 0 (the largest part) is a pale blue."""
    h = (0.58 + 0.381966 * i) % 1.0
    s, v = (0.45, 0.85) if i == 0 else (0.6, 0.9)
    k = [(n + h * 6) % 6 for n in (5, 3, 1)]
    return tuple(v - v * s * max(0.0, min(kk, 4 - kk, 1.0)) for kk in k)


STRAND_RED = (0.9, 0.02, 0.02)


def colour_frame(objects, rest, sliver_area, marker_radius, mat, marker_mat, collection):
    """Writes the "preview" colours and sliver markers for one frame; returns its numbers."""
    per_object, offsets, classes, n_classes = welded_parts(objects)
    area, centre = face_area_by_class(objects, per_object, offsets, classes, n_classes)
    order = sorted(range(n_classes), key=lambda c: -area[c])
    rank = {c: r for r, c in enumerate(order)}
    max_stretch, strand_faces, strand_area, reference = 0.0, 0, 0.0, set()
    for o, (part, _), off in zip(objects, per_object, offsets):
        me = o.data
        stretch, ref = edge_stretch(o, rest)
        reference.update(r for r in ref.split("+") if r)
        if stretch:
            max_stretch = max(max_stretch, max(stretch.values()))
        long_edges = {me.edges[i].key for i, s in stretch.items() if s > STRAND_STRETCH}
        colours = [0.0] * (4 * len(me.loops))
        for p in me.polygons:
            strand = any(k in long_edges for k in p.edge_keys)
            if strand:
                strand_faces += 1
                strand_area += p.area
            c = STRAND_RED if strand else palette(rank[classes[off + part[p.vertices[0]]]])
            for li in p.loop_indices:
                colours[4 * li:4 * li + 4] = (c[0], c[1], c[2], 1.0)
        attr = me.color_attributes.new(name="preview", type="FLOAT_COLOR", domain="CORNER")
        attr.data.foreach_set("color", colours)
        me.materials.clear()
        me.materials.append(mat)
    slivers = [c for c in range(n_classes) if area[c] < sliver_area]
    for c in slivers:
        bpy.ops.mesh.primitive_uv_sphere_add(radius=marker_radius, location=centre[c], segments=12, ring_count=6)
        marker = bpy.context.active_object
        marker.data.materials.append(marker_mat)
        for coll in marker.users_collection:
            coll.objects.unlink(marker)
        collection.objects.link(marker)
    return {
        "objects": len(objects),
        "loose_parts": n_classes,
        "loose_parts_per_object": {o.name: n for o, (_, n) in zip(objects, per_object)},
        "slivers": len(slivers),
        "sliver_area": sum(area[c] for c in slivers),
        "part_areas": [area[c] for c in order],
        "max_edge_stretch": max_stretch,
        "strand_faces": strand_faces,
        "strand_area": strand_area,
        "stretch_reference": "+".join(sorted(reference)),
    }




def set_up_render(width, height, samples, threads):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    if hasattr(bpy.context.view_layer, "cycles"):
        bpy.context.view_layer.cycles.use_denoising = False
    scene.cycles.max_bounces, scene.cycles.diffuse_bounces, scene.cycles.glossy_bounces = 3, 2, 1
    scene.cycles.transmission_bounces, scene.cycles.transparent_max_bounces = 0, 2
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.view_settings.view_transform = "Standard"
    if threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads


# ---------------------------------------------------------------------------------------------------
# Contact sheet: thumbnails with frame numbers, composed with numpy (bundled with Blender)

DIGITS = {  # 5 x 7 glyphs, top row first
    "0": ["01110", "10001", "10011", "10101", "11001", "10001", "01110"],
    "1": ["00100", "01100", "00100", "00100", "00100", "00100", "01110"],
    "2": ["01110", "10001", "00001", "00010", "00100", "01000", "11111"],
    "3": ["11110", "00001", "00001", "01110", "00001", "00001", "11110"],
    "4": ["00010", "00110", "01010", "10010", "11111", "00010", "00010"],
    "5": ["11111", "10000", "11110", "00001", "00001", "10001", "01110"],
    "6": ["00110", "01000", "10000", "11110", "10001", "10001", "01110"],
    "7": ["11111", "00001", "00010", "00100", "01000", "01000", "01000"],
    "8": ["01110", "10001", "10001", "01110", "10001", "10001", "01110"],
    "9": ["01110", "10001", "10001", "01111", "00001", "00010", "01100"],
}


def contact_sheet(pngs, labels, path, thumb_width=240):
    import numpy as np

    first = bpy.data.images.load(pngs[0])
    w0, h0 = first.size
    bpy.data.images.remove(first)
    tw = min(thumb_width, w0)
    th = max(1, round(h0 * tw / w0))
    scale, strip, pad = 2, 7 * 2 + 8, 6
    cols = min(len(pngs), max(1, math.ceil(math.sqrt(len(pngs)))), 8)
    rows = math.ceil(len(pngs) / cols)
    cell_w, cell_h = tw + pad, th + strip + pad
    sheet_w, sheet_h = cols * cell_w + pad, rows * cell_h + pad
    sheet = np.zeros((sheet_h, sheet_w, 4), dtype=np.float32)  # row 0 = top
    sheet[..., :3], sheet[..., 3] = 0.12, 1.0
    for k, (png, label) in enumerate(zip(pngs, labels)):
        img = bpy.data.images.load(png)
        img.scale(tw, th)
        px = np.array(img.pixels[:], dtype=np.float32).reshape(th, tw, 4)[::-1]  # Blender rows: bottom first
        bpy.data.images.remove(img)
        x0, y0 = pad + (k % cols) * cell_w, pad + (k // cols) * cell_h
        sheet[y0:y0 + th, x0:x0 + tw] = px
        sheet[y0:y0 + th, x0:x0 + tw, 3] = 1.0
        gx, gy = x0 + 2, y0 + th + 4
        for ch in str(label):
            for r, row in enumerate(DIGITS[ch]):
                for c, bit in enumerate(row):
                    if bit == "1":
                        sheet[gy + r * scale:gy + (r + 1) * scale, gx + c * scale:gx + (c + 1) * scale, :3] = 0.95
            gx += 6 * scale
    out = bpy.data.images.new("contact sheet", sheet_w, sheet_h, alpha=False)
    out.pixels.foreach_set(sheet[::-1].ravel())
    out.filepath_raw = path
    out.file_format = "PNG"
    out.save()
    return [sheet_w, sheet_h]


# ---------------------------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(prog="preview.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--staging", default=None, help="folder for files being written (default: --out)")
    ap.add_argument("--size", nargs=2, type=int, default=[640, 480])
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--rest", default=None, help="frame 0, the rest state for edge stretch")
    ap.add_argument("--sliver-area", type=float, default=0.0)
    ap.add_argument("--frame", nargs=2, action="append", metavar=("NUMBER", "PATH"), required=True)
    args = ap.parse_args(script_arguments())
    width, height = args.size
    frames = [(int(n), p) for n, p in args.frame]
    os.makedirs(args.out, exist_ok=True)
    staging = args.staging or args.out
    started = time.perf_counter()

    empty_scene()
    set_up_render(width, height, args.samples, args.threads)
    rest = {}
    if args.rest:
        rest_objects = import_frame(args.rest)
        rest = rest_shapes(rest_objects)
        for o in rest_objects:
            o.name = "rest " + o.name  # frees the shell names for the frames
            o.hide_render = True
    # Pass 1: one bounding box over every chosen frame, so the camera does not move between frames.
    lo, hi = Vector((math.inf,) * 3), Vector((-math.inf,) * 3)
    for _, path in frames:
        objects = import_frame(path)
        if objects:
            a, b = bounding_box(objects)
            lo, hi = Vector(map(min, lo, a)), Vector(map(max, hi, b))
        remove_objects(objects)
    if not all(math.isfinite(x) for x in lo):
        lo, hi = Vector((-1, -1, -1)), Vector((1, 1, 1))
    cam, back, right, up, diagonal = place_camera(lo, hi, width, height)
    camera = {"location": list(cam.location), "matrix": [list(row) for row in cam.rotation_euler.to_matrix()],
              "lens": cam.data.lens, "sensor_width": cam.data.sensor_width}
    add_lights_and_world(back, right, up)
    mat, marker_mat = part_material(), marker_material()
    say("camera framing box %s .. %s (all %d frame(s)); %dx%d px, %d samples, Cycles on the CPU, no denoiser"
        % (tuple(round(x, 3) for x in lo), tuple(round(x, 3) for x in hi), len(frames), width, height, args.samples))

    # Pass 2: import, colour, render, remove, frame by frame.
    records, pngs = [], []
    for number, path in frames:
        collection = bpy.data.collections.new("frame %d" % number)
        bpy.context.scene.collection.children.link(collection)
        objects = import_frame(path, collection)
        record = colour_frame(objects, rest, args.sliver_area, 0.012 * diagonal, mat, marker_mat, collection)
        png = os.path.join(args.out, "frame_%05d.png" % number)
        staged = os.path.join(staging, ".frame_%05d.partial.png" % number)
        bpy.context.scene.render.filepath = staged
        t0, c0 = time.perf_counter(), time.process_time()
        bpy.ops.render.render(write_still=True)
        publish(staged, png)
        record.update({"frame": number, "file": path, "png": png, "render_seconds": time.perf_counter() - t0,
                       "render_cpu_seconds": time.process_time() - c0})
        records.append(record)
        pngs.append(png)
        say("frame %d: %s (%.2f s): %d loose part(s), %d sliver(s), max edge stretch %.2f, %d strand face(s)"
            % (number, png, record["render_seconds"], record["loose_parts"], record["slivers"],
               record["max_edge_stretch"], record["strand_faces"]))
        remove_objects(list(collection.objects))
        bpy.data.collections.remove(collection)

    sheet = os.path.join(args.out, "contact_sheet.png")
    staged_sheet = os.path.join(staging, ".contact_sheet.partial.png")
    sheet_size = contact_sheet(pngs, [n for n, _ in frames], staged_sheet)
    publish(staged_sheet, sheet)
    say("contact sheet: %s (%d x %d px)" % (sheet, sheet_size[0], sheet_size[1]))
    seconds = [r["render_seconds"] for r in records]
    summary = {
        "size": [width, height], "samples": args.samples, "engine": "CYCLES (CPU, no denoiser)",
        "blender_version": bpy.app.version_string, "strand_stretch": STRAND_STRETCH, "weld_distance": WELD_DISTANCE,
        "sliver_area": args.sliver_area, "camera_box": [list(lo), list(hi)], "camera": camera, "frames": records,
        "contact_sheet": sheet, "contact_sheet_size": sheet_size,
        "render_seconds_per_frame": sum(seconds) / len(seconds),
        "render_cpu_seconds_per_frame": sum(r["render_cpu_seconds"] for r in records) / len(records),
        "wall_seconds": time.perf_counter() - started,
    }
    tmp = os.path.join(staging, ".preview.json.tmp")
    with open(tmp, "w") as f:
        json.dump(summary, f, indent=2)
    publish(tmp, os.path.join(args.out, "preview.json"))


if __name__ == "__main__":
    main()

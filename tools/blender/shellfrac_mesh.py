"""Mesh side of shellfrac's Blender tools: import a frame file with Blender's importer for its format, count
loose parts (optionally across patch seams), and measure edge stretch against the rest state.
Used by preview.py (the `shellfrac preview` renderer) and count_loose_parts.py (the real-client check), so
both count alike. Runs inside Blender (bpy, bmesh, mathutils)."""
import os
import re
import sys

import bmesh
import bpy
from mathutils import Matrix, Vector
from mathutils.bvhtree import BVHTree
from mathutils.geometry import barycentric_transform

# Importers by file extension; the shellfrac binary refuses other formats before Blender starts. Not
# readable by Blender 3.4 (Debian): FBX (it cannot parse assimp's binary FBX, and reads no ASCII FBX), X3D
# (its importer opens files with mode "rU", gone in Python 3.11).
SUPPORTED_EXTENSIONS = (".obj", ".ply", ".stl", ".gltf", ".glb", ".dae")
WELD_DISTANCE = 1.0e-4    # seam weld tolerance [m]; Blender's own "Merge by Distance" default
# shellfrac's +y points against gravity (scene default [0, -9.81, 0]), as OBJ and glTF assume; the
# importers that do not convert Y-up to Blender's Z-up get this rotation: (x, y, z) -> (x, -z, y).
Y_UP_TO_Z_UP = Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))


def script_arguments():
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def import_frame(path, collection=None):
    """Imports one frame file; returns its mesh objects with their transforms applied to the vertices
    (so vertex coordinates are world coordinates, Blender Z-up), in the given collection."""
    ext = os.path.splitext(path)[1].lower()
    if ext not in SUPPORTED_EXTENSIONS:
        raise SystemExit("cannot import %s: supported frame formats are %s" % (path, ", ".join(SUPPORTED_EXTENSIONS)))
    if collection is not None:
        bpy.context.view_layer.active_layer_collection = bpy.context.view_layer.layer_collection.children[collection.name]
    before = set(bpy.data.objects)
    rotate = False
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path)  # Blender 3.4's C++ importer; its defaults convert Y-up
    elif ext == ".ply":
        bpy.ops.import_mesh.ply(filepath=path)  # no axis conversion in this importer
        rotate = True
    elif ext == ".stl":
        bpy.ops.import_mesh.stl(filepath=path, axis_forward="-Z", axis_up="Y")
    elif ext in (".gltf", ".glb"):
        import numpy
        if "bool" not in numpy.__dict__:  # Blender 3.4's glTF add-on uses numpy.bool, gone since numpy 1.24
            numpy.bool = bool
        bpy.ops.import_scene.gltf(filepath=path, merge_vertices=False)
    elif ext == ".fbx":
        bpy.ops.import_scene.fbx(filepath=path)
    elif ext == ".dae":
        bpy.ops.wm.collada_import(filepath=path)
    elif ext == ".x3d":
        bpy.ops.import_scene.x3d(filepath=path)
    new = [o for o in bpy.data.objects if o not in before]
    meshes = [o for o in new if o.type == "MESH"]
    for o in meshes:
        world = o.matrix_world.copy()
        if rotate:
            world = Y_UP_TO_Z_UP @ world
        o.parent = None
        o.data.transform(world)
        o.matrix_world = Matrix.Identity(4)
    for o in new:
        if o.type != "MESH":
            bpy.data.objects.remove(o)
    return meshes


def remove_objects(objects):
    for o in objects:
        mesh = o.data
        bpy.data.objects.remove(o)
        if mesh is not None and mesh.users == 0:
            bpy.data.meshes.remove(mesh)


def loose_parts(obj):
    """Loose parts of one mesh object, as Blender's "Separate by Loose Parts" sees them (vertices joined
    by edges; a vertex without edges is a part of its own). Returns (part index per vertex, count)."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    part = [-1] * len(bm.verts)
    count = 0
    for start in bm.verts:
        if part[start.index] >= 0:
            continue
        part[start.index] = count
        stack = [start]
        while stack:
            v = stack.pop()
            for e in v.link_edges:
                w = e.other_vert(v)
                if part[w.index] < 0:
                    part[w.index] = count
                    stack.append(w)
        count += 1
    bm.free()
    return part, count


class UnionFind:
    def __init__(self, n):
        self.parent = list(range(n))

    def find(self, i):
        while self.parent[i] != i:
            self.parent[i] = self.parent[self.parent[i]]
            i = self.parent[i]
        return i

    def union(self, a, b):
        a, b = self.find(a), self.find(b)
        if a != b:
            self.parent[max(a, b)] = min(a, b)


def welded_parts(objects, weld_distance=WELD_DISTANCE):
    """Loose parts over several objects, joining two objects' parts where a boundary vertex of one lies
    within weld_distance of the other's surface (patch seams: the frames keep patches as separate objects,
    and non-conforming seams do not share vertices). Returns (per object: (part per vertex, count),
    class per global part, number of classes); global part ids number the objects' parts in order."""
    per_object = [loose_parts(o) for o in objects]
    offsets, total = [], 0
    for _, n in per_object:
        offsets.append(total)
        total += n
    uf = UnionFind(total)
    if len(objects) > 1 and weld_distance > 0:
        trees = []
        for o in objects:
            me = o.data
            trees.append(BVHTree.FromPolygons([v.co for v in me.vertices], [list(p.vertices) for p in me.polygons])
                         if len(me.polygons) else None)
        for a, oa in enumerate(objects):
            bm = bmesh.new()
            bm.from_mesh(oa.data)
            boundary = [v.co.copy() for v in bm.verts if v.is_boundary]
            indices = [v.index for v in bm.verts if v.is_boundary]
            bm.free()
            for b, ob in enumerate(objects):
                if b == a or trees[b] is None:
                    continue
                polys = ob.data.polygons
                for co, vi in zip(boundary, indices):
                    hit = trees[b].find_nearest(co, weld_distance)
                    if hit[0] is not None:
                        pb = per_object[b][0][polys[hit[2]].vertices[0]]
                        uf.union(offsets[a] + per_object[a][0][vi], offsets[b] + pb)
    roots = {}
    classes = [roots.setdefault(uf.find(g), len(roots)) for g in range(total)]
    return per_object, offsets, classes, len(roots)


def face_area_by_class(objects, per_object, offsets, classes, n_classes):
    area = [0.0] * n_classes
    centre = [Vector((0, 0, 0)) for _ in range(n_classes)]
    for o, (part, _), off in zip(objects, per_object, offsets):
        for p in o.data.polygons:
            c = classes[off + part[p.vertices[0]]]
            area[c] += p.area
            centre[c] += p.area * p.center
    return area, [centre[c] / area[c] if area[c] > 0 else centre[c] for c in range(n_classes)]


class RestShape:
    """Rest positions of one patch as a function of its UV (the patch parameters shellfrac writes as
    texture coordinates): the frame-0 mesh, triangulated, searched in the UV plane."""

    def __init__(self, obj):
        me = obj.data
        self.ok = bool(me.uv_layers) and len(me.polygons) > 0
        if not self.ok:
            return
        uv = me.uv_layers.active.data
        self.uv, self.xyz, self.tris = [], [], []
        for p in me.polygons:
            loops = list(p.loop_indices)
            for k in range(1, len(loops) - 1):
                self.tris.append([len(self.uv), len(self.uv) + 1, len(self.uv) + 2])
                for li in (loops[0], loops[k], loops[k + 1]):
                    self.uv.append(Vector((uv[li].uv[0], uv[li].uv[1], 0.0)))
                    self.xyz.append(me.vertices[me.loops[li].vertex_index].co.copy())
        self.tree = BVHTree.FromPolygons(self.uv, self.tris)

    def position(self, u, v):
        q = Vector((u, v, 0.0))
        hit = self.tree.find_nearest(q)
        if hit[0] is None:
            return None
        a, b, c = self.tris[hit[2]]
        p = hit[0]
        return barycentric_transform(p, self.uv[a], self.uv[b], self.uv[c], self.xyz[a], self.xyz[b], self.xyz[c])


def edge_stretch(obj, rest):
    """World length over rest length for every edge of obj (rest length from the frame-0 mesh through
    the UVs); without UVs or a rest shape, over the median edge length of obj instead. Returns a dict
    edge index -> stretch, and the name of the reference used."""
    me = obj.data
    lengths = {e.index: (me.vertices[e.vertices[0]].co - me.vertices[e.vertices[1]].co).length for e in me.edges}
    if rest is not None and rest.ok and me.uv_layers:
        uv = me.uv_layers.active.data
        vertex_uv = {}
        for li, loop in enumerate(me.loops):
            vertex_uv.setdefault(loop.vertex_index, uv[li].uv.copy())
        rest_of = {}
        for vi, t in vertex_uv.items():
            rest_of[vi] = rest.position(t[0], t[1])
        out = {}
        for e in me.edges:
            a, b = rest_of.get(e.vertices[0]), rest_of.get(e.vertices[1])
            if a is None or b is None:
                continue
            rl = (a - b).length
            if rl > 0:
                out[e.index] = lengths[e.index] / rl
        if out:
            return out, "rest"
    values = sorted(lengths.values())
    median = values[len(values) // 2] if values else 0.0
    return ({i: l / median for i, l in lengths.items()} if median > 0 else {}), "median"


def base_name(name):
    """An imported object's name without the ".001" Blender appends when the name is taken."""
    return re.sub(r"\.\d{3}$", "", name)

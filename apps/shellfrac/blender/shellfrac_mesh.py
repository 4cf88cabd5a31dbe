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
        # Blender 3.4's C++ importer; its default axes convert Y-up. It makes one object per file and
        # ignores the "g" lines naming the shells unless asked to keep them as vertex groups.
        bpy.ops.wm.obj_import(filepath=path, import_vertex_groups=True)
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


def patch_of_faces(obj):
    """The patch (shell) name of every face of obj. OBJ frames name the shells with groups, which Blender
    3.4 imports as vertex groups (import_vertex_groups); glTF and COLLADA give each shell an object of its
    own; a format with neither (PLY, STL: all shells in one object) is one patch as far as Blender can tell."""
    me = obj.data
    default = base_name(obj.name)
    names = {g.index: g.name for g in obj.vertex_groups}
    if not names:
        return [default] * len(me.polygons)
    groups = [{g.group for g in v.groups} for v in me.vertices]
    out = []
    for p in me.polygons:
        common = set.intersection(*(groups[i] for i in p.vertices))
        out.append(names[min(common)] if common else default)
    return out


def patches(objects):
    """[(object index, patch name, face indices)] over all objects."""
    out = []
    for oi, o in enumerate(objects):
        faces = {}
        for fi, name in enumerate(patch_of_faces(o)):
            faces.setdefault(name, []).append(fi)
        out.extend((oi, name, f) for name, f in faces.items())
    return out


def welded_parts(objects, weld_distance=WELD_DISTANCE):
    """Loose parts over several objects and patches, joining two patches' parts where a boundary vertex of
    one lies within weld_distance of the other's faces: the seams, which the frames do not weld (patches are
    separate objects or groups, and non-conforming seams share no vertices). The two sides of a crack lie in
    one patch and are never joined. Returns (per object: (part per vertex, count), offset of each object's
    parts in the global numbering, class per global part, number of classes)."""
    per_object = [loose_parts(o) for o in objects]
    offsets, total = [], 0
    for _, n in per_object:
        offsets.append(total)
        total += n
    uf = UnionFind(total)
    pieces = patches(objects)
    if len(pieces) > 1 and weld_distance > 0:
        trees, boundaries = [], []
        for oi, _, faces in pieces:
            me = objects[oi].data
            polys = [list(me.polygons[f].vertices) for f in faces]
            trees.append(BVHTree.FromPolygons([v.co for v in me.vertices], polys))
            uses = {}
            for f in faces:
                for key in me.polygons[f].edge_keys:
                    uses[key] = uses.get(key, 0) + 1
            boundaries.append(sorted({v for key, n in uses.items() if n == 1 for v in key}))
        for a, (oa, _, _) in enumerate(pieces):
            verts = objects[oa].data.vertices
            for b, (ob, _, faces_b) in enumerate(pieces):
                if b == a:
                    continue
                polys_b = objects[ob].data.polygons
                for vi in boundaries[a]:
                    hit = trees[b].find_nearest(verts[vi].co, weld_distance)
                    if hit[0] is not None:
                        pb = per_object[ob][0][polys_b[faces_b[hit[2]]].vertices[0]]
                        uf.union(offsets[oa] + per_object[oa][0][vi], offsets[ob] + pb)
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
    texture coordinates): the patch's faces in frame 0, triangulated, searched in the UV plane."""

    def __init__(self, obj, faces):
        me = obj.data
        self.ok = bool(me.uv_layers) and len(faces) > 0
        if not self.ok:
            return
        uv = me.uv_layers.active.data
        self.uv, self.xyz, self.tris = [], [], []
        for f in faces:
            loops = list(me.polygons[f].loop_indices)
            for k in range(1, len(loops) - 1):
                self.tris.append([len(self.uv), len(self.uv) + 1, len(self.uv) + 2])
                for li in (loops[0], loops[k], loops[k + 1]):
                    self.uv.append(Vector((uv[li].uv[0], uv[li].uv[1], 0.0)))
                    self.xyz.append(me.vertices[me.loops[li].vertex_index].co.copy())
        # Several shells in one object without groups (PLY, STL) overlap in the UV plane: a UV then names
        # no single rest point. Their triangles then cover more than their bounding box.
        area = sum(abs((self.uv[b] - self.uv[a]).cross(self.uv[c] - self.uv[a]).z) / 2 for a, b, c in self.tris)
        lo = [min(t[i] for t in self.uv) for i in (0, 1)]
        hi = [max(t[i] for t in self.uv) for i in (0, 1)]
        self.ok = area <= (hi[0] - lo[0]) * (hi[1] - lo[1]) * (1 + 1e-3)
        self.tree = BVHTree.FromPolygons(self.uv, self.tris)

    def position(self, u, v):
        hit = self.tree.find_nearest(Vector((u, v, 0.0)))
        if hit[0] is None:
            return None
        a, b, c = self.tris[hit[2]]
        return barycentric_transform(hit[0], self.uv[a], self.uv[b], self.uv[c], self.xyz[a], self.xyz[b], self.xyz[c])


def rest_shapes(objects):
    """The rest shape of every patch of the frame-0 objects, by patch name."""
    return {name: RestShape(objects[oi], faces) for oi, name, faces in patches(objects)}


def edge_stretch(obj, rest):
    """World length over rest length of the edges of obj. The rest length comes from the frame-0 mesh of
    the same patch at the same UVs (rest: patch name -> RestShape; a frame of a single patch also matches
    the only rest shape there is). Edges without one are measured against the median edge of obj instead.
    Returns a dict edge index -> stretch, and the reference used ("rest", "median" or both)."""
    me = obj.data
    lengths = [(me.vertices[e.vertices[0]].co - me.vertices[e.vertices[1]].co).length for e in me.edges]
    out = {}
    if me.uv_layers:
        uv = me.uv_layers.active.data
        only = next(iter(rest.values())) if len(rest) == 1 else None
        for p, name in zip(me.polygons, patch_of_faces(obj)):
            shape = rest.get(name, only)
            if shape is None or not shape.ok:
                continue
            loops = list(p.loop_indices)
            at = [shape.position(uv[li].uv[0], uv[li].uv[1]) for li in loops]
            for k, li in enumerate(loops):  # loop k runs from corner k to corner k + 1
                a, b = at[k], at[(k + 1) % len(loops)]
                if a is not None and b is not None and (a - b).length > 0:
                    out[me.loops[li].edge_index] = lengths[me.loops[li].edge_index] / (a - b).length
    refs = {"rest"} if out else set()
    if len(out) < len(lengths):
        values = sorted(lengths)
        median = values[len(values) // 2]
        if median > 0:
            refs.add("median")
            for i, l in enumerate(lengths):
                out.setdefault(i, l / median)
    return out, "+".join(sorted(refs))


def base_name(name):
    """An imported object's name without the ".001" Blender appends when the name is taken."""
    return re.sub(r"\.\d{3}$", "", name)

#!/usr/bin/env python3
"""Reads crackflow's transform cache with VTK and compares it with crackflow's expectation.

usage: read_transform_cache.py DIR STEM EXPECTED.json [--houdini-doc docs/animation-output.md]

EXPECTED.json is written by tests/rigid/animation_output_test.cpp (pieces with rest meshes; per
frame the live pieces' position, orient x y z w, v, w). Checks, to 1e-12 relative (the files hold
every double exactly, so the errors are 0 unless something is wrong):
  - STEM.pvd, parsed here with xml.etree (plain VTK has no .pvd reader): one DataSet per frame with
    the frame's timestep, part 0 and the file STEM_<ffff>.vtp;
  - every frame's .vtp through vtkXMLPolyDataReader: one point and vertex cell per live piece,
    P = position, PointData name (string), piece, orient, pivot (0), v, w, and FieldData TimeValue;
  - STEM_rest.vtp: the rest meshes of all pieces in order, CellData piece, inside and uv, FieldData piece_names;
  - with --houdini-doc: the Python SOP code of that document (the ```python block that imports
    hou) run against a stand-in for Houdini's hou module, for both modes and every frame, must
    build the same points, attributes and named rest polygons.
Prints a JSON summary; exits 1 with the reasons on any failure, 2 if VTK is missing.
"""
import json
import math
import os
import re
import sys
import types
import xml.etree.ElementTree as ET

TOLERANCE = 1e-12

try:
    import vtk
except ImportError:
    print("read_transform_cache: cannot import vtk; install Debian's python3-vtk9 "
          "(apt-get install python3-vtk9) and run this with /usr/bin/python3", file=sys.stderr)
    sys.exit(2)


class Comparison:
    """Collects the largest relative error per quantity and the failures."""

    def __init__(self):
        self.max_error = {}
        self.errors = []

    def values(self, what, where, got, want):
        got, want = list(got), list(want)
        if len(got) != len(want):
            self.errors.append(f"{where}: {what} has {len(got)} values, expected {len(want)}")
            return
        for g, w in zip(got, want):
            err = abs(g - w) / max(1.0, abs(w)) if math.isfinite(g) else math.inf
            self.max_error[what] = max(self.max_error.get(what, 0.0), err)
            if err > TOLERANCE:
                self.errors.append(f"{where}: {what} is {got}, expected {want}")
                return

    def equal(self, what, where, got, want):
        if got != want:
            self.errors.append(f"{where}: {what} is {got!r}, expected {want!r}")


def read_vtp(path, cmp):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    failed = []
    reader.AddObserver("ErrorEvent", lambda *args: failed.append(True))
    reader.Update()
    if failed or reader.GetOutput() is None:
        cmp.errors.append(f"{path}: vtkXMLPolyDataReader failed")
        return None
    return reader.GetOutput()


def tuples(array):
    if array is None:
        return None
    n = array.GetNumberOfComponents()
    return [[array.GetComponent(i, c) for c in range(n)] for i in range(array.GetNumberOfTuples())]


def strings(array):
    if array is None or not array.IsA("vtkStringArray"):
        return None
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def flat(rows):
    return [x for row in rows for x in row]


def check_collection(directory, stem, expected, cmp):
    path = os.path.join(directory, stem + ".pvd")
    root = ET.parse(path).getroot()
    cmp.equal("VTKFile type", path, root.get("type"), "Collection")
    datasets = root.findall("Collection/DataSet")
    cmp.equal("number of DataSets", path, len(datasets), len(expected["frames"]))
    files = []
    for f, (ds, frame) in enumerate(zip(datasets, expected["frames"])):
        where = f"{path} frame {f}"
        cmp.values("timestep", where, [float(ds.get("timestep"))], [frame["time"]])
        cmp.equal("part", where, ds.get("part"), "0")
        cmp.equal("file", where, ds.get("file"), "%s_%04d.vtp" % (stem, f))
        files.append(os.path.join(directory, ds.get("file")))
    return files


def check_frame(path, f, frame, pieces, cmp):
    out = read_vtp(path, cmp)
    if out is None:
        return
    where = f"{os.path.basename(path)} (frame {f})"
    poses = frame["poses"]
    cmp.equal("number of points", where, out.GetNumberOfPoints(), len(poses))
    cmp.equal("number of vertex cells", where, out.GetNumberOfVerts(), len(poses))
    if out.GetNumberOfPoints() != len(poses):
        return
    pd = out.GetPointData()
    cmp.values("TimeValue", where, [out.GetFieldData().GetArray("TimeValue").GetValue(0)], [frame["time"]])
    cmp.values("P", where, flat(out.GetPoint(i) for i in range(len(poses))), flat(p["position"] for p in poses))
    cmp.equal("name", where, strings(pd.GetAbstractArray("name")), [pieces[p["piece"]]["name"] for p in poses])
    piece = pd.GetArray("piece")
    cmp.equal("piece", where, [int(piece.GetValue(i)) for i in range(len(poses))] if piece else None,
              [p["piece"] for p in poses])
    for name, key, comps in (("orient", "orient", 4), ("v", "v", 3), ("w", "w", 3)):
        rows = tuples(pd.GetArray(name))
        if rows is None or any(len(r) != comps for r in rows):
            cmp.errors.append(f"{where}: no {comps}-component array {name!r}")
            continue
        cmp.values(name, where, flat(rows), flat(p[key] for p in poses))
    pivot = tuples(pd.GetArray("pivot"))
    cmp.values("pivot", where, flat(pivot or []), [0.0] * (3 * len(poses)))


def check_rest(path, pieces, cmp):
    out = read_vtp(path, cmp)
    if out is None:
        return
    where = os.path.basename(path)
    cmp.equal("piece_names", where, strings(out.GetFieldData().GetAbstractArray("piece_names")), [p["name"] for p in pieces])
    cmp.values("rest points", where, flat(out.GetPoint(i) for i in range(out.GetNumberOfPoints())),
               flat(x for p in pieces for x in p["rest"]))
    triangles, cell_piece, base = [], [], 0
    for i, p in enumerate(pieces):
        triangles += [[base + v for v in t] for t in p["triangles"]]
        cell_piece += [i] * len(p["triangles"])
        base += len(p["rest"])
    polys = out.GetPolys()
    got = []
    ids = vtk.vtkIdList()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        got.append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
    cmp.equal("triangles", where, got, triangles)
    arr = out.GetCellData().GetArray("piece")
    cmp.equal("cell piece", where, [int(arr.GetValue(c)) for c in range(arr.GetNumberOfTuples())] if arr else None, cell_piece)
    arr = out.GetCellData().GetArray("inside")
    cmp.equal("cell inside", where, [int(arr.GetValue(c)) for c in range(arr.GetNumberOfTuples())] if arr else None,
              [flag for p in pieces for flag in p["inside"]])
    arr = out.GetCellData().GetArray("uv")
    if any(p["uv"] is not None for p in pieces):
        want = [x for p in pieces for w in (p["uv"] or [[0.0] * 6] * len(p["triangles"])) for x in w]
        got = None if arr is None or arr.GetNumberOfComponents() != 6 else \
            [arr.GetComponent(c, k) for c in range(arr.GetNumberOfTuples()) for k in range(6)]
        cmp.values("cell uv", where, got or [], want)
    else:
        cmp.equal("cell uv (none)", where, arr is None, True)


# ---- the Houdini Python SOP of docs/animation-output.md, against a stand-in for hou -----------

class FakeVertex:
    def __init__(self, geo, point):
        self.geo, self.point, self.attribs = geo, point, {}

    def setAttribValue(self, name, value):
        if name not in self.geo.attribs["vertex"]:
            raise KeyError(f"attribute {name!r} was not added to the vertices")
        self.attribs[name] = tuple(float(c) for c in value)


class FakeElement:
    def __init__(self, geo, kind):
        self.geo, self.kind, self.attribs, self.corners, self.position = geo, kind, {}, [], None

    @property
    def vertices_points(self):
        return [v.point for v in self.corners]

    def setPosition(self, x):
        self.position = tuple(float(c) for c in x)

    def addVertex(self, point):
        self.corners.append(FakeVertex(self.geo, point))
        return self.corners[-1]

    def vertices(self):
        return tuple(self.corners)

    def setAttribValue(self, name, value):
        if name not in self.geo.attribs[self.kind]:
            raise KeyError(f"attribute {name!r} was not added to the {self.kind}s")
        self.attribs[name] = value


class FakeGroup:
    def __init__(self):
        self.prims = []

    def add(self, prim):
        self.prims.append(prim)


class FakeGeometry:
    def __init__(self):
        self.points, self.prims, self.attribs, self.groups = [], [], {"point": {}, "prim": {}, "vertex": {}}, {}

    def createPrimGroup(self, name):
        if name in self.groups:
            raise ValueError(f"group {name!r} exists")
        self.groups[name] = FakeGroup()
        return self.groups[name]

    def addAttrib(self, kind, name, default):
        self.attribs[kind][name] = default

    def createPoint(self):
        self.points.append(FakeElement(self, "point"))
        return self.points[-1]

    def createPolygon(self):
        self.prims.append(FakeElement(self, "prim"))
        return self.prims[-1]


def run_houdini_code(code, directory, stem, mode, frame):
    geo = FakeGeometry()
    hou = types.ModuleType("hou")
    hou.attribType = types.SimpleNamespace(Point="point", Prim="prim", Vertex="vertex")
    hou.pwd = lambda: types.SimpleNamespace(geometry=lambda: geo)
    hou.frame = lambda: float(frame)
    sys.modules["hou"] = hou
    settings = {"CACHE": directory, "STEM": stem, "MODE": mode, "FIRST_FRAME": 1}
    for name, value in settings.items():
        code, n = re.subn(rf"^{name} = .*$", f"{name} = {value!r}", code, count=1, flags=re.M)
        if n != 1:
            raise ValueError(f"the Houdini code has no line '{name} = ...'")
    exec(compile(code, "docs/animation-output.md (Houdini Python SOP)", "exec"), {"__name__": "houdini_sop"})
    return geo


def check_houdini(doc, directory, stem, expected, cmp):
    with open(doc) as f:
        blocks = re.findall(r"```python\n(.*?)```", f.read(), flags=re.S)
    code = next((b for b in blocks if "import hou" in b), None)
    if code is None:
        cmp.errors.append(f"{doc}: no ```python block that imports hou")
        return
    pieces = expected["pieces"]
    rest = run_houdini_code(code, directory, stem, "rest", 1)
    want = [(pieces[i]["name"], [tuple(pieces[i]["rest"][v]) for v in reversed(t)])
            for i in range(len(pieces)) for t in pieces[i]["triangles"]]
    got = [(p.attribs.get("name"), [v.position for v in p.vertices_points]) for p in rest.prims]
    cmp.equal("Houdini rest polygons (name, clockwise points)", "rest", got, want)
    inside = set(id(p) for p in rest.groups["inside"].prims) if "inside" in rest.groups else set()
    cmp.equal("Houdini group inside", "rest", [int(id(p) in inside) for p in rest.prims],
              [flag for p in pieces for flag in p["inside"]])
    if any(p["uv"] is not None for p in pieces):  # per vertex, in Houdini's (reversed) corner order
        want_uv = [x for p in pieces for w in (p["uv"] or [[0.0] * 6] * len(p["triangles"]))
                   for k in (2, 1, 0) for x in (w[2 * k], w[2 * k + 1], 0.0)]
        got_uv = [x for p in rest.prims for v in p.corners for x in v.attribs.get("uv", ())]
        cmp.values("Houdini vertex uv", "rest", got_uv, want_uv)
    for f, frame in enumerate(expected["frames"]):
        geo = run_houdini_code(code, directory, stem, "points", 1 + f)
        where = f"Houdini frame {1 + f} (crackflow frame {f})"
        poses = frame["poses"]
        cmp.equal("number of points", where, len(geo.points), len(poses))
        if len(geo.points) != len(poses):
            continue
        cmp.values("Houdini P", where, flat(p.position for p in geo.points), flat(q["position"] for q in poses))
        cmp.equal("Houdini name", where, [p.attribs["name"] for p in geo.points], [pieces[q["piece"]]["name"] for q in poses])
        cmp.equal("Houdini piece", where, [p.attribs["piece"] for p in geo.points], [q["piece"] for q in poses])
        for name in ("orient", "v", "w"):
            cmp.values("Houdini " + name, where, flat(p.attribs[name] for p in geo.points), flat(q[name] for q in poses))
        cmp.values("Houdini pivot", where, flat(p.attribs["pivot"] for p in geo.points), [0.0] * (3 * len(poses)))
    past = run_houdini_code(code, directory, stem, "points", 1 + len(expected["frames"]))
    cmp.equal("points after the last frame", "Houdini", len(past.points), 0)


def main():
    args = sys.argv[1:]
    doc = None
    if "--houdini-doc" in args:
        k = args.index("--houdini-doc")
        doc = args[k + 1]
        del args[k:k + 2]
    if len(args) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    directory, stem, expected_path = args
    with open(expected_path) as f:
        expected = json.load(f)
    cmp = Comparison()
    files = check_collection(directory, stem, expected, cmp)
    for f, (path, frame) in enumerate(zip(files, expected["frames"])):
        check_frame(path, f, frame, expected["pieces"], cmp)
    check_rest(os.path.join(directory, stem + "_rest.vtp"), expected["pieces"], cmp)
    if doc:
        check_houdini(doc, directory, stem, expected, cmp)
    print(json.dumps({"reader": "vtkXMLPolyDataReader", "vtk": vtk.vtkVersion.GetVTKVersion(), "frames": len(files),
                      "houdini_code_checked": bool(doc), "tolerance": TOLERANCE, "max_relative_error": cmp.max_error,
                      "ok": not cmp.errors}))
    if cmp.errors:
        print("\n".join(cmp.errors[:50]), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

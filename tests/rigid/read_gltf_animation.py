#!/usr/bin/env python3
"""Plays crackflow's .glb with VTK's glTF reader and compares it with crackflow's expectation.

usage: read_gltf_animation.py SCENE.glb EXPECTED.json

EXPECTED.json is written by tests/rigid/animation_output_test.cpp: the pieces (name, parent,
class, first/last frame, rest vertices) and per frame the live pieces with their world vertices
in glTF axes, x = R_up (position + rotation x_rest), computed by crackflow in double precision.

Checks (exit 1 with the reasons on any failure, 2 if VTK is missing; a JSON summary on stdout):
  - the file's own structure, parsed here from the GLB chunks: root "crackflow_scene", node 1 + i
    named like piece i with extras id / parent / class;
  - at every frame time VTK's reader with the animation enabled puts every vertex of a live piece
    at its expected position to 1e-5 relative (float32 data), and collapses every hidden piece
    (scale 0) to a single point;
  - half-way between frames a piece is shown exactly when it was at the earlier frame (STEP scale).
Frames are sampled one float32 step after the frame time: glTF's STEP key k holds from t_k on, but
VTK 9.1 still returns key k - 1 at exactly t_k (it takes key k only after t_k). One float32 step
(~1e-8 s) moves the LINEAR poses by far less than the tolerance and gives key k in both readings.
Vertices are matched to crackflow's rest vertices through the float32 rest positions stored in the
file (the writer splits a vertex once per distinct normal, so the file has more vertices).
"""
import json
import struct
import sys

TOLERANCE = 1e-5  # relative, float32 positions and keys


def fail_import():
    print("read_gltf_animation: cannot import vtk; install Debian's python3-vtk9 "
          "(apt-get install python3-vtk9) and run this with /usr/bin/python3", file=sys.stderr)
    sys.exit(2)


try:
    import vtk
except ImportError:
    fail_import()


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def just_after(t):
    """The float32 after t rounded to float32 (times are >= 0, so the next bit pattern)."""
    bits = struct.unpack("<I", struct.pack("<f", f32(t)))[0]
    return struct.unpack("<f", struct.pack("<I", bits + 1))[0]


def read_glb(path):
    """The JSON document and the BIN chunk of a .glb."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2 or length != len(data):
        raise ValueError(f"{path}: not a glTF 2.0 binary of {len(data)} bytes")
    offset, doc, binary = 12, None, b""
    while offset < length:
        size, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8:offset + 8 + size]
        if kind == 0x4E4F534A:
            doc = json.loads(chunk.decode("utf-8"))
        elif kind == 0x004E4942:
            binary = chunk
        offset += 8 + size
    return doc, binary


def accessor_floats(doc, binary, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    n = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[acc["type"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    flat = struct.unpack_from(f"<{n * acc['count']}f", binary, start)
    return [flat[i:i + n] for i in range(0, len(flat), n)]


def check_structure(doc, expected, errors):
    nodes = doc["nodes"]
    if nodes[0].get("name") != "crackflow_scene":
        errors.append(f"node 0 is {nodes[0].get('name')!r}, not the root 'crackflow_scene'")
    for i, p in enumerate(expected["pieces"]):
        node = nodes[1 + i]
        extras = node.get("extras", {})
        if node.get("name") != p["name"]:
            errors.append(f"node {1 + i} is named {node.get('name')!r}, expected piece {i} {p['name']!r}")
        want = {"id": i, "parent": p["parent"], "class": p["class"]}
        got = {k: extras.get(k) for k in want}
        if got != want or "volume" not in extras or "mass" not in extras:
            errors.append(f"piece {i} {p['name']!r}: extras {extras} do not match {want} (+ volume, mass)")


def rest_index_maps(doc, binary, expected, errors):
    """For every piece, the crackflow rest vertex of each vertex in the file."""
    maps = []
    for i, p in enumerate(expected["pieces"]):
        mesh = doc["meshes"][doc["nodes"][1 + i]["mesh"]]
        positions = accessor_floats(doc, binary, mesh["primitives"][0]["attributes"]["POSITION"])
        by_float = {tuple(f32(c) for c in x): k for k, x in enumerate(p["rest"])}
        index = [by_float.get(tuple(x)) for x in positions]
        if None in index:
            errors.append(f"piece {i} {p['name']!r}: file vertex {index.index(None)} is no rest vertex of crackflow's mesh")
        if set(index) != set(range(len(p["rest"]))):
            errors.append(f"piece {i} {p['name']!r}: the file does not use every rest vertex")
        maps.append(index)
    return maps


def leaf_polydata(block):
    while block is not None and block.IsA("vtkMultiBlockDataSet"):
        block = block.GetBlock(0)
    return block


def piece_points(output, node):
    """The points VTK placed for glTF node `node` (VTK names the blocks Node_<index>)."""
    root = output.GetBlock(0)  # the scene's root node
    for b in range(root.GetNumberOfBlocks()):
        name = root.GetMetaData(b).Get(vtk.vtkCompositeDataSet.NAME())
        if name == f"Node_{node}":
            poly = leaf_polydata(root.GetBlock(b))
            pts = poly.GetPoints()
            return [pts.GetPoint(k) for k in range(pts.GetNumberOfPoints())]
    raise KeyError(f"VTK's output has no block Node_{node}")


def norm(v):
    return sum(c * c for c in v) ** 0.5


def spread(points):
    return max(norm([a - b for a, b in zip(p, points[0])]) for p in points)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    glb, expected_path = sys.argv[1], sys.argv[2]
    with open(expected_path) as f:
        expected = json.load(f)
    errors = []
    doc, binary = read_glb(glb)
    check_structure(doc, expected, errors)
    maps = rest_index_maps(doc, binary, expected, errors)
    if errors:
        print("\n".join(errors), file=sys.stderr)
        return 1

    reader = vtk.vtkGLTFReader()
    reader.SetFileName(glb)
    reader.UpdateInformation()
    names = [reader.GetAnimationName(k) for k in range(reader.GetNumberOfAnimations())]
    if names != ["simulation"]:
        print(f"animations {names}, expected ['simulation']", file=sys.stderr)
        return 1
    reader.SetFrameRate(expected["frame_rate"])
    reader.EnableAnimation(0)

    pieces = expected["pieces"]
    frames = expected["frames"]
    stats = {"vertices_compared": 0, "max_relative_error": 0.0, "hidden_checks": 0, "max_hidden_spread": 0.0,
             "midpoint_checks": 0}

    def sample(t):
        reader.UpdateTimeStep(t)
        return reader.GetOutput()

    for f, frame in enumerate(frames):
        output = sample(just_after(frame["time"]))
        alive = {pose["piece"]: pose for pose in frame["poses"]}
        for i, p in enumerate(pieces):
            points = piece_points(output, 1 + i)
            where = f"frame {f} (t = {frame['time']} s), piece {i} {p['name']!r}"
            if len(points) != len(maps[i]):
                errors.append(f"{where}: VTK read {len(points)} vertices, the file has {len(maps[i])}")
                continue
            if i in alive:
                size = max(norm(x) for x in p["rest"])
                for k, x in enumerate(points):
                    want = alive[i]["world_gltf"][maps[i][k]]
                    err = norm([a - b for a, b in zip(x, want)]) / max(norm(want), size)
                    stats["max_relative_error"] = max(stats["max_relative_error"], err)
                    stats["vertices_compared"] += 1
                    if err > TOLERANCE:
                        errors.append(f"{where}: vertex {k} at {x}, crackflow has {want} (relative error {err:.3g})")
            else:
                s = spread(points)
                stats["hidden_checks"] += 1
                stats["max_hidden_spread"] = max(stats["max_hidden_spread"], s)
                if s > 1e-9:
                    errors.append(f"{where}: hidden, but its vertices span {s} m (scale not 0)")

    # Between frames the STEP scale keeps the earlier frame's visibility.
    for f in range(len(frames) - 1):
        output = sample(0.5 * (frames[f]["time"] + frames[f + 1]["time"]))
        for i, p in enumerate(pieces):
            shown = p["first"] <= f <= p["last"]
            s = spread(piece_points(output, 1 + i))
            stats["midpoint_checks"] += 1
            if shown != (s > 1e-9):
                errors.append(f"between frames {f} and {f + 1}: piece {i} {p['name']!r} is "
                              f"{'hidden' if s <= 1e-9 else 'shown'}, expected {'shown' if shown else 'hidden'}")

    stats.update(reader="vtkGLTFReader", vtk=vtk.vtkVersion.GetVTKVersion(), frames=len(frames), pieces=len(pieces),
                 tolerance=TOLERANCE, ok=not errors)
    print(json.dumps(stats))
    if errors:
        print("\n".join(errors[:50]), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

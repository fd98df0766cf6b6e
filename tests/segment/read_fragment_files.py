"""Reads crackflow's fragment files with VTK (an independent reader) and prints one JSON object
per file: points, cells, texture coordinates, and the materials (OBJ: VTK's MaterialNames and
MaterialIds; PLY: the face property 'inside' from the ASCII data; glTF: cells over all blocks).
usage: read_fragment_files.py FILE..."""
import json
import sys

import vtk


def obj(path):
    r = vtk.vtkOBJReader()
    r.SetFileName(path)
    r.Update()
    o = r.GetOutput()
    names = o.GetFieldData().GetAbstractArray("MaterialNames")
    ids = o.GetCellData().GetArray("MaterialIds")
    count = {}
    if names is not None and ids is not None:
        for i in range(ids.GetNumberOfTuples()):
            n = names.GetValue(int(ids.GetValue(i)))
            count[n] = count.get(n, 0) + 1
    return {"points": o.GetNumberOfPoints(), "cells": o.GetNumberOfCells(),
            "tcoords": o.GetPointData().GetTCoords() is not None, "materials": count}


def ply(path):
    r = vtk.vtkPLYReader()
    r.SetFileName(path)
    r.Update()
    o = r.GetOutput()
    # The face property 'inside' (VTK keeps only the properties it knows): ASCII data after the header.
    with open(path) as f:
        lines = f.read().split("\n")
    end = lines.index("end_header")
    header = lines[:end]
    nv = int([l for l in header if l.startswith("element vertex")][0].split()[2])
    face_props = header[[i for i, l in enumerate(header) if l.startswith("element face")][0] + 1:]
    inside = None
    if "property uchar inside" in face_props:
        inside = sum(int(l.split()[-1]) for l in lines[end + 1 + nv:] if l.strip())
    return {"points": o.GetNumberOfPoints(), "cells": o.GetNumberOfCells(),
            "tcoords": o.GetPointData().GetTCoords() is not None,
            "normals": o.GetPointData().GetNormals() is not None, "inside": inside}


def glb(path):
    r = vtk.vtkGLTFReader()
    r.SetFileName(path)
    r.Update()
    it = r.GetOutput().NewIterator()
    it.InitTraversal()
    points = cells = 0
    tcoords = True
    while not it.IsDoneWithTraversal():
        b = it.GetCurrentDataObject()
        points += b.GetNumberOfPoints()
        cells += b.GetNumberOfCells()
        tcoords = tcoords and b.GetPointData().GetTCoords() is not None
        it.GoToNextItem()
    return {"points": points, "cells": cells, "tcoords": tcoords}


for p in sys.argv[1:]:
    kind = {"obj": obj, "ply": ply, "glb": glb}[p.rsplit(".", 1)[1]]
    print(json.dumps({"file": p, **kind(p)}))

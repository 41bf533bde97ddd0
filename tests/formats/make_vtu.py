#!/usr/bin/env python3
"""Writes the .vtu test files with VTK's own writer (vtkXMLUnstructuredGridWriter, python3-vtk9).

    make_vtu.py DIR [N]

DIR/<mode>-<compressor>-<header>.vtu for mode ascii|binary|appended|appended64 (appended data
base64-encoded), compressor none|zlib, header 32|64 (ascii only with none-32), and DIR/same.vtp:
the same points and arrays as PolyData (the oracle the .vtp reader gives). N nodes (default 500),
node i at (i*37 % 101 / 10, i*53 % 97 / 10, i*11 % 89 / 10) in double precision; PointData:
"f" = x*x + y - z (float64, the active scalars), "g" = i (int32), "vec" (3 components, 3,4,0);
cells: tetrahedra over consecutive nodes (i, i+1, i+2, i+3) for i = 0, 4, ... up to N - 8, so the
last nodes are referenced by no cell (read all the same). With the environment variable NAN_NODE=k,
node k's x is NaN (dropped and counted by the reader).
"""
import os
import sys

import vtk

d = sys.argv[1]
n = int(sys.argv[2]) if len(sys.argv) > 2 else 500
nan_node = int(os.environ.get("NAN_NODE", "-1"))
os.makedirs(d, exist_ok=True)

pts = vtk.vtkPoints()
pts.SetDataTypeToDouble()
f = vtk.vtkDoubleArray()
f.SetName("f")
g = vtk.vtkIntArray()
g.SetName("g")
vec = vtk.vtkFloatArray()
vec.SetName("vec")
vec.SetNumberOfComponents(3)
for i in range(n):
    x, y, z = (i * 37 % 101) / 10, (i * 53 % 97) / 10, (i * 11 % 89) / 10
    if i == nan_node:
        x = float("nan")
    pts.InsertNextPoint(x, y, z)
    f.InsertNextValue(x * x + y - z)
    g.InsertNextValue(i)
    vec.InsertNextTuple3(3, 4, 0)

ug = vtk.vtkUnstructuredGrid()
ug.SetPoints(pts)
ug.Allocate(n // 4)
for i in range(0, n - 7, 4):
    ids = vtk.vtkIdList()
    for k in range(4):
        ids.InsertNextId(i + k)
    ug.InsertNextCell(vtk.VTK_TETRA, ids)
for a in (g, vec):
    ug.GetPointData().AddArray(a)
ug.GetPointData().SetScalars(f)

for mode in ("ascii", "binary", "appended", "appended64"):
    for comp in ("none", "zlib"):
        for header in (32, 64):
            if mode == "ascii" and (comp != "none" or header != 32):
                continue
            w = vtk.vtkXMLUnstructuredGridWriter()
            w.SetInputData(ug)
            w.SetFileName(os.path.join(d, "%s-%s-%d.vtu" % (mode, comp, header)))
            if mode == "ascii":
                w.SetDataModeToAscii()
            elif mode == "binary":
                w.SetDataModeToBinary()
            else:
                w.SetDataModeToAppended()
                w.SetEncodeAppendedData(1 if mode == "appended64" else 0)
            if comp == "zlib":
                w.SetCompressorTypeToZLib()
            else:
                w.SetCompressorTypeToNone()
            w.SetHeaderTypeToUInt64() if header == 64 else w.SetHeaderTypeToUInt32()
            if w.Write() != 1:
                sys.exit("vtkXMLUnstructuredGridWriter failed")

pd = vtk.vtkPolyData()
pd.SetPoints(pts)
for a in (g, vec):
    pd.GetPointData().AddArray(a)
pd.GetPointData().SetScalars(f)
w = vtk.vtkXMLPolyDataWriter()
w.SetInputData(pd)
w.SetFileName(os.path.join(d, "same.vtp"))
w.SetDataModeToAppended()
w.SetCompressorTypeToZLib()
if w.Write() != 1:
    sys.exit("vtkXMLPolyDataWriter failed")

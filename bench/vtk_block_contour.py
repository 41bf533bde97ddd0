#!/usr/bin/python3
"""VTK per-block contour baseline for `meshless-bench multiblock` (dissertation chapter 4,
Figures 4.6-4.8: the naive per-block isosurface whose cracks the meshless method removes).

Reads a multiblock data set as ParaView does and contours every block on its own with
vtkContourFilter (normals and scalars off), REPS times; prints one JSON object on stdout:

  {"vtk_version": "9.1.0", "blocks": B, "triangles": T, "best_seconds": fastest total filter time
   over the reps (reading excluded), "boundary_edges": open edges of the union of the blocks'
   surfaces after merging exactly coincident points (vtkCleanPolyData, tolerance 0),
   "crack_edges": those of them not lying on a face of the data's bounding box}

Inputs: --input FILE.vtm (vtkXMLMultiBlockDataReader: .vts/.vti/.vtr pieces, point data),
--input FILE.vthb (vtkXMLUniformGridAMRReader, all levels; the cell data of every box is moved to
its points with vtkCellDataToPointData, box by box, as ParaView's contour of AMR cell data does),
or --plot3d XYZ Q (vtkMultiBlockPLOT3DReader, binary, density = scalar function 100).
Must run under an interpreter with the vtk module (Debian: /usr/bin/python3 with python3-vtk9).
Exit status 2 with a one-line message on stderr on bad arguments or data.

With --ply-out FILE the union of the blocks' triangles is also written there (binary PLY, the
merged points), for the bench's coverage measure.

usage: vtk_block_contour.py (--input FILE | --plot3d XYZ Q) --iso V [--reps R] [--ply-out FILE]
"""
import argparse
import json
import sys
import time


def leaves(ds, out):
    import vtk
    if ds is None:
        return
    if isinstance(ds, vtk.vtkCompositeDataSet):
        it = ds.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            out.append(it.GetCurrentDataObject())
            it.GoToNextItem()
    else:
        out.append(ds)


def main():
    ap = argparse.ArgumentParser(description="VTK per-block contour (naive multiblock isosurface)")
    ap.add_argument("--input")
    ap.add_argument("--plot3d", nargs=2, metavar=("XYZ", "Q"))
    ap.add_argument("--iso", type=float, required=True)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--ply-out")
    a = ap.parse_args()
    try:
        import vtk
    except ImportError:
        print("vtk_block_contour.py: the vtk module is not installed (python3-vtk9)", file=sys.stderr)
        return 2
    blocks = []
    amr = False
    if a.plot3d:
        r = vtk.vtkMultiBlockPLOT3DReader()
        r.SetXYZFileName(a.plot3d[0])
        r.SetQFileName(a.plot3d[1])
        r.SetScalarFunctionNumber(100)
        r.AutoDetectFormatOn()
        r.Update()
        leaves(r.GetOutput(), blocks)
    elif a.input and a.input.endswith(".vthb"):
        r = vtk.vtkXMLUniformGridAMRReader()
        r.SetFileName(a.input)
        r.SetMaximumLevelsToReadByDefault(0)
        r.Update()
        leaves(r.GetOutput(), blocks)
        amr = True
    elif a.input:
        r = vtk.vtkXMLMultiBlockDataReader()
        r.SetFileName(a.input)
        r.Update()
        leaves(r.GetOutput(), blocks)
    else:
        print("vtk_block_contour.py: give --input FILE or --plot3d XYZ Q", file=sys.stderr)
        return 2
    blocks = [b for b in blocks if b is not None and b.GetNumberOfPoints() > 0]
    if not blocks:
        print("vtk_block_contour.py: no block with points", file=sys.stderr)
        return 2
    inputs = []
    for b in blocks:
        if amr:
            c2p = vtk.vtkCellDataToPointData()
            c2p.SetInputData(b)
            c2p.Update()
            pd = c2p.GetOutput()
        else:
            pd = b
        if pd.GetPointData().GetScalars() is None:
            arr = pd.GetPointData().GetArray(0)
            if arr is None:
                print("vtk_block_contour.py: a block has no point scalars", file=sys.stderr)
                return 2
            pd.GetPointData().SetScalars(arr)
        inputs.append(pd)
    best = None
    outputs = []
    for _ in range(max(1, a.reps)):
        outputs = []
        t0 = time.perf_counter()
        for pd in inputs:
            cf = vtk.vtkContourFilter()
            cf.SetInputData(pd)
            cf.SetValue(0, a.iso)
            cf.ComputeNormalsOff()
            cf.ComputeScalarsOff()
            cf.Update()
            outputs.append(cf.GetOutput())
        t = time.perf_counter() - t0
        best = t if best is None else min(best, t)
    app = vtk.vtkAppendPolyData()
    for o in outputs:
        app.AddInputData(o)
    app.Update()
    triangles = app.GetOutput().GetNumberOfPolys()
    clean = vtk.vtkCleanPolyData()
    clean.SetInputConnection(app.GetOutputPort())
    clean.SetTolerance(0.0)
    clean.PointMergingOn()
    if a.ply_out:
        tri = vtk.vtkTriangleFilter()
        tri.SetInputConnection(clean.GetOutputPort())
        w = vtk.vtkPLYWriter()
        w.SetInputConnection(tri.GetOutputPort())
        w.SetFileName(a.ply_out)
        w.SetFileTypeToBinary()
        if not w.Write():
            raise RuntimeError("cannot write " + a.ply_out)
    fe = vtk.vtkFeatureEdges()
    fe.SetInputConnection(clean.GetOutputPort())
    fe.BoundaryEdgesOn()
    fe.FeatureEdgesOff()
    fe.NonManifoldEdgesOff()
    fe.ManifoldEdgesOff()
    fe.Update()
    edges = fe.GetOutput()
    # data bounding box over all blocks
    lo = [float("inf")] * 3
    hi = [float("-inf")] * 3
    for b in blocks:
        bb = b.GetBounds()
        for k in range(3):
            lo[k] = min(lo[k], bb[2 * k])
            hi[k] = max(hi[k], bb[2 * k + 1])
    diag = sum((hi[k] - lo[k]) ** 2 for k in range(3)) ** 0.5
    eps = 1e-6 * diag

    def on_face(p, q):
        for k in range(3):
            if abs(p[k] - lo[k]) <= eps and abs(q[k] - lo[k]) <= eps:
                return True
            if abs(p[k] - hi[k]) <= eps and abs(q[k] - hi[k]) <= eps:
                return True
        return False

    cracks = 0
    lines = edges.GetLines()
    ids = vtk.vtkIdList()
    lines.InitTraversal()
    n_edges = 0
    while lines.GetNextCell(ids):
        n_edges += 1
        p = edges.GetPoint(ids.GetId(0))
        q = edges.GetPoint(ids.GetId(ids.GetNumberOfIds() - 1))
        if not on_face(p, q):
            cracks += 1
    print(json.dumps({"vtk_version": vtk.vtkVersion.GetVTKVersion(), "blocks": len(blocks), "triangles": triangles,
                      "best_seconds": best, "boundary_edges": n_edges, "crack_edges": cracks}))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except Exception as e:  # noqa: BLE001 - one line on stderr, exit 2
        print("vtk_block_contour.py: %s" % str(e).splitlines()[0] if str(e) else repr(e), file=sys.stderr)
        sys.exit(2)

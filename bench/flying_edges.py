#!/usr/bin/python3
"""VTK Flying Edges baseline for `meshless bench speed` (dissertation section 3.6 comparison).

Loads a headerless raw volume (x fastest, little endian) written by `meshless-bench`, runs
vtkFlyingEdges3D single-threaded with normals on (gradients and scalars off) for each isovalue
REPS times, and prints one JSON object on stdout:

  {"vtk_version": "9.1.0", "smp_backend": "Sequential", "reps": R,
   "mean_seconds": mean wall seconds per isosurface over all isovalues and reps,
   "per_iso": [{"iso": v, "seconds": mean seconds, "best_seconds": fastest of the reps,
                "triangles": n, "points": n}, ...],
   "sum_best_seconds": sum over the isovalues of best_seconds}

Times are of the filter alone (vtkFlyingEdges3D.Update() on the volume already in memory), never of
loading the file. `meshless-bench speed` uses mean_seconds, `meshless-bench process` best_seconds.

Must run under an interpreter that has the vtk module (Debian: /usr/bin/python3 with
python3-vtk9). Exit status 2 with a one-line message on stderr on bad arguments or data.

usage: flying_edges.py --raw FILE --dims X,Y,Z --type uint8|int16|uint16|float32
                       [--spacing SX,SY,SZ] [--origin OX,OY,OZ] --isos V1,V2,... [--reps R]
"""
import argparse
import json
import os
import sys
import time


def main():
    ap = argparse.ArgumentParser(description="VTK Flying Edges baseline (single-threaded)")
    ap.add_argument("--raw", required=True)
    ap.add_argument("--dims", required=True)
    ap.add_argument("--type", required=True, choices=["uint8", "int16", "uint16", "float32"])
    ap.add_argument("--spacing", default="1,1,1")
    ap.add_argument("--origin", default="0,0,0")
    ap.add_argument("--isos", required=True)
    ap.add_argument("--reps", type=int, default=10)
    a = ap.parse_args()

    try:
        import vtk
    except ImportError:
        sys.stderr.write("flying_edges.py: the vtk module is missing (apt-get install python3-vtk9)\n")
        return 2

    dims = [int(x) for x in a.dims.split(",")]
    spacing = [float(x) for x in a.spacing.split(",")]
    origin = [float(x) for x in a.origin.split(",")]
    isos = [float(x) for x in a.isos.split(",") if x]
    size = {"uint8": 1, "int16": 2, "uint16": 2, "float32": 4}[a.type]
    expected = dims[0] * dims[1] * dims[2] * size
    if len(dims) != 3 or min(dims) < 1 or a.reps < 1 or not isos:
        sys.stderr.write("flying_edges.py: bad --dims, --reps or --isos\n")
        return 2
    if os.path.getsize(a.raw) != expected:
        sys.stderr.write("flying_edges.py: %s: expected %d bytes for %s %s, found %d\n"
                         % (a.raw, expected, a.dims, a.type, os.path.getsize(a.raw)))
        return 2
    with open(a.raw, "rb") as f:
        data = f.read()

    # Single thread: the Sequential SMP backend where it can be chosen, else one thread.
    backend = "default"
    smp = vtk.vtkSMPTools
    try:
        if smp.SetBackend("Sequential"):
            backend = "Sequential"
    except (AttributeError, TypeError):
        pass
    if backend != "Sequential":
        smp.Initialize(1)
        try:
            backend = smp.GetBackend() + " (1 thread)"
        except AttributeError:
            backend = "Initialize(1)"

    imp = vtk.vtkImageImport()
    {"uint8": imp.SetDataScalarTypeToUnsignedChar,
     "int16": imp.SetDataScalarTypeToShort,
     "uint16": imp.SetDataScalarTypeToUnsignedShort,
     "float32": imp.SetDataScalarTypeToFloat}[a.type]()
    imp.SetNumberOfScalarComponents(1)
    imp.SetDataExtent(0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    imp.SetWholeExtent(0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    imp.SetDataSpacing(*spacing)
    imp.SetDataOrigin(*origin)
    imp.CopyImportVoidPointer(data, len(data))
    imp.Update()
    image = vtk.vtkImageData()
    image.DeepCopy(imp.GetOutput())

    fe = vtk.vtkFlyingEdges3D()
    fe.SetInputData(image)
    fe.ComputeNormalsOn()
    fe.ComputeGradientsOff()
    fe.ComputeScalarsOff()
    fe.SetNumberOfContours(1)

    # warm-up (first-touch allocations, lazy initialisation)
    fe.SetValue(0, isos[len(isos) // 2])
    fe.Update()

    per_iso = []
    total = 0.0
    for iso in isos:
        fe.SetValue(0, iso)
        t = 0.0
        best = float("inf")
        for _ in range(a.reps):
            fe.Modified()
            t0 = time.perf_counter()
            fe.Update()
            dt = time.perf_counter() - t0
            t += dt
            best = min(best, dt)
        out = fe.GetOutput()
        per_iso.append({"iso": iso, "seconds": t / a.reps, "best_seconds": best,
                        "triangles": out.GetNumberOfPolys(), "points": out.GetNumberOfPoints()})
        total += t
    json.dump({"vtk_version": vtk.vtkVersion.GetVTKVersion(), "smp_backend": backend, "reps": a.reps,
               "mean_seconds": total / (a.reps * len(isos)), "per_iso": per_iso,
               "sum_best_seconds": sum(p["best_seconds"] for p in per_iso)}, sys.stdout)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

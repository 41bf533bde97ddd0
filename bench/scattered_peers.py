#!/usr/bin/python3
"""Peers of `meshless isosurface POINTS` for `meshless-bench scattered` (dissertation chapter 5).

What users do today with scattered samples and no mesh, one method per run, timed by the bench as a
whole process (interpreter start and imports included; the stage times below are printed as well):

  griddata  SciPy griddata(method='linear') (a global Qhull Delaunay triangulation, barycentric
            interpolation) onto a regular grid over the points' bounding box, grid nodes outside the
            convex hull (NaN) filled from their nearest data point (scipy.spatial.cKDTree), then
            marching cubes on the grid (vtkFlyingEdges3D).
  delaunay  vtkDelaunay3D over all the points (the global tetrahedrization, alpha 0 = the convex
            hull), then vtkContourFilter on its tetrahedra (marching tetrahedra on the data values).
  interp    vtkPointInterpolator with a vtkGaussianKernel on the N closest points (--neighbours,
            default 8; radius = 2 x the grid spacing, sharpness 2) onto the same grid, then
            vtkFlyingEdges3D.

Input: a binary little-endian PLY with vertex properties x, y, z and one scalar (named by --value,
default "value"), as `meshless sample` and meshless-bench write them (any of float/double per
property). The grid: --grid N nodes per axis over the bounding box of the points.
Output: --out FILE, the triangle mesh (binary PLY, float x y z, triangle faces, coincident points
merged), read back by the bench, which measures distances, normals and coverage on it exactly as on
the meshless points. Stdout: one JSON object {"method", "vtk_version", "scipy_version", "points",
"grid", "triangles", "vertices", "read_seconds", "interpolate_seconds", "contour_seconds",
"write_seconds"}. Exit status 2 with one line on stderr on bad arguments or data; 3 when numpy,
scipy (griddata) or vtk cannot be imported; `--check` only tests the imports of --method.

usage: scattered_peers.py --method griddata|delaunay|interp --input POINTS.ply --iso V --out MESH.ply
                          [--grid N] [--value NAME] [--neighbours K]
"""
import argparse
import json
import sys
import time


PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "<i2", "int16": "<i2",
             "ushort": "<u2", "uint16": "<u2", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
             "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8"}


def read_ply_points(path, value_name, np):
    with open(path, "rb") as f:
        head = b""
        while not head.endswith(b"end_header\n"):
            line = f.readline()
            if not line:
                raise ValueError("%s: no end_header" % path)
            head += line
            if len(head) > 1 << 20:
                raise ValueError("%s: header over 1 MiB" % path)
        lines = head.decode("ascii", "replace").splitlines()
        if not lines or lines[0] != "ply":
            raise ValueError("%s: not a PLY file" % path)
        if "format binary_little_endian 1.0" not in lines:
            raise ValueError("%s: only binary_little_endian PLY is read here" % path)
        count = None
        props = []
        element = None
        for ln in lines:
            w = ln.split()
            if not w:
                continue
            if w[0] == "element":
                element = w[1]
                if element == "vertex":
                    count = int(w[2])
            elif w[0] == "property" and element == "vertex":
                if w[1] == "list" or w[1] not in PLY_TYPES:
                    raise ValueError("%s: vertex property %s not read here" % (path, " ".join(w[1:])))
                props.append((w[2], PLY_TYPES[w[1]]))
        names = [p[0] for p in props]
        for need in ("x", "y", "z", value_name):
            if need not in names:
                raise ValueError("%s: no vertex property '%s'" % (path, need))
        if count is None or count < 4:
            raise ValueError("%s: fewer than 4 points" % path)
        dt = np.dtype(props)
        data = np.fromfile(f, dtype=dt, count=count)
        if data.shape[0] != count:
            raise ValueError("%s: %d points announced, %d present" % (path, count, data.shape[0]))
    xyz = np.column_stack([data["x"], data["y"], data["z"]]).astype(np.float64)
    val = data[value_name].astype(np.float64)
    keep = np.isfinite(xyz).all(axis=1) & np.isfinite(val)
    return xyz[keep], val[keep]


def grid_geometry(xyz, n):
    lo = xyz.min(axis=0)
    hi = xyz.max(axis=0)
    spacing = [(hi[k] - lo[k]) / (n - 1) if hi[k] > lo[k] else 1.0 for k in range(3)]
    return lo, spacing


def image_data(vtk, ns, n, lo, spacing, values):
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetOrigin(*[float(x) for x in lo])
    img.SetSpacing(*spacing)
    if values is not None:
        arr = ns.numpy_to_vtk(values, deep=1)
        arr.SetName("value")
        img.GetPointData().SetScalars(arr)
    return img


def flying_edges(vtk, img, iso):
    fe = vtk.vtkFlyingEdges3D()
    fe.SetInputData(img)
    fe.SetValue(0, iso)
    fe.ComputeNormalsOff()
    fe.ComputeGradientsOff()
    fe.ComputeScalarsOff()
    fe.Update()
    return fe.GetOutput()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--method", required=True, choices=["griddata", "delaunay", "interp"])
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--input")
    ap.add_argument("--iso", type=float)
    ap.add_argument("--out")
    ap.add_argument("--grid", type=int, default=64)
    ap.add_argument("--value", default="value")
    ap.add_argument("--neighbours", type=int, default=8)
    a = ap.parse_args()
    try:
        import numpy as np
        import vtk
        from vtk.util import numpy_support as ns
        scipy_version = None
        if a.method == "griddata":
            import scipy
            from scipy.interpolate import griddata
            from scipy.spatial import cKDTree
            scipy_version = scipy.__version__
    except ImportError as e:
        sys.stderr.write("scattered_peers.py: %s (python3-numpy, python3-scipy, python3-vtk9)\n" % e)
        return 3
    if a.check:
        return 0
    if a.input is None or a.iso is None or a.out is None:
        sys.stderr.write("scattered_peers.py: --input, --iso and --out are required\n")
        return 2
    if a.grid < 2 or a.grid > 1024 or a.neighbours < 1:
        sys.stderr.write("scattered_peers.py: --grid expects 2..1024, --neighbours >= 1\n")
        return 2

    t0 = time.perf_counter()
    xyz, val = read_ply_points(a.input, a.value, np)
    t1 = time.perf_counter()
    n = a.grid
    lo, spacing = grid_geometry(xyz, n)
    if a.method == "griddata":
        ax = [lo[k] + spacing[k] * np.arange(n) for k in range(3)]
        # x fastest (VTK's point order): meshgrid with indexing 'ij' over (z, y, x)
        gz, gy, gx = np.meshgrid(ax[2], ax[1], ax[0], indexing="ij")
        q = np.column_stack([gx.ravel(), gy.ravel(), gz.ravel()])
        g = griddata(xyz, val, q, method="linear")
        bad = ~np.isfinite(g)
        if bad.any():
            _, idx = cKDTree(xyz).query(q[bad])
            g[bad] = val[idx]
        t2 = time.perf_counter()
        mesh = flying_edges(vtk, image_data(vtk, ns, n, lo, spacing, g), a.iso)
    elif a.method == "delaunay":
        pts = vtk.vtkPoints()
        pts.SetData(ns.numpy_to_vtk(xyz, deep=1))
        pd = vtk.vtkPolyData()
        pd.SetPoints(pts)
        arr = ns.numpy_to_vtk(val, deep=1)
        arr.SetName("value")
        pd.GetPointData().SetScalars(arr)
        d = vtk.vtkDelaunay3D()
        d.SetInputData(pd)
        d.Update()
        t2 = time.perf_counter()
        cf = vtk.vtkContourFilter()
        cf.SetInputConnection(d.GetOutputPort())
        cf.SetValue(0, a.iso)
        cf.ComputeNormalsOff()
        cf.ComputeScalarsOff()
        cf.Update()
        mesh = cf.GetOutput()
    else:
        pts = vtk.vtkPoints()
        pts.SetData(ns.numpy_to_vtk(xyz, deep=1))
        pd = vtk.vtkPolyData()
        pd.SetPoints(pts)
        arr = ns.numpy_to_vtk(val, deep=1)
        arr.SetName("value")
        pd.GetPointData().SetScalars(arr)
        loc = vtk.vtkStaticPointLocator()
        loc.SetDataSet(pd)
        loc.BuildLocator()
        k = vtk.vtkGaussianKernel()
        k.SetKernelFootprintToNClosest()
        k.SetNumberOfPoints(a.neighbours)
        k.SetRadius(2.0 * max(spacing))
        k.SetSharpness(2.0)
        pi = vtk.vtkPointInterpolator()
        pi.SetInputData(image_data(vtk, ns, n, lo, spacing, None))
        pi.SetSourceData(pd)
        pi.SetKernel(k)
        pi.SetLocator(loc)
        pi.SetNullPointsStrategyToClosestPoint()
        pi.Update()
        t2 = time.perf_counter()
        out = pi.GetOutput()
        out.GetPointData().SetActiveScalars("value")
        mesh = flying_edges(vtk, out, a.iso)
    t3 = time.perf_counter()
    clean = vtk.vtkCleanPolyData()
    clean.SetInputData(mesh)
    clean.SetTolerance(0.0)
    clean.PointMergingOn()
    tri = vtk.vtkTriangleFilter()
    tri.SetInputConnection(clean.GetOutputPort())
    tri.Update()
    res = tri.GetOutput()
    w = vtk.vtkPLYWriter()
    w.SetInputData(res)
    w.SetFileName(a.out)
    w.SetFileTypeToBinary()
    if not w.Write():
        raise RuntimeError("cannot write " + a.out)
    t4 = time.perf_counter()
    print(json.dumps({"method": a.method, "vtk_version": vtk.vtkVersion.GetVTKVersion(), "scipy_version": scipy_version,
                      "points": int(xyz.shape[0]), "grid": n if a.method != "delaunay" else 0,
                      "triangles": res.GetNumberOfPolys(), "vertices": res.GetNumberOfPoints(),
                      "read_seconds": t1 - t0, "interpolate_seconds": t2 - t1, "contour_seconds": t3 - t2,
                      "write_seconds": t4 - t3}))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except Exception as e:  # noqa: BLE001 - one line on stderr, exit 2
        msg = str(e).splitlines()[0] if str(e) else repr(e)
        print("scattered_peers.py: %s" % msg, file=sys.stderr)
        sys.exit(2)

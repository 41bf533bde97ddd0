"""meshless: point-based isosurfaces and meshless fields of volume data, without meshing or resampling.

NumPy arrays in, NumPy arrays out; the work runs in the compiled libraries with the GIL released.

    >>> import numpy as np, meshless
    >>> x, y, z = np.mgrid[-1:1:64j, -1:1:64j, -1:1:64j]
    >>> surf = meshless.isosurface((x*x + y*y + z*z).astype(np.float32), 0.5, spacing=(2/63,) * 3, origin=(-1, -1, -1))
    >>> surf.points.shape[1], surf.normals.shape[1]
    (3, 3)

Volumes are 3-D arrays indexed [x, y, z], as VTK and PyVista think of them: a raw file read by NumPy
is ``np.fromfile(f, dtype).reshape(nz, ny, nx).T``, a Fortran-ordered view that is used in place.
C-ordered arrays and ``np.memmap`` are used in place too (uint8, int16, uint16, float32); other dtypes
and non-contiguous views are converted to one float32 copy.

Functions (keyword-only options; ``threads=0`` means every core this process may use):
    isosurface(volume, iso, ...)            iso-splatting of a regular volume (dissertation chapter 3)
    isosurface_points(points, values, iso)  the isosurface straight from scattered data (chapter 5)
    isosurface_blocks(blocks, iso, ...)     crack-free isosurface of overlapping curvilinear blocks (chapter 4)
    Field(points, values, kind=...)         a meshless field: field(q) -> values, field.gradient(q), save/load .mlf
    mc(volume, iso, ...)                    the marching-cubes mesh (the baseline): vertices, faces, normals
    read_points(path), PointSet.write(path) oriented points from and to PLY
Errors: ValueError for bad arguments; DataError (a ValueError) for unusable data, with the command's
one-line message; OSError when a file cannot be read or written.
"""

import numpy as _np

from . import _core
from ._core import DataError

__all__ = ["DataError", "PointSet", "Field", "isosurface", "isosurface_points", "isosurface_blocks", "mc", "read_points", "info"]


class PointSet:
    """Oriented points of an isosurface.

    Attributes (NumPy arrays sharing one buffer the PointSet owns; nothing was copied):
        points  (n, 3) float32  world positions
        normals (n, 3) float32  unit normals, pointing toward decreasing values (VTK's convention)
        radius  (n,)   float32  splat radius, world units
        values  (n,)   float32  the field's value at each point (the isovalue, within the projection's tolerance)
        block   (n,)   uint32   isosurface_blocks only: the block each point was seeded in, else None
        stats   dict            what the run counted (cells, seeds, Newton outcomes, ...)
        warnings list of str    what the run warned about (isosurface_points)
        comments list of str    read_points: the PLY's comments
    Methods: write(path) writes the PLY `meshless isosurface` writes.
    """

    __slots__ = ("points", "normals", "radius", "values", "block", "stats", "warnings", "comments")

    def __init__(self, arrays):
        self.points = arrays["points"]
        self.normals = arrays["normals"]
        self.radius = arrays["radius"]
        self.values = arrays["values"]
        self.block = arrays.get("block")
        self.stats = arrays.get("stats", {})
        self.warnings = list(arrays.get("warnings", []))
        self.comments = list(arrays.get("comments", []))

    def write(self, path):
        """Writes the points as the PLY `meshless isosurface -o out.ply` writes (binary little endian,
        x y z nx ny nz radius value, and block when there are block ids), atomically."""
        _core._write_points(str(path), self.points, self.normals, self.radius, self.values, self.block)

    def __len__(self):
        return len(self.points)

    def __repr__(self):
        return "meshless.PointSet(%d points)" % len(self)

    def to_vtk(self):
        """A vtkPolyData with one vertex cell per point, the normals as its Normals and `radius`,
        `value` (and `block`) point arrays: what `meshless isosurface -o out.vtp` writes, for
        ParaView and VTK pipelines. Needs VTK's Python module (python3-vtk9); the arrays are copied
        into VTK's."""
        from vtkmodules.util import numpy_support as ns
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

        n = len(self)
        pts = vtkPoints()
        pts.SetData(ns.numpy_to_vtk(_np.ascontiguousarray(self.points), deep=True))
        cells = vtkCellArray()
        offsets = _np.arange(n + 1, dtype=_np.int64)
        cells.SetData(ns.numpy_to_vtk(offsets, deep=True, array_type=ns.get_vtk_array_type(_np.int64)),
                      ns.numpy_to_vtk(offsets[:-1].copy(), deep=True, array_type=ns.get_vtk_array_type(_np.int64)))
        poly = vtkPolyData()
        poly.SetPoints(pts)
        poly.SetVerts(cells)
        normals = ns.numpy_to_vtk(_np.ascontiguousarray(self.normals), deep=True)
        normals.SetName("Normals")
        poly.GetPointData().SetNormals(normals)
        for name, arr in (("radius", self.radius), ("value", self.values), ("block", self.block)):
            if arr is None:
                continue
            a = ns.numpy_to_vtk(_np.ascontiguousarray(arr), deep=True)
            a.SetName(name)
            poly.GetPointData().AddArray(a)
        poly.GetPointData().SetActiveScalars("value")
        return poly

    def to_pyvista(self):
        """The same as a pyvista.PolyData (needs PyVista)."""
        import pyvista
        return pyvista.wrap(self.to_vtk())


def isosurface(volume, iso, *, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), projection="approx", threads=0):
    """Iso-splatting of a regular volume (dissertation chapter 3): one sample per active cell,
    projected onto the trilinear isosurface ("approx": Newton steps, the default; "exact": ray
    casting within the cell; "none": the cell samples). The same points `meshless isosurface` writes
    for the same volume (in another order for a C-ordered array).

    volume: 3-D array indexed [x, y, z]; spacing, origin: world units per axis. An np.memmap of a
    file (modes r, r+, w+) is read slab by slab and its pages handed back as they are done, so a
    volume bigger than RAM takes a few slabs of memory. Returns a PointSet."""
    volume = _np.asanyarray(volume)
    # a file mapped shared (np.memmap modes r, r+, w+) streams slab by slab, its pages handed back
    # as they are done: bounded memory for volumes bigger than RAM; the same points
    shared = isinstance(volume, _np.memmap) and getattr(volume, "mode", None) in ("r", "r+", "w+", "readonly", "readwrite", "write")
    return PointSet(_core._isosurface_volume(volume, float(iso), spacing, origin, projection, int(threads), bool(shared)))


def _field_params(kind, hardy_c=0.025, hardy_c_world=0.0, binning=5.0, max_points=140, alpha=0.75, local_points=160,
                  normalise_axes=False):
    return _core._field_params(kind, float(hardy_c), float(hardy_c_world), float(binning), int(max_points),
                               float(alpha), int(local_points), bool(normalise_axes))


class Field:
    """A meshless field fitted to scattered values (dissertation sections 2.1.1, 4.3 and 5.5): a drop-in
    for scipy.interpolate.RBFInterpolator where it fits, linear in the points instead of cubic.

        Field(points, values, kind="mpu", *, value_name="", hardy_c=0.025, hardy_c_world=0, binning=5, max_points=140,
              alpha=0.75, local_points=160, normalise_axes=False, threads=0)

    points (n, 3), values (n,): rows with a NaN/Inf are dropped. kind: "mpu" (the multi-level partition
    of unity, the default for points as in `meshless fit`), "rbf-grid" (the RBF grid of multiblock
    data) or "global-rbf" (Hardy's global multiquadric, small sets only). The options are those of
    `meshless fit` (see `meshless fit --help`): hardy_c is Hardy's c as a fraction of the bounding-box
    diagonal, hardy_c_world overrides it in world units; value_name is what the .mlf records as the
    values' name (a CSV column's, say).

    field(queries) -> values (m,); field.gradient(queries) -> (m, 3); queries (m, 3).
    field.save("f.mlf") writes what `meshless fit` writes; Field.load("f.mlf") reads it (and any .mlf
    `meshless fit` wrote)."""

    __slots__ = ("_f", "threads")

    def __init__(self, points, values, kind="mpu", *, value_name="", threads=0, **options):
        if points is None:  # Field.load
            self._f, self.threads = values, int(threads)
            return
        self._f = _core._Field(_np.asarray(points, dtype=_np.float64), _np.asarray(values, dtype=_np.float64),
                               _field_params(kind, **options), int(threads), str(value_name))
        self.threads = int(threads)

    def __call__(self, queries):
        return self._f._evaluate(_np.asarray(queries, dtype=_np.float64), False, self.threads)

    def gradient(self, queries):
        """The gradient (m, 3) at queries (m, 3), value units per world unit."""
        return self._f._evaluate(_np.asarray(queries, dtype=_np.float64), True, self.threads)

    def save(self, path, *, zstd_level=1):
        """Writes the fitted field to a .mlf (the file `meshless fit` writes, read by `--field F.mlf`)."""
        self._f._save(str(path), int(zstd_level))

    @staticmethod
    def load(path, *, threads=0):
        """A field read from a .mlf (written by `meshless fit` or Field.save)."""
        return Field(None, _core._Field._load(str(path)), threads=threads)

    @property
    def kind(self):
        return self._f.kind

    @property
    def bounds(self):
        """((xmin, ymin, zmin), (xmax, ymax, zmax)): the field's domain, world units."""
        return self._f.bounds

    @property
    def value_name(self):
        return self._f.value_name

    @property
    def stats(self):
        """What the fit counted: input and merged points, local interpolants, c, memory, seconds."""
        return self._f.stats

    def __repr__(self):
        return "meshless.Field(kind=%r, points=%d)" % (self.kind, self._f.points)


def isosurface_points(points, values, iso, *, field="mpu", samples=2, reg_gap=4.0, max_cells=20_000_000, max_level=10,
                      tolerance=0.01, max_iterations=20, max_travel=2.0, threads=0, **field_options):
    """The isosurface straight from scattered data (dissertation chapter 5): binning grid, marching
    3x3x3 stencils tetrahedralised by CGAL's Delaunay, marching tetrahedra, a barycentric lattice of
    samples(samples+1)/2 seeds per triangle, Newton onto the meshless field. The same points
    `meshless isosurface POINTS` writes for the same data and options.

    points (n, 3), values (n,); field: a kind ("mpu", "rbf-grid", "global-rbf", with the Field options
    as keywords) or a Field fitted to these points. reg_gap, max_cells, max_level, tolerance,
    max_iterations, max_travel: as the CLI's --reg-gap ... --max-travel. Returns a PointSet."""
    if isinstance(field, Field):
        if field_options:
            raise ValueError("field options (%s) apply when field names a kind, not to a fitted Field" % ", ".join(field_options))
        f = field._f
    else:
        f = _field_params(field, **field_options)
    points, values = _np.asarray(points, dtype=_np.float64), _np.asarray(values, dtype=_np.float64)
    return PointSet(_core._isosurface_points(points, values, float(iso), f, int(samples), float(reg_gap), int(max_cells),
                                             int(max_level), float(tolerance), int(max_iterations), float(max_travel),
                                             int(threads)))


def isosurface_blocks(blocks, iso, *, field="rbf-grid", samples=3, tolerance=0.01, max_iterations=20, max_travel=2.0,
                      threads=0, **field_options):
    """Crack-free isosurface of overlapping curvilinear blocks (dissertation chapter 4): one meshless
    field over every block's valid nodes, each block's marching-cubes triangles seeded on a
    barycentric lattice and projected onto it by Newton.

    blocks: a list of (coords, values) or (coords, values, iblank): coords (ni, nj, nk, 3) world
    positions, values (ni, nj, nk), iblank (ni, nj, nk) with 0 = blanked (PLOT3D's IBLANK). Nodes with a
    NaN/Inf are blanked too. Returns a PointSet whose `block` says which block seeded each point."""
    params = _field_params(field, **field_options)
    return PointSet(_core._isosurface_blocks(list(blocks), float(iso), params, int(samples), float(tolerance),
                                             int(max_iterations), float(max_travel), int(threads)))


def read_points(path):
    """The oriented points of a PLY point set (`meshless isosurface -o out.ply`, or any PLY with
    x y z nx ny nz radius value vertices) as a PointSet; `comments` holds the PLY's comments (the
    isovalue, the field, the bounds the command recorded)."""
    return PointSet(_core._read_points(str(path)))


def info(path, *, value_range=False):
    """What `meshless info PATH` prints about a file the tool reads or writes (volumes, brick, sample
    and point stores, point/sample streams, PLY point sets and meshes, PNG, .mlf, .mlh, multiblock and
    AMR grids, point sets), as a string with the same bytes; value_range=True also reads a volume
    whole for its value range (`--value-range`). A damaged or unknown file raises DataError, one
    that cannot be read OSError."""
    return _core._info(str(path), bool(value_range))


def mc(volume, iso, *, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), threads=0):
    """The marching-cubes mesh of a volume (the triangle baseline, `meshless mc`): (vertices (n, 3)
    float32, faces (m, 3) uint32, normals (n, 3) float32). Normals point toward decreasing values and
    faces wind counter-clockwise seen from the normal side, as in VTK and scikit-image's
    marching_cubes(..., gradient_direction="descent")."""
    return _core._mc(_np.asanyarray(volume), float(iso), spacing, origin, int(threads))

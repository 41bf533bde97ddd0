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
    read_volume(path, ...)                  any volume the commands read, as a Volume ([x, y, z] array, mapped when raw)
    read_points(path, ...), PointSet.save() oriented or scattered points from any point file; saved as the commands write
    read_multiblock(paths, ...)             curvilinear blocks and AMR boxes (chapter 4) as Blocks
    from_vtk(obj), obj.to_vtk()             VTK/PyVista datasets in and out (VTK's buffers, no copy where they fit)
    render(volume | store | field, ...)     ray-cast volume rendering (sections 6.6, 7.4): an Image
    splat(pointset | path, ...)             surface splatting of oriented points (section 3.6): an Image
    read_image(path), Image.save(path)      PNG pictures in and out (the product's PNG reader and writer)
    hierarchy(points, values, ...)          the cluster binary tree of chapter 6; tree.lod(level=|error=)
    open_store(path), Store.isosurface(iso) a brick, sample or point store's isosurface as a generator of batches
Ctrl-C interrupts isosurface(), isosurface_points() and isosurface_blocks() within a second.
Errors: ValueError for bad arguments; DataError (a ValueError) for unusable data, with the command's
one-line message; OSError when a file cannot be read or written.
"""

import numpy as _np

from . import _core
from ._core import DataError, __version__

__all__ = ["DataError", "PointSet", "Volume", "Block", "Multiblock", "read_volume", "read_multiblock", "from_vtk", "Field", "Image", "ClusterTree", "Store", "isosurface", "isosurface_points",
           "isosurface_blocks", "mc", "read_points", "info", "render", "splat", "read_image", "hierarchy", "open_store"]


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
        comments list of str    read_points: the PLY's comments (written back by save)
        value_name str          scattered data: the values' name in the file ("" when none)
        blocks   list of dict   read_points of scattered data: the file's blocks (name, dims, first, count)
    Scattered data (a level of detail, ClusterTree.lod; read_points of a CSV, VTP, PLOT3D, .npy, .mlc,
    ... file) is points (n, 3) and values (n,) float64 owning the reader's or the extraction's
    buffers, normals and radius None.
    Methods: save(path) (or write(path)) writes by extension what the commands write for the same
    data: oriented points as `meshless isosurface -o x.ply|x.vtp`, scattered data as
    `meshless lod -o x.ply|x.csv|x.vtp`; to_vtk(), to_pyvista().
    """

    __slots__ = ("points", "normals", "radius", "values", "block", "stats", "warnings", "comments", "value_name",
                 "blocks", "has_values")

    def __init__(self, arrays):
        self.points = arrays["points"]
        self.normals = arrays.get("normals")
        self.radius = arrays.get("radius")
        self.values = arrays["values"]
        self.block = arrays.get("block")
        self.stats = arrays.get("stats", {})
        self.warnings = list(arrays.get("warnings", []))
        self.comments = list(arrays.get("comments", []))
        self.value_name = arrays.get("value_name", "")
        self.blocks = list(arrays.get("blocks", []))
        self.has_values = bool(arrays.get("has_values", True))

    def save(self, path):
        """Writes the points by extension, atomically, the bytes the commands write for the same data
        (with `comments` as the file's comments):
        oriented points (normals and radius): .ply as `meshless isosurface -o out.ply` (binary little
        endian, x y z nx ny nz radius value, and block when there are block ids), .vtp as `-o out.vtp`;
        scattered data (normals None): .ply (double x y z value), .csv (x,y,z,value, 17 digits) or
        .vtp, as `meshless lod -o`. Another extension raises ValueError."""
        path = str(path)
        if self.normals is None:
            _core._write_point_set(path, self.points, self.values, str(self.value_name or ""), self.has_values,
                                   list(self.comments))
            return
        _core._write_points(path, self.points, self.normals, self.radius, self.values, self.block,
                            list(self.comments) or None)

    write = save

    def __len__(self):
        return len(self.points)

    def __repr__(self):
        return "meshless.PointSet(%d points)" % len(self)

    def to_vtk(self):
        """A vtkPolyData with one vertex cell per point: oriented points with the normals as its
        Normals and `radius`, `value` (and `block`) point arrays, what `meshless isosurface -o
        out.vtp` writes; scattered data with its values as the array named `value_name` (or
        "value"). For ParaView and VTK pipelines; from_vtk() reads it back. Needs VTK's Python
        module (python3-vtk9); the arrays are copied into VTK's."""
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
        if self.normals is not None:
            normals = ns.numpy_to_vtk(_np.ascontiguousarray(self.normals), deep=True)
            normals.SetName("Normals")
            poly.GetPointData().SetNormals(normals)
            arrays = (("radius", self.radius), ("value", self.values), ("block", self.block))
            active = "value"
        else:
            active = self.value_name or "value"
            arrays = ((active, self.values),)
        for name, arr in arrays:
            if arr is None:
                continue
            a = ns.numpy_to_vtk(_np.ascontiguousarray(arr), deep=True)
            a.SetName(name)
            poly.GetPointData().AddArray(a)
        poly.GetPointData().SetActiveScalars(active)
        return poly

    def to_pyvista(self):
        """The same as a pyvista.PolyData (needs PyVista)."""
        import pyvista
        return pyvista.wrap(self.to_vtk())


class Volume:
    """A regular volume read by read_volume(): its samples and where they lie.

    Attributes:
        array        (nx, ny, nz) ndarray indexed [x, y, z] (Fortran order), uint8, int16, uint16 or
                     float32: the reader's own buffer, owned by the array (a raw payload is a private
                     mapping of the file: nothing read or copied until touched; writes stay in memory)
        spacing      (sx, sy, sz) world units between samples; origin (x, y, z) of sample [0, 0, 0]
        patient_axes (3, 3) float64 or None: row i is the LPS direction of world axis i, where the
                     header says it (NIfTI sform/qform, NRRD space, MetaImage TransformMatrix)
        patient_axes_source  the header fields it came from, or None
        length_unit  the unit of the world coordinates where the file states it ("mm", "um", "m", "cm",
                     "nm": DICOM, NIfTI xyzt_units, NRRD space units, OME-Zarr axes), or None
        value_unit   the values' unit where the file states it (DICOM Rescale Type, "HU" for a CT; NRRD
                     sample units), or None
        format       the reader's name ("raw", "nrrd", "metaimage", "vti", "nifti", "dicom", ...)
        warnings     list of str: what the command would warn about (raw options a header overrides)
    np.asarray(volume) is `array`; isosurface(), mc() and render() take a Volume with its spacing and
    origin."""

    __slots__ = ("array", "spacing", "origin", "patient_axes", "patient_axes_source", "length_unit", "value_unit", "format", "warnings")

    def __init__(self, arrays):
        self.array = arrays["array"]
        self.spacing = tuple(arrays["spacing"])
        self.origin = tuple(arrays["origin"])
        self.patient_axes = arrays.get("patient_axes")
        self.patient_axes_source = arrays.get("patient_axes_source")
        self.length_unit = arrays.get("length_unit")
        self.value_unit = arrays.get("value_unit")
        self.format = arrays.get("format", "")
        self.warnings = list(arrays.get("warnings", []))

    shape = property(lambda self: self.array.shape)
    dtype = property(lambda self: self.array.dtype)

    def __array__(self, dtype=None, copy=None):
        if dtype is not None and _np.dtype(dtype) != self.array.dtype:
            return self.array.astype(dtype)
        return self.array.copy() if copy else self.array

    def __repr__(self):
        return "meshless.Volume(%s %s, spacing=%s)" % ("x".join(map(str, self.shape)), self.dtype, self.spacing)

    def to_vtk(self):
        """A vtkImageData over the same samples (no copy: VTK's scalars array `values` is the
        array's memory, which the vtkImageData keeps alive), spacing and origin. Needs VTK's Python
        module (python3-vtk9)."""
        from vtkmodules.util import numpy_support as ns
        from vtkmodules.vtkCommonDataModel import vtkImageData

        flat = self.array.ravel(order="F")  # a view: the array is Fortran-ordered
        img = vtkImageData()
        img.SetDimensions(*self.shape)
        img.SetSpacing(*self.spacing)
        img.SetOrigin(*self.origin)
        scalars = ns.numpy_to_vtk(flat, deep=False)
        scalars.SetName("values")
        img.GetPointData().SetScalars(scalars)
        return img

    def to_pyvista(self):
        """The same as a pyvista.ImageData (needs PyVista)."""
        import pyvista
        return pyvista.wrap(self.to_vtk())


def _volume_args(volume, spacing, origin):
    """A Volume's array with its spacing and origin unless given; defaults 1 and 0 for arrays."""
    if isinstance(volume, Volume):
        return (volume.array, volume.spacing if spacing is None else spacing,
                volume.origin if origin is None else origin)
    return (_np.asanyarray(volume), (1.0, 1.0, 1.0) if spacing is None else spacing,
            (0.0, 0.0, 0.0) if origin is None else origin)


def _isovalues(iso):
    """iso as a list of floats: one number, or a sequence of them (at least one)."""
    if _np.ndim(iso) == 0:
        return [float(iso)]
    values = [float(v) for v in _np.asarray(iso, dtype=float).ravel()]
    if not values:
        raise ValueError("iso: give at least one isovalue")
    return values


def _concatenated(parts, isos):
    """The point sets of several isovalues one after another (`meshless isosurface --iso V1,V2,...`)."""
    arrays = {k: _np.concatenate([p[k] for p in parts]) for k in ("points", "normals", "radius", "values")}
    stats = {k: sum(p["stats"][k] for p in parts) for k in parts[0]["stats"]}
    stats["isovalues"] = list(isos)
    arrays["stats"] = stats
    arrays["warnings"] = [w for p in parts for w in p.get("warnings", [])]
    return arrays


def isosurface(volume, iso, *, spacing=None, origin=None, projection="approx", threads=0):
    """Iso-splatting of a regular volume (dissertation chapter 3): one sample per active cell,
    projected onto the trilinear isosurface ("approx": Newton steps, the default; "exact": ray
    casting within the cell; "none": the cell samples). The same points `meshless isosurface` writes
    for the same volume (in another order for a C-ordered array).

    volume: 3-D array indexed [x, y, z] or a Volume (read_volume; its spacing and origin unless
    given); spacing, origin: world units per axis (default 1 and 0). iso: a number, or a sequence of
    them: their surfaces one after another, each point's value its isovalue (as `meshless isosurface
    --iso V1,V2,...`). An np.memmap of a file (modes r, r+, w+) is read slab by slab and its pages
    handed back as they are done, so a volume bigger than RAM takes a few slabs of memory. Returns a
    PointSet."""
    volume, spacing, origin = _volume_args(volume, spacing, origin)
    # a file mapped shared (np.memmap modes r, r+, w+) streams slab by slab, its pages handed back
    # as they are done: bounded memory for volumes bigger than RAM; the same points
    shared = isinstance(volume, _np.memmap) and getattr(volume, "mode", None) in ("r", "r+", "w+", "readonly", "readwrite", "write")
    isos = _isovalues(iso)
    parts = [_core._isosurface_volume(volume, v, spacing, origin, projection, int(threads), bool(shared)) for v in isos]
    return PointSet(parts[0] if len(parts) == 1 else _concatenated(parts, isos))


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
    NaN/Inf are blanked too. Or the Blocks of read_multiblock (an AMR hierarchy's boxes with their
    levels and covered nodes, as `meshless isosurface` takes them). Returns a PointSet whose `block` says which block seeded each point."""
    params = _field_params(field, **field_options)
    blocks = [(b.coords, b.values, b.valid, b.covered, b.level, b.cell_centred) if isinstance(b, Block) else tuple(b)
              for b in blocks]
    return PointSet(_core._isosurface_blocks(blocks, float(iso), params, int(samples), float(tolerance),
                                             int(max_iterations), float(max_travel), int(threads)))


def read_points(path, *, value="", columns="", q_component=0, level=None, error=None):
    """A point set from any file the commands read points from, as a PointSet, through their readers
    (dissertation chapters 4-5 inputs):
    - an oriented PLY point set (`meshless isosurface -o out.ply`: x y z nx ny nz radius value
      vertices): oriented points (float32), `comments` the PLY's (isovalue, field, bounds);
    - scattered data: CSV/TSV/text, PLY, VTP, VTS, NumPy .npy, PLOT3D (.xyz/.bin + q, .p3d), a point
      store (.mlc, every brick), a level of detail of a .mlh (level= or error=; the finest without),
      a volume (one point per voxel): points (n, 3) and values (n,) float64 views of the reader's
      buffers (no copy), `value_name`, `blocks`; rows with a NaN/Inf dropped (stats).
    value, columns, q_component: as `meshless fit --value/--columns/--q-component` (the scalar by
    name; text columns "x,y,z,value"; PLOT3D q component 0..5). DataError for a damaged file,
    OSError for one that cannot be read."""
    return PointSet(_core._read_point_set(str(path), str(value), str(columns), int(q_component),
                                          None if level is None else int(level), None if error is None else float(error)))


def read_volume(path, *, spacing=None, origin=None, series="", array="", dims=None, dtype=None, big_endian=False,
                memory=None, resolution_level=0):
    """A regular volume from any file `meshless isosurface` reads (raw name_XxYxZ_type.raw, NRRD,
    MetaImage, VTK legacy, VTI, vtk.js, SLC, NIfTI, Voreen .dat, a DICOM folder/DICOMDIR/slice, a 3-D
    .npy, a Zarr store, an HDF5 dataset "file.h5:/group/name", a brick store .mlb read whole), through
    the command's reader, as a Volume whose array is indexed
    [x, y, z]. Samples lying raw in the file in host byte order are mapped, not read: the array is
    the mapping, nothing copied (a compressed or converted payload is decoded once, into the array's
    own buffer).

    dims (nx, ny, nz), dtype ("uint8", "int16", "uint16", "float32"), big_endian, spacing: a raw
    file's layout, as --dims/--type/--endian/--spacing (a file that describes itself keeps its own,
    with a warning in `warnings`); spacing and origin given also replace what the file says in the
    result. series: the DICOM series (Series Instance UID or its number), as --series. array: the
    point array of a .vti, VTK legacy or vtk.js volume holding several, by name, or the dataset of an
    HDF5 file ("/group/name"), as --array (default: the active scalars, else the first; an HDF5 file's
    only 3-D dataset; ValueError for a format of one unnamed array). resolution_level: an OME-Zarr
    image's multiscale level, 0 the full resolution, as --resolution-level. memory: the
    most bytes a volume read whole may take ('2G' or an int; default the machine's memory), as
    --memory. DataError for a damaged file, OSError for one that cannot be read or does not fit."""
    sp = None if spacing is None else tuple(float(x) for x in spacing)
    vol = Volume(_core._read_volume(str(path), None if dims is None else tuple(int(n) for n in dims),
                                    None if dtype is None else _np.dtype(dtype).name, bool(big_endian), sp, str(series),
                                    str(array), None if memory is None else _memory_bytes(memory), int(resolution_level)))
    if sp is not None:
        if len(sp) != 3 or not all(_np.isfinite(sp)) or min(sp) <= 0:
            raise ValueError("spacing: expected three numbers > 0")
        vol.spacing = sp
    if origin is not None:
        org = tuple(float(x) for x in origin)
        if len(org) != 3 or not all(_np.isfinite(org)):
            raise ValueError("origin: expected three finite numbers")
        vol.origin = org
    return vol


class Block:
    """One curvilinear block or AMR box of read_multiblock (dissertation chapter 4), i fastest:
    coords (ni, nj, nk, 3) and values (ni, nj, nk) float64 views of the reader's lattice (no copy),
    valid (ni, nj, nk) uint8 or None (0: IBLANK 0 or a NaN/Inf node), covered (uint8 or None: AMR
    nodes a finer level covers), name, level (AMR), cell_centred. A Block unpacks as
    (coords, values, valid); isosurface_blocks takes it whole."""

    __slots__ = ("coords", "values", "valid", "covered", "name", "level", "cell_centred")

    def __init__(self, d):
        for k in Block.__slots__:
            setattr(self, k, d[k])

    def __iter__(self):
        return iter((self.coords, self.values, self.valid))

    def __len__(self):
        return 3

    def __getitem__(self, i):
        return (self.coords, self.values, self.valid)[i]

    def __repr__(self):
        return "meshless.Block(%r, %s)" % (self.name, "x".join(map(str, self.values.shape)))


class Multiblock(list):
    """The blocks of read_multiblock (a list of Block), with value_name, format ("plot3d", "vts",
    "vtm", "vthb", "vtm-amr", "volume"), notes and stats (blanked, nonfinite, covered nodes)."""

    def __init__(self, d, blocks=()):
        super().__init__([Block(b) for b in d["blocks"]] + [Block(b) for b in blocks])
        self.value_name, self.format = d["value_name"], d["format"]
        self.notes, self.stats = list(d["notes"]), dict(d["stats"])


def _vtk_point_array(data, name):
    """A point-data array of a VTK dataset as NumPy (a view of VTK's buffer), by name or the active
    scalars, else the first array; None when there is none."""
    from vtkmodules.util import numpy_support as ns
    pd = data.GetPointData()
    arr = pd.GetArray(name) if name else (pd.GetScalars() or (pd.GetArray(0) if pd.GetNumberOfArrays() else None))
    if name and arr is None:
        raise ValueError("from_vtk: the dataset has no point array named %r" % (name,))
    if arr is None:
        return None, ""
    a = ns.vtk_to_numpy(arr)
    if a.ndim != 1:
        raise ValueError("from_vtk: point array %r has %d components; give array= a scalar one" % (arr.GetName(), a.shape[1]))
    return a, arr.GetName() or ""


def _vtk_block(grid, name, array):
    """A vtkStructuredGrid as a Block: coords and values are views of VTK's buffers (i fastest)."""
    from vtkmodules.util import numpy_support as ns
    ni, nj, nk = grid.GetDimensions()
    pts = ns.vtk_to_numpy(grid.GetPoints().GetData()).astype(_np.float64, copy=False)
    vals, _ = _vtk_point_array(grid, array)
    if vals is None:
        raise ValueError("from_vtk: structured grid %r has no point scalars" % (name,))
    ghosts = grid.GetPointData().GetArray("vtkGhostType")
    valid = None
    if ghosts is not None:  # HIDDENPOINT (2): VTK's blanking, PLOT3D's IBLANK 0
        valid = ((ns.vtk_to_numpy(ghosts) & 2) == 0).astype(_np.uint8).reshape(nk, nj, ni).T
    return {"coords": pts.reshape(nk, nj, ni, 3).transpose(2, 1, 0, 3),
            "values": vals.astype(_np.float64, copy=False).reshape(nk, nj, ni).T, "valid": valid, "covered": None,
            "name": name, "level": 0, "cell_centred": False}


def from_vtk(obj, *, array=None):
    """A VTK or PyVista dataset as the module's objects, through VTK's buffers (vtk.util.numpy_support:
    no copy where the dtype already fits):
    - vtkImageData (pyvista.ImageData/UniformGrid) -> Volume: the point scalars (or `array`) as an
      [x, y, z] Fortran-ordered view of VTK's buffer (uint8, int16, uint16, float32 in place, other
      types converted once by isosurface()), spacing, origin (a direction matrix is not applied);
    - vtkPolyData (pyvista.PolyData) -> PointSet: with `Normals` and a `radius` array (what
      PointSet.to_vtk() and `meshless isosurface -o x.vtp` make), oriented points whose arrays are
      views of VTK's (float32); otherwise scattered data, points (n, 3) and the point scalars (or
      `array`) as values, float64;
    - vtkStructuredGrid -> Multiblock of one Block (coords (ni, nj, nk, 3), values, valid from the
      ghost array's hidden points: VTK's blanking);
    - vtkMultiBlockDataSet -> Multiblock of its structured grids (nested sets flattened, in order).
    The returned arrays keep the VTK arrays alive. Needs VTK's Python module (python3-vtk9): the
    meshless module itself imports without it. ValueError for other datasets."""
    from vtkmodules.util import numpy_support as ns
    from vtkmodules.vtkCommonDataModel import vtkImageData, vtkMultiBlockDataSet, vtkPolyData, vtkStructuredGrid

    if isinstance(obj, vtkImageData):
        nx, ny, nz = obj.GetDimensions()
        vals, _ = _vtk_point_array(obj, array)
        if vals is None:
            raise ValueError("from_vtk: the image data has no point scalars")
        return Volume({"array": vals.reshape(nz, ny, nx).T, "spacing": obj.GetSpacing(), "origin": obj.GetOrigin(),
                       "format": "vtk"})
    if isinstance(obj, vtkPolyData):
        pd = obj.GetPointData()
        n = obj.GetNumberOfPoints()
        pts = ns.vtk_to_numpy(obj.GetPoints().GetData()) if n else _np.zeros((0, 3))
        normals, radius = pd.GetNormals(), pd.GetArray("radius")
        if normals is not None and radius is not None and array is None:
            value = pd.GetArray("value")
            d = {"points": pts.astype(_np.float32, copy=False),
                 "normals": ns.vtk_to_numpy(normals).astype(_np.float32, copy=False),
                 "radius": ns.vtk_to_numpy(radius).astype(_np.float32, copy=False),
                 "values": (ns.vtk_to_numpy(value) if value is not None else _np.zeros(n)).astype(_np.float32, copy=False)}
            block = pd.GetArray("block")
            if block is not None:
                d["block"] = ns.vtk_to_numpy(block).astype(_np.uint32, copy=False)
            return PointSet(d)
        vals, name = _vtk_point_array(obj, array)
        return PointSet({"points": pts.astype(_np.float64, copy=False),
                         "values": _np.zeros(n) if vals is None else vals.astype(_np.float64, copy=False),
                         "value_name": name, "has_values": vals is not None})
    if isinstance(obj, vtkStructuredGrid):
        return Multiblock({"blocks": [], "value_name": "", "format": "vtk", "notes": [], "stats": {}},
                          [_vtk_block(obj, "block 0", array)])
    if isinstance(obj, vtkMultiBlockDataSet):
        blocks = []

        def walk(mb, prefix):
            for i in range(mb.GetNumberOfBlocks()):
                b = mb.GetBlock(i)
                name = prefix + str(i)
                if isinstance(b, vtkMultiBlockDataSet):
                    walk(b, name + ".")
                elif isinstance(b, vtkStructuredGrid):
                    blocks.append(_vtk_block(b, "block " + name, array))
                elif b is not None:
                    raise ValueError("from_vtk: block %s is a %s; blocks are vtkStructuredGrid" % (name, b.GetClassName()))
        walk(obj, "")
        return Multiblock({"blocks": [], "value_name": "", "format": "vtk", "notes": [], "stats": {}}, blocks)
    raise ValueError("from_vtk: expected vtkImageData, vtkPolyData, vtkStructuredGrid or vtkMultiBlockDataSet (or their "
                     "PyVista wrappers), got %s" % type(obj).__name__)


def read_multiblock(paths, *, value="", q_component=0):
    """Multiblock grids and AMR hierarchies with their blocks kept (dissertation chapter 4), through
    the reader of `meshless isosurface BLOCKS` and `meshless mc BLOCKS`: PLOT3D (.xyz/.x/.g/.bin with
    its q file, .p3d), VTK XML .vts/.vti/.vtr, .vtm, .vthb and older AMR .vtm; several files give
    their blocks in order. value, q_component: the scalar, as --value/--q-component. Returns a
    Multiblock, a list of Block, which isosurface_blocks takes as it is."""
    if isinstance(paths, (str, bytes)) or hasattr(paths, "__fspath__"):
        paths = [paths]
    return Multiblock(_core._read_multiblock([str(p) for p in paths], str(value), int(q_component)))


def info(path, *, value_range=False):
    """What `meshless info PATH` prints about a file the tool reads or writes (volumes, brick, sample
    and point stores, point/sample streams, PLY point sets and meshes, PNG, .mlf, .mlh, multiblock and
    AMR grids, point sets), as a string with the same bytes; value_range=True also reads a volume
    whole for its value range (`--value-range`). A damaged or unknown file raises DataError, one
    that cannot be read OSError."""
    return _core._info(str(path), bool(value_range))


def mc(volume, iso, *, spacing=None, origin=None, threads=0):
    """The marching-cubes mesh of a volume (the triangle baseline, `meshless mc`): (vertices (n, 3)
    float32, faces (m, 3) uint32, normals (n, 3) float32). Normals point toward decreasing values and
    faces wind counter-clockwise seen from the normal side, as in VTK and scikit-image's
    marching_cubes(..., gradient_direction="descent"). iso: a number, or a sequence of them: one
    mesh holding their surfaces in order, none welded to another (as `meshless mc --iso V1,V2,...`)."""
    volume, spacing, origin = _volume_args(volume, spacing, origin)
    meshes = [_core._mc(volume, v, spacing, origin, int(threads)) for v in _isovalues(iso)]
    if len(meshes) == 1:
        return meshes[0]
    offsets = _np.cumsum([0] + [len(m[0]) for m in meshes[:-1]])
    return (_np.concatenate([m[0] for m in meshes]),
            _np.concatenate([m[1] + _np.asarray(o, dtype=m[1].dtype) for m, o in zip(meshes, offsets)]),
            _np.concatenate([m[2] for m in meshes]))


class Image:
    """A picture made by render() or splat(), or read by read_image(): 8-bit RGB, top row first.

    Attributes:
        pixels   (height, width, 3) uint8  the recipe's own buffer (nothing was copied; read-only
                                          use is expected, writes change this Image)
        stats    dict                     what the run counted (rays, samples, points drawn, seconds)
        warnings list of str              what the command would have printed to stderr
    Methods: save(path) writes the PNG the command writes (formats/png_writer, the same bytes);
    _repr_png_() gives those bytes to Jupyter; np.asarray(image) is `pixels`.
    The command's pictures carry no alpha (they are composited over the background), so there is no
    fourth channel."""

    __slots__ = ("pixels", "stats", "warnings")

    def __init__(self, arrays):
        self.pixels = arrays["pixels"]
        self.stats = arrays.get("stats", {})
        self.warnings = list(arrays.get("warnings", []))

    @property
    def width(self):
        return self.pixels.shape[1]

    @property
    def height(self):
        return self.pixels.shape[0]

    def __array__(self, dtype=None, copy=None):
        if dtype is not None and _np.dtype(dtype) != self.pixels.dtype:
            return self.pixels.astype(dtype)
        return self.pixels.copy() if copy else self.pixels

    def save(self, path):
        """Writes the picture as the PNG `meshless render/splat -o path` writes (8-bit RGB), atomically."""
        _core._write_png(self.pixels, str(path))

    def _repr_png_(self):
        return _core._png_bytes(self.pixels)

    def __repr__(self):
        return "meshless.Image(%dx%d)" % (self.width, self.height)


def read_image(path):
    """A PNG file as an Image (any PNG, converted to 8-bit RGB as `meshless render --compare` reads it)."""
    return Image({"pixels": _core._read_png(str(path))})


def _camera(size, azimuth, elevation, up, view, zoom, ortho):
    w, h = size
    return {"size": (int(w), int(h)), "azimuth": None if azimuth is None else float(azimuth),
            "elevation": None if elevation is None else float(elevation), "up": up, "view": view,
            "zoom": float(zoom), "ortho": bool(ortho)}


_SIZE_SUFFIX = {"": 0, "B": 0, "K": 10, "M": 20, "G": 30, "T": 40}


def _memory_bytes(memory):
    """'256M', '1G', '512K', a byte count (int or digits): bytes, as the commands' --memory reads them."""
    if isinstance(memory, int):
        n = memory
    else:
        import re
        m = re.fullmatch(r"(\d+)([KMGT]?)(I?B)?|(\d+)(B)", str(memory).strip().upper())
        if not m:
            raise ValueError("memory: expected a size like 256M, 1G, 512K or a byte count, got %r" % (memory,))
        n = int(m.group(1) or m.group(4)) << _SIZE_SUFFIX[m.group(2) or ""]
    if n <= 0:
        raise ValueError("memory: expected a positive size, got %r" % (memory,))
    return n


def render(source, *, points=None, values=None, spacing=None, origin=None, tf="grey",
           range=None, step=None, ref_step=None, bounds=None, shade=False, no_skip=False, background=(0.0, 0.0, 0.0),
           size=(512, 512), azimuth=None, elevation=None, up=None, view=None, zoom=1.0, ortho=False, memory="256M",
           threads=0):
    """Direct volume rendering by ray casting the field itself (dissertation section 6.6, Figure 6.6;
    section 7.4), what `meshless render` runs with the options of the same names: front-to-back
    emission-absorption compositing, the opacity corrected for the step, early ray termination,
    empty-space skipping. Returns an Image whose pixels equal those of `meshless render ... -o x.png`.

    source: a volume (3-D array indexed [x, y, z], spacing and origin in world units per axis, used
    in place when Fortran-ordered, else copied once to Fortran order), sampled trilinearly; a Store
    (open_store), read through its brick cache within `memory` ('256M', '1G' or bytes); or a Field,
    sampled over `points` (n, 3) and `values` (n,), the data it was fitted to (they give the box and
    the empty-space bounds).
    tf: a preset ("grey", "viridis", "ct-bone", "ct-skin") spanning `range` (lo, hi; default the
    data's value range) or a file of 'value r g b a' rows. step, ref_step: world units between samples
    and the slab the opacities are for (default half the voxel or mean point spacing). bounds:
    (x0, y0, z0, x1, y1, z1), the frame. background: RGB in [0, 1].
    Camera: size (width, height) pixels; azimuth, elevation degrees (default 30, 20); up ("x", "-z",
    ...); view ("+x" ... "-z", "iso"); zoom; ortho. threads=0: every CPU; the pixels do not depend on it."""
    cam = _camera(size, azimuth, elevation, up, view, zoom, ortho)
    memory = _memory_bytes(memory)
    opts = {"tf": str(tf), "range": range, "step": step, "ref_step": ref_step,
            "bounds": None if bounds is None else [float(b) for b in bounds], "shade": bool(shade),
            "no_skip": bool(no_skip), "background": background, "threads": int(threads)}
    if isinstance(source, Field):
        if points is None or values is None:
            raise ValueError("render(field): give points= and values=, the data the field was fitted to")
        return Image(_core._render_points(source._f, _np.asarray(points, dtype=_np.float64),
                                          _np.asarray(values, dtype=_np.float64), cam, opts))
    if points is not None or values is not None:
        raise ValueError("points= and values= go with a Field; a volume or store carries its own samples")
    if isinstance(source, Store):
        if source.kind != "brick":
            raise ValueError("render: %s is a %s store; render ray casts a brick store (.mlb)" % (source.path, source.kind))
        return Image(_core._render_store(source.path, memory, cam, opts))
    if isinstance(source, (str, bytes)) or hasattr(source, "__fspath__"):
        raise ValueError("render: give a volume array, a Store (meshless.open_store) or a Field, not a path")
    source, spacing, origin = _volume_args(source, spacing, origin)
    return Image(_core._render_volume(source, spacing, origin, cam, opts))


def splat(source, *, size=(800, 800), azimuth=None, elevation=None, up=None, view=None, zoom=1.0, ortho=False,
          kernel="ewa", shading="phong", color="auto", colormap="viridis", range=None, colorbar=False, threads=0):
    """Surface splatting of oriented points (dissertation section 3.6), what `meshless splat` runs
    with the options of the same names: quad or EWA kernels, depth-tested, normalised, lit by a
    headlight. Returns an Image whose pixels equal those of `meshless splat ... -o x.png`.

    source: a PointSet (isosurface(), read_points(); written once to a temporary PLY with its
    comments, which the recipe reads in place, so a PointSet read from a file frames and colours as
    that file does), or the path of a PLY point set, a `meshless mc` mesh PLY or a point stream.
    color: "auto", "value", "block", "normal" or "none"; colormap "viridis", "coolwarm", "gray";
    range (lo, hi) of the colour map; colorbar draws the legend. kernel "ewa" or "quad"; shading
    "phong" or "lambert". Camera options as render(); size (width, height) pixels, default 800x800."""
    cam = _camera(size, azimuth, elevation, up, view, zoom, ortho)
    args = (cam, str(kernel), str(shading), str(color), str(colormap), range, bool(colorbar), int(threads))
    if isinstance(source, PointSet):
        if source.normals is None:
            raise ValueError("splat: the points have no normals (a level of detail); render(Field(...)) draws scattered data")
        import tempfile, os
        with tempfile.TemporaryDirectory(prefix="meshless-splat-") as d:
            path = os.path.join(d, "points.ply")
            _core._write_points(path, source.points, source.normals, source.radius, source.values, source.block,
                                source.comments or None)
            return Image(_core._splat(path, *args))
    return Image(_core._splat(str(source), *args))


class ClusterTree:
    """The cluster binary tree of dissertation chapter 6 (sections 6.1, 6.3), made by hierarchy() or
    ClusterTree.load(path) (a .mlh of `meshless hierarchy`).

    lod(count=N), lod(fraction=F), lod(level=L) or lod(error=E): a level of detail, the N (or F x the
    samples) clusters left after the refinement's first splits, or (section 6.4) the clusters at
    depth L or the first clusters of error <= E on every path, as a PointSet of scattered data (section 6.5):
    points (n, 3) and values (n,) float64 owning the extraction's buffers, normals and radius None;
    the points `meshless lod TREE --level L -o lod.ply` writes, in its order. A count beyond the leaves,
    a level beyond the depth or an error below the one reached gives the finest level (a warning in `warnings`).
    save(path) writes the .mlh `meshless hierarchy` writes (the same bytes for the same samples,
    options and value name). Attributes: depth, stats, bounds, value_range, value_name, notes."""

    __slots__ = ("_t",)

    def __init__(self, tree):
        self._t = tree

    def lod(self, *, count=None, fraction=None, level=None, error=None):
        arrays = self._t._lod(None if level is None else int(level), None if error is None else float(error),
                              None if count is None else int(count), None if fraction is None else float(fraction))
        arrays.setdefault("value_name", self.value_name)
        return PointSet(arrays)

    def save(self, path):
        self._t._save(str(path))

    @staticmethod
    def load(path):
        return ClusterTree(_core._ClusterTree._load(str(path)))

    depth = property(lambda self: self._t.depth)
    stats = property(lambda self: self._t.stats)
    bounds = property(lambda self: self._t.bounds)
    value_range = property(lambda self: self._t.value_range)
    value_name = property(lambda self: self._t.value_name)
    notes = property(lambda self: list(self._t.notes))

    def __repr__(self):
        s = self.stats
        return "meshless.ClusterTree(%d samples, %d nodes, depth %d)" % (s["samples"], s["nodes"], s["depth"])


def hierarchy(points, values=None, *, max_splits=None, max_error=0.0, min_cluster=2, neighbours=25, hardy_c=0.025,
              hardy_c_world=None, pca_scaling="normalised", split_order="weighted", size_term=0.2, cluster_value="mean",
              value_name="", threads=0):
    """Builds the cluster binary tree of dissertation chapter 6 (sections 6.1, 6.3), what
    `meshless hierarchy` runs with the options of the same names: one cluster of every sample,
    refined by splitting, along the plane through its centre normal to the dominant principal axis
    of its (x, y, z, f) samples, the cluster of largest |C| (sigma^2 + t^2) (split_order="weighted",
    t = size_term x the value range) or of largest error sigma (split_order="max-error", the
    dissertation's); cluster values are means (cluster_value="mean") or local multiquadric fits ("fit").

    points: (n, 3) world positions with values (n,), or a PointSet (its points and values); rows
    with a NaN/Inf are dropped (counted in stats). value_name: what the .mlh records as the values'
    name. The tree does not depend on `threads`. Returns a ClusterTree."""
    if isinstance(points, PointSet):
        if values is not None:
            raise ValueError("hierarchy(pointset): the values are the PointSet's; give no values")
        points, values = points.points, points.values
    elif values is None:
        raise ValueError("hierarchy: give points (n, 3) and values (n,), or a PointSet")
    params = _core._hierarchy_params(max_splits, float(max_error), int(min_cluster), int(neighbours), float(hardy_c),
                                     hardy_c_world, str(pca_scaling), str(split_order), float(size_term), str(cluster_value))
    return ClusterTree(_core._hierarchy(_np.asarray(points, dtype=_np.float64), _np.asarray(values, dtype=_np.float64),
                                        params, int(threads), str(value_name)))


class Store:
    """A store opened by open_store(path) (dissertation section 3.6 and chapter 5 out of core):
    kind "brick": a brick store (.mlb, `meshless convert VOLUME -o vol.mlb`: Morton-ordered zstd
    bricks with a value-range index); "sample": a sample store (.mls, `meshless convert vol.mlb -o
    vol.mls`: paradigm (A), a span-space index of the cells over its .mlb); "point": a point store
    (.mlc, `meshless convert POINTS -o pts.mlc`: scattered points in Morton-ordered bricks).

    Attributes: path, kind, value_range; brick and sample stores: dims (nx, ny, nz), spacing, origin
    (world units), dtype; point stores: count, brick_count, bounds ((lo), (hi)), value_name.
    info(): the report of `meshless info STORE`.
    isosurface(iso, ...) yields the isosurface's points batch by batch, what `meshless isosurface
    STORE --iso V` writes, in its order; bricks() (point stores) yields each brick's points;
    probe(positions, ...) (point stores) evaluates the field slab by slab within a budget;
    render(store, ...) ray casts a brick store."""

    __slots__ = ("_s",)

    def __init__(self, s):
        self._s = s

    path = property(lambda self: self._s.path)
    kind = property(lambda self: self._s.kind)
    dims = property(lambda self: self._s.dims if self._s.kind != "point" else None)
    spacing = property(lambda self: self._s.spacing if self._s.kind != "point" else None)
    origin = property(lambda self: self._s.origin if self._s.kind != "point" else None)
    value_range = property(lambda self: self._s.value_range)
    dtype = property(lambda self: self._s.dtype if self._s.kind != "point" else "float64")
    count = property(lambda self: self._s.count if self._s.kind == "point" else None)
    brick_count = property(lambda self: self._s.brick_count if self._s.kind == "point" else None)
    bounds = property(lambda self: self._s.bounds if self._s.kind == "point" else None)
    value_name = property(lambda self: self._s.value_name if self._s.kind == "point" else "")

    def info(self):
        """The report `meshless info STORE` prints (the same bytes)."""
        return info(self.path)

    def isosurface(self, iso, *, projection="approx", memory="256M", threads=0, field="mpu", samples=2, reg_gap=4.0,
                   max_cells=20_000_000, max_level=10, tolerance=0.01, max_iterations=20, max_travel=2.0,
                   **field_options):
        """A generator of PointSets, the isosurface's points batch by batch; their concatenation is
        what `meshless isosurface STORE --iso V` writes, in its order, for any `threads`.

        Brick store: chapter 3 over the active bricks, read through a brick cache of `memory` bytes
        ('256M', '1G' or an int); sample store: paradigm (A) (section 3.5), the candidate rows of its
        span-space index recomputed from its .mlb (the .mlb's points); projection as isosurface().
        Point store: chapter 5 slab by slab (the mpu field, max_travel > 0), the store's points and
        their field within `memory` ('1G' as `--memory 1G`); samples, reg_gap, max_cells,
        max_level, tolerance, max_iterations, max_travel and the field options as
        isosurface_points(); warnings of the plan in the generator's first PointSet.
        Memory stays the store's budget, the batches in flight and at most 4 finished batches; the
        graph runs on its own threads, the GIL released, and stops when the generator is closed or
        dropped. A damaged brick raises DataError at the batch it is met, after those before it."""
        # started here, so that bad options and a damaged header raise at the call
        if self.kind == "point":
            if projection != "approx":
                raise ValueError("projection: a point store's points are projected onto its field (Newton)")
            warnings = []
            run = self._s._point_isosurface(float(iso), _field_params(field, **field_options), int(samples),
                                            float(reg_gap), int(max_cells), int(max_level), float(tolerance),
                                            int(max_iterations), float(max_travel), _memory_bytes(memory), int(threads),
                                            warnings)
            return _batches(run, warnings)
        if field != "mpu" or field_options:
            raise ValueError("field options apply to a point store (.mlc); %s is a %s store" % (self.path, self.kind))
        return _batches(self._s._isosurface(float(iso), str(projection), _memory_bytes(memory), int(threads)))

    def probe(self, positions, *, memory="1G", threads=0, field="mpu", max_gap=1.0, extrapolate="nan", **field_options):
        """A point store's field at positions (m, 3): (values (m,), gradients (m, 3)), the numbers
        `meshless probe STORE --at-file F --memory M` writes, for any `memory` and `threads`. The mpu
        field (section 5.5) is built slab by slab along z within `memory` ('1G' as `--memory 1G`, or an
        int); max_gap and extrapolate as probe's --max-gap and --extrapolate (NaN where the data does
        not reach; max_gap=0: no support test); the field options as isosurface_points()."""
        if self.kind != "point":
            raise ValueError("probe: %s is a %s store; probe() evaluates a point store's (.mlc) field" % (self.path, self.kind))
        return self._s._probe(_np.asarray(positions, dtype=_np.float64), _field_params(field, **field_options), float(max_gap),
                              str(extrapolate), _memory_bytes(memory), int(threads))

    def bricks(self):
        """A point store's bricks, one PointSet each (points (count, 3), values (count,) float64 views
        of the decoded brick; stats: brick, level, key, first, bounds), in the store's Morton order:
        their concatenation is read_points(STORE). One brick in memory at a time."""
        if self.kind != "point":
            raise ValueError("bricks: %s is a %s store; bricks() reads a point store's (.mlc)" % (self.path, self.kind))
        return (PointSet(self._s._brick(i)) for i in range(self._s.brick_count))

    def __repr__(self):
        if self.kind == "point":
            return "meshless.Store(%r, point store, %d points)" % (self.path, self.count)
        return "meshless.Store(%r, %s store, dims=%s)" % (self.path, self.kind, self.dims)


def _batches(run, warnings=()):
    try:
        while True:
            arrays = run._next()
            if arrays is None:
                return
            if warnings:
                arrays["warnings"], warnings = list(warnings), ()
            yield PointSet(arrays)
    finally:
        run._stop()


def open_store(path):
    """Opens a brick store (.mlb), a sample store (.mls) or a point store (.mlc), by content: DataError
    when the file is none of them or is damaged, OSError when it cannot be read. Returns a Store."""
    return Store(_core._Store._open(str(path)))

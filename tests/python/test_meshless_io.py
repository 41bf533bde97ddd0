"""The Python module's files, stores, VTK interop and Ctrl-C (python/README.md): oracles are NumPy's own
reading of the same bytes, analytic volumes written by NumPy, the CLI's outputs for the same data
(identical bytes and points), round trips, and /proc/self/maps for what is mapped rather than copied.

Run by ctest (tests/CMakeLists.txt) as tests/python/test_meshless.py is: PYTHONPATH = the build's
python folder, MESHLESS = the built executable, MESHLESS_SHARED_DATA = ../shared/data (tests that
need it are skipped without it).
"""
import ctypes
import gzip
import os
import signal
import tempfile
import threading
import time
import unittest

import numpy as np

import meshless
from test_meshless import SANITIZED, cli, xyz  # (the module's other tests; functions only)
from test_meshless import read_ply_vertices as ply_vertices

DATA = os.environ.get("MESHLESS_SHARED_DATA", "")
TOOTH = os.path.join(DATA, "tooth", "tooth_103x94x161_uint8.raw")
HEADSQ = os.path.join(DATA, "vtk_headsq", "quarter.nhdr")
MNI = os.path.join(DATA, "mni152_brain", "avg152T1_RL_nifti.nii.gz")
COMB = os.path.join(DATA, "plot3d", "combxyz.bin")
LIDC2 = os.path.join(DATA, "vtkjs_LIDC2", "LIDC2.vti")
NEGHIP = os.path.join(DATA, "neghip", "neghip_64x64x64_uint8.raw")
MULTICOMB = [os.path.join(DATA, "plot3d", "multicomb_%d.vts" % i) for i in range(3)]

try:
    import vtkmodules.vtkCommonDataModel  # noqa: F401  (python3-vtk9; the module imports without it)
    HAVE_VTK = True
except ImportError:
    HAVE_VTK = False


def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def mapping_of(address):
    """The file /proc/self/maps says `address` lies in ("" for anonymous memory)."""
    with open("/proc/self/maps") as f:
        for line in f:
            w = line.split()
            lo, hi = (int(x, 16) for x in w[0].split("-"))
            if lo <= address < hi:
                return w[5] if len(w) > 5 else ""
    return None


def sphere(n=40):
    x, y, z = np.mgrid[-1:1:n * 1j, -1:1:n * 1j, -1:1:n * 1j]
    return np.asfortranarray((x * x + y * y + z * z).astype(np.float32))


class ReadVolume(unittest.TestCase):
    @unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
    def test_a_raw_volume_is_the_file_mapped_in_place_and_equals_numpys_reading(self):
        v = meshless.read_volume(TOOTH)
        want = np.fromfile(TOOTH, np.uint8).reshape(161, 94, 103).T
        self.assertEqual(v.shape, (103, 94, 161))
        self.assertEqual(v.dtype, np.uint8)
        self.assertTrue(v.array.flags.f_contiguous)
        self.assertTrue(np.array_equal(v.array, want))
        self.assertEqual((v.spacing, v.origin, v.format), ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0), "raw"))
        # no copy: the array's memory is the file's mapping, and the array's base owns it
        self.assertEqual(os.path.realpath(mapping_of(v.array.ctypes.data)), os.path.realpath(TOOTH))
        self.assertFalse(v.array.flags.owndata)
        self.assertIs(np.asarray(v), v.array)
        # what isosurface() makes of it is what it makes of NumPy's array
        a, b = meshless.isosurface(v, 100.5), meshless.isosurface(want, 100.5)
        self.assertTrue(np.array_equal(a.points, b.points))

    @unittest.skipUnless(os.path.exists(HEADSQ), "needs ../shared/data")
    def test_nrrd_slices_spacing_and_the_clis_points(self):
        v = meshless.read_volume(HEADSQ)
        self.assertEqual(v.shape, (64, 64, 93))
        self.assertEqual(v.dtype, np.int16)
        self.assertEqual(v.spacing, (3.2, 3.2, 1.5))
        for k in (0, 46, 92):  # slice k is the file quarter.(k+1): 64x64 little-endian int16, x fastest
            sl = np.fromfile(os.path.join(DATA, "vtk_headsq", "quarter.%d" % (k + 1)), "<i2").reshape(64, 64).T
            self.assertTrue(np.array_equal(v.array[:, :, k], sl))
        self.assertIsNotNone(v.patient_axes)  # space: 3D-left-handed
        self.assertEqual(v.patient_axes.shape, (3, 3))
        self.assertIsNone(v.length_unit)  # no space units
        with tempfile.TemporaryDirectory() as d:
            ply = os.path.join(d, "h.ply")
            cli("isosurface", HEADSQ, "--iso", "1000.5", "-o", ply)
            want = ply_vertices(ply)
        s = meshless.isosurface(v, 1000.5)
        self.assertTrue(np.array_equal(s.points, xyz(want)))
        self.assertTrue(np.array_equal(s.radius, want["radius"]))

    @unittest.skipUnless(os.path.exists(MNI), "needs ../shared/data")
    def test_nifti_gz_is_decoded_once_with_its_spacing_and_patient_axes(self):
        v = meshless.read_volume(MNI)
        self.assertEqual((v.shape, v.dtype, v.spacing, v.format), ((91, 109, 91), np.uint8, (2.0, 2.0, 2.0), "nifti"))
        self.assertIsNotNone(v.patient_axes)
        self.assertTrue(np.allclose(np.abs(v.patient_axes), np.eye(3)))
        self.assertEqual(v.length_unit, "mm")  # xyzt_units 10: millimetres (and seconds)
        self.assertEqual((int(v.array.min()), int(v.array.max())), (0, 255))  # SOURCES.md's range

    @unittest.skipUnless(os.path.isdir(LIDC2), "needs ../shared/data")
    def test_a_vtkjs_volume_equals_its_gzip_payload_read_by_numpy(self):
        v = meshless.read_volume(os.path.join(LIDC2, "index.json"))
        (gz,) = [os.path.join(LIDC2, "data", n) for n in os.listdir(os.path.join(LIDC2, "data"))]
        with gzip.open(gz) as f:
            want = np.frombuffer(f.read(), np.uint8).reshape(133, 256, 256).T
        self.assertEqual((v.format, v.spacing), ("vtkjs", (1.40625, 1.40625, 2.5)))
        self.assertTrue(np.array_equal(v.array, want))
        self.assertTrue(v.array.flags.f_contiguous and not v.array.flags.owndata)

    def test_read_volume_array_chooses_the_point_array_of_a_multi_array_vti(self):
        a = np.arange(60, dtype=np.float32).reshape(3, 4, 5)  # (z, y, x): the file's x fastest
        b = -a

        def text(v):
            return " ".join("%g" % x for x in v.ravel())

        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "two.vti")
            with open(path, "w") as f:
                f.write('<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">\n'
                        '<ImageData WholeExtent="0 4 0 3 0 2" Origin="0 0 0" Spacing="1 1 1">\n<Piece Extent="0 4 0 3 0 2">\n'
                        '<PointData>\n<DataArray type="Float32" Name="a" format="ascii">' + text(a) + '</DataArray>\n'
                        '<DataArray type="Float32" Name="b" format="ascii">' + text(b) + '</DataArray>\n'
                        '</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n')
            self.assertTrue(np.array_equal(meshless.read_volume(path).array, a.T))  # the default: the first
            self.assertTrue(np.array_equal(meshless.read_volume(path, array="b").array, b.T))
            with self.assertRaises(meshless.DataError) as e:
                meshless.read_volume(path, array="c")
            self.assertIn("'a' (float32), 'b' (float32)", str(e.exception))
            raw = os.path.join(d, "v_5x4x3_uint8.raw")
            a.astype(np.uint8).tofile(raw)
            with self.assertRaises(ValueError):  # one unnamed array
                meshless.read_volume(raw, array="a")

    def test_a_nrrd_written_by_numpy_reads_back_and_options_and_errors(self):
        vol = sphere(24)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.nrrd")
            with open(path, "wb") as f:
                f.write(b"NRRD0004\ntype: float\ndimension: 3\nsizes: 24 24 24\nspacings: 0.5 0.25 2\n"
                        b"space origin: (1,2,3)\nendian: little\nencoding: raw\n\n")
                f.write(vol.tobytes(order="F"))
            v = meshless.read_volume(path)
            self.assertTrue(np.array_equal(v.array, vol))
            self.assertEqual((v.spacing, v.origin), ((0.5, 0.25, 2.0), (1.0, 2.0, 3.0)))
            w = meshless.read_volume(path, spacing=(1, 1, 1), origin=(0, 0, 0))
            self.assertEqual((w.spacing, w.origin), ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0)))
            self.assertTrue(any("describes itself" in x for x in w.warnings))
            # the volume's own spacing and origin are what isosurface() uses unless given
            s = meshless.isosurface(v, 0.5)
            r = np.linalg.norm((s.points - (1, 2, 3)) / (0.5, 0.25, 2.0) - 11.5, axis=1) * 2 / 23
            self.assertLess(np.abs(r - np.sqrt(0.5)).max(), 2e-2)
            # a headerless raw file with the layout given, as --dims/--type/--endian
            raw = os.path.join(d, "blob.raw")
            blob = (np.arange(24 ** 3).reshape(24, 24, 24) % 1000).astype(">i2")
            blob.tofile(raw)  # C order: the last axis is the file's x
            r16 = meshless.read_volume(raw, dims=(24, 24, 24), dtype="int16", big_endian=True)
            self.assertEqual(r16.dtype, np.int16)
            self.assertTrue(np.array_equal(r16.array, blob.T))
            with open(os.path.join(d, "short.nrrd"), "wb") as f:
                f.write(b"NRRD0004\ntype: float\ndimension: 3\nsizes: 24 24 24\nencoding: raw\n\nshort")
            with self.assertRaises(meshless.DataError) as e:
                meshless.read_volume(os.path.join(d, "short.nrrd"))
            self.assertIn("short.nrrd", str(e.exception))
            with self.assertRaises(OSError):
                meshless.read_volume(os.path.join(d, "missing.nrrd"))
            with self.assertRaises(ValueError):
                meshless.read_volume(raw, dims=(24, 24, 24), dtype="complex64")
            with self.assertRaises(ValueError):
                meshless.read_volume(path, spacing=(1, float("nan"), 1))
            gz = os.path.join(d, "s.nhdr")  # a gzip payload is decoded into memory: the budget applies
            with open(gz, "wb") as f:
                f.write(b"NRRD0004\ntype: float\ndimension: 3\nsizes: 24 24 24\nencoding: gzip\ndata file: s.raw.gz\n\n")
            with gzip.open(os.path.join(d, "s.raw.gz"), "wb") as f:
                f.write(vol.tobytes(order="F"))
            self.assertTrue(np.array_equal(meshless.read_volume(gz).array, vol))
            with self.assertRaises(OSError) as e:  # more than the budget given: refused before reading
                meshless.read_volume(gz, memory=1000)
            self.assertIn("s.nhdr", str(e.exception))

    def test_the_array_outlives_the_volume_object_and_a_brick_store_reads_whole(self):
        vol = sphere(20)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s_20x20x20_float32.raw")
            vol.T.tofile(path)  # x fastest
            a = meshless.read_volume(path).array
            mlb = os.path.join(d, "s.mlb")
            cli("convert", path, "-o", mlb)
            b = meshless.read_volume(mlb)
            self.assertEqual(b.format, "brick-store")
        self.assertTrue(np.array_equal(a, vol))  # the mapping outlives the deleted file and the Volume
        self.assertTrue(np.array_equal(b.array, vol))

    def test_an_hdf5_dataset_by_path_or_array_and_the_levels_of_other_formats_refused(self):
        try:
            import h5py
        except ImportError:
            self.skipTest("python3-h5py is not installed")
        vol = sphere(20)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "two.h5")
            with h5py.File(path, "w") as f:
                f.create_dataset("scans/ct", data=vol.T, chunks=(4, 8, 20), compression="gzip", shuffle=True)  # (z, y, x)
                f.create_dataset("other", data=vol.T.astype(np.uint8))
            a = meshless.read_volume(path + ":/scans/ct")
            self.assertEqual(a.format, "hdf5")
            self.assertTrue(np.array_equal(a.array, vol))
            b = meshless.read_volume(path, array="other")
            self.assertEqual(b.array.dtype, np.uint8)
            with self.assertRaises(meshless.DataError) as e:
                meshless.read_volume(path)
            self.assertIn("holds 2 volumes (/other, /scans/ct)", str(e.exception))
            raw = os.path.join(d, "s_20x20x20_float32.raw")
            vol.T.tofile(raw)
            with self.assertRaises(ValueError) as e:
                meshless.read_volume(raw, resolution_level=1)
            self.assertIn("--resolution-level applies to OME-Zarr images", str(e.exception))


class ReadPointsAndWriters(unittest.TestCase):
    def test_csv_points_are_the_numbers_written_and_views_of_the_readers_buffers(self):
        rng = np.random.default_rng(3)
        pts, val = rng.normal(size=(500, 3)), rng.normal(size=500)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "p.csv")
            np.savetxt(path, np.column_stack([pts, val]), delimiter=",", fmt="%.17g", header="x,y,z,rho", comments="")
            p = meshless.read_points(path)
        self.assertIsNone(p.normals)
        self.assertTrue(np.array_equal(p.points, pts) and np.array_equal(p.values, val))
        self.assertEqual(p.value_name, "rho")
        self.assertFalse(p.points.flags.owndata)
        self.assertIs(p.points.base, p.values.base)  # one capsule holds the reader's point set

    @unittest.skipUnless(os.path.exists(COMB), "needs ../shared/data")
    def test_plot3d_density_has_the_documented_count_and_range(self):
        p = meshless.read_points(COMB)
        self.assertEqual(len(p), 57 * 33 * 25)
        self.assertAlmostEqual(float(p.values.min()), 0.1978, places=4)
        self.assertAlmostEqual(float(p.values.max()), 0.7104, places=4)
        self.assertEqual(p.blocks[0]["dims"], (57, 33, 25))

    @unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
    def test_oriented_points_saved_are_the_bytes_the_cli_writes_ply_and_vtp(self):
        with tempfile.TemporaryDirectory() as d:
            ply, vtp = os.path.join(d, "t.ply"), os.path.join(d, "t.vtp")
            cli("isosurface", TOOTH, "--iso", "100.5", "-o", ply)
            cli("isosurface", TOOTH, "--iso", "100.5", "-o", vtp)
            p = meshless.read_points(ply)
            self.assertGreater(len(p), 10000)
            self.assertTrue(any("iso" in c for c in p.comments))
            p.save(os.path.join(d, "py.ply"))
            p.save(os.path.join(d, "py.vtp"))
            self.assertEqual(read_bytes(os.path.join(d, "py.ply")), read_bytes(ply))
            self.assertEqual(read_bytes(os.path.join(d, "py.vtp")), read_bytes(vtp))
            with self.assertRaises(ValueError):
                p.save(os.path.join(d, "py.csv"))  # oriented points: .ply or .vtp, as the command
            self.assertFalse(os.path.exists(os.path.join(d, "py.csv")))

    def test_scattered_points_saved_are_the_bytes_of_meshless_lod(self):
        rng = np.random.default_rng(5)
        pts = rng.uniform(-1, 1, (400, 3))
        val = (pts ** 2).sum(1)
        with tempfile.TemporaryDirectory() as d:
            tree = os.path.join(d, "t.mlh")
            meshless.hierarchy(pts, val, max_splits=60, value_name="r2").save(tree)
            lod = meshless.read_points(tree, level=4)  # the reader of every command: a .mlh's level of detail
            self.assertEqual(lod.value_name, "r2")
            for ext in ("csv", "ply", "vtp"):
                out = os.path.join(d, "cli." + ext)
                cli("lod", tree, "--level", "4", "-o", out)
                lod.comments = ["meshless lod level 4 of " + tree, "meshless field: hardy-c-rel 0.025"]  # the c it carries (a weighted tree's)
                lod.save(os.path.join(d, "py." + ext))
                self.assertEqual(read_bytes(os.path.join(d, "py." + ext)), read_bytes(out), ext)
            back = meshless.read_points(os.path.join(d, "py.csv"))
            self.assertTrue(np.array_equal(back.points, lod.points) and np.array_equal(back.values, lod.values))
            with self.assertRaises(ValueError):
                lod.save(os.path.join(d, "x.obj"))

    @unittest.skipUnless(all(os.path.exists(p) for p in MULTICOMB), "needs ../shared/data")
    def test_multiblock_blocks_are_the_files_lattices_and_give_the_clis_surface(self):
        mb = meshless.read_multiblock(MULTICOMB)
        self.assertEqual(len(mb), 3)
        self.assertEqual([b.values.shape for b in mb], [(6, 12, 9), (8, 12, 9), (9, 12, 9)])
        b0 = mb[0]
        self.assertEqual(b0.coords.shape, (6, 12, 9, 3))
        self.assertFalse(b0.coords.flags.owndata)
        self.assertIs(b0.coords.base, b0.values.base)
        # the lattice is i fastest: the first block's first row of nodes is the file's first points
        pts = meshless.read_points(MULTICOMB[0])
        self.assertTrue(np.array_equal(b0.coords[:, 0, 0], pts.points[:6]))
        self.assertTrue(np.array_equal(b0.values.T.ravel(), pts.values))
        with tempfile.TemporaryDirectory() as d:
            ply = os.path.join(d, "c.ply")
            cli("isosurface", *MULTICOMB, "--iso", "0.4", "-o", ply)
            want = ply_vertices(ply)
        s = meshless.isosurface_blocks(mb, 0.4)
        self.assertTrue(np.array_equal(s.points, xyz(want)))
        self.assertTrue(np.array_equal(s.block, want["block"]))


    @unittest.skipUnless(os.path.exists(NEGHIP), "needs ../shared/data")
    def test_an_amr_hierarchys_boxes_give_the_clis_surface(self):
        with tempfile.TemporaryDirectory() as d:
            vthb, ply = os.path.join(d, "n.vthb"), os.path.join(d, "n.ply")
            source = NEGHIP
            if SANITIZED:  # the field of neghip's 64^3 nodes takes minutes instrumented: a 24^3 ball
                source = os.path.join(d, "ball_24x24x24_uint8.raw")
                x, y, z = np.mgrid[0:24, 0:24, 0:24] - 11.5
                ball = np.clip(255 - 20 * np.sqrt(x * x + y * y + z * z), 0, 255).astype(np.uint8)
                ball.T.tofile(source)  # x fastest
            cli("split", source, "--layout", "amr", "--iso", "128", "-o", vthb)
            cli("isosurface", vthb, "--iso", "128", "-o", ply)
            want = ply_vertices(ply)
            mb = meshless.read_multiblock(vthb)
        self.assertEqual(mb.format, "vthb")
        self.assertEqual(sorted({b.level for b in mb}), [0, 1, 2])
        self.assertTrue(all(b.cell_centred for b in mb))
        self.assertTrue(any(b.covered is not None for b in mb))
        s = meshless.isosurface_blocks(mb, 128)
        self.assertGreater(len(s), 100)
        self.assertTrue(np.array_equal(s.points, xyz(want)))


def write_scattered_csv(path, n=4000, seed=7):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-1, 1, (n, 3))
    np.savetxt(path, np.column_stack([pts, (pts ** 2).sum(1)]), delimiter=",", fmt="%.17g", header="x,y,z,r2",
               comments="")
    return pts


class Stores(unittest.TestCase):
    @unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
    def test_a_sample_stores_batches_are_meshless_isosurface_of_it(self):
        with tempfile.TemporaryDirectory() as d:
            mlb, mls, ply = (os.path.join(d, n) for n in ("t.mlb", "t.mls", "t.ply"))
            cli("convert", TOOTH, "-o", mlb)
            cli("generate", mlb, "--all", "-o", mls)
            cli("isosurface", mls, "--iso", "100.5", "-o", ply)
            want = ply_vertices(ply)
            s = meshless.open_store(mls)
            self.assertEqual((s.kind, s.dims, s.dtype), ("sample", (103, 94, 161), "uint8"))
            self.assertIn(os.path.basename(mls), s.info())
            for threads in (1, 2):
                g = s.isosurface(100.5, threads=threads)
                batches = list(g)
                pts = np.concatenate([b.points for b in batches])
                self.assertTrue(np.array_equal(pts, xyz(want)))
                self.assertTrue(np.array_equal(np.concatenate([b.radius for b in batches]), want["radius"]))
            with self.assertRaises(ValueError):
                s.bricks()
            with self.assertRaises(ValueError):
                s.isosurface(100.5, field="rbf-grid")

    def test_a_point_stores_bricks_and_its_isosurface_within_a_budget_are_the_clis(self):
        with tempfile.TemporaryDirectory() as d:
            csv, mlc, ply = (os.path.join(d, n) for n in ("p.csv", "p.mlc", "p.ply"))
            pts = write_scattered_csv(csv)
            cli("convert", csv, "-o", mlc)
            s = meshless.open_store(mlc)
            self.assertEqual((s.kind, s.count, s.value_name), ("point", len(pts), "r2"))
            bricks = list(s.bricks())
            self.assertEqual(len(bricks), s.brick_count)
            whole = meshless.read_points(mlc)
            self.assertTrue(np.array_equal(np.concatenate([b.points for b in bricks]), whole.points))
            self.assertTrue(np.array_equal(np.concatenate([b.values for b in bricks]), whole.values))
            # the same points as the CSV's, in another (Morton) order
            self.assertTrue(np.array_equal(np.unique(whole.points, axis=0), np.unique(pts, axis=0)))
            self.assertTrue(np.allclose(whole.values, (whole.points ** 2).sum(1), rtol=0, atol=1e-12))
            cli("isosurface", mlc, "--iso", "0.5", "--memory", "8M", "-o", ply)
            want = ply_vertices(ply)
            batches = list(s.isosurface(0.5, memory="8M", threads=2))
            got = np.concatenate([b.points for b in batches])
            self.assertGreater(len(got), 100)
            self.assertTrue(np.array_equal(got, xyz(want)))
            self.assertLess(np.abs(np.linalg.norm(got, axis=1) - np.sqrt(0.5)).max(), 0.05)
            with self.assertRaises(ValueError):
                s.isosurface(0.5, field="rbf-grid")
            with self.assertRaises(ValueError):
                meshless.render(s)
            # the field at positions, slab by slab: the numbers `meshless probe` writes
            at = np.random.default_rng(4).uniform(-1.1, 1.1, size=(500, 3))
            at_csv, probe_csv = os.path.join(d, "at.csv"), os.path.join(d, "probe.csv")
            np.savetxt(at_csv, at, delimiter=",", fmt="%.17g")
            cli("probe", mlc, "--at-file", at_csv, "--memory", "8M", "-o", probe_csv)
            want = np.loadtxt(probe_csv, delimiter=",", skiprows=1)
            for memory, threads in (("8M", 1), ("1G", 2)):
                values, grads = s.probe(at, memory=memory, threads=threads)
                self.assertEqual((values.shape, grads.shape), ((500,), (500, 3)))
                self.assertTrue(np.allclose(values, want[:, 3], rtol=1e-8, atol=0, equal_nan=True))
                self.assertTrue(np.allclose(grads, want[:, 4:7], rtol=1e-8, atol=0, equal_nan=True))
            self.assertGreater(np.isfinite(values).sum(), 100)
            self.assertTrue(np.isnan(values).any())  # (positions beyond the data)
            with self.assertRaises(ValueError):
                s.probe(at, field="rbf-grid")
            with self.assertRaises(ValueError):
                s.probe(at, extrapolate="far")

    def test_not_a_store(self):
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "x.mlc")
            with open(bad, "wb") as f:
                f.write(b"MLC\x00garbage")
            with self.assertRaises(meshless.DataError):
                meshless.open_store(bad)
            with self.assertRaises(OSError):
                meshless.open_store(os.path.join(d, "missing.mls"))


@unittest.skipUnless(HAVE_VTK, "needs python3-vtk9")
class Vtk(unittest.TestCase):
    def test_image_data_both_ways_without_a_copy(self):
        vol = sphere(16)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s_16x16x16_float32.raw")
            vol.T.tofile(path)
            v = meshless.read_volume(path, spacing=(0.5, 1, 2), origin=(1, 2, 3))
            img = v.to_vtk()
        self.assertEqual(img.GetDimensions(), (16, 16, 16))
        self.assertEqual(img.GetSpacing(), (0.5, 1.0, 2.0))
        back = meshless.from_vtk(img)
        self.assertTrue(np.shares_memory(back.array, v.array))  # VTK's scalars are the reader's mapping
        self.assertTrue(np.array_equal(back.array, vol))
        self.assertEqual((back.spacing, back.origin), ((0.5, 1.0, 2.0), (1.0, 2.0, 3.0)))
        self.assertEqual(img.GetScalarComponentAsDouble(3, 5, 7, 0), float(vol[3, 5, 7]))  # [x, y, z] in VTK too
        del v, img
        a = meshless.isosurface(back, 0.5)
        self.assertGreater(len(a), 100)

    def test_poly_data_round_trips_oriented_and_scattered_points(self):
        s = meshless.isosurface(sphere(20), 0.5)
        poly = s.to_vtk()
        back = meshless.from_vtk(poly)
        for name in ("points", "normals", "radius", "values"):
            self.assertTrue(np.array_equal(getattr(back, name), getattr(s, name)), name)
        from vtkmodules.util import numpy_support as ns
        self.assertTrue(np.shares_memory(back.points, ns.vtk_to_numpy(poly.GetPoints().GetData())))
        # scattered data (a level of detail): points and values, float64 both ways
        lod = meshless.hierarchy(s.points, s.values + s.points[:, 0], max_splits=30, value_name="f").lod(level=3)
        sc = meshless.from_vtk(lod.to_vtk())
        self.assertIsNone(sc.normals)
        self.assertTrue(np.array_equal(sc.points, lod.points) and np.array_equal(sc.values, lod.values))
        self.assertEqual(sc.value_name, "f")

    @unittest.skipUnless(all(os.path.exists(p) for p in MULTICOMB), "needs ../shared/data")
    def test_structured_grids_are_the_blocks_read_multiblock_reads(self):
        from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
        from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader
        mb = vtkMultiBlockDataSet()
        for i, path in enumerate(MULTICOMB):
            r = vtkXMLStructuredGridReader()
            r.SetFileName(path)
            r.Update()
            mb.SetBlock(i, r.GetOutput())
        ours = meshless.read_multiblock(MULTICOMB, value="Density")
        theirs = meshless.from_vtk(mb, array="Density")
        self.assertEqual(len(theirs), 3)
        for a, b in zip(ours, theirs):
            self.assertTrue(np.array_equal(a.coords, b.coords))
            self.assertTrue(np.array_equal(a.values, b.values))
        s1, s2 = meshless.isosurface_blocks(ours, 0.4), meshless.isosurface_blocks(theirs, 0.4)
        self.assertTrue(np.array_equal(s1.points, s2.points))
        with self.assertRaises(ValueError):
            meshless.from_vtk(object())


def rss_kib():
    """This process's RSS after glibc hands its free pages back (malloc_trim: the worker threads'
    arenas keep freed blocks otherwise, which is caching, not a leak)."""
    ctypes.CDLL("libc.so.6").malloc_trim(0)
    with open("/proc/self/status") as f:
        return int(next(line for line in f if line.startswith("VmRSS")).split()[1])


class Interrupt(unittest.TestCase):
    def interrupted_call(self, call, after=0.4):
        """Runs call() while a timer thread sends SIGINT after `after` s: (interrupted, seconds from
        the signal to the exception)."""
        fired = []

        def handler(sig, frame):
            raise KeyboardInterrupt

        def send():
            fired.append(time.monotonic())
            os.kill(os.getpid(), signal.SIGINT)

        old = signal.signal(signal.SIGINT, handler)
        timer = threading.Timer(after, send)
        try:
            try:
                timer.start()
                call()
                time.sleep(after + 1)  # the call ended first: the signal lands here
                return False, None
            except KeyboardInterrupt:
                return True, time.monotonic() - fired[0]
        finally:
            timer.join()
            signal.signal(signal.SIGINT, old)

    def test_ctrl_c_stops_a_long_isosurface_within_a_second_and_leaks_nothing(self):
        n = 320  # a corrugated field: a quarter of the 32 M cells are active, many seconds of work
        i = np.arange(n, dtype=np.float32)
        vol = np.sin(i * 0.9)[:, None, None] + np.sin(i * 0.8)[None, :, None] + np.sin(i * 0.7)[None, None, :]
        vol = np.asfortranarray(vol, dtype=np.float32)
        tasks = len(os.listdir("/proc/self/task"))
        rss = []
        for _ in range(3):
            interrupted, latency = self.interrupted_call(lambda: meshless.isosurface(vol, 0.1, threads=2))
            self.assertTrue(interrupted)
            self.assertLess(latency, 3.0 if SANITIZED else 1.0)  # (instrumented batches take longer to drain)
            rss.append(rss_kib())
        if not SANITIZED:  # (ASan's quarantine holds freed blocks)
            self.assertLess(rss[-1] - rss[0], 64 * 1024)  # the partial results freed each time
        self.assertLessEqual(len(os.listdir("/proc/self/task")), tasks + 4)  # the worker joined (the pool may stay)
        # the module still works after an interrupt
        self.assertGreater(len(meshless.isosurface(sphere(16), 0.5)), 10)


if __name__ == "__main__":
    unittest.main()

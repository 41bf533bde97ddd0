"""The Python module `meshless` (python/): oracles are analytic fields with known isosurfaces, the
CLI's own outputs for the same data (identical bytes), closed-mesh checks and round trips.

Run by ctest (tests/CMakeLists.txt) with Debian's python3, PYTHONPATH = the build's python folder,
MESHLESS = the built executable and MESHLESS_SHARED_DATA = ../shared/data (tests that need it are
skipped without it).
"""
import os
import subprocess
import tempfile
import threading
import time
import unittest

import numpy as np

import meshless

MESHLESS = os.environ.get("MESHLESS", "meshless")
DATA = os.environ.get("MESHLESS_SHARED_DATA", "")
TOOTH = os.path.join(DATA, "tooth", "tooth_103x94x161_uint8.raw")


def read_ply_points(path):
    """The vertex records of a binary little-endian PLY point set that `meshless` wrote."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    props = [line.split()[2] for line in header.splitlines() if line.startswith("property")]
    n = int(next(line for line in header.splitlines() if line.startswith("element vertex")).split()[2])
    dt = np.dtype([(p, "<u4" if p == "block" else "<f4") for p in props])
    return np.frombuffer(data[end:end + n * dt.itemsize], dt)


def sphere_volume(n=48, order="F", dtype=np.float32):
    """r^2 on [-1, 1]^3 sampled n^3, indexed [x, y, z]; spacing and origin."""
    x, y, z = np.mgrid[-1:1:n * 1j, -1:1:n * 1j, -1:1:n * 1j]
    v = np.asarray((x * x + y * y + z * z).astype(dtype), order=order)
    h = 2.0 / (n - 1)
    return v, (h, h, h), (-1.0, -1.0, -1.0)


class VolumeIsosurface(unittest.TestCase):
    def test_sphere_points_lie_on_it_with_normals_toward_decreasing_values(self):
        v, sp, org = sphere_volume()
        s = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
        self.assertGreater(len(s), 1000)
        r = np.linalg.norm(s.points, axis=1)
        self.assertLess(np.abs(r - np.sqrt(0.5)).max(), 2e-3)
        inward = -s.points / r[:, None]  # r^2 decreases toward the centre
        self.assertGreater((s.normals * inward).sum(1).min(), 0.99)
        self.assertTrue(np.all(s.radius > 0))
        self.assertEqual(s.stats["active_cells"], len(s) + s.stats["too_far"] + s.stats["flat"])

    def test_results_share_one_buffer_and_nothing_is_copied_in(self):
        v, sp, org = sphere_volume(order="F")
        s = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
        self.assertIsNotNone(s.points.base)  # views of the records the library made, no copy out
        self.assertIs(s.points.base, s.normals.base)
        self.assertIs(s.points.base, s.values.base)
        self.assertFalse(s.points.flags.owndata)
        del s.normals, s.radius  # the buffer lives as long as any array of it
        self.assertEqual(s.points.shape[1], 3)

    def test_c_and_fortran_order_and_dtypes_give_the_same_surface(self):
        f, sp, org = sphere_volume(order="F")
        a = meshless.isosurface(f, 0.5, spacing=sp, origin=org)
        c = meshless.isosurface(np.ascontiguousarray(f), 0.5, spacing=sp, origin=org)
        d = meshless.isosurface(f.astype(np.float64), 0.5, spacing=sp, origin=org)  # converted: one float32 copy
        self.assertLessEqual(abs(len(a) - len(c)), len(a) // 1000 + 1)
        self.assertEqual(len(a), len(d))
        rc = np.linalg.norm(c.points, axis=1)
        self.assertLess(np.abs(rc - np.sqrt(0.5)).max(), 2e-3)
        self.assertTrue(np.array_equal(a.points, d.points))

    def test_anisotropic_spacing_and_origin_in_world_units(self):
        v, _, _ = sphere_volume(n=40)
        s = meshless.isosurface(v, 0.5, spacing=(1.0, 2.0, 3.0), origin=(10.0, 20.0, 30.0))
        lo, hi = s.points.min(0), s.points.max(0)
        self.assertTrue(np.all(lo >= [10, 20, 30]) and np.all(hi <= [10 + 39, 20 + 78, 30 + 117]))
        self.assertGreater((hi - lo)[2], 2 * (hi - lo)[0])

    @unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
    def test_same_bytes_as_the_cli_on_a_real_ct_and_a_memmap_works_in_place(self):
        vol = np.fromfile(TOOTH, np.uint8).reshape(161, 94, 103).T
        s = meshless.isosurface(vol, 100.5, threads=2)
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "t.ply")
            subprocess.run([MESHLESS, "isosurface", TOOTH, "--iso", "100.5", "-o", out, "--threads", "1"], check=True)
            p = read_ply_points(out)
            self.assertEqual(len(p), len(s))
            self.assertTrue(np.array_equal(np.stack([p["x"], p["y"], p["z"]], 1), s.points))
            self.assertTrue(np.array_equal(np.stack([p["nx"], p["ny"], p["nz"]], 1), s.normals))
            self.assertTrue(np.array_equal(p["radius"], s.radius) and np.array_equal(p["value"], s.values))
            r = meshless.read_points(out)  # the CLI's own reader agrees with this test's parser
            self.assertTrue(np.array_equal(r.points, s.points) and np.array_equal(r.radius, s.radius))
            self.assertTrue(any(c.startswith("iso 100.5") for c in r.comments))
            s.write(os.path.join(d, "py.ply"))
            self.assertTrue(np.array_equal(read_ply_points(os.path.join(d, "py.ply")), p))
        mm = np.memmap(TOOTH, np.uint8, mode="r", shape=(161, 94, 103)).T
        m = meshless.isosurface(mm, 100.5)
        self.assertTrue(np.array_equal(m.points, s.points))

    def test_to_vtk_gives_the_polydata_paraview_reads(self):
        try:
            from vtkmodules.util import numpy_support as ns
        except ImportError:
            self.skipTest("VTK's Python module is not installed (python3-vtk9)")
        v, sp, org = sphere_volume(n=24)
        s = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
        poly = s.to_vtk()
        self.assertEqual(poly.GetNumberOfPoints(), len(s))
        self.assertEqual(poly.GetNumberOfVerts(), len(s))
        self.assertTrue(np.array_equal(ns.vtk_to_numpy(poly.GetPoints().GetData()), s.points))
        self.assertTrue(np.array_equal(ns.vtk_to_numpy(poly.GetPointData().GetNormals()), s.normals))
        self.assertTrue(np.array_equal(ns.vtk_to_numpy(poly.GetPointData().GetArray("radius")), s.radius))
        self.assertEqual(poly.GetPointData().GetScalars().GetName(), "value")

    def test_a_memmap_streams_slab_by_slab_with_the_same_points_and_keeps_private_changes(self):
        v, sp, org = sphere_volume(n=40)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "v.raw")
            np.asfortranarray(v).T.tofile(path)  # z slowest: the raw layout
            want = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
            for mode in ("r", "r+"):
                mm = np.memmap(path, np.float32, mode=mode, shape=(40, 40, 40)).T
                got = meshless.isosurface(mm, 0.5, spacing=sp, origin=org)
                self.assertTrue(np.array_equal(got.points, want.points), mode)
                del mm
            cm = np.memmap(path, np.float32, mode="r", shape=(40, 40, 40))  # C order: x and z swapped, streamed too
            c = meshless.isosurface(cm, 0.5, spacing=sp, origin=org)
            self.assertTrue(np.array_equal(c.points, meshless.isosurface(np.array(cm), 0.5, spacing=sp, origin=org).points))
            del cm
            cow = np.memmap(path, np.float32, mode="c", shape=(40, 40, 40)).T
            cow[20, 20, 20] = 7.0  # a private change: must survive the call (no pages handed back)
            meshless.isosurface(cow, 0.5, spacing=sp, origin=org)
            self.assertEqual(cow[20, 20, 20], 7.0)
            del cow

    def test_bad_arguments_are_value_errors(self):
        v, sp, org = sphere_volume(n=8)
        for call in (lambda: meshless.isosurface(np.zeros((4, 4)), 1.0),
                     lambda: meshless.isosurface(np.zeros((1, 4, 4), np.float32), 1.0),
                     lambda: meshless.isosurface(v, float("nan")),
                     lambda: meshless.isosurface(v, 0.5, spacing=(1, 0, 1)),
                     lambda: meshless.isosurface(v, 0.5, spacing=(1, 1)),
                     lambda: meshless.isosurface(v, 0.5, projection="fast")):
            with self.assertRaises(ValueError):
                call()


class Fields(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rng = np.random.default_rng(7)
        cls.pts = rng.uniform(-1, 1, (8000, 3))
        cls.val = (cls.pts ** 2).sum(1)

    def test_fits_and_interpolates_a_quadratic_with_its_gradient(self):
        for kind in ("mpu", "rbf-grid"):
            f = meshless.Field(self.pts, self.val, kind, threads=2)
            q = np.random.default_rng(8).uniform(-0.7, 0.7, (2000, 3))
            self.assertLess(np.abs(f(q) - (q ** 2).sum(1)).max(), 0.01, kind)
            self.assertLess(np.abs(f.gradient(q) - 2 * q).max(), 0.2, kind)
            self.assertTrue(np.allclose(f(self.pts[:100]), self.val[:100], atol=1e-6), kind)
            self.assertEqual(f.kind, kind)

    def test_values_do_not_depend_on_the_thread_count(self):
        f1 = meshless.Field(self.pts, self.val, threads=1)
        f2 = meshless.Field(self.pts, self.val, threads=2)
        q = np.random.default_rng(9).uniform(-1, 1, (5000, 3))
        self.assertTrue(np.array_equal(f1(q), f2(q)))
        f2.threads = 1
        self.assertTrue(np.array_equal(f2(q), f1(q)))

    def test_save_writes_the_bytes_of_meshless_fit_and_load_reads_them_back(self):
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, "p.csv")
            np.savetxt(csv, np.column_stack([self.pts, self.val]), delimiter=",", fmt="%.17g", header="x,y,z,v", comments="")
            subprocess.run([MESHLESS, "fit", csv, "-o", os.path.join(d, "cli.mlf")], check=True, stderr=subprocess.DEVNULL)
            f = meshless.Field(self.pts, self.val, value_name="v")
            f.save(os.path.join(d, "py.mlf"))
            with open(os.path.join(d, "cli.mlf"), "rb") as a, open(os.path.join(d, "py.mlf"), "rb") as b:
                self.assertEqual(a.read(), b.read())
            g = meshless.Field.load(os.path.join(d, "cli.mlf"))
            q = np.random.default_rng(3).uniform(-1, 1, (500, 3))
            self.assertTrue(np.array_equal(f(q), g(q)))
            self.assertEqual(g.value_name, "v")
            with self.assertRaises(OSError):
                meshless.Field.load(os.path.join(d, "missing.mlf"))
            with open(os.path.join(d, "bad.mlf"), "wb") as bad:
                bad.write(b"not a field")
            with self.assertRaises(meshless.DataError):
                meshless.Field.load(os.path.join(d, "bad.mlf"))
            self.assertTrue(issubclass(meshless.DataError, ValueError))

    def test_non_finite_rows_are_dropped_and_bad_input_refused(self):
        pts, val = self.pts.copy(), self.val.copy()
        pts[0, 1] = np.nan
        val[1] = np.inf
        f = meshless.Field(pts, val)
        self.assertEqual(f.stats["input_points"], len(pts) - 2)
        for call in (lambda: meshless.Field(np.zeros((5, 2)), np.zeros(5)),
                     lambda: meshless.Field(self.pts, self.val[:10]),
                     lambda: meshless.Field(np.zeros((5, 3)), np.zeros(5)),
                     lambda: meshless.Field(self.pts, self.val, "spline"),
                     lambda: meshless.Field(self.pts, self.val, alpha=0.2)):
            with self.assertRaises(ValueError):
                call()

    def test_the_gil_is_released_while_the_field_is_built(self):
        pts = np.random.default_rng(1).uniform(0, 1, (60000, 3))
        val = pts.sum(1)
        busy = threading.Event()
        done = threading.Event()

        def fit():
            busy.set()
            meshless.Field(pts, val, threads=1)
            done.set()

        t = threading.Thread(target=fit)
        t.start()
        busy.wait()
        spins = 0
        while not done.is_set():
            spins += 1
        t.join()
        self.assertGreater(spins, 10000)  # this thread ran while the fit did


class ScatteredAndBlocks(unittest.TestCase):
    def test_scattered_isosurface_of_a_sphere(self):
        rng = np.random.default_rng(2)
        pts = rng.uniform(-1, 1, (15000, 3))
        s = meshless.isosurface_points(pts, (pts ** 2).sum(1), 0.5, threads=2)
        r = np.linalg.norm(s.points, axis=1)
        self.assertGreater(len(s), 1000)
        self.assertLess(np.abs(r - np.sqrt(0.5)).max(), 5e-3)
        self.assertGreater((s.normals * (-s.points / r[:, None])).sum(1).min(), 0.9)
        self.assertEqual(s.stats["newton"]["converged"], len(s))
        self.assertIsNone(s.block)

    def test_scattered_same_bytes_as_the_cli_and_a_fitted_field_reused(self):
        rng = np.random.default_rng(5)
        pts = rng.uniform(0, 1, (4000, 3))
        val = np.sin(6 * pts[:, 0]) + pts[:, 1] * pts[:, 2]
        with tempfile.TemporaryDirectory() as d:
            csv, ply = os.path.join(d, "p.csv"), os.path.join(d, "s.ply")
            np.savetxt(csv, np.column_stack([pts, val]), delimiter=",", fmt="%.17g", header="x,y,z,v", comments="")
            subprocess.run([MESHLESS, "isosurface", csv, "--iso", "0.5", "-o", ply, "--threads", "2"], check=True)
            p = read_ply_points(ply)
        q = meshless.isosurface_points(pts, val, 0.5, threads=1)
        self.assertEqual(len(p), len(q))
        self.assertTrue(np.array_equal(np.stack([p["x"], p["y"], p["z"]], 1), q.points))
        self.assertTrue(np.array_equal(p["value"], q.values))
        g = meshless.isosurface_points(pts, val, 0.5, field=meshless.Field(pts, val))
        self.assertTrue(np.array_equal(g.points, q.points))
        with self.assertRaises(ValueError):
            meshless.isosurface_points(pts, val, 0.5, field=meshless.Field(pts, val), hardy_c=0.01)
        empty = meshless.isosurface_points(pts, val, 99.0)
        self.assertEqual(len(empty), 0)

    def test_overlapping_blocks_give_one_crack_free_sphere_with_block_ids(self):
        def block(x0, x1, n=18):
            g = np.mgrid[x0:x1:n * 1j, -1:1:28j, -1:1:28j]
            c = np.stack(g, axis=-1)
            return c, (c ** 2).sum(-1)

        s = meshless.isosurface_blocks([block(-1, 0.1), block(-0.1, 1)], 0.5, threads=2)
        r = np.linalg.norm(s.points, axis=1)
        self.assertLess(np.abs(r - np.sqrt(0.5)).max(), 1e-3)
        self.assertEqual(set(np.unique(s.block)), {0, 1})
        self.assertEqual(s.block.dtype, np.uint32)
        c, v = block(-1, 1, 30)
        iblank = np.ones(v.shape, int)
        iblank[:4] = 0
        b = meshless.isosurface_blocks([(c, v, iblank)], 0.5)
        self.assertGreater(b.stats["invalid_cells"], 0)
        self.assertTrue(np.all(b.points[:, 0] > -1 + 3 * 2 / 29 - 1e-6))
        with tempfile.TemporaryDirectory() as d:
            s.write(os.path.join(d, "b.ply"))
            back = meshless.read_points(os.path.join(d, "b.ply"))
            self.assertTrue(np.array_equal(back.block, s.block) and np.array_equal(back.points, s.points))
            with self.assertRaises(ValueError):
                s.write(os.path.join(d, "b.obj"))
            with self.assertRaises(OSError):
                meshless.read_points(os.path.join(d, "missing.ply"))
            with open(os.path.join(d, "bad.ply"), "wb") as bad:
                bad.write(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\nproperty float x\nend_header\n")
            with self.assertRaises(meshless.DataError):
                meshless.read_points(os.path.join(d, "bad.ply"))
        with self.assertRaises(ValueError):
            meshless.isosurface_blocks([(c, v[:-1])], 0.5)
        with self.assertRaises(ValueError):
            meshless.isosurface_blocks([], 0.5)


class MarchingCubes(unittest.TestCase):
    def test_a_closed_consistently_wound_mesh_in_either_order(self):
        v, sp, org = sphere_volume(n=32)
        meshes = [meshless.mc(v, 0.5, spacing=sp, origin=org), meshless.mc(np.ascontiguousarray(v), 0.5, spacing=sp, origin=org)]
        vols = []
        for verts, faces, normals in meshes:
            edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
            _, counts = np.unique(edges, axis=0, return_counts=True)
            self.assertTrue(np.all(counts == 2))  # closed: every edge in two triangles
            directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
            self.assertEqual(len(np.unique(directed, axis=0)), len(directed))  # consistently wound
            a, b, c = (verts[faces[:, i]].astype(float) for i in range(3))
            vols.append((a * np.cross(b, c)).sum() / 6)
            # counter-clockwise seen from the normal side: the winding's normal agrees with the vertex normals
            wn = np.cross(b - a, c - a)
            self.assertGreater(((wn * normals[faces[:, 0]]).sum(1) > 0).mean(), 0.99)
        self.assertAlmostEqual(vols[0], vols[1], places=4)
        self.assertAlmostEqual(abs(vols[0]), 4 / 3 * np.pi * 0.5 ** 1.5, delta=0.02)  # inward normals: negative volume
        self.assertLess(vols[0], 0)


class Info(unittest.TestCase):
    def test_the_report_of_meshless_info_byte_for_byte(self):
        with tempfile.TemporaryDirectory() as d:
            v, sp, org = sphere_volume(n=16)
            ply = os.path.join(d, "s.ply")
            meshless.isosurface(v, 0.5, spacing=sp, origin=org).write(ply)
            nrrd = os.path.join(d, "v.nrrd")
            with open(nrrd, "wb") as f:
                f.write(b"NRRD0004\ntype: float\ndimension: 3\nsizes: 16 16 16\nendian: little\nencoding: raw\n\n")
                f.write(np.ascontiguousarray(v.T, dtype="<f4").tobytes())
            for path, extra in ((ply, []), (nrrd, []), (nrrd, ["--value-range"])):
                cli = subprocess.run([MESHLESS, "info", path] + extra, check=True, capture_output=True).stdout.decode()
                self.assertEqual(meshless.info(path, value_range=bool(extra)), cli)
            lo, hi = float(v.min()), float(v.max())
            self.assertIn(f"value range: {lo:g} .. {hi:g}\n", meshless.info(nrrd, value_range=True))
            bad = os.path.join(d, "bad.nrrd")
            with open(bad, "wb") as f:
                f.write(b"NRRD0004\ntype: float\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n\nshort")
            with self.assertRaises(meshless.DataError):
                meshless.info(bad)
            with self.assertRaises(OSError):
                meshless.info(os.path.join(d, "missing.nrrd"))


if __name__ == "__main__":
    unittest.main()

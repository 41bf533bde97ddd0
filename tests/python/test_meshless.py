"""The Python module `meshless` (python/): oracles are analytic fields with known isosurfaces, the
CLI's own outputs for the same data (identical bytes), closed-mesh checks and round trips.

Run by ctest (tests/CMakeLists.txt) with Debian's python3, PYTHONPATH = the build's python folder,
MESHLESS = the built executable and MESHLESS_SHARED_DATA = ../shared/data (tests that need it are
skipped without it).
"""
import os
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import numpy as np

import meshless

MESHLESS = os.environ.get("MESHLESS", "meshless")
DATA = os.environ.get("MESHLESS_SHARED_DATA", "")
# the sanitizer tier preloads its runtime into python3; the meshless it runs carries its own
CLI_ENV = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
SANITIZED = os.environ.get("MESHLESS_SANITIZED") == "1"
TOOTH = os.path.join(DATA, "tooth", "tooth_103x94x161_uint8.raw")
FUEL = os.path.join(DATA, "fuel", "fuel_64x64x64_uint8.raw")


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
            subprocess.run([MESHLESS, "isosurface", TOOTH, "--iso", "100.5", "-o", out, "--threads", "1"], check=True, env=CLI_ENV)
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

    @unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
    def test_several_isovalues_are_the_single_runs_concatenated_as_the_cli_writes_them(self):
        vol = np.fromfile(TOOTH, np.uint8).reshape(161, 94, 103).T
        a, b = meshless.isosurface(vol, 150.5), meshless.isosurface(vol, 60.5)
        ab = meshless.isosurface(vol, [150.5, 60.5])
        for name in ("points", "normals", "radius", "values"):
            self.assertTrue(np.array_equal(getattr(ab, name), np.concatenate([getattr(a, name), getattr(b, name)])))
        self.assertEqual(ab.stats["active_cells"], a.stats["active_cells"] + b.stats["active_cells"])
        self.assertEqual(ab.stats["isovalues"], [150.5, 60.5])
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "t.ply")
            subprocess.run([MESHLESS, "isosurface", TOOTH, "--iso", "150.5,60.5", "-o", out], check=True, env=CLI_ENV)
            p = read_ply_points(out)
            self.assertTrue(np.array_equal(np.stack([p["x"], p["y"], p["z"]], 1), ab.points))
            self.assertTrue(np.array_equal(p["value"], ab.values))
        with self.assertRaises(ValueError):
            meshless.isosurface(vol, [])

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
            subprocess.run([MESHLESS, "fit", csv, "-o", os.path.join(d, "cli.mlf")], check=True, env=CLI_ENV, stderr=subprocess.DEVNULL)
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
            subprocess.run([MESHLESS, "isosurface", csv, "--iso", "0.5", "-o", ply, "--threads", "2"], check=True, env=CLI_ENV)
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
    def test_several_isovalues_give_one_mesh_of_the_single_meshes_none_welded_to_another(self):
        v, sp, org = sphere_volume(n=32)
        (va, fa, na), (vb, fb, nb) = meshless.mc(v, 0.5, spacing=sp, origin=org), meshless.mc(v, 0.2, spacing=sp, origin=org)
        verts, faces, normals = meshless.mc(v, [0.5, 0.2], spacing=sp, origin=org)
        self.assertTrue(np.array_equal(verts, np.concatenate([va, vb])))
        self.assertTrue(np.array_equal(normals, np.concatenate([na, nb])))
        self.assertTrue(np.array_equal(faces, np.concatenate([fa, fb + len(va)])))
        self.assertEqual(faces.dtype, fa.dtype)

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
                cli = subprocess.run([MESHLESS, "info", path] + extra, check=True, env=CLI_ENV, capture_output=True).stdout.decode()
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


def cli(*args):
    """Runs this build's meshless with the given arguments (stderr kept for the failure message)."""
    r = subprocess.run([MESHLESS] + [str(a) for a in args], capture_output=True, env=CLI_ENV)
    if r.returncode != 0:
        raise AssertionError("meshless %s: exit %d: %s" % (" ".join(map(str, args)), r.returncode, r.stderr.decode()))
    return r


def read_ply_vertices(path):
    """Every vertex property of a binary little-endian PLY, in the file's types (float, double, uint)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in lines, lines[:3]
    types = {"float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8", "uint": "<u4", "uint32": "<u4",
             "uchar": "u1", "uint8": "u1", "int": "<i4"}
    props, n, inside = [], 0, False
    for line in lines:
        w = line.split()
        if w[:2] == ["element", "vertex"]:
            n, inside = int(w[2]), True
        elif w[:1] == ["element"]:
            inside = False
        elif w[:1] == ["property"] and inside:
            props.append((w[2], types[w[1]]))
    dt = np.dtype(props)
    return np.frombuffer(data[end:end + n * dt.itemsize], dt)


def xyz(v):
    return np.stack([v["x"], v["y"], v["z"]], 1)


def scattered(n=3000, seed=11):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0, 1, (n, 3))
    return pts, np.sin(5 * pts[:, 0]) + pts[:, 1] * pts[:, 2] + 0.3 * pts[:, 2]


def write_csv(path, pts, val):
    np.savetxt(path, np.column_stack([pts, val]), delimiter=",", fmt="%.17g", header="x,y,z,v", comments="")


def assert_owns_its_buffer(test, a):
    """The array is a view of a buffer the library filled (a capsule base), not a copy NumPy made."""
    test.assertFalse(a.flags.owndata)
    test.assertIsNotNone(a.base)
    test.assertNotIsInstance(a.base, np.ndarray)


class Pictures(unittest.TestCase):
    @unittest.skipUnless(os.path.exists(FUEL), "needs ../shared/data")
    def test_render_of_a_volume_has_the_pixels_and_png_bytes_of_meshless_render(self):
        vol = np.fromfile(FUEL, np.uint8).reshape(64, 64, 64).T
        opts = dict(size=(96, 80), tf="viridis", shade=True, azimuth=40, elevation=-15)
        img = meshless.render(vol, threads=2, **opts)
        self.assertEqual(img.pixels.shape, (80, 96, 3))
        self.assertEqual(img.pixels.dtype, np.uint8)
        assert_owns_its_buffer(self, img.pixels)
        self.assertTrue(np.shares_memory(np.asarray(img), img.pixels))
        self.assertGreater(img.stats["rays_hit"], 0)
        with tempfile.TemporaryDirectory() as d:
            png = os.path.join(d, "cli.png")
            cli("render", FUEL, "--size", "96x80", "--tf", "viridis", "--shade", "--azimuth", "40", "--elevation", "-15",
                "--threads", "1", "-o", png)
            ref = meshless.read_image(png)
            assert_owns_its_buffer(self, ref.pixels)
            self.assertTrue(np.array_equal(img.pixels, ref.pixels))
            self.assertGreater(len(np.unique(img.pixels.reshape(-1, 3), axis=0)), 50)  # a picture, not a blank
            with open(png, "rb") as f:
                cli_bytes = f.read()
            self.assertEqual(img._repr_png_(), cli_bytes)  # the product's own PNG writer
            img.save(os.path.join(d, "py.png"))
            with open(os.path.join(d, "py.png"), "rb") as f:
                self.assertEqual(f.read(), cli_bytes)
            # a C-ordered copy of the same volume: the same picture (one Fortran-ordered copy inside)
            c = meshless.render(np.ascontiguousarray(vol), threads=1, **opts)
            self.assertTrue(np.array_equal(c.pixels, ref.pixels))
            # the brick store through its cache, as `meshless render vol.mlb --memory 16M`
            mlb = os.path.join(d, "fuel.mlb")
            cli("convert", FUEL, "-o", mlb)
            cli("render", mlb, "--memory", "16M", "--size", "64x64", "--tf", "viridis", "--view", "+z", "-o", png)
            s = meshless.render(meshless.open_store(mlb), memory="16M", size=(64, 64), tf="viridis", view="+z")
            self.assertTrue(np.array_equal(s.pixels, meshless.read_image(png).pixels))
            self.assertGreater((s.pixels.sum(2) > 0).sum(), 200)  # the fuel drawn, not a blank

    def test_render_of_a_field_over_its_points_equals_meshless_render_of_the_points(self):
        pts, val = scattered(2500)
        with tempfile.TemporaryDirectory() as d:
            csv, png = os.path.join(d, "p.csv"), os.path.join(d, "f.png")
            write_csv(csv, pts, val)
            cli("render", csv, "--field", "mpu", "--size", "48x40", "--tf", "grey", "--range", "0,1.5", "--ortho", "-o", png)
            f = meshless.Field(pts, val, threads=2)
            img = meshless.render(f, points=pts, values=val, size=(48, 40), range=(0, 1.5), ortho=True)
            self.assertTrue(np.array_equal(img.pixels, meshless.read_image(png).pixels))
            self.assertGreater(img.pixels.max(), 0)
        with self.assertRaises(ValueError):
            meshless.render(f)  # the field's points are needed for its box
        with self.assertRaises(ValueError):
            meshless.render(f, points=pts[:, :2], values=val)

    def test_render_of_a_synthetic_sphere_is_round_and_independent_of_threads(self):
        v, sp, org = sphere_volume(n=40)
        a = meshless.render(v, spacing=sp, origin=org, size=(64, 64), view="+z", ortho=True, tf="grey", range=(0, 0.6), threads=1)
        b = meshless.render(v, spacing=sp, origin=org, size=(64, 64), view="+z", ortho=True, tf="grey", range=(0, 0.6), threads=2)
        self.assertTrue(np.array_equal(a.pixels, b.pixels))
        lum = a.pixels.astype(float).sum(2)
        self.assertTrue(np.allclose(lum, lum[::-1, :], atol=3) and np.allclose(lum, lum[:, ::-1], atol=3))  # symmetric
        self.assertEqual(lum[0, 0], 0)  # outside the box: the background
        self.assertGreater(lum[32, 32], 0)

    def test_bad_render_and_splat_arguments_raise_value_errors(self):
        v, sp, org = sphere_volume(n=8)
        for call in (lambda: meshless.render(np.zeros((4, 4))),
                     lambda: meshless.render(v, size=(0, 10)),
                     lambda: meshless.render(v, tf="no-such-preset-or-file"),
                     lambda: meshless.render(v, range=(2, 1)),
                     lambda: meshless.render(v, view="+q"),
                     lambda: meshless.render(v, view="+x", azimuth=10),
                     lambda: meshless.render(v, up="w"),
                     lambda: meshless.render(v, background=(2, 0, 0)),
                     lambda: meshless.render(v, step=0),
                     lambda: meshless.render(v, bounds=(0, 0, 0, 1, 1)),
                     lambda: meshless.render(v, threads=-1),
                     lambda: meshless.render(v, points=np.zeros((3, 3))),
                     lambda: meshless.render("vol.raw"),
                     lambda: meshless.render(v, memory="12Q"),
                     lambda: meshless.splat(meshless.isosurface(v, 0.5), kernel="round"),
                     lambda: meshless.splat(meshless.isosurface(v, 0.5), color="red"),
                     lambda: meshless.Image({"pixels": np.zeros((4, 4), np.uint8)}).save("x.png")):
            with self.assertRaises(ValueError):
                call()

    def test_splat_has_the_pixels_of_meshless_splat_for_a_file_and_a_point_set(self):
        v, sp, org = sphere_volume(n=32)
        s = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
        with tempfile.TemporaryDirectory() as d:
            ply, png = os.path.join(d, "s.ply"), os.path.join(d, "s.png")
            s.write(ply)
            for opts, args in (({}, []),
                               ({"kernel": "quad", "color": "normal", "size": (70, 50), "azimuth": 120},
                                ["--kernel", "quad", "--color", "normal", "--size", "70x50", "--azimuth", "120"]),
                               ({"color": "value", "range": (0.4, 0.6), "colorbar": True, "shading": "lambert", "size": (90, 90)},
                                ["--color", "value", "--range", "0.4,0.6", "--colorbar", "--shading", "lambert", "--size", "90x90"])):
                cli("splat", ply, "-o", png, *args)
                ref = meshless.read_image(png).pixels
                from_set = meshless.splat(s, threads=2, **opts)
                from_file = meshless.splat(ply, threads=1, **opts)
                self.assertTrue(np.array_equal(from_set.pixels, ref), opts)
                self.assertTrue(np.array_equal(from_file.pixels, ref), opts)
                assert_owns_its_buffer(self, from_set.pixels)
                self.assertEqual(from_set.stats["drawn"], len(s))
            with self.assertRaises(OSError):
                meshless.splat(os.path.join(d, "missing.ply"))
            with open(os.path.join(d, "bad.png"), "wb") as f:
                f.write(b"\x89PNG\r\n\x1a\nnot really")
            with self.assertRaises(meshless.DataError):
                meshless.read_image(os.path.join(d, "bad.png"))
            with self.assertRaises(OSError):
                meshless.read_image(os.path.join(d, "missing.png"))

    @unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
    def test_splat_of_points_read_back_frames_them_as_the_file_records(self):
        with tempfile.TemporaryDirectory() as d:
            ply, png = os.path.join(d, "t.ply"), os.path.join(d, "t.png")
            cli("isosurface", TOOTH, "--iso", "100.5", "-o", ply)
            cli("splat", ply, "-o", png, "--size", "120x100", "--elevation", "35")
            ref = meshless.read_image(png).pixels
            back = meshless.read_points(ply)  # its comments record the surface's bounds, the frame
            self.assertTrue(np.array_equal(meshless.splat(back, size=(120, 100), elevation=35).pixels, ref))
            self.assertTrue(np.array_equal(meshless.splat(ply, size=(120, 100), elevation=35).pixels, ref))


class LevelsOfDetail(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.pts, cls.val = scattered(3000)

    def test_the_tree_and_its_levels_equal_meshless_hierarchy_and_lod(self):
        tree = meshless.hierarchy(self.pts, self.val, value_name="v", threads=2)
        self.assertEqual(tree.stats["samples"], len(self.pts))
        self.assertGreater(tree.depth, 5)
        with tempfile.TemporaryDirectory() as d:
            csv, mlh = os.path.join(d, "p.csv"), os.path.join(d, "t.mlh")
            write_csv(csv, self.pts, self.val)
            cli("hierarchy", csv, "-o", mlh, "--threads", "1")
            tree.save(os.path.join(d, "py.mlh"))
            with open(mlh, "rb") as a, open(os.path.join(d, "py.mlh"), "rb") as b:
                self.assertEqual(a.read(), b.read())
            loaded = meshless.ClusterTree.load(mlh)
            for flag, value, kw in (("--level", "6", {"level": 6}), ("--error", "0.05", {"error": 0.05}),
                                    ("--level", "0", {"level": 0}), ("--count", "37", {"count": 37}),
                                    ("--fraction", "0.01", {"fraction": 0.01})):
                out = os.path.join(d, "lod.ply")
                cli("lod", mlh, flag, value, "-o", out)
                want = read_ply_vertices(out)
                for t in (tree, loaded):
                    got = t.lod(**kw)
                    self.assertEqual(got.points.dtype, np.float64)
                    self.assertTrue(np.array_equal(got.points, xyz(want)), kw)
                    self.assertTrue(np.array_equal(got.values, want["value"]), kw)
                    self.assertIsNone(got.normals)
                if len(want) < 4:  # the point-set readers need 4 points
                    with self.assertRaises(meshless.DataError):
                        meshless.read_points(out)
                    continue
                back = meshless.read_points(out)  # the commands' reader: the same points, as float64
                self.assertTrue(np.array_equal(back.points, tree.lod(**kw).points))
                self.assertIsNone(back.normals)
        self.assertEqual(len(tree.lod(level=0)), 1)
        self.assertEqual(len(tree.lod(level=2)), 4)

    def test_lod_arrays_own_the_extraction_and_a_point_set_builds_a_tree(self):
        tree = meshless.hierarchy(self.pts, self.val, max_splits=200)
        lod = tree.lod(level=30)  # beyond the depth: the finest, with a warning
        self.assertEqual(len(lod), 201)
        self.assertTrue(any("finest" in w or "depth" in w for w in lod.warnings), lod.warnings)
        assert_owns_its_buffer(self, lod.points)
        assert_owns_its_buffer(self, lod.values)
        self.assertEqual(lod.points.shape, (201, 3))
        v, sp, org = sphere_volume(n=24)
        surf = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
        self.assertEqual(len(meshless.hierarchy(surf).lod(level=3)), 1)  # one value everywhere: nothing to split
        surf.values[:] = surf.points[:, 2]  # the PointSet's own buffer: its values are now the height
        t = meshless.hierarchy(surf, min_cluster=50)
        self.assertEqual(t.stats["samples"], len(surf))
        u = meshless.hierarchy(surf.points.astype(np.float64), surf.values.astype(np.float64), min_cluster=50)
        self.assertEqual(len(t.lod(level=3)), 8)
        self.assertTrue(np.array_equal(t.lod(level=5).points, u.lod(level=5).points))
        with self.assertRaises(ValueError):
            lod.write("x.obj")  # scattered data: .ply, .csv or .vtp

    def test_bad_arguments_and_files(self):
        tree = meshless.hierarchy(self.pts[:200], self.val[:200])
        for call in (lambda: tree.lod(),
                     lambda: tree.lod(level=1, error=1.0),
                     lambda: tree.lod(count=0),
                     lambda: tree.lod(fraction=1.5),
                     lambda: tree.lod(count=3, fraction=0.1),
                     lambda: meshless.hierarchy(self.pts, self.val, split_order="best"),
                     lambda: meshless.hierarchy(self.pts, self.val, size_term=-1),
                     lambda: meshless.hierarchy(self.pts, self.val, cluster_value="median"),
                     lambda: tree.lod(level=-1),
                     lambda: tree.lod(error=float("nan")),
                     lambda: meshless.hierarchy(self.pts),
                     lambda: meshless.hierarchy(self.pts[:, :2], self.val),
                     lambda: meshless.hierarchy(self.pts, self.val[:10]),
                     lambda: meshless.hierarchy(self.pts, self.val, min_cluster=1),
                     lambda: meshless.hierarchy(self.pts, self.val, neighbours=0),
                     lambda: meshless.hierarchy(self.pts, self.val, pca_scaling="pca"),
                     lambda: meshless.hierarchy(self.pts, self.val, max_error=-1)):
            with self.assertRaises(ValueError):
                call()
        with self.assertRaises(meshless.DataError):
            meshless.hierarchy(np.full((10, 3), np.nan), np.zeros(10))  # no finite sample
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(OSError):
                meshless.ClusterTree.load(os.path.join(d, "missing.mlh"))
            with open(os.path.join(d, "bad.mlh"), "wb") as f:
                f.write(b"\x89MLH\r\n\x1a\n" + bytes(100))
            with self.assertRaises(meshless.DataError):
                meshless.ClusterTree.load(os.path.join(d, "bad.mlh"))


@unittest.skipUnless(os.path.exists(TOOTH), "needs ../shared/data")
class BrickStores(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.mlb = os.path.join(cls.dir.name, "tooth.mlb")
        cli("convert", TOOTH, "-o", cls.mlb)
        cls.ply = os.path.join(cls.dir.name, "tooth.ply")
        cli("isosurface", cls.mlb, "--iso", "100.5", "--memory", "16M", "-o", cls.ply)
        cls.want = read_ply_vertices(cls.ply)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_the_batches_concatenated_are_meshless_isosurface_of_the_store(self):
        store = meshless.open_store(self.mlb)
        self.assertEqual(store.dims, (103, 94, 161))
        self.assertEqual(store.dtype, "uint8")
        for threads in (1, 2):
            batches = list(store.isosurface(100.5, memory="16M", threads=threads))
            self.assertGreater(len(batches), 1)
            for b in batches:
                assert_owns_its_buffer(self, b.points)
                self.assertIs(b.points.base, b.normals.base)
            pts = np.concatenate([b.points for b in batches])
            self.assertEqual(len(pts), len(self.want))
            self.assertTrue(np.array_equal(pts, xyz(self.want)))
            self.assertTrue(np.array_equal(np.concatenate([b.normals for b in batches]),
                                           np.stack([self.want["nx"], self.want["ny"], self.want["nz"]], 1)))
            self.assertTrue(np.array_equal(np.concatenate([b.radius for b in batches]), self.want["radius"]))

    def test_closing_early_stops_the_graph_and_nothing_is_left_running(self):
        store = meshless.open_store(self.mlb)
        sum(len(b) for b in store.isosurface(100.5, memory="4M", threads=2))  # the worker pool started
        before = len(os.listdir("/proc/self/task"))
        for _ in range(3):
            g = store.isosurface(100.5, memory="4M", threads=2)
            first = next(g)
            self.assertGreater(len(first), 0)
            g.close()
            h = store.isosurface(100.5, threads=1)
            del h  # never started by the caller: dropped, its thread stopped
        self.assertLessEqual(len(os.listdir("/proc/self/task")), before)  # the graphs' threads joined
        self.assertEqual(len(list(store.isosurface(1e9))), 0)  # nothing active

    @unittest.skipIf(SANITIZED, "RSS bounds: ASan's shadow memory and quarantine count in RSS")
    def test_memory_stays_the_cache_and_a_few_batches_while_a_slow_consumer_reads(self):
        big = os.path.join(self.dir.name, "tooth4.mlb")  # 98 M voxels, about 31 MiB of points at 100.5
        cli("synth", "--upsample", "4", TOOTH, "-o", big)
        script = (
            "import resource, sys, time, meshless\n"
            "store = meshless.open_store(sys.argv[1])\n"
            "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
            "n = 0\n"
            "for b in store.isosurface(100.5, memory='4M', threads=2):\n"
            "    n += len(b)\n"
            "    time.sleep(0.0005)  # slower than the graph: an unbounded queue would hold every batch\n"
            "print(n * 32, (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) * 1024)\n")
        r = subprocess.run([sys.executable, "-c", script, big], capture_output=True, check=True, text=True)
        output, growth = map(int, r.stdout.split())
        self.assertGreater(output, 25 << 20)
        self.assertLess(growth, output // 2, "peak RSS grew %.1f MiB for %.1f MiB of points" % (growth / 2**20, output / 2**20))

    def test_bad_stores_and_arguments(self):
        store = meshless.open_store(self.mlb)
        for call in (lambda: store.isosurface(float("nan")),
                     lambda: store.isosurface(100.5, memory="12Q"),
                     lambda: store.isosurface(100.5, memory="1K"),
                     lambda: store.isosurface(100.5, projection="fast"),
                     lambda: store.isosurface(100.5, threads=-2)):
            with self.assertRaises(ValueError):
                call()
        with self.assertRaises(meshless.DataError):
            meshless.open_store(TOOTH)  # a raw volume, not a store
        with self.assertRaises(OSError):
            meshless.open_store(os.path.join(self.dir.name, "missing.mlb"))
        with open(self.mlb, "rb") as f:
            data = bytearray(f.read())
        bad = os.path.join(self.dir.name, "damaged.mlb")
        data[len(data) // 4: 3 * len(data) // 4] = bytes(3 * len(data) // 4 - len(data) // 4)  # bricks zeroed
        with open(bad, "wb") as f:
            f.write(bytes(data))
        with self.assertRaises(meshless.DataError):
            for _ in meshless.open_store(bad).isosurface(100.5):
                pass


class ReleasedGil(unittest.TestCase):
    def test_two_python_threads_render_and_splat_at_once_with_the_same_results(self):
        v, sp, org = sphere_volume(n=96)
        surf = meshless.isosurface(v, 0.5, spacing=sp, origin=org)
        jobs = [lambda: meshless.render(v, spacing=sp, origin=org, size=(200, 200), shade=True, threads=1).pixels,
                lambda: meshless.splat(surf, size=(300, 300), threads=1).pixels]
        t0 = time.perf_counter()
        want = [job() for job in jobs]
        sequential = time.perf_counter() - t0
        got = [None, None]
        busy = threading.Event()

        def run(i):
            busy.set()
            got[i] = jobs[i]()

        threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
        t0 = time.perf_counter()
        for t in threads:
            t.start()
        busy.wait()
        spins = 0
        while any(t.is_alive() for t in threads):
            spins += 1
        for t in threads:
            t.join()
        concurrent = time.perf_counter() - t0
        self.assertTrue(np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1]))
        self.assertGreater(spins, 10000)  # this thread ran while both pictures were made
        print("\nGIL: render + splat sequential %.3f s, two threads %.3f s" % (sequential, concurrent))


if __name__ == "__main__":
    unittest.main()

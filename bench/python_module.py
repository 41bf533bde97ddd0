#!/usr/bin/env python3
"""The Python module's numbers (meshless-bench python; python/README.md), each against its baseline
measured in the same run:
  - equality: meshless.isosurface on the tooth CT against `meshless isosurface` on the same file
  - no hidden copies: peak RSS of isosurface on an np.memmap volume (1 GiB; --quick 64 MiB), in a
    child process, minus the RSS before the call and the output's bytes
  - call overhead of a small Field query (one point), microseconds per call
  - two Python threads calling isosurface on two volumes at once, against the two calls in sequence
  - Field (mpu) against scipy.interpolate.RBFInterpolator(neighbors=50, kernel="multiquadric") on
    the same 10^5 points (--quick 10^4): build + 10^6 queries (--quick 10^5), and the RMS error at the queries
Output: lines "TABLE<TAB>title<TAB>col...", "ROW<TAB>cell...", "NOTE<TAB>text" for meshless-bench,
or readable tables with --text. Needs the module (PYTHONPATH=<build>/python) and NumPy; SciPy for
the last table (skipped without it).

usage: python_module.py --meshless EXE [--data DIR] [--scratch DIR] [--quick] [--text]
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

import meshless


class Out:
    def __init__(self, text):
        self.text = text

    def table(self, title, header, rows):
        if self.text:
            print("\n" + title)
            print(" | ".join(header))
            for r in rows:
                print(" | ".join(r))
        else:
            print("TABLE\t" + title + "\t" + "\t".join(header))
            for r in rows:
                print("ROW\t" + "\t".join(r))
        sys.stdout.flush()

    def note(self, text):
        print(("NOTE\t" if not self.text else "") + text)
        sys.stdout.flush()


def equality(out, args):
    tooth = os.path.join(args.data, "tooth", "tooth_103x94x161_uint8.raw")
    if not os.path.exists(tooth):
        out.note("equality: %s not found, skipped" % tooth)
        return
    vol = np.fromfile(tooth, np.uint8).reshape(161, 94, 103).T
    t0 = time.perf_counter()
    s = meshless.isosurface(vol, 100.5)
    tp = time.perf_counter() - t0
    with tempfile.TemporaryDirectory(dir=args.scratch) as d:
        ply = os.path.join(d, "t.ply")
        t0 = time.perf_counter()
        subprocess.run([args.meshless, "isosurface", tooth, "--iso", "100.5", "-o", ply], check=True)
        tc = time.perf_counter() - t0
        p = meshless.read_points(ply)  # the PLY reader `meshless splat` uses
    same = len(p) == len(s) and np.array_equal(p.points, s.points) and np.array_equal(p.normals, s.normals) and \
        np.array_equal(p.radius, s.radius) and np.array_equal(p.values, s.values)
    out.table("Python = CLI (tooth CT, iso 100.5)", ["points", "identical arrays", "python call s", "CLI process s"],
              [[str(len(s)), "yes" if same else "NO", "%.3f" % tp, "%.3f" % tc]])


CHILD = r"""
import resource, sys, numpy as np, meshless
path, n = sys.argv[1], int(sys.argv[2])
vol = np.memmap(path, np.uint8, mode="r", shape=(n, n, n)).T
def rss():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"): return int(line.split()[1]) * 1024
before = rss()
s = meshless.isosurface(vol, 100.5)
print(before, rss(), len(s) * 32)
"""


def memmap_rss(out, args):
    n = 256 if args.quick else 1024
    with tempfile.TemporaryDirectory(dir=args.scratch) as d:
        path = os.path.join(d, "ball.raw")
        # a ball of radius n/3 (255 inside, 0 outside), written slab by slab
        x = np.arange(n, dtype=np.float32) - n / 2
        with open(path, "wb") as f:
            for k in range(n):
                r2 = x[None, :] ** 2 + x[:, None] ** 2 + (k - n / 2) ** 2
                f.write(np.where(r2 < (n / 3) ** 2, 255, 0).astype(np.uint8).tobytes())
        r = subprocess.run([sys.executable, "-c", CHILD, path, str(n)], check=True, capture_output=True, text=True)
        before, peak, output = (int(v) for v in r.stdout.split())
    grown = peak - before - output
    mib = 1 << 20
    out.table("No hidden copies: isosurface of an np.memmap volume (uint8 %d^3, %.0f MiB)" % (n, n ** 3 / mib),
              ["peak RSS before MiB", "peak RSS after MiB", "output MiB", "growth beyond the output MiB", "target MiB"],
              [["%.0f" % (before / mib), "%.0f" % (peak / mib), "%.1f" % (output / mib), "%.0f" % (grown / mib), "64"]])
    out.note("a shared np.memmap is read slab by slab and its pages are handed back as they are done "
             "(python/src/array_slices.hpp): the growth is the slabs in flight and the results being collected")


def overhead(out, args):
    rng = np.random.default_rng(0)
    pts = rng.uniform(-1, 1, (20000, 3))
    f = meshless.Field(pts, (pts ** 2).sum(1))
    q = np.array([[0.1, 0.2, 0.3]])
    for _ in range(100):
        f(q)
    k = 2000 if args.quick else 20000
    t0 = time.perf_counter()
    for _ in range(k):
        f(q)
    us = (time.perf_counter() - t0) / k * 1e6
    out.table("Call overhead: Field(q) for one point", ["calls", "us per call", "target us"], [[str(k), "%.1f" % us, "20"]])


def best_pair(call, inputs, reps=3):
    """Best-of-reps seconds of the calls in sequence and of one thread per call, started together."""
    for x in inputs:
        call(x)
    best_seq, best_par = 1e9, 1e9
    for _ in range(reps):
        t0 = time.perf_counter()
        for x in inputs:
            call(x)
        best_seq = min(best_seq, time.perf_counter() - t0)
        ts = [threading.Thread(target=call, args=(x,)) for x in inputs]
        t0 = time.perf_counter()
        for t in ts:
            t.start()
        for t in ts:
            t.join()
        best_par = min(best_par, time.perf_counter() - t0)
    return best_seq, best_par


def two_threads(out, args):
    n = 160 if args.quick else 320
    x = np.linspace(-1, 1, n, dtype=np.float32)
    a = np.asfortranarray(x[:, None, None] ** 2 + x[None, :, None] ** 2 + x[None, None, :] ** 2)
    b = np.asfortranarray(np.abs(x[:, None, None]) + x[None, :, None] ** 2 + x[None, None, :] ** 4)
    rng = np.random.default_rng(4)
    m = 10000 if args.quick else 40000
    clouds = [rng.uniform(-1, 1, (m, 3)) for _ in range(2)]
    rows = []
    seq, par = best_pair(lambda v: meshless.isosurface(v, 0.5, threads=1), [a, b])
    rows.append(["isosurface, two %d^3 float32 volumes (memory-bound)" % n, "%.3f" % seq, "%.3f" % par, "%.2f" % (par / seq)])
    seq, par = best_pair(lambda p: meshless.isosurface_points(p, (p ** 2).sum(1), 0.5, threads=1), clouds)
    rows.append(["isosurface_points, two sets of %d points (compute-bound)" % m, "%.3f" % seq, "%.3f" % par, "%.2f" % (par / seq)])
    out.table("GIL released: two Python threads against the two calls in sequence (threads=1 each; target <= 0.60)",
              ["calls", "in sequence s", "two threads s", "ratio"], rows)


def field_vs_scipy(out, args):
    try:
        from scipy.interpolate import RBFInterpolator
    except ImportError:
        out.note("Field vs SciPy: scipy not installed, skipped (python3-scipy)")
        return
    n, m = (10000, 100000) if args.quick else (100000, 1000000)
    rng = np.random.default_rng(1)
    pts = rng.uniform(0, 1, (n, 3))

    def franke(p):
        x, y, z = 9 * p[:, 0], 9 * p[:, 1], 9 * p[:, 2]
        return (0.75 * np.exp(-((x - 2) ** 2 + (y - 2) ** 2 + (z - 2) ** 2) / 4) +
                0.75 * np.exp(-((x + 1) ** 2) / 49 - (y + 1) / 10 - (z + 1) / 10) +
                0.5 * np.exp(-((x - 7) ** 2 + (y - 3) ** 2 + (z - 5) ** 2) / 4) -
                0.2 * np.exp(-(x - 4) ** 2 - (y - 7) ** 2 - (z - 5) ** 2))

    val = franke(pts)
    q = rng.uniform(0.05, 0.95, (m, 3))
    truth = franke(q)
    rows = []
    t0 = time.perf_counter()
    f = meshless.Field(pts, val)
    vm = f(q)
    tm = time.perf_counter() - t0
    # SciPy's epsilon for the multiquadric: 1 / (the mean nearest-neighbour spacing), its usual shape
    spacing = (1.0 / n) ** (1 / 3)
    t0 = time.perf_counter()
    r = RBFInterpolator(pts, val, neighbors=50, kernel="multiquadric", epsilon=1.0 / spacing)
    vs = r(q)
    ts = time.perf_counter() - t0
    rms = lambda v: float(np.sqrt(np.nanmean((v - truth) ** 2)))
    rows.append(["meshless.Field (mpu)", "%.2f" % tm, "%.2e" % rms(vm), "1.00"])
    rows.append(["scipy RBFInterpolator(neighbors=50, multiquadric)", "%.2f" % ts, "%.2e" % rms(vs), "%.1f" % (ts / tm)])
    out.table("Field against SciPy: Franke's function, %d uniform points, build + %d queries" % (n, m),
              ["interpolant", "build + queries s", "RMS error", "time / meshless"], rows)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--meshless", required=True)
    p.add_argument("--data", default=os.environ.get("MESHLESS_DATA", "../shared/data"))
    p.add_argument("--scratch", default=None)
    p.add_argument("--quick", action="store_true")
    p.add_argument("--text", action="store_true")
    args = p.parse_args()
    out = Out(args.text)
    out.note("meshless %s, NumPy %s, Python %s" % (os.path.dirname(meshless.__file__), np.__version__, sys.version.split()[0]))
    for part in (equality, memmap_rss, overhead, two_threads, field_vs_scipy):
        part(out, args)


if __name__ == "__main__":
    main()

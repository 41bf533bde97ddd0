#!/usr/bin/env python3
"""SciPy reference interpolant for `meshless bench fields` (accuracy).

Fits scipy.interpolate.RBFInterpolator to scattered samples and evaluates it at test points; the
bench computes the errors (against the exact function) itself, on the same test points as its own
fields, so both sides are measured identically.

Files (little-endian, written by the bench into a scratch folder):
  --points FILE   int64 n, then n records of float64 x, y, z, value
  --tests FILE    int64 m, then m records of float64 x, y, z
  --out FILE      written here: m float64 predictions (one per test point, same order)
One or more --config KERNEL:EPSILON:DEGREE (e.g. multiquadric:23.09:1, thin_plate_spline:1:1) each
fit once with --neighbors K (0 = global); the predictions of config i go to FILE.i.

Kernel conventions (SciPy): 'multiquadric' is -sqrt(1 + (eps r)^2) = -(1/c) sqrt(r^2 + c^2) with
eps = 1/c, i.e. Hardy's multiquadric with constant c up to a factor absorbed by the weights, so
eps = 1 / c_world matches the meshless fields; degree 1 adds the same linear polynomial.
'thin_plate_spline' is r^2 log r (epsilon ignored by scale invariance), degree 1 by default.

Stdout: one JSON object {"scipy": version, "numpy": version, "n": n, "m": m, "configs": [{"kernel",
"epsilon", "degree", "neighbors", "fit_seconds", "eval_seconds", "out"}]}.
Exit status 3 (message on stderr) when SciPy cannot be imported; `--check` only tests the import.
"""
import argparse
import json
import sys
import time


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="only check that scipy imports (exit 0/3)")
    ap.add_argument("--points")
    ap.add_argument("--tests")
    ap.add_argument("--out")
    ap.add_argument("--neighbors", type=int, default=50)
    ap.add_argument("--config", action="append", default=[], help="KERNEL:EPSILON:DEGREE")
    a = ap.parse_args()
    try:
        import numpy as np
        import scipy
        from scipy.interpolate import RBFInterpolator
    except ImportError as e:  # pragma: no cover - depends on the machine
        print(f"SciPy not installed (apt-get install python3-scipy): {e}", file=sys.stderr)
        return 3
    if a.check:
        print(json.dumps({"scipy": scipy.__version__, "numpy": np.__version__}))
        return 0
    if not (a.points and a.tests and a.out and a.config):
        ap.error("--points, --tests, --out and at least one --config are required")

    def read(path, cols):
        with open(path, "rb") as f:
            n = int(np.frombuffer(f.read(8), dtype="<i8")[0])
            data = np.frombuffer(f.read(), dtype="<f8")
        if data.size != n * cols:
            raise SystemExit(f"{path}: expected {n} records of {cols} float64, got {data.size} values")
        return data.reshape(n, cols)

    pts = read(a.points, 4)
    tst = np.ascontiguousarray(read(a.tests, 3))
    y = pts[:, :3].copy()
    d = pts[:, 3].copy()
    res = {"scipy": scipy.__version__, "numpy": np.__version__, "n": int(len(y)), "m": int(len(tst)),
           "configs": []}
    for i, c in enumerate(a.config):
        kernel, eps, degree = c.split(":")
        eps, degree = float(eps), int(degree)
        nb = a.neighbors if 0 < a.neighbors < len(y) else None
        t0 = time.perf_counter()
        f = RBFInterpolator(y, d, neighbors=nb, kernel=kernel, epsilon=eps, degree=degree)
        t1 = time.perf_counter()
        pred = f(tst)
        t2 = time.perf_counter()
        out = f"{a.out}.{i}"
        np.asarray(pred, dtype="<f8").tofile(out)
        res["configs"].append({"kernel": kernel, "epsilon": eps, "degree": degree, "neighbors": nb or 0,
                               "fit_seconds": t1 - t0, "eval_seconds": t2 - t1, "out": out})
    print(json.dumps(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())

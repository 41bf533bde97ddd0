"""`pip install ./python` into a fresh virtual environment, offline, with the project's own build backend
(python/build_backend/meshless_build.py): the wheel's contents and RECORD, the installed module imported
from another folder, its version equal to the command's, uninstall, and a bad setting refused.

The backend builds the target meshless_python in the build folder this test is given
(MESHLESS_BUILD_DIR, the ctest build), which is built already, so no compiling happens here.
"""

import base64
import hashlib
import os
import subprocess
import sys
import tempfile
import unittest
import venv
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
BUILD_DIR = os.environ.get("MESHLESS_BUILD_DIR")
MESHLESS = os.environ.get("MESHLESS")


def _clean_env():
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "PIP_CONFIG_FILE")}
    env.update(PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INDEX="1", PIP_NO_INPUT="1")
    return env


@unittest.skipUnless(BUILD_DIR and MESHLESS, "needs MESHLESS_BUILD_DIR and MESHLESS (set by ctest)")
class PipInstall(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="meshless-pip-")
        cls.root = Path(cls.tmp.name)
        cls.env_dir = cls.root / "venv"
        # Debian's numpy from the system's site folder; pip from python3-venv's bundled wheel
        venv.EnvBuilder(system_site_packages=True, with_pip=True).create(cls.env_dir)
        cls.python = cls.env_dir / "bin" / "python"

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def pip(self, *args):
        return subprocess.run([str(self.python), "-m", "pip", *args], cwd=self.root, env=_clean_env(),
                              capture_output=True, text=True, timeout=600)

    def in_venv(self, code):
        return subprocess.run([str(self.python), "-c", code], cwd=self.root, env=_clean_env(),
                              capture_output=True, text=True, timeout=120)

    def test_1_wheel_contents_and_record(self):
        out = self.root / "wheels"
        done = self.pip("wheel", "--no-deps", "--config-settings", f"build-dir={BUILD_DIR}", "-w", str(out), str(REPO / "python"))
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        wheels = list(out.glob("meshless-*.whl"))
        self.assertEqual(len(wheels), 1, [w.name for w in out.iterdir()])
        tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
        self.assertIn(f"-{tag}-{tag}-", wheels[0].name)
        with zipfile.ZipFile(wheels[0]) as wheel:
            names = wheel.namelist()
            self.assertIn("meshless/__init__.py", names)
            self.assertTrue(any(n.startswith("meshless/_core.") and n.endswith(".so") for n in names), names)
            record_name = next(n for n in names if n.endswith(".dist-info/RECORD"))
            rows = [line.split(",") for line in wheel.read(record_name).decode().splitlines()]
            self.assertEqual(sorted(r[0] for r in rows), sorted(names))
            for name, digest, size in rows:
                if name == record_name:
                    self.assertEqual((digest, size), ("", ""))
                    continue
                data = wheel.read(name)
                expected = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
                self.assertEqual(digest, "sha256=" + expected, name)
                self.assertEqual(int(size), len(data), name)
            metadata = wheel.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
            self.assertIn("Name: meshless", metadata)
            self.assertIn("Requires-Dist: numpy", metadata)

    def test_2_install_import_uninstall(self):
        done = self.pip("install", "--config-settings", f"build-dir={BUILD_DIR}", str(REPO / "python"))
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        code = ("import meshless, numpy as np\n"
                "x, y, z = np.mgrid[-1:1:24j, -1:1:24j, -1:1:24j]\n"
                "s = meshless.isosurface((x*x + y*y + z*z).astype(np.float32), 0.5)\n"
                "print(meshless.__file__); print(meshless.__version__); print(len(s.points))\n")
        ran = self.in_venv(code)
        self.assertEqual(ran.returncode, 0, ran.stderr)
        where, version, count = ran.stdout.split()
        self.assertTrue(Path(where).resolve().is_relative_to(self.env_dir.resolve()), where)
        command_version = subprocess.run([MESHLESS, "--version"], capture_output=True, text=True, check=True).stdout.split()[-1]
        self.assertEqual(version, command_version)
        self.assertGreater(int(count), 100)
        done = self.pip("uninstall", "-y", "meshless")
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        site = Path(self.in_venv("import sysconfig; print(sysconfig.get_path('platlib'))").stdout.strip())
        self.assertFalse((site / "meshless").exists(), list((site / "meshless").iterdir()) if (site / "meshless").exists() else None)

    def test_3_bad_settings_refused(self):
        done = self.pip("wheel", "--no-deps", "--config-settings", "jobs=many", "--config-settings",
                        f"build-dir={BUILD_DIR}", "-w", str(self.root / "never"), str(REPO / "python"))
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("jobs='many': expected a positive whole number", done.stdout + done.stderr)
        empty = self.root / "not-configured"
        empty.mkdir()
        (empty / "CMakeCache.txt").write_text("# not a build of meshless\n")
        done = self.pip("wheel", "--no-deps", "--config-settings", f"build-dir={empty}", "-w", str(self.root / "never"), str(REPO / "python"))
        self.assertNotEqual(done.returncode, 0)
        self.assertFalse((self.root / "never").exists() and any((self.root / "never").iterdir()))


if __name__ == "__main__":
    unittest.main()

"""The PEP 517 build backend of the Python module `meshless` (standard library only).

`pip install ./python` calls build_wheel(): it configures the repository's CMake project in a build
folder (unless that folder is configured already), builds the module's target `meshless_python`, and
writes a wheel of the package `meshless` (python/meshless/__init__.py and the compiled _core) for the
interpreter pip runs. No sdist is made (the module is built from a checkout; build_sdist raises
UnsupportedOperation, as PEP 517 provides).

Settings (pip's --config-settings / -C, or the environment):
    build-dir=DIR   (MESHLESS_BUILD_DIR)   the CMake build folder; relative to the repository's root.
                                          Default: build-python. A folder configured already (such as
                                          build/, made by scripts/setup.sh) is built, not configured.
    jobs=N          (MESHLESS_BUILD_JOBS)  parallel compile jobs (default: every core).
    cmake-args=ARGS (MESHLESS_CMAKE_ARGS)  more arguments for the first configuration (split like a shell).
Errors raise BuildError with one line naming what is missing.
"""

import base64
import hashlib
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from pathlib import Path

_PYTHON_DIR = Path(__file__).resolve().parent.parent  # python/
_REPO = _PYTHON_DIR.parent


class BuildError(RuntimeError):
    """The wheel cannot be built: the message says what is missing or wrong."""


class UnsupportedOperation(Exception):
    """PEP 517's way to say that this backend makes no source distributions."""


def _setting(config_settings, key, env):
    value = (config_settings or {}).get(key)
    if isinstance(value, list):  # pip passes a repeated -C key as a list: the last one wins
        value = value[-1] if value else None
    return value if value is not None else os.environ.get(env)


def _project():
    with open(_PYTHON_DIR / "pyproject.toml", "rb") as f:
        project = tomllib.load(f)["project"]
    text = (_REPO / "CMakeLists.txt").read_text(encoding="utf-8")
    found = re.search(r"project\(\s*meshless\s+VERSION\s+([0-9][0-9.]*)", text)
    if not found:
        raise BuildError(f"{_REPO / 'CMakeLists.txt'}: no 'project(meshless VERSION x.y.z)' line to take the version from")
    return project, found.group(1)


def _dist_name(project, version):
    return f"{re.sub(r'[-_.]+', '_', project['name']).lower()}-{version}"


def _wheel_tag():
    interpreter = f"{sys.implementation.name[:2]}{sys.version_info.major}{sys.version_info.minor}"
    if sys.implementation.name == "cpython":
        interpreter = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = re.sub(r"[-.]", "_", sysconfig.get_platform())
    return f"{interpreter}-{interpreter}-{platform}"


def _metadata(project, version):
    lines = ["Metadata-Version: 2.1", f"Name: {project['name']}", f"Version: {version}",
             f"Summary: {project.get('description', '')}"]
    if "requires-python" in project:
        lines.append(f"Requires-Python: {project['requires-python']}")
    lines += [f"Requires-Dist: {dependency}" for dependency in project.get("dependencies", [])]
    readme = _PYTHON_DIR / "README.md"
    if readme.exists():
        lines += ["Description-Content-Type: text/markdown", "", readme.read_text(encoding="utf-8")]
    return "\n".join(lines) + "\n"


def _run(command, what):
    print("meshless_build: " + " ".join(shlex.quote(str(part)) for part in command), file=sys.stderr, flush=True)
    try:
        subprocess.run([str(part) for part in command], check=True, cwd=_REPO)
    except FileNotFoundError:
        raise BuildError(f"{what}: '{command[0]}' was not found (install cmake and a C++ compiler: scripts/setup.sh build)") from None
    except subprocess.CalledProcessError as error:
        raise BuildError(f"{what} failed with exit status {error.returncode} (its output is above)") from None


def _build_module(config_settings):
    build_dir = Path(_setting(config_settings, "build-dir", "MESHLESS_BUILD_DIR") or "build-python")
    if not build_dir.is_absolute():
        build_dir = _REPO / build_dir
    jobs = _setting(config_settings, "jobs", "MESHLESS_BUILD_JOBS") or str(os.cpu_count() or 1)
    if not re.fullmatch(r"[1-9][0-9]*", jobs):
        raise BuildError(f"jobs={jobs!r}: expected a positive whole number")
    if not (build_dir / "CMakeCache.txt").exists():
        command = ["cmake", "-S", _REPO, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DMESHLESS_BUILD_TESTS=OFF",
                   "-DMESHLESS_BUILD_BENCH=OFF", f"-DPython_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja"):
            command += ["-G", "Ninja"]
        command += shlex.split(_setting(config_settings, "cmake-args", "MESHLESS_CMAKE_ARGS") or "")
        _run(command, "configuring the CMake project")
    _run(["cmake", "--build", build_dir, "--target", "meshless_python", "--parallel", jobs], "building the module")
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    module = build_dir / "python" / "meshless" / f"_core{suffix}"
    if not module.exists():
        made = sorted(p.name for p in (build_dir / "python" / "meshless").glob("_core*"))
        raise BuildError(f"{build_dir}: no {module.name} for this Python ({sys.executable}); the folder holds "
                         f"{', '.join(made) or 'no module'}: give another build-dir for this interpreter")
    return module


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    project, version = _project()
    module = _build_module(config_settings)
    dist = _dist_name(project, version)
    tag = _wheel_tag()
    files = [(f"meshless/{p.name}", p.read_bytes()) for p in sorted((_PYTHON_DIR / "meshless").glob("*.py"))]
    files.append((f"meshless/{module.name}", module.read_bytes()))
    info = f"{dist}.dist-info"
    files.append((f"{info}/METADATA", _metadata(project, version).encode()))
    files.append((f"{info}/WHEEL", _wheel_file().encode()))
    files.append((f"{info}/top_level.txt", b"meshless\n"))
    record = "\n".join([_record_line(name, data) for name, data in files] + [f"{info}/RECORD,,"]) + "\n"
    files.append((f"{info}/RECORD", record.encode()))
    wheel_name = f"{dist}-{tag}.whl"
    target = Path(wheel_directory) / wheel_name
    partial = target.with_name(target.name + ".part")
    try:
        with zipfile.ZipFile(partial, "w", compression=zipfile.ZIP_DEFLATED) as wheel:
            for name, data in files:
                entry = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
                entry.external_attr = (0o755 if name.endswith(".so") else 0o644) << 16
                entry.compress_type = zipfile.ZIP_DEFLATED
                wheel.writestr(entry, data)
        os.replace(partial, target)
    finally:
        partial.unlink(missing_ok=True)
    return wheel_name


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    """The wheel's METADATA and WHEEL without building it (pip asks for them first)."""
    project, version = _project()
    info = Path(metadata_directory) / f"{_dist_name(project, version)}.dist-info"
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata(project, version), encoding="utf-8")
    (info / "WHEEL").write_text(_wheel_file(), encoding="utf-8")
    return info.name


def _wheel_file():
    return f"Wheel-Version: 1.0\nGenerator: meshless_build\nRoot-Is-Purelib: false\nTag: {_wheel_tag()}\n"


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def build_sdist(sdist_directory, config_settings=None):
    raise UnsupportedOperation("meshless makes no source distribution: build the wheel from a checkout (pip install ./python)")

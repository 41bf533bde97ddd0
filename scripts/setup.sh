#!/usr/bin/env bash
# meshless set-up on a fresh Debian 12 machine: installs the Debian packages the project needs,
# builds in Release what the task needs, then runs it.
#   scripts/setup.sh demo    install + build the `meshless` executable only + `meshless demo -o out/demo`
#                            (without the DICOM and HDF5 readers: GDCM and libhdf5 are neither installed nor linked)
#   scripts/setup.sh test    install + build everything, tests and meshless-bench included + ctest,
#                            then the sanitizer tier (what `sanitize` does)
#   scripts/setup.sh sanitize  install + build meshless, the tests and the libFuzzer targets with
#                            Clang and -fsanitize=address,undefined (+ fuzzer-no-link) in $BUILD_DIR-asan
#                            (no meshless-bench) + ctest there + every fuzzer FUZZ_SECONDS seconds;
#                            without clang++-14: GCC, the tests only (no fuzzing)
#   scripts/setup.sh bench   install (+ VTK and SciPy, the baselines) + build meshless and meshless-bench
#   scripts/setup.sh deps    install only;   scripts/setup.sh build   install + build meshless and the tests
# build and test also build the Python module `meshless` (python/) and install it for Debian's python3
# (cmake --install BUILD_DIR --component python: /usr/local/lib/python3.X/dist-packages/meshless).
# Environment: BUILD_DIR (default build), JOBS (default nproc), SKIP_APT=1 to skip apt-get,
# SKIP_SANITIZE=1 to leave the sanitizer tier out of `test`, FUZZ_SECONDS (default 5; 0: no fuzzing)
# per libFuzzer target in the sanitizer tier. ccache is used when installed.
set -euo pipefail
cd "$(dirname "$0")/.."
what="${1:-demo}"
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"

PACKAGES=(build-essential cmake ninja-build pkg-config git
          libeigen3-dev libnanoflann-dev libboost-iostreams-dev libzstd-dev libcgal-dev
          catch2 libtbb-dev libpng-dev zlib1g-dev libcli11-dev libdeflate-dev
          libpugixml-dev libsimdjson-dev libblosc-dev
          libopenmpi-dev openmpi-bin)
# the benchmarks' baselines (bench/flying_edges.py, bench/rbf_reference.py) and /usr/bin/time
BENCH_PACKAGES=(python3-vtk9 python3-scipy time)
# the Python module (build, test): pybind11 and Debian's python3 with its headers and NumPy; VTK's
# Python modules for its to_vtk/from_vtk (their tests and the README's example run them); zarr-python,
# the Zarr reader's second writer in tests/cli/test_zarr_cli.cpp (skipped without it); pip and venv
# for `pip install ./python` (tests/python/test_pip_install.py)
PYTHON_PACKAGES=(pybind11-dev python3-dev python3-numpy python3-pytest python3-vtk9 python3-zarr python3-pip python3-venv)
# the sanitizer tier's compiler and its libFuzzer runtime (test, sanitize)
SANITIZE_PACKAGES=(clang-14 libclang-rt-14-dev)
# the DICOM reader (GDCM), the DICOM test series' writer and JPEG converter (build, test, sanitize; not demo)
DICOM_PACKAGES=(libgdcm-dev python3-pydicom libgdcm-tools)
# the HDF5 reader (libhdf5) and the HDF5 fuzz seeds' writer (build, test, sanitize; not demo)
HDF5_PACKAGES=(libhdf5-dev python3-h5py)

install_deps() {
  [ "${SKIP_APT:-0}" = 1 ] && return 0
  local missing=()
  for p in "${PACKAGES[@]}" "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

LAUNCHER=()
command -v ccache >/dev/null 2>&1 && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

# configure TESTS BENCH [TARGET...]: configures with the tests and meshless-bench ON or OFF, then
# builds the given targets (all when none). EXTRA_CMAKE (an array) adds options; DIR, when set,
# is the build folder instead of BUILD_DIR.
build() {
  local tests="$1" bench="$2" dir="${DIR:-$BUILD_DIR}"
  shift 2
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${LAUNCHER[@]}" "${EXTRA_CMAKE[@]}" \
        -DMESHLESS_BUILD_TESTS="$tests" -DMESHLESS_BUILD_BENCH="$bench" >/dev/null
  if [ $# -eq 0 ]; then
    cmake --build "$dir" -j "$JOBS"
  else
    cmake --build "$dir" -j "$JOBS" --target "$@"
  fi
}
EXTRA_CMAKE=()

# Installs the module the build made where Debian's python3 finds it, and checks that it imports
# from another folder (the package is not there: only the installed one can answer).
install_python_module() {
  [ -f "$BUILD_DIR/python/meshless/__init__.py" ] || return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo cmake --install "$BUILD_DIR" --component python >/dev/null
  (cd / && /usr/bin/python3 -c "import meshless") || { echo "setup: the installed Python module does not import" >&2; return 1; }
  echo "setup: installed the Python module: /usr/bin/python3 -c 'import meshless' works from any folder" >&2
}

# The sanitizer tier: every target built with AddressSanitizer + UndefinedBehaviorSanitizer (any
# report fails its test; tests/CMakeLists.txt says what differs under it),
# in its own folder, without meshless-bench. With Clang and its libFuzzer runtime, the same build
# also carries libFuzzer's coverage instrumentation (-DMESHLESS_BUILD_FUZZ=ON) and links the fuzz
# targets (tests/fuzz/); after the suite, scripts/fuzz.sh runs each FUZZ_SECONDS seconds from its
# seed corpus, and any crash, leak, timeout or OOM fails the tier.
sanitize() {
  local DIR="$BUILD_DIR-asan" EXTRA_CMAKE=(-DMESHLESS_SANITIZE=address,undefined -DMESHLESS_WITH_DICOM=ON -DMESHLESS_WITH_HDF5=ON) fuzz=0
  local secs="${FUZZ_SECONDS:-5}" clang
  clang=$(command -v clang++-14 || true)
  if [ -n "$clang" ] && ls "$("$clang" --print-runtime-dir)"/libclang_rt.fuzzer-*.a >/dev/null 2>&1; then
    EXTRA_CMAKE+=(-DCMAKE_CXX_COMPILER="$clang" -DMESHLESS_BUILD_FUZZ=ON)
    fuzz=1
  else
    echo "setup: clang++-14 with its libFuzzer runtime (clang-14 libclang-rt-14-dev) not found: the sanitizer" >&2
    echo "       tier builds with $(command -v c++) and runs the tests only, without the fuzzers" >&2
    EXTRA_CMAKE+=(-DMESHLESS_BUILD_FUZZ=OFF)
  fi
  # a folder configured with another compiler: start it again (CMake cannot switch in place)
  if [ -f "$DIR/CMakeCache.txt" ]; then
    local was
    was=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$DIR/CMakeCache.txt")
    if { [ "$fuzz" = 1 ] && [ "$was" != "$clang" ]; } || { [ "$fuzz" = 0 ] && [[ "$was" == *clang* ]]; }; then
      rm -rf "$DIR/CMakeCache.txt" "$DIR/CMakeFiles"
    fi
  fi
  build ON OFF
  ctest --test-dir "$DIR" --output-on-failure -j "$JOBS"
  if [ "$fuzz" = 1 ] && [ "$secs" != 0 ]; then
    echo "setup: running every fuzzer for $secs s (scripts/fuzz.sh $secs $DIR)" >&2
    scripts/fuzz.sh "$secs" "$DIR"
  fi
}

case "$what" in
  deps) install_deps ;;
  build) install_deps "${PYTHON_PACKAGES[@]}" "${DICOM_PACKAGES[@]}" "${HDF5_PACKAGES[@]}"; EXTRA_CMAKE=(-DMESHLESS_WITH_DICOM=ON -DMESHLESS_WITH_HDF5=ON); build ON OFF; install_python_module ;;
  demo) install_deps; EXTRA_CMAKE=(-DMESHLESS_WITH_DICOM=OFF -DMESHLESS_WITH_HDF5=OFF); build OFF OFF meshless; "$BUILD_DIR/cli/meshless" demo -o out/demo ;;
  test)
    if [ "${SKIP_SANITIZE:-0}" = 1 ]; then install_deps "${PYTHON_PACKAGES[@]}" "${DICOM_PACKAGES[@]}" "${HDF5_PACKAGES[@]}"; else install_deps "${PYTHON_PACKAGES[@]}" "${DICOM_PACKAGES[@]}" "${HDF5_PACKAGES[@]}" "${SANITIZE_PACKAGES[@]}"; fi
    EXTRA_CMAKE=(-DMESHLESS_WITH_DICOM=ON -DMESHLESS_WITH_HDF5=ON); build ON ON; install_python_module; ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS"
    [ "${SKIP_SANITIZE:-0}" = 1 ] || sanitize ;;
  sanitize) install_deps "${SANITIZE_PACKAGES[@]}" "${DICOM_PACKAGES[@]}" "${HDF5_PACKAGES[@]}"; sanitize ;;
  bench)
    install_deps "${BENCH_PACKAGES[@]}"
    build OFF ON meshless meshless-bench
    echo "setup: built $BUILD_DIR/bench/meshless-bench; e.g. $BUILD_DIR/bench/meshless-bench process --markdown /tmp/process.md" >&2
    echo "       ($BUILD_DIR/bench/meshless-bench --help lists the sections; bench/README.md explains the rows)" >&2 ;;
  *) echo "usage: scripts/setup.sh demo|test|sanitize|bench|deps|build" >&2; exit 1 ;;
esac

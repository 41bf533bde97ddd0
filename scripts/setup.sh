#!/usr/bin/env bash
# meshless set-up on a fresh Debian 12 machine: installs the Debian packages the project needs,
# builds in Release, then runs the demo or the test suite.
#   scripts/setup.sh demo    install + build + `meshless demo -o out/demo`
#   scripts/setup.sh test    install + build + the whole test suite (ctest)
#   scripts/setup.sh deps    install only;   scripts/setup.sh build   install + build only
# Environment: BUILD_DIR (default build), JOBS (default nproc), SKIP_APT=1 to skip apt-get.
set -euo pipefail
cd "$(dirname "$0")/.."
what="${1:-demo}"
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"

PACKAGES=(build-essential cmake ninja-build pkg-config git
          libeigen3-dev libnanoflann-dev libboost-iostreams-dev libzstd-dev libcgal-dev
          catch2 libtbb-dev libpng-dev zlib1g-dev
          libopenmpi-dev openmpi-bin)

install_deps() {
  [ "${SKIP_APT:-0}" = 1 ] && return 0
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

build() {
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$BUILD_DIR" -j "$JOBS"
}

case "$what" in
  deps) install_deps ;;
  build) install_deps; build ;;
  demo) install_deps; build; "$BUILD_DIR/cli/meshless" demo -o out/demo ;;
  test) install_deps; build; ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" ;;
  *) echo "usage: scripts/setup.sh demo|test|deps|build" >&2; exit 1 ;;
esac

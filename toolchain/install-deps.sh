#!/usr/bin/env bash
# Installs the build and runtime dependencies from Debian bookworm's packages.
# Idempotent: packages already present are left as they are and apt is not asked twice.
# Usage (as root): toolchain/install-deps.sh [--rtlib-only] [--cross] [--fuzz] [--format]
#   --rtlib-only  only what rtlib and its tests need (no station libraries)
#   --cross       add the aarch64 cross compiler and qemu user emulation (preset aarch64)
#   --fuzz        add clang with libFuzzer and the sanitizer runtimes (toolchain/fuzz, the asan-ubsan preset)
#   --format      add clang-format 14, the version whose layout .clang-format fixes (toolchain/format)
set -euo pipefail

core_packages=(
  build-essential cmake ninja-build ccache git ca-certificates pkg-config
  libeigen3-dev libspectra-dev libgtest-dev libgmock-dev libbenchmark-dev
)
station_packages=(
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools
  libopencv-core-dev libopencv-imgproc-dev libopencv-videoio-dev
  libapriltag-dev liburdfdom-dev
  libyaml-cpp-dev libsuitesparse-dev zlib1g-dev
  libopenblas0-serial  # the BLAS of CHOLMOD's supernodal factors (SparseCholesky, docs/tissue.md)
  nlohmann-json3-dev  # navbench's JSON
  libopenigtlink-dev  # OpenIGTLink: the bridge to PlusServer and 3D Slicer
  libx11-dev iproute2
  openssl  # navtool security init makes its test CA and identities with the openssl program
  python3-vtk9  # VTK's own readers check the files navtool export and solve write
  xvfb  # a virtual X server: navview's window is tested in it
)
cross_packages=(g++-aarch64-linux-gnu qemu-user)
fuzz_packages=(clang-14 libclang-rt-14-dev)
format_packages=(clang-format-14)

packages=("${core_packages[@]}")
with_station=1
for option in "$@"; do
  case "$option" in
    --rtlib-only) with_station=0 ;;
    --cross) packages+=("${cross_packages[@]}") ;;
    --fuzz) packages+=("${fuzz_packages[@]}") ;;
    --format) packages+=("${format_packages[@]}") ;;
    *) echo "install-deps: unknown option '$option' (--rtlib-only, --cross, --fuzz, --format)" >&2; exit 2 ;;
  esac
done
if [[ $with_station -eq 1 ]]; then
  packages+=("${station_packages[@]}")
fi

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "install-deps: missing packages (${missing[*]}); run as root to install them" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# crackflow set-up on Debian 12: installs the missing packages, builds, and then either runs
# the default pipeline (./setup.sh demo) or the whole test suite (./setup.sh test).
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(cmake ninja-build g++ pkg-config binutils  # binutils: nm/objdump for Build.NoFmaInExactAvx512Clones
          libeigen3-dev libopenvdb-dev libboost-iostreams-dev libtbb-dev libyaml-cpp-dev libcli11-dev libjemalloc-dev
          libcgal-dev libcgal-demo libgmp-dev libmpfr-dev libbullet-dev libpng-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          libtinygltf-dev python3-vtk9 python3-openvdb
          slurmctld slurmd slurm-client munge)  # the Slurm batch test: a one-node cluster on loopback

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "setup: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# The animation tests' glTF validator runs on node; the build installs it with npm (tests/tools).
# Any node + npm will do (e.g. NodeSource's nodejs, which bundles npm); else Debian's.
ensure_npm() {
  command -v npm >/dev/null 2>&1 && return 0
  echo "setup: installing nodejs npm"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm
}

configure() {
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
}

case "${1:-}" in
  demo)
    install_missing
    configure
    cmake --build build --target crackflow -j"$(nproc)"
    ./build/runtime/crackflow run pipelines/default.yaml --out out/default
    ;;
  test)
    install_missing
    ensure_npm
    configure
    cmake --build build -j"$(nproc)"
    ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900
    ;;
  *)
    echo "usage: ./setup.sh demo   # install, build, run pipelines/default.yaml (outputs in out/default)"
    echo "       ./setup.sh test   # install, build, run the whole test suite"
    exit 2
    ;;
esac

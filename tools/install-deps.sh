#!/usr/bin/env bash
# Installs what sdfbrick needs on Debian 12, skipping what is already there (idempotent).
# Run as root (or with sudo available). Everything comes from Debian's own packages.
set -euo pipefail

packages=(
  cmake g++ make pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers
  libglm-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libopenimageio-dev
  libassimp-dev
  libopenvdb-dev libnanovdb-dev libboost-iostreams-dev  # OpenVDB's CMake module asks for Boost.Iostreams
  libgtest-dev libbenchmark-dev
  libsodium-dev
  clang-14 libfuzzer-14-dev
  python3-matplotlib python3-numpy
  pybind11-dev python3-pybind11 python3-pytest  # the Python module (host/python/) and its tests
  slurm-wlm munge
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=()
[ "$(id -u)" -eq 0 ] || sudo=(sudo)
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"

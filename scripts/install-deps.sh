#!/usr/bin/env bash
# Installs every Debian package shellflow needs to build, test, run and plot.
# Idempotent and non-interactive: packages already installed are skipped, and
# nothing is asked. Needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libgmsh-dev gmsh
  libyaml-cpp-dev libcli11-dev libfmt-dev libspdlog-dev libnanoflann-dev
  libomp-dev libgtest-dev libgmock-dev libbenchmark-dev libsuitesparse-dev
  # serial METIS 5.1: partitions of the fluid mesh (mesh/partition.h)
  libmetis-dev
  # OpenMPI 4.1: the ranks of distributed runs (src/shellflow/mpi, CTest label mpi)
  libopenmpi-dev openmpi-bin
  python3 python3-matplotlib python3-numpy python3-meshio
  # the fuzz preset (tests/fuzz): clang with libFuzzer and the sanitizer runtimes
  clang-14 libclang-rt-14-dev
  # the format check of CI (scripts/check-format.sh)
  clang-format-14
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"

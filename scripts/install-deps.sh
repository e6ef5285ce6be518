#!/usr/bin/env bash
# Installs the build and run dependencies from Debian 12 packages (ParaView's own VTK, CGAL, HDF5, ...).
# OpenMPI: the MPI domain decomposition (docs/parallel.md; a build without it stays serial).
# Do not add libvtk9-dev: it pulls python3-vtk9, which conflicts with python3-paraview (pvpython).
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PACKAGES=(build-essential cmake ninja-build git
          paraview paraview-dev python3-paraview python3-matplotlib xvfb
          libcgal-dev libhdf5-dev libeigen3-dev libgtest-dev libbenchmark-dev
          libcli11-dev nlohmann-json3-dev libtbb-dev
          libopenmpi-dev openmpi-bin)
# sanitizer + libFuzzer stage (scripts/fuzz_smoke.sh): clang and its runtimes, without the recommended
# llvm-14-dev (saves ~150 MB of downloads)
LEAN_PACKAGES=(clang-14 libclang-rt-14-dev)
missing=()
lean=()
for p in "${LEAN_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || lean+=("$p")
done
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ] && [ ${#lean[@]} -eq 0 ]; then
  echo "install-deps: all $(( ${#PACKAGES[@]} + ${#LEAN_PACKAGES[@]} )) packages present"
else
  echo "install-deps: installing ${missing[*]} ${lean[*]}"
  $SUDO apt-get update -qq
  [ ${#missing[@]} -eq 0 ] || $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
  [ ${#lean[@]} -eq 0 ] || $SUDO apt-get install -y -qq --no-install-recommends "${lean[@]}" >/dev/null
  echo "install-deps: done"
fi
# ParaView 5.11 cannot load Python plugins on Python 3.11 without this start-up fix (paraview/README.md);
# installed with ParaView's own Python into its site directory
if ! $SUDO pvpython "$(dirname "$0")/../paraview/install_compat.py"; then
  echo "install-deps: WARNING: the ParaView plugin fix was not installed; see paraview/README.md" >&2
fi

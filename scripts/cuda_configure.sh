#!/usr/bin/env bash
# Configures the CUDA build the GPU machine runs (docs/gpu.md): Release, double, -DVARSPH_CUDA=ON, without VTK
# and CGAL (that machine has neither), Ninja, ccache where installed. Usage: cuda_configure.sh DIR [-DKEY=VALUE...]
# Prints the nvcc it uses; exits 3 (and configures nothing) when there is no nvcc.
set -euo pipefail
cd "$(dirname "$0")/.."
dir="$1"
shift
nvcc="$(command -v nvcc || true)"
if [ -z "$nvcc" ] && [ -x /usr/local/cuda/bin/nvcc ]; then nvcc=/usr/local/cuda/bin/nvcc; fi
if [ -z "$nvcc" ]; then
  echo "no nvcc on PATH or at /usr/local/cuda/bin/nvcc"
  exit 3
fi
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache
                                           -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_COMPILER="$nvcc" -DVARSPH_CUDA=ON \
      -DVARSPH_VTK=OFF -DVARSPH_CGAL=OFF "${launcher[@]}" "$@" >/dev/null
echo "$nvcc"

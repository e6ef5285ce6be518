#!/usr/bin/env bash
# Compiles the CUDA backend's device translation units (src/exec/cuda/*.cu) with nvcc, without a GPU and
# without running anything, so that a merge that breaks device code fails CI (issue 34; docs/gpu.md
# "The device code in CI"). Only the .cu objects are built: the C++ half of the CUDA build is code that CI's
# release build compiles already. Without nvcc the stage says so and passes.
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${VARSPH_CUDA_BUILD_DIR:-build/cuda}"
rc=0
nvcc="$(bash scripts/cuda_configure.sh "$dir")" || rc=$?
if [ "$rc" -eq 3 ]; then
  echo "cuda-compile-check: SKIPPED: $nvcc (the device code was not compiled)"
  exit 0
elif [ "$rc" -ne 0 ]; then
  exit "$rc"
fi
mapfile -t objects < <(ninja -C "$dir" -t targets all | grep -o '^[^:]*\.cu\.o' | sort -u)
if [ ${#objects[@]} -eq 0 ]; then
  echo "cuda-compile-check: FAILED: the CUDA build in $dir lists no .cu object" >&2
  exit 1
fi
start=$SECONDS
ninja -C "$dir" "${objects[@]}"
echo "cuda-compile-check: ${#objects[@]} device translation unit(s) compiled by $nvcc" \
     "($("$nvcc" --version | tail -1)) in $(( SECONDS - start )) s"

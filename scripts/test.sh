#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the fast test tier (what CI runs).
# Slower tiers: ctest --preset validation / ctest --preset benchmark (see README).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
bash scripts/cuda_compile_check.sh   # the CUDA backend's .cu through nvcc, nothing run (docs/gpu.md; passes without nvcc)
bash scripts/fuzz_smoke.sh   # ASan+UBSan libFuzzer harnesses: regressions, seeds, a few seconds each (docs/reliability.md)
ctest --preset fast -j"$(nproc)" --output-on-failure

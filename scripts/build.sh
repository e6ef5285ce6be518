#!/usr/bin/env bash
# Configures and builds the Release (double precision, portable) preset into build/release.
#   bash scripts/build.sh              everything: the solver, ~200 test and benchmark programs (scripts/test.sh, CI)
#   bash scripts/build.sh varsph       only the named targets (scripts/quickstart.sh: the command alone)
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# ccache, where installed, makes rebuilds after a merge cheap (CI has none and builds plainly)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake --preset release "${generator[@]}" "${launcher[@]}" >/dev/null
targets=()
[ $# -eq 0 ] || targets=(--target "$@")
cmake --build --preset release -j"$(nproc)" "${targets[@]}"

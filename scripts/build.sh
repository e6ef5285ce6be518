#!/usr/bin/env bash
# Configures and builds the Release (double precision, portable) preset into build/release.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake --preset release "${generator[@]}" >/dev/null
cmake --build --preset release -j"$(nproc)"

#!/usr/bin/env bash
# Builds here what the device check runs and packs it into one folder that runs on the GPU machine without
# building (issue 34; docs/gpu.md "The device check"). The GPU machine has CUDA, CMake and ninja but maybe none
# of varsph's libraries and no package registry, and its lease is 15 minutes: nothing is built there.
#   bash scripts/device_bundle.sh [BUNDLE_DIR]      (default bundle/, git-ignored)
# 1. builds varsph, bench_gpu, bench_step and test_gpu_vs_cpu with nvcc, without VTK and CGAL, the solver core as
#    one shared library (build/bundle, scripts/cuda_configure.sh); MPI is compiled in when found (varsph calls
#    MPI_Init only under mpirun);
# 2. copies them, stripped, with every shared library they load except the C/C++ runtime (glibc's libraries,
#    libstdc++, libgcc_s: the GPU machine's Ubuntu 24.04 has newer ones, which run what Debian 12 built) and the
#    NVIDIA driver (libcuda), the scenes they read, bench/parallel/scaling.py and device_check.sh;
# 3. proves that the programs start with only the bundle on LD_LIBRARY_PATH: every library resolves inside it
#    or to the runtime, `varsph --version`, a CPU run of a short scene, and `--device cuda` refused cleanly
#    where no GPU is present; and that the folder stays within 50 MiB.
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$(pwd)"
bundle="${1:-bundle}"
dir="${VARSPH_BUNDLE_BUILD_DIR:-build/bundle}"
max_mib=50
say() { echo "device_bundle: $*"; }

rc=0
# varsph_core as one shared library: four programs with a static core each would be 43 MB of the 50 MiB
nvcc="$(bash scripts/cuda_configure.sh "$dir" -DVARSPH_SHARED_CORE=ON)" || rc=$?
if [ "$rc" -ne 0 ]; then
  say "cannot configure the CUDA build ($nvcc)" >&2
  exit 1
fi
programs=(varsph bench_gpu bench_step test_gpu_vs_cpu)
ninja -C "$dir" "${programs[@]}"

rm -rf "$bundle"
mkdir -p "$bundle/bin" "$bundle/lib" "$bundle/lib-mpi" "$bundle/pipelines/validation" "$bundle/bench/parallel"
bundle="$(cd "$bundle" && pwd)"
for p in "${programs[@]}"; do
  exe="$(find "$dir" -name "$p" -type f -perm -u+x -not -path '*/CMakeFiles/*' | head -1)"
  [ -n "$exe" ] || { say "built no $p in $dir" >&2; exit 1; }
  cp "$exe" "$bundle/bin/$p"
  strip --strip-unneeded "$bundle/bin/$p"
done

# The C/C++ runtime stays the machine's own: glibc's libraries must match its ld-linux (a Debian 12 libresolv
# on Ubuntu 24.04's glibc would fail on GLIBC_PRIVATE symbols), and libstdc++ / libgcc_s are backward compatible.
mpi_libs='^(libmpi|libmpi_cxx|libopen-rte|libopen-pal)\.so'
runtime='^(ld-linux.*|libc|libm|libmvec|libpthread|libdl|librt|libresolv|libanl|libutil|libnsl|libnss_.*|libstdc\+\+|libgcc_s|libcuda)\.so'
for p in "${programs[@]}"; do
  ldd "$bundle/bin/$p" | awk '/not found/ {print "MISSING " $1} /=> \// {print $3}'
done | sort -u | while read -r lib rest; do
  if [ "$lib" = MISSING ]; then say "a library of the programs is not found here: $rest" >&2; exit 1; fi
  name="$(basename "$lib")"
  if [[ "$name" =~ $runtime ]]; then continue; fi
  # Open MPI's own libraries apart: device_check.sh uses them only where the machine has no Open MPI 4 of its
  # own (its mpirun loads its own plugins, which must match its libmpi)
  if [[ "$name" =~ $mpi_libs ]]; then cp -L "$lib" "$bundle/lib-mpi/$name"; else cp -L "$lib" "$bundle/lib/$name"; fi
done

strip --strip-unneeded "$bundle"/lib/libvarsph_core.so*  # ours; Debian's libraries come stripped

# the scenes the check's programs read (bench_gpu, bench_step, test_gpu_vs_cpu, scaling.py): none reads a mesh
# (bench_gpu --engineering takes only engineering_3d's method blocks)
for s in dam_break_2d_paper dam_break_3d_dsph bench_box_3d poiseuille_2d hydrostatic_2d_adami \
         dam_break_2d_dsph_val validation/taylor_green_dx0.02 engineering_2d engineering_3d; do
  cp "pipelines/$s.json" "$bundle/pipelines/$s.json"
done
cp bench/parallel/scaling.py "$bundle/bench/parallel/"
cp scripts/device_check.sh "$bundle/"
{
  echo "varsph device bundle: $(git -C "$repo" rev-parse --short HEAD)$(git -C "$repo" diff --quiet HEAD -- src bench tests scripts || echo ' (with uncommitted changes)'), built $(date -u +%FT%TZ) on $(uname -srm)"
  echo "compiler: $(c++ --version | head -1); nvcc: $("$nvcc" --version | tail -1)"
  echo "cmake: -DCMAKE_BUILD_TYPE=Release -DVARSPH_CUDA=ON -DVARSPH_VTK=OFF -DVARSPH_CGAL=OFF, nvcc $(grep -o -m1 -- '--generate-code=[^ ]*' "$dir/build.ninja" | head -1), shared core, MPI $(grep -q -a MPI_Init_thread "$bundle"/lib/libvarsph_core.so* && echo compiled in || echo absent)"
  echo "programs: ${programs[*]}; libraries: $(ls "$bundle/lib" "$bundle/lib-mpi" | tr '\n' ' ')"
} > "$bundle/MANIFEST.txt"

# --- the proof: only the bundle on LD_LIBRARY_PATH ----------------------------------------------------------
export LD_LIBRARY_PATH="$bundle/lib:$bundle/lib-mpi"
for p in "${programs[@]}"; do
  ldd "$bundle/bin/$p" | awk '/=> \// {print $3} /not found/ {print "NOT-FOUND:" $1}' | while read -r lib; do
    name="$(basename "$lib")"
    if [[ "$lib" == NOT-FOUND:* ]]; then say "$p: ${lib#NOT-FOUND:} not found with only the bundle" >&2; exit 1; fi
    if [[ "$lib" != "$bundle/lib/"* ]] && [[ "$lib" != "$bundle/lib-mpi/"* ]] && ! [[ "$name" =~ $runtime ]]; then
      say "$p loads $lib from outside the bundle" >&2
      exit 1
    fi
  done
done
say "every library of ${programs[*]} resolves to $bundle/lib or to the C/C++ runtime"
"$bundle/bin/varsph" --version
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
"$bundle/bin/varsph" run "$bundle/pipelines/dam_break_2d_paper.json" -o "$scratch/cpu" --quiet \
  --set time.end=0.002 --set output.every=0.001 --threads 2
say "CPU run of the paper dam break to t = 0.002 s: exit 0, $(ls "$scratch/cpu" | wc -l) entries in its run directory"
VARSPH_SOURCE_DIR="$bundle" "$bundle/bin/bench_step" --case dam_break_2d_paper_1682 --steps 5 --threads 1 | tail -1
set +e
why="$("$bundle/bin/varsph" run "$bundle/pipelines/dam_break_2d_paper.json" -o "$scratch/gpu" --device cuda \
      --set time.end=0.002 2>&1)"
rc=$?
set -e
if command -v nvidia-smi >/dev/null && nvidia-smi >/dev/null 2>&1; then
  say "--device cuda on this machine's GPU: exit $rc"
elif [ "$rc" -eq 2 ]; then
  say "--device cuda without a GPU: refused, exit 2: $(echo "$why" | tail -1)"
else
  say "--device cuda without a GPU gave exit $rc, not 2: $why" >&2
  exit 1
fi
size=$(du -sb "$bundle" | cut -f1)
say "$bundle: $(( size / 1048576 )) MiB ($size bytes; limit $max_mib MiB), $(ls "$bundle/lib" "$bundle/lib-mpi" | grep -c '\.so') libraries"
if [ "$size" -gt $(( max_mib * 1048576 )) ]; then
  say "the bundle is larger than $max_mib MiB" >&2
  exit 1
fi

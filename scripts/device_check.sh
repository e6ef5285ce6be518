#!/usr/bin/env bash
# The one command a session with a GPU runs (issue 34; docs/gpu.md "The device check"). From the repository
# root of the device tool's copy, with the bundle carried (scripts/device_bundle.sh builds it):
#   bash bundle/device_check.sh                    every stage, at most 8 minutes on the 16-core H100 machine
#   bash scripts/device_check.sh --cpu-only        the CPU stages at small sizes, on any machine (the fast test)
# Options: --out DIR (default $OUT, the device tool's output folder), --bin DIR (the programs: the bundle's bin/
# next to this script, else build/release/bin), --budget S (wall seconds for all stages together).
# Writes at most 8 files into the output folder, one per stage and summary.txt (a table of every stage's status,
# seconds and figures). Every stage runs under its own `timeout`, clipped to what is left of the budget, so a
# hang or a crash loses that stage and never the rest; the script exits 0 when it wrote the summary, whatever
# the stages did (the summary says what failed).
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cpu_only=0
out="${OUT:-}"
bin=""
budget=""
while [ $# -gt 0 ]; do
  case "$1" in
    --cpu-only) cpu_only=1 ;;
    --out) out="$2"; shift ;;
    --bin) bin="$2"; shift ;;
    --budget) budget="$2"; shift ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "device_check: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done
if [ -z "$out" ]; then
  echo "device_check: no output folder: set OUT or pass --out DIR" >&2
  exit 2
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"
# Inside the bundle: bin/, lib/ and the scenes sit next to this script. In the source tree: build/release.
if [ -d "$here/bin" ]; then
  root="$here"
  [ -n "$bin" ] || bin="$here/bin"
  libs="$here/lib"
  # the bundle's Open MPI libraries only where the machine has no Open MPI 4 (libmpi.so.40) of its own: a
  # machine's mpirun loads its own plugins, which must match the libmpi the ranks load
  if ! ldconfig -p 2>/dev/null | grep -q 'libmpi\.so\.40 '; then libs="$libs:$here/lib-mpi"; fi
  export LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
else
  root="$(cd "$here/.." && pwd)"
  [ -n "$bin" ] || bin="$root/build/release/bin"
fi
bin="$(cd "$bin" && pwd)"
export VARSPH_SOURCE_DIR="$root"  # the programs read their scenes here (src/core/source_dir.hpp)
cores="$(nproc)"
if [ -z "$budget" ]; then
  if [ "$cpu_only" -eq 1 ]; then budget=240; else budget=465; fi  # 465 s + the summary: under 8 minutes
fi
start=$SECONDS
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# --- the stage runner: stage NAME FILE LIMIT_S CMD... appends CMD's output to FILE and records the outcome ---
names=() states=() secs=() files=()
record() {  # record NAME STATE SECONDS FILE
  names+=("$1"); states+=("$2"); secs+=("$3"); files+=("$4")
}
stage() {
  local name="$1" file="$2" limit="$3"
  shift 3
  local left=$(( budget - (SECONDS - start) ))
  if [ "$left" -lt 5 ]; then
    echo "### $name: not run, the check's budget of $budget s is spent" >> "$out/$file"
    record "$name" "NOT RUN (budget spent)" 0 "$file"
    return
  fi
  [ "$limit" -le "$left" ] || limit="$left"
  echo "### $name ($(date -u +%FT%TZ), limit ${limit} s): $*" >> "$out/$file"
  local t0=$SECONDS rc=0
  timeout -k 5 "$limit" "$@" >> "$out/$file" 2>&1 || rc=$?
  local state="ok"
  if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then state="TIMEOUT after ${limit} s"
  elif [ "$rc" -eq 77 ]; then state="skipped (no device)"
  elif [ "$rc" -ne 0 ]; then state="FAILED (exit $rc)"
  fi
  echo "### $name: $state in $(( SECONDS - t0 )) s" >> "$out/$file"
  record "$name" "$state" $(( SECONDS - t0 )) "$file"
}
skip() {  # skip NAME FILE REASON
  echo "### $1: skipped: $3" >> "$out/$2"
  record "$1" "skipped: $3" 0 "$2"
}
have() { [ -x "$bin/$1" ]; }

# --- 1. the machine: device, driver, CPU, the bundle --------------------------------------------------------
machine() {
  echo "date: $(date -u +%FT%TZ); host: $(uname -srm); cores: $cores; load: $(cut -d' ' -f1-3 /proc/loadavg)"
  grep -m1 "model name" /proc/cpuinfo
  echo "cpu flags: $(grep -m1 -o -w -E 'avx2|avx512f' /proc/cpuinfo | sort -u | tr '\n' ' ')"
  grep -E "MemTotal" /proc/meminfo
  [ -f "$root/MANIFEST.txt" ] && cat "$root/MANIFEST.txt"
  "$bin/varsph" --version
  if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=name,driver_version,memory.total,compute_cap,clocks.max.sm --format=csv
    nvidia-smi
  else
    echo "no nvidia-smi"
  fi
  command -v mpirun >/dev/null && mpirun --version | head -1
  return 0
}
export -f machine  # `timeout` runs programs, not functions: a child bash runs it
export bin root cores
stage machine device.txt 20 bash -c machine

# --- 2. the device against the CPU: paper dam break, 3D dam break, periodic box (and the rest of the suite) ----
if [ "$cpu_only" -eq 1 ]; then
  skip gpu_vs_cpu gpu_vs_cpu.txt "--cpu-only"
elif ! have test_gpu_vs_cpu; then
  skip gpu_vs_cpu gpu_vs_cpu.txt "no test_gpu_vs_cpu in $bin"
else
  stage gpu_vs_cpu gpu_vs_cpu.txt 120 env OMP_NUM_THREADS="$cores" "$bin/test_gpu_vs_cpu"
fi

# --- 3. bench_gpu: DualSPHysics' 3D dam break at 171k, 1.4 M, 10.8 M particles; the paper case (10^4 steps);
# the engineering set-up on the same dam break -------------------------------------------------------------
if ! have bench_gpu; then
  skip bench_gpu bench_gpu.txt "no bench_gpu in $bin"
elif [ "$cpu_only" -eq 1 ]; then
  stage bench_gpu_cpu_tiny bench_gpu.txt 60 "$bin/bench_gpu" --device cpu --tiny --steps 2 --threads "$cores"
  stage bench_gpu_cpu_engineering bench_gpu.txt 60 "$bin/bench_gpu" --device cpu --engineering --dp 0.015 --steps 2 \
    --threads "$cores"
else
  stage bench_gpu_171k bench_gpu.txt 60 "$bin/bench_gpu" --device cuda --dp 0.0085 --steps 50
  stage bench_gpu_1.4M bench_gpu.txt 60 "$bin/bench_gpu" --device cuda --dp 0.004 --steps 50
  stage bench_gpu_10.8M bench_gpu.txt 120 "$bin/bench_gpu" --device cuda --dp 0.002 --steps 20
  stage bench_gpu_paper bench_gpu.txt 40 "$bin/bench_gpu" --device cuda --paper
  # the README's engineering set-up (Riemann, dummy walls, symplectic Euler) on the same dam break
  stage bench_gpu_engineering_1.4M bench_gpu.txt 60 "$bin/bench_gpu" --device cuda --engineering --dp 0.004 --steps 50
fi

# --- 4. bench_step: 1, 2, 4, 8, 16 threads; the pair sweeps (scalar, avx2, avx512) where the CPU has them ------
threads=""
for t in 1 2 4 8 16; do [ "$t" -le "$cores" ] && threads="$threads${threads:+,}$t"; done
case ",$threads," in *",$cores,"*) ;; *) [ "$cores" -lt 16 ] && threads="$threads,$cores" ;; esac
if ! have bench_step; then
  skip bench_step bench_step.txt "no bench_step in $bin"
elif [ "$cpu_only" -eq 1 ]; then
  stage bench_step_threads bench_step.txt 60 "$bin/bench_step" --case dam_break_2d_paper_1682 --steps 20 --threads "$threads"
else
  stage bench_step_2d_430k bench_step.txt 60 "$bin/bench_step" --case dam_break_2d_430k --steps 10 --threads "$threads"
  stage bench_step_3d_100k bench_step.txt 40 "$bin/bench_step" --case box_3d_100k --steps 10 --threads "$threads"
  for isa in scalar avx2 avx512; do
    if [ "$isa" = scalar ] || grep -q -w "${isa/avx512/avx512f}" /proc/cpuinfo; then
      stage "bench_step_sweep_$isa" bench_step.txt 30 env VARSPH_SIMD="$isa" "$bin/bench_step" \
        --case dam_break_2d_430k --steps 5 --threads "1,$cores"
    else
      skip "bench_step_sweep_$isa" bench_step.txt "this CPU has no $isa"
    fi
  done
fi

# --- 5. MPI strong (1-16 ranks) and weak (2.5e5 fluid particles per rank) scaling: bench/parallel/scaling.py ---
mpirun_exe="$(command -v mpirun || true)"
if [ -x "$root/mpi/bin/mpirun" ]; then  # an Open MPI carried in the bundle (scripts/device_bundle.sh)
  export OPAL_PREFIX="$root/mpi" PATH="$root/mpi/bin:$PATH"
  mpirun_exe="$root/mpi/bin/mpirun"
fi
ranks=""
for p in 1 2 4 8 16; do [ "$p" -le "$cores" ] && ranks="$ranks${ranks:+,}$p"; done
if [ "$cpu_only" -eq 1 ]; then ranks="1,2"; fi
mpi_why=""
mpi_compiled() {  # MPI's entry point in varsph or in the bundle's shared core
  local f
  for f in "$bin/varsph" "$root"/lib/libvarsph_core.so*; do
    [ -f "$f" ] && grep -q -a MPI_Init_thread "$f" && return 0
  done
  return 1
}
if ! have varsph || ! mpi_compiled; then mpi_why="this varsph was built without MPI"
elif [ -z "$mpirun_exe" ]; then mpi_why="no mpirun on PATH or in the bundle"
elif ! command -v python3 >/dev/null; then mpi_why="no python3 (bench/parallel/scaling.py)"
elif [ ! -f "$root/bench/parallel/scaling.py" ]; then mpi_why="no bench/parallel/scaling.py under $root"
fi
for mode in strong weak; do
  if [ -n "$mpi_why" ]; then
    skip "mpi_$mode" mpi_scaling.txt "$mpi_why"
    continue
  fi
  if [ "$cpu_only" -eq 1 ]; then
    size=(--steps 2 --strong-fluid 8000 --weak-fluid-per-rank 8000)
    bind=()
  else
    size=(--steps 5)  # setup and `varsph info` dominate a run; 5 steps of 0.1-1.8 s are timed
    bind=(--bind)
  fi
  stage "mpi_$mode" mpi_scaling.txt 120 python3 "$root/bench/parallel/scaling.py" --varsph "$bin/varsph" \
    --mode "$mode" --ranks "$ranks" --threads 1 "${bind[@]}" "${size[@]}" --scratch "$work/scaling" \
    --out "$work/mpi_$mode.csv"
  [ -f "$work/mpi_$mode.csv" ] && { echo "--- mpi_$mode.csv"; cat "$work/mpi_$mode.csv"; } >> "$out/mpi_scaling.txt"
done

# --- the summary: one row per stage, then the figures each stage printed ------------------------------------
{
  echo "# varsph device check, $(date -u +%FT%TZ), $([ "$cpu_only" -eq 1 ] && echo "--cpu-only" || echo "full"), $cores cores, $(( SECONDS - start )) s of a $budget s budget"
  printf "%-28s %-32s %6s  %s\n" stage status seconds file
  for k in "${!names[@]}"; do
    printf "%-28s %-32s %6s  %s\n" "${names[$k]}" "${states[$k]}" "${secs[$k]}" "${files[$k]}"
  done
  echo
  echo "## figures"
  if [ -f "$out/device.txt" ] && command -v nvidia-smi >/dev/null; then
    echo "device: $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1 | head -1)"
  fi
  # the measured differences per case, the counts, each failed test once
  [ -f "$out/gpu_vs_cpu.txt" ] && grep -h -E '^\[cuda\]|^\[  PASSED  \]|^\[  FAILED  \]|^\[  SKIPPED \] [0-9]' \
    "$out/gpu_vs_cpu.txt" | grep -v ' (.* ms)$' | awk '!seen[$0]++' 
  [ -f "$out/bench_gpu.txt" ] && grep -h -E '^device |^cuda |^cpu |^paper ' "$out/bench_gpu.txt" | awk '!/^device / || !seen++'
  [ -f "$out/bench_step.txt" ] && grep -h -E '^case |^(dam_break|box_3d)' "$out/bench_step.txt" | awk '!/^case / || !seen++'
  [ -f "$out/mpi_scaling.txt" ] && grep -h -E '^(mode|strong|weak) ' "$out/mpi_scaling.txt"
} > "$out/summary.txt"
cat "$out/summary.txt"
exit 0

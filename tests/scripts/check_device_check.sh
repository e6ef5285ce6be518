#!/usr/bin/env bash
# Runs scripts/device_check.sh --cpu-only on a build tree's programs and asserts what it wrote (the fast test
# device_check_cpu_only; docs/gpu.md "The device check").
#   check_device_check.sh DEVICE_CHECK_SH BIN_DIR SCRATCH_DIR
# 1. the real programs: at most 8 files, the summary's row for every stage with its status, and the figures
#    (bench_step at 1 and 2 threads with a positive rate, the CPU bench_gpu line, the MPI tables when MPI ran);
# 2. a hanging bench_step and a missing bench_gpu under a short budget: the hang is cut by its own limit and
#    reported, the missing program is named, and the summary is still written.
set -uo pipefail
check="$1" bin="$(cd "$2" && pwd)" scratch="$3"
rm -rf "$scratch"
mkdir -p "$scratch"
fail() {
  echo "FAIL: $*"
  [ -f "$out/summary.txt" ] && cat "$out/summary.txt"
  exit 1
}
row() {  # row STAGE REGEX: the summary's row for STAGE has a status matching REGEX
  grep -Eq "^$1 +$2" "$out/summary.txt" || fail "summary: no row '$1' with status /$2/"
}

out="$scratch/real"
bash "$check" --cpu-only --bin "$bin" --out "$out" > "$scratch/real.log" 2>&1 || fail "device_check exited $?"
n=$(ls "$out" | wc -l)
[ "$n" -le 8 ] || fail "$n files written (at most 8): $(ls "$out")"
for f in device.txt bench_gpu.txt bench_step.txt mpi_scaling.txt gpu_vs_cpu.txt summary.txt; do
  [ -s "$out/$f" ] || fail "no $f"
done
grep -q '^# varsph device check, .*--cpu-only' "$out/summary.txt" || fail "summary: no title line"
row machine 'ok '
row gpu_vs_cpu 'skipped: --cpu-only'
row bench_gpu_cpu_tiny 'ok '
row bench_gpu_cpu_engineering 'ok '
row bench_step_threads 'ok '
grep -q 'varsph [0-9]' "$out/device.txt" || fail "device.txt: no varsph --version"
# bench_step's figures in the summary: the paper case at 1 and 2 threads, fluid-particle steps/s > 0
for t in 1 2; do
  awk -v t="$t" '$1 == "dam_break_2d_paper_1682" && $4 == t && $7 > 0 {ok = 1} END {exit !ok}' "$out/summary.txt" ||
    fail "summary: no bench_step row at $t thread(s) with a positive rate"
done
awk '$1 == "cpu" && $3 > 0 && $6 > 0 {n++} END {exit n != 2}' "$out/summary.txt" ||
  fail "summary: not two bench_gpu lines on the CPU (tiny, engineering) with particles and ms/step"
if grep -Eq '^mpi_strong +ok ' "$out/summary.txt"; then
  row mpi_weak 'ok '
  for mode in strong weak; do
    for p in 1 2; do
      awk -v m="$mode" -v p="$p" '$1 == m && $2 == p && $6 > 0 && $7 > 0 {ok = 1} END {exit !ok}' "$out/summary.txt" ||
        fail "summary: no MPI $mode row at $p rank(s) with s/step and efficiency"
    done
  done
else
  row mpi_strong 'skipped: '  # only where this build has no MPI or the machine no mpirun / python3
fi

# a hang and a missing program, under a 10 s budget
fake="$scratch/fakebin"
mkdir -p "$fake"
ln -s "$bin/varsph" "$fake/varsph"
printf '#!/bin/sh\nexec sleep 600\n' > "$fake/bench_step"
chmod +x "$fake/bench_step"
out="$scratch/broken"
start=$SECONDS
bash "$check" --cpu-only --bin "$fake" --out "$out" --budget 10 > "$scratch/broken.log" 2>&1 ||
  fail "device_check exited $? with a broken stage"
[ $(( SECONDS - start )) -lt 40 ] || fail "the budget of 10 s did not hold: $(( SECONDS - start )) s"
row machine 'ok '
row bench_gpu 'skipped: no bench_gpu in '
row bench_step_threads 'TIMEOUT after [0-9]+ s'
grep -Eq '^mpi_strong +(NOT RUN \(budget spent\)|skipped: )' "$out/summary.txt" || fail "summary: mpi_strong ran past the budget"
echo "device_check --cpu-only: $(ls "$scratch/real" | wc -l) files, every stage reported; a hang and a missing program reported"

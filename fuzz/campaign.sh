#!/usr/bin/env bash
# A long fuzzing campaign of one harness (issue 16; docs/reliability.md, "Fuzzing"):
#   bash fuzz/campaign.sh TARGET RUNS
# TARGET is a harness name without "fuzz_" (scene, checkpoint, stl, stl_read, ..., poly2d). It fuzzes
# build/fuzz-ubsan/fuzz_TARGET (UndefinedBehaviorSanitizer alone: 1.2-1.6 x the inputs per second of
# ASan + UBSan) for RUNS executions from the persistent corpus runs/fuzz/corpus/TARGET, then replays the
# whole corpus once under ASan+UBSan (build/fuzz), so every input kept was also seen by ASan. The first
# use seeds the corpus from fuzz/make_corpus.py. Crashers land in runs/fuzz/artifacts/ (keep them as
# fuzz/regressions/). One line per campaign is appended to runs/fuzz/campaign.log: UTC end, target,
# executions, seconds, exec/s, coverage, corpus files, commit, load. Builds (once):
#   cmake -S fuzz -B build/fuzz-ubsan -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14 \
#         -DVARSPH_FUZZ_SANITIZERS=undefined && cmake --build build/fuzz-ubsan
#   cmake -S fuzz -B build/fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14 \
#         && cmake --build build/fuzz
set -euo pipefail
cd "$(dirname "$0")/.."
target="${1:?usage: fuzz/campaign.sh TARGET RUNS}"
runs="${2:?usage: fuzz/campaign.sh TARGET RUNS}"
fmt="${target%_read}"  # the reader harnesses share their format's corpus seeds
corpus="runs/fuzz/corpus/$target"
mkdir -p runs/fuzz/artifacts
if [ ! -d "$corpus" ]; then
  seeds="$(mktemp -d)"
  /usr/bin/python3 fuzz/make_corpus.py "$seeds" --varsph build/release/bin/varsph >/dev/null
  mkdir -p "$corpus" && cp "$seeds/$fmt"/* "$corpus"/ && rm -rf "$seeds"
fi
scratch="$(mktemp -d -p /dev/shm 2>/dev/null || mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
export VARSPH_FUZZ_TMP="$scratch" LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp"
opts=(-timeout=30 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536 -artifact_prefix=runs/fuzz/artifacts/"$target"-)
log="runs/fuzz/$target.$(date -u +%Y%m%dT%H%M%S).log"
start=$(date +%s)
build/fuzz-ubsan/fuzz_"$target" "${opts[@]}" -runs="$runs" -print_final_stats=1 "$corpus" fuzz/regressions/"$fmt" >"$log" 2>&1
secs=$(( $(date +%s) - start ))
# every input kept, replayed once under ASan+UBSan
build/fuzz/fuzz_"$target" "${opts[@]}" -runs=0 "$corpus" >>"$log" 2>&1
done_runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | head -n 1 | grep -o '[0-9]*$')
cov=$(grep -o 'DONE *cov: [0-9]*' "$log" | head -n 1 | grep -o '[0-9]*$')
printf '%s %s runs=%s seconds=%s exec_per_s=%s cov=%s corpus=%s commit=%s load="%s"\n' \
  "$(date -u +%FT%TZ)" "$target" "$done_runs" "$secs" "$(( done_runs / (secs > 0 ? secs : 1) ))" "$cov" \
  "$(ls "$corpus" | wc -l)" "$(git rev-parse --short HEAD)" "$(cut -d' ' -f1-3 /proc/loadavg)" | tee -a runs/fuzz/campaign.log

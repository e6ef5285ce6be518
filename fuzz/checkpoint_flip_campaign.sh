#!/usr/bin/env bash
# Every-bit checkpoint flip campaign in pieces (issue 16, docs/reliability.md "Every-bit checkpoint flips").
# Runs test_checkpoint_damage_all once per range of PIECE bytes, so a crash (or a wrong state) in one piece is
# recorded with its range and the campaign goes on with the next; prints one line per piece and the totals.
#   usage: fuzz/checkpoint_flip_campaign.sh [TEST_BINARY] [PIECE] [FIRST] [END]
#   e.g.:  nice -n 10 bash fuzz/checkpoint_flip_campaign.sh build/release/tests/io/test_checkpoint_damage_all
set -u
bin=${1:-build/release/tests/io/test_checkpoint_damage_all}
piece=${2:-4096}
first=${3:-0}
end=${4:-}
[[ -x $bin ]] || { echo "no test binary $bin" >&2; exit 2; }
if [[ -z $end ]]; then  # the file size: a one-byte piece prints it
  end=$(VARSPH_FLIP_FIRST=0 VARSPH_FLIP_END=1 "$bin" | sed -n 's/.*\] \([0-9]*\)-byte checkpoint.*/\1/p')
  [[ -n $end ]] || { echo "could not learn the checkpoint size from $bin" >&2; exit 2; }
fi
refused=0 intact=0 failed=0
for ((a = first; a < end; a += piece)); do
  b=$((a + piece < end ? a + piece : end))
  t0=$EPOCHREALTIME
  out=$(VARSPH_FLIP_FIRST=$a VARSPH_FLIP_END=$b "$bin" 2>&1)
  rc=$?
  dt=$(awk "BEGIN { print $EPOCHREALTIME - $t0 }")
  line=$(grep -o '[0-9]* refused (exit 2), [0-9]* in unread bytes' <<<"$out" | tail -1)
  if [[ $rc -eq 0 && -n $line ]]; then
    r=${line%% refused*}; i=${line#*, }; i=${i%% in unread*}
    refused=$((refused + r)); intact=$((intact + i))
    printf 'bytes %6d..%6d: rc 0, %6d refused, %6d unread, %.1f s\n' "$a" $((b - 1)) "$r" "$i" "$dt"
  else
    failed=$((failed + 1))
    printf 'bytes %6d..%6d: rc %d FAILED after %.1f s; last lines:\n' "$a" $((b - 1)) "$rc" "$dt"
    tail -n 8 <<<"$out" | sed 's/^/    /'
  fi
done
echo "total bytes $first..$((end - 1)): $((8 * (end - first))) flips, $refused refused (exit 2), $intact unread, $failed pieces failed"
[[ $failed -eq 0 ]]

#!/usr/bin/env bash
# Builds the libFuzzer targets (scripts/sanitized_build.sh: clang, ASan + UBSan) and runs each
# for SECONDS (default 60), seeded with the shipped scenes and fuzz/corpus. Fails on any crash,
# hang, leak or report; the input that caused it is left in build-asan/ (make it a regression
# test). One OpenMP thread: libFuzzer runs one input at a time.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
bash scripts/sanitized_build.sh scene_fuzz override_fuzz
for target in scene_fuzz override_fuzz; do
  work=build-asan/corpus-$target
  mkdir -p "$work"
  seeds=fuzz/corpus/override
  [ $target = scene_fuzz ] && seeds=scenes
  log=build-asan/$target.log
  rc=0
  OMP_NUM_THREADS=1 build-asan/fuzz/$target "$work" "$seeds" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="build-asan/$target-" >"$log" 2>&1 ||
    rc=$?
  runs=$(grep -oP '^stat::number_of_executed_units: *\K[0-9]+' "$log" || echo "?")
  echo "fuzz: $target: $runs inputs in $seconds s, exit $rc"
  if [ $rc -ne 0 ]; then
    grep -E "ERROR|SUMMARY|Test unit written|what\(\)" "$log" | head -20
    exit 1
  fi
done

#!/usr/bin/env bash
# run.sh BUILD_DIR [SECONDS] [HARNESS...] — runs the libFuzzer harnesses of a fuzz build
# (scripts/setup --fuzz BUILD_DIR && ninja -C BUILD_DIR) one after the other, each for
# SECONDS (default 45) on one core, from seed corpora built by corpus.py (in
# BUILD_DIR/fuzz/corpus) plus what earlier runs kept (BUILD_DIR/fuzz/NAME). HARNESS:
# scene set csv stl ckpt (default all). Limits: 10 s per input (a hang counts), 2 GB of
# memory. Prints one line per harness, "fuzz NAME: ok (...)" or "fuzz NAME: FAILED
# (...)" with the input that failed saved as BUILD_DIR/fuzz/NAME-crash-... (replay it
# with BUILD_DIR/tests/fuzz/fuzz_NAME FILE, or replay_NAME FILE in any build), and
# exits 1 when any failed. FUZZ_SEED: libFuzzer's -seed (default 0, a random one; CI
# gives one, so that a run's inputs repeat for the same code and machine speed).
set -u
here=$(cd "$(dirname "$0")" && pwd)
[ -d "${1:-}" ] || { echo "usage: tests/fuzz/run.sh BUILD_DIR [SECONDS] [HARNESS...]"; exit 2; }
build=$(cd "$1" && pwd)
secs=${2:-45}
shift $(($# < 2 ? $# : 2))
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(scene set csv stl ckpt)
work=$build/fuzz
mkdir -p "$work"
if ! /usr/bin/python3 "$here/corpus.py" "$build/esfera" "$work/corpus" > "$work/corpus.log" 2>&1; then
  cat "$work/corpus.log"
  echo "fuzz corpus: FAILED (tests/fuzz/corpus.py)"
  exit 1
fi
failed=0
for h in "${harnesses[@]}"; do
  exe=$build/tests/fuzz/fuzz_$h
  dict=$work/corpus/yaml.dict
  case $h in csv | stl | ckpt) dict=$work/corpus/$h.dict ;; esac
  if [ ! -x "$exe" ]; then
    echo "fuzz $h: FAILED (no $exe: configure with scripts/setup --fuzz $build)"
    failed=$((failed + 1))
    continue
  fi
  mkdir -p "$work/$h"
  log=$work/$h.log
  (cd "$work" && "$exe" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    -seed="${FUZZ_SEED:-0}" \
    -dict="$dict" -artifact_prefix="$work/$h-" -print_final_stats=1 \
    "$work/$h" "$work/corpus/$h" < /dev/null > "$log" 2>&1)
  rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  if [ "$rc" = 0 ]; then
    echo "fuzz $h: ok ($runs runs, $rate/s, $secs s)"
  else
    failed=$((failed + 1))
    grep -E '^==[0-9]+==ERROR|runtime error|^SUMMARY|Test unit written|ALARM|out-of-memory' "$log" | head -5
    echo "fuzz $h: FAILED (exit $rc after ${runs:-?} runs; log $log)"
  fi
done
[ "$failed" = 0 ]

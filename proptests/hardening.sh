#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (clang, build-asan/),
# then every reader under libFuzzer for SECONDS each (default 60), seeded from cases/.
# Exit non-zero on any sanitizer report, test failure or fuzzer finding (crash, leak, timeout, OOM).
# Usage: bash proptests/hardening.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
bash .ci/setup --hardening
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DDCAD_SANITIZE=ON -DDCAD_FUZZ=ON > /dev/null
cmake --build build-asan -j2
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-asan -j2 --output-on-failure

# seed corpora: case files, netlists, and dcad's own results as results to check
work=build-asan/fuzz
rm -rf "$work" && mkdir -p "$work"/{case,netlist,result,waveform,typed}
cp cases/*.json "$work/case/"
cp cases/*.cir "$work/netlist/"
for t in case netlist result waveform; do  # inputs that once crashed a reader, and seeds (kept as seeds, and as tests)
  [ -d "proptests/fuzz/regressions/$t" ] && cp proptests/fuzz/regressions/$t/* "$work/$t/"
done
for f in cases/harmonic-oscillator.json cases/gauge-free-particle.json cases/rounded-minus-one.json; do
  for b in reference fast certified; do build-asan/dcad solve "$f" --json --backend "$b" > "$work/result/$(basename "$f" .json)-$b.json" || true; done
done
status=0
printf "\x03\x00\x01" > "$work/typed/seed"  # the deck, its first node out of range
for t in case netlist result waveform typed; do
  log="$work/fuzz_$t.log"
  echo "== fuzz_$t: ${seconds} s"
  if ! build-asan/proptests/fuzz/fuzz_$t -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len=65536 \
       -artifact_prefix="$work/crash-$t-" "$work/$t" > "$log" 2>&1; then
    status=1
    tail -40 "$log"
  fi
  grep -E "^Done [0-9]+ runs" "$log" || true
done
[ $status -eq 0 ] && echo "hardening: sanitizer suite and fuzzers clean" || echo "hardening: FINDINGS (artifacts in $work)"
exit $status

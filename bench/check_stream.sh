#!/usr/bin/env bash
# `dcad check` of a large ngspice binary raw file in bounded memory (issue 45 §3: a 546 MB raw file in
# <= 500 MB RSS).  The KxK RLC power grid of bench/check_waveform.sh (K = 15: 1,069 branches), every vector saved
# (`.save all`: about 1,070 vectors), TMAX 1 ps over ROWS ps: ROWS points of doubles.  ngspice's time and
# dcad's (time, peak RSS) side by side, one run each; the file's size beside them.
#   cmake -S . -B build && cmake --build build -j2 --target dcad
#   bash bench/check_stream.sh [build]          (K=15, ROWS=64000 by default: about 546 MB)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
rows=${ROWS:-64000}
work=$(mktemp -d)
csv=bench/results/check_stream.csv
K=${K:-15}
deck=$work/grid.cir
awk -v k="$K" -v stop="$rows" 'BEGIN { print "RLC power grid " k "x" k " with a 1 A load, every vector saved"; print "Vdd vdd 0 DC 1.2"; print "Rs vdd g_1_1 10m";
  for (i = 1; i <= k; i++) for (j = 1; j <= k; j++) {
    printf "C_%d_%d g_%d_%d 0 100p\n", i, j, i, j;
    if (j < k) printf "Rh_%d_%d g_%d_%d h_%d_%d 50m\nLh_%d_%d h_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i, j+1;
    if (i < k) printf "Rv_%d_%d g_%d_%d w_%d_%d 50m\nLv_%d_%d w_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i+1, j }
  print "Iload g_" k "_" k " 0 PULSE(0 1 1n 100p 100p 2n 10n)";
  print ".save all"; print ".options reltol=1e-6"; printf ".tran 1p %dp 0 1p\n", stop; print ".end" }' > "$deck"
t0=$(date +%s.%N)
ngspice -b -r "$work/grid.raw" "$deck" > "$work/ng.log" 2>&1 || true
t1=$(date +%s.%N)
mb=$(( $(stat -c %s "$work/grid.raw") / 1000000 ))
set +e
/usr/bin/time -f "%e %M" -o "$work/time" "$build/dcad" check "$work/grid.raw" "$deck" > "$work/check.txt" 2> "$work/check.err"
rc=$?
set -e
read -r secs kb < <(tail -1 "$work/time")
points=$(grep -o '[0-9]* time points' "$work/check.txt" | cut -d' ' -f1 || true)
vectors=$(grep -cE '^  (agrees|DISAGREES|UNDECIDED)' "$work/check.txt" || true)
[ -f "$csv" ] || echo "file_mb,points,vectors,ngspice_seconds,check_seconds,check_peak_mb,exit" > "$csv"
echo "$mb,$points,$vectors,$(echo "$t1 - $t0" | bc),$secs,$((kb / 1024)),$rc" | tee -a "$csv"
[ $rc -eq 0 ] || { grep -E "DISAGREES|UNDECIDED" "$work/check.txt" | head -5; tail -3 "$work/check.err"; }
rm -rf "$work"

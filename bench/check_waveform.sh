#!/usr/bin/env bash
# `dcad check WAVEFORM DECK` against size (issue 28's goal: a 10^4-row, 20-vector raw file on a
# 1,000-branch circuit in <= 5 s).  Family: a K×K RLC power grid (50 mΩ + 1 nH per segment, 100 pF per
# node, 1.2 V through 10 mΩ) with a 1 A PULSE load; ngspice-39 (reltol 1e-6, TMAX 1 ps over 10 ns:
# about 10^4 rows) saves 20 vectors (10 node voltages, 10 inductor currents) to a binary raw file; dcad
# checks it.  One process per run, the same run for every size.
#   cmake -S . -B build && cmake --build build -j2 --target dcad
#   bash bench/check_waveform.sh [build]          (SIZES="5 15" for a subset)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=$(mktemp -d)
csv=bench/results/check_waveform.csv
[ -n "${SIZES:-}" ] || echo "K,branches,rows,vectors,ngspice_seconds,check_seconds,check_peak_mb,verdict" > "$csv"
for K in ${SIZES:-5 15 30 60}; do
  deck=$work/grid$K.cir
  awk -v k="$K" 'BEGIN { print "RLC power grid " k "x" k " with a 1 A load"; print "Vdd vdd 0 DC 1.2"; print "Rs vdd g_1_1 10m";
    for (i = 1; i <= k; i++) for (j = 1; j <= k; j++) {
      printf "C_%d_%d g_%d_%d 0 100p\n", i, j, i, j;
      if (j < k) printf "Rh_%d_%d g_%d_%d h_%d_%d 50m\nLh_%d_%d h_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i, j+1;
      if (i < k) printf "Rv_%d_%d g_%d_%d w_%d_%d 50m\nLv_%d_%d w_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i+1, j }
    print "Iload g_" k "_" k " 0 PULSE(0 1 1n 100p 100p 2n 10n)";
    printf ".save"; for (i = 1; i <= 5; i++) printf " v(g_%d_%d) v(g_%d_%d) i(lh_%d_1) i(lv_1_%d)", i, i, k, k - i + 1, i, i; print "";
    print ".options reltol=1e-6"; print ".tran 1p 10n 0 1p"; print ".end" }' > "$deck"
  branches=$(grep -c '^[RLCVI]' "$deck")
  t0=$(date +%s.%N)
  timeout 600 ngspice -b -r "$work/grid$K.raw" "$deck" > "$work/ng$K.log" 2>&1 || true
  t1=$(date +%s.%N)
  set +e
  /usr/bin/time -f "%e %M" -o "$work/time$K" "$build/dcad" check "$work/grid$K.raw" "$deck" > "$work/check$K.txt" 2> "$work/check$K.err"
  rc=$?
  set -e
  read -r secs kb < <(tail -1 "$work/time$K")
  rows=$(grep -o '[0-9]* time points' "$work/check$K.txt" | cut -d' ' -f1)
  vectors=$(grep -cE '^  (agrees|DISAGREES|UNDECIDED)' "$work/check$K.txt" || true)
  nd=$(grep -cE '^  DISAGREES' "$work/check$K.txt" || true)
  nu=$(grep -cE '^  UNDECIDED' "$work/check$K.txt" || true)
  verdict=$([ $rc -eq 0 ] && echo agrees || ([ $rc -eq 3 ] && echo "exit 3: $nd disagree $nu undecided" || echo "exit $rc"))
  echo "$K,$branches,$rows,$vectors,$(echo "$t1 - $t0" | bc),$secs,$((kb / 1024)),$verdict" | tee -a "$csv"
  [ $rc -eq 0 ] || grep -A1 -E "DISAGREES|UNDECIDED" "$work/check$K.txt" | head -12  # what disagrees, and by how much
done
rm -rf "$work"

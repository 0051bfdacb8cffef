#!/usr/bin/env bash
# Time and memory against size for `dcad solve --json` on RLC decks with sources (issue 27), every
# backend, 10 … 10^5 branches, one process per run (what a user's CI pays), each capped at CAP seconds
# (default 60): a backend stops at the first size it does not finish.  Two families written as circuit
# engineers write them:
#   rc-ladder  a 1 V PULSE driving S sections of 1 kΩ series and 1 nF shunt (2S + 1 branches);
#   rlc-grid   a K×K power grid: 50 mΩ + 1 nH per segment, a 100 pF decap per node, 1.2 V through 10 mΩ.
# Writes bench/results/rlc_scaling.csv and bench/charts/rlc_scaling.png (seconds and peak MB).
#   cmake -S . -B build && cmake --build build -j2 --target dcad
#   bash bench/rlc_scaling.sh [build] [CAP]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cap=${2:-60}
work=$(mktemp -d)
csv=bench/results/rlc_scaling.csv
echo "family,backend,branches,seconds,peak_rss_mb,dims,certified" > "$csv"
ladder() {  # ladder FILE SECTIONS
  awk -v s="$2" 'BEGIN { print "RC ladder, " s " sections"; print "V1 n0 0 PULSE(0 1 0 1n 1n 10u 20u)";
    for (i = 1; i <= s; i++) printf "R%d n%d n%d 1k\nC%d n%d 0 1n\n", i, i-1, i, i, i;
    print ".tran 10n 40u"; print ".end" }' > "$1"
}
grid() {  # grid FILE K
  awk -v k="$2" 'BEGIN { print "RLC power grid " k "x" k; print "Vdd vdd 0 DC 1.2"; print "Rs vdd g_1_1 10m";
    for (i = 1; i <= k; i++) for (j = 1; j <= k; j++) {
      printf "C_%d_%d g_%d_%d 0 100p\n", i, j, i, j;
      if (j < k) printf "Rh_%d_%d g_%d_%d h_%d_%d 50m\nLh_%d_%d h_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i, j+1;
      if (i < k) printf "Rv_%d_%d g_%d_%d w_%d_%d 50m\nLv_%d_%d w_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i+1, j }
    print ".tran 10p 10n"; print ".end" }' > "$1"
}
run_family() {  # run_family NAME GENERATOR SIZES...
  local family=$1 gen=$2; shift 2
  for backend in fast certified reference; do
    for size in "$@"; do
      deck="$work/$family$size.cir"
      [ -f "$deck" ] || "$gen" "$deck" "$size"
      branches=$(tail -n +2 "$deck" | grep -c '^[RLCVI]')
      t0=$(date +%s%N)
      if ! /usr/bin/time -f "%M" -o "$work/time" timeout "$cap" "$build/dcad" solve "$deck" --json --backend "$backend" > "$work/out.json" 2> /dev/null; then
        echo "$family $backend: stops at $branches branches (over ${cap} s or failed)"
        break
      fi
      secs=$(awk -v a="$t0" -v b="$(date +%s%N)" 'BEGIN { printf "%.4f", (b - a) / 1e9 }')
      read -r kb < "$work/time"
      dims=$(tr -d ' \n' < "$work/out.json" | grep -o '"dims":\[[-0-9,]*\]' | sed 's/"dims"://; s/,/ /g')
      cert=$(grep -q '"certified": true' "$work/out.json" && echo yes || echo no)
      echo "$family,$backend,$branches,$secs,$((kb / 1024)),$dims,$cert" | tee -a "$csv"
    done
  done
}
run_family rc-ladder ladder 5 15 50 150 500 1500 5000 15000 50000
run_family rlc-grid grid 2 3 5 10 15 30 50 100 150
gnuplot <<GP
set terminal pngcairo size 1200,520 font ',11'
set output 'bench/charts/rlc_scaling.png'
set datafile separator ','
set logscale xy
set grid
set key top left
set multiplot layout 1,2 title 'dcad solve --json on RLC decks with sources (graph route for R, L, C > 0): one process per point'
set xlabel 'branches'
set ylabel 'seconds'
plot for [f in "rc-ladder rlc-grid"] for [b in "fast certified reference"] '< grep ^'.f.','.b.', $csv' using 3:4 with linespoints title f.' '.b
set ylabel 'peak resident MB'
plot for [f in "rc-ladder rlc-grid"] for [b in "fast certified reference"] '< grep ^'.f.','.b.', $csv' using 3:5 with linespoints title f.' '.b
unset multiplot
GP
rm -rf "$work"
echo "wrote $csv and bench/charts/rlc_scaling.png"

#!/usr/bin/env bash
# `dcad simulate` at every size (issue 27): time, memory and accuracy of the sparse route against size,
# with ngspice at reltol 1e-6 on the same decks in the same run.  Family: a K×K RLC power grid (50 mΩ +
# 1 nH per segment, 100 pF per node, 1.2 V through 10 mΩ) with a 1 A PULSE load at the far corner,
# 1,000 output rows (10 ns at 10 ps), from the DC operating point.  Accuracy: the largest difference
# over the run of v(g_K_K) and of the supply current from an independent oracle (bench/grid_exact.py:
# the grid written by hand as an ODE, dense scipy expm) where it fits (K ≤ 30), relative to each
# vector's largest magnitude; the dense exact route on the smallest deck.  Each run is one process,
# capped at CAP seconds (default 120).
#   cmake -S . -B build && cmake --build build -j2 --target dcad;  bash .ci/setup --bench (numpy, scipy)
#   bash bench/sparse_simulate.sh [build] [CAP]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cap=${2:-120}
work=$(mktemp -d)
csv=bench/results/sparse_simulate.csv
echo "tool,K,branches,seconds,peak_rss_mb,err_v,err_supply,note" > "$csv"
grid() {  # grid FILE K
  awk -v k="$2" 'BEGIN { print "RLC power grid " k "x" k " with a 1 A load"; print "Vdd vdd 0 DC 1.2"; print "Rs vdd g_1_1 10m";
    for (i = 1; i <= k; i++) for (j = 1; j <= k; j++) {
      printf "C_%d_%d g_%d_%d 0 100p\n", i, j, i, j;
      if (j < k) printf "Rh_%d_%d g_%d_%d h_%d_%d 50m\nLh_%d_%d h_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i, j+1;
      if (i < k) printf "Rv_%d_%d g_%d_%d w_%d_%d 50m\nLv_%d_%d w_%d_%d g_%d_%d 1n\n", i, j, i, j, i, j, i, j, i, j, i+1, j }
    print "Iload g_" k "_" k " 0 PULSE(0 1 1n 100p 100p 2n 10n)"; print ".tran 10p 10n"; print ".end" }' > "$1"
}
compare() {  # compare RESULT.csv ORACLE.csv K → "err_v,err_supply" (RESULT: t,v,i columns)
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys, csv
a = [[float(x) for x in r] for r in list(csv.reader(open(sys.argv[1])))[1:]]
b = [[float(x) for x in r] for r in list(csv.reader(open(sys.argv[2])))[1:]]
n = min(len(a), len(b))
out = []
for j in (1, 2):  # the supply current against at least the load's 1 A (on large grids it stays ~0 for 10 ns)
    scale = max([abs(r[j]) for r in b[:n]] + [1.0 if j == 2 else 0.0])
    out.append("%.3g" % (max(abs(a[i][j] - b[i][j]) for i in range(n)) / scale))
print(",".join(out))
PY
}
run() {  # run TOOL K BRANCHES COMMAND... → seconds,peak_mb (or empty when over the cap)
  local t0 kb
  shift 3
  t0=$(date +%s%N)
  local rc=0
  /usr/bin/time -f "%M" -o "$work/time" timeout "$cap" "$@" > "$work/out" 2> "$work/err" || rc=$?
  # ngspice -b exits 1 after a .control run ("no simulations run" refers to .plot/.print): judged by its output file
  if [ "$rc" = 124 ] || { [ "$rc" != 0 ] && [ "$1" != ngspice ]; }; then echo ""; return; fi
  kb=$(grep -o '^[0-9]*$' "$work/time" | tail -1)
  awk -v a="$t0" -v b="$(date +%s%N)" -v kb="$kb" 'BEGIN { printf "%.3f,%d", (b - a) / 1e9, kb / 1024 }'
}
for K in 3 10 30 70 142; do
  deck="$work/grid$K.cir"
  grid "$deck" "$K"
  branches=$(tail -n +2 "$deck" | grep -c '^[RLCVI]')
  oracle=""
  if [ "$K" -le 30 ]; then
    /usr/bin/python3 bench/grid_exact.py "$K" 1000 > "$work/oracle.csv"
    oracle="$work/oracle.csv"
  fi
  for route in sparse dense; do
    [ "$route" = dense ] && [ "$branches" -gt 60 ] && continue
    tm=$(run "dcad-$route" "$K" "$branches" "$build/dcad" simulate "$deck" --tstop 10n --step 10p --route "$route" --vars "q_C_${K}_${K},v_Rs" --csv "$work/dcad.csv")
    if [ -z "$tm" ]; then echo "dcad-$route,$K,$branches,,,,over ${cap} s" | tee -a "$csv"; continue; fi
    est=$(grep -o 'estimated error [^ ]*' "$work/err" | awk '{print $3}')
    errs=","
    if [ -n "$oracle" ]; then
      awk -F, 'NR == 1 { print "t,v,i"; next } { printf "%s,%.17g,%s\n", $1, $2 / 100e-12, $3 }' "$work/dcad.csv" > "$work/dcad_v.csv"
      errs=$(compare "$work/dcad_v.csv" "$oracle")
    fi
    echo "dcad-$route,$K,$branches,$tm,$errs,estimate $est" | tee -a "$csv"
  done
  # ngspice: the same deck, reltol 1e-6, output interpolated onto the 10 ps grid
  sed "s|^\.tran.*|.options reltol=1e-6 abstol=1e-15 vntol=1e-12 interp\n.tran 10p 10n\n.control\nrun\nwrdata $work/ng.txt v(g_${K}_${K}) i(vdd)\n.endc|" "$deck" > "$work/ng.cir"
  rm -f "$work/ng.txt"
  tm=$(run ngspice "$K" "$branches" ngspice -b "$work/ng.cir")
  if [ -z "$tm" ] || [ ! -s "$work/ng.txt" ]; then echo "ngspice,$K,$branches,,,,over ${cap} s" | tee -a "$csv"; continue; fi
  errs=","
  if [ -n "$oracle" ]; then  # wrdata: t v t i; ngspice's i(vdd) flows into vdd's + terminal: the supply current is −i(vdd)
    awk 'BEGIN { print "t,v,i" } { printf "%s,%s,%.17g\n", $1, $2, -$4 }' "$work/ng.txt" > "$work/ng.csv"
    errs=$(compare "$work/ng.csv" "$oracle")
  fi
  echo "ngspice,$K,$branches,$tm,$errs,reltol 1e-6" | tee -a "$csv"
done
gnuplot <<GP
set terminal pngcairo size 1200,520 font ',11'
set output 'bench/charts/sparse_simulate.png'
set datafile separator ','
set logscale xy
set grid
set key top left
set multiplot layout 1,2 title 'simulate, RLC power grid with a load, 1000 rows: dcad sparse route vs ngspice (reltol 1e-6), one process per point'
set xlabel 'branches'
set ylabel 'seconds'
plot for [t in "dcad-sparse dcad-dense ngspice"] '< grep ^'.t.', $csv' using 3:4 with linespoints title t
set ylabel 'peak resident MB'
plot for [t in "dcad-sparse dcad-dense ngspice"] '< grep ^'.t.', $csv' using 3:5 with linespoints title t
unset multiplot
GP
rm -rf "$work"
echo "wrote $csv and bench/charts/sparse_simulate.png"

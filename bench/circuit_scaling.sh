#!/usr/bin/env bash
# Scaling of `dcad solve --backend fast` on LC circuits (the graph route, CEF §6), 10^2 … 10^6
# branches, ladders and grids; one process per size so that the peak RSS is that size's own.
# Fits the exponent b of total_s ≈ a·branches^b over the sizes ≥ 5·10^3 (least squares on logs).
#   cmake -S . -B build -DDCAD_BUILD_BENCH=ON && cmake --build build -j2 --target bench_circuit
#   bash bench/circuit_scaling.sh [build] [max_branches=1000000]
set -euo pipefail
build=${1:-build}
max=${2:-1000000}
out=$(mktemp)
echo "family,branches,nodes,read_s,tower_s,json_s,total_s,c,dim_Mc,peak_rss_mb"
for family in ladder grid; do
  for n in 100 1000 10000 100000 1000000; do
    [ "$n" -le "$max" ] || continue
    "$build/bench_circuit" "$family" "$n" | tee -a "$out"
  done
done
awk -F, '$2 >= 5000 { x = log($2); y = log($7); k = $1; n[k]++; sx[k] += x; sy[k] += y; sxx[k] += x*x; sxy[k] += x*y;
                       mx = log($10); smy[k] += mx; sxm[k] += x*mx }
  END { for (k in n) if (n[k] >= 2) {
          d = n[k]*sxx[k] - sx[k]*sx[k];
          printf "fitted exponent %s: time ~ branches^%.2f, peak memory ~ branches^%.2f (sizes >= 5e3)\n", k,
                 (n[k]*sxy[k] - sx[k]*sy[k]) / d, (n[k]*sxm[k] - sx[k]*smy[k]) / d } }' "$out"
rm -f "$out"

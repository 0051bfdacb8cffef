#!/usr/bin/env bash
# Time against size for every backend of `dcad solve --json` on LC ladders with capacitor loops
# (µH/nF: a series inductor and a shunt capacitor per section, a bridging capacitor between
# neighbouring nodes: 3 branches a section, c = 3), 10 … 10^5 branches, one process per run
# (what a user's CI pays), each run capped at CAP seconds (default 60): a backend stops at the first
# size it does not finish.  Writes bench/results/backend_scaling.csv and bench/charts/backend_scaling.png.
#   cmake -S . -B build && cmake --build build -j2 --target dcad
#   bash bench/backend_scaling.sh [build] [CAP]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cap=${2:-60}
work=$(mktemp -d)
csv=bench/results/backend_scaling.csv
echo "backend,branches,seconds,peak_rss_mb,equations_of_motion,certified" > "$csv"
ladder() {  # ladder FILE SECTIONS
  awk -v s="$2" 'BEGIN { print "ladder with capacitor loops, " 3*s " branches"; print "C0 n0 0 1n";
    for (i = 1; i <= s; i++) { printf "L%d n%d n%d 1u%s\nC%d n%d 0 1n\n", i, i-1, i, (i == 1 ? " IC=1m" : ""), i, i;
                               if (i > 1) printf "CB%d n%d n%d 1n\n", i, i-1, i }
    print ".end" }' > "$1"
}
for backend in fast certified reference; do
  for sections in 3 10 33 100 333 1000 3333 10000 33333; do
    deck="$work/ladder$sections.cir"
    [ -f "$deck" ] || ladder "$deck" "$sections"
    branches=$((3 * sections))
    t0=$(date +%s%N)
    if ! /usr/bin/time -f "%M" -o "$work/time" timeout "$cap" "$build/dcad" solve "$deck" --json --backend "$backend" > "$work/out.json" 2> /dev/null; then
      echo "$backend: stops at $branches branches (over ${cap} s or failed)"
      break
    fi
    secs=$(awk -v a="$t0" -v b="$(date +%s%N)" 'BEGIN { printf "%.4f", (b - a) / 1e9 }')
    read -r kb < "$work/time"
    eom=$(grep -q '"reduced"' "$work/out.json" && echo yes || echo no)
    cert=$(grep -q '"certified": true' "$work/out.json" && echo yes || echo no)
    echo "$backend,$branches,$secs,$((kb / 1024)),$eom,$cert" | tee -a "$csv"
  done
done
gnuplot <<GP
set terminal pngcairo size 900,560 font ',11'
set output 'bench/charts/backend_scaling.png'
set datafile separator ','
set logscale xy
set xlabel 'branches (LC ladder with capacitor loops)'
set ylabel 'seconds per dcad solve --json (one process)'
set key top left
set grid
set title 'filled: with the equations of motion; open: tower and loops only (above 120 branches)'
plot for [i=1:3] '< grep ^'.word("fast certified reference", i).', $csv' using 2:3 with lines lw 2 lc i title word("fast certified reference", i), \
     for [i=1:3] '< grep ^'.word("fast certified reference", i).', $csv | grep yes,[a-z]*\$' using 2:3 with points pt 7 ps 1.3 lc i notitle, \
     for [i=1:3] '< grep ^'.word("fast certified reference", i).', $csv | grep no,[a-z]*\$' using 2:3 with points pt 6 ps 1.3 lc i notitle
GP
rm -rf "$work"
echo "wrote $csv and bench/charts/backend_scaling.png"

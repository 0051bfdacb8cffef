#!/usr/bin/env bash
# Certified `dcad check` of ngspice's tight output on an 8-branch LC filter (issue 45 §3: about 6,500
# points in <= 2 s, certified).  The deck: V PULSE, R 50, L 10u, C 10n, L 10u, C 10n, R 50, C 1n;
# `.options reltol=1e-7 abstol=1e-15 vntol=1e-12`, `.tran 10n 40u 0 TMAX` for each TMAX below; ngspice
# writes a binary raw file, dcad checks it.  ngspice's time and dcad's (time, peak RSS) side by side, one
# run each.
#   cmake -S . -B build && cmake --build build -j2 --target dcad
#   bash bench/check_filter.sh [build]          (TMAXES="9n 1n" for a subset)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=$(mktemp -d)
csv=bench/results/check_filter.csv
echo "tmax,points,ngspice_seconds,check_seconds,check_peak_mb,certified,verdict" > "$csv"
for tmax in ${TMAXES:-20n 9n 6n 1n}; do
  deck=$work/filter.cir
  cat > "$deck" <<DECK
8-branch LC filter
V1 in 0 PULSE(0 1 1u 10n 10n 5u 20u)
R1 in a 50
L1 a b 10u
C1 b 0 10n
L2 b c 10u
C2 c 0 10n
R2 c 0 50
C3 a 0 1n
.options reltol=1e-7 abstol=1e-15 vntol=1e-12
.tran 10n 40u 0 $tmax
.end
DECK
  t0=$(date +%s.%N)
  ngspice -b -r "$work/f.raw" "$deck" > "$work/ng.log" 2>&1
  t1=$(date +%s.%N)
  set +e
  /usr/bin/time -f "%e %M" -o "$work/time" "$build/dcad" check "$work/f.raw" "$deck" > "$work/check.txt" 2> "$work/check.err"
  rc=$?
  set -e
  read -r secs kb < <(tail -1 "$work/time")
  points=$(grep -o '[0-9]* time points' "$work/check.txt" | cut -d' ' -f1)
  cert=$(grep -q 'certified: yes' "$work/check.txt" && echo yes || echo no)
  echo "$tmax,$points,$(echo "$t1 - $t0" | bc),$secs,$((kb / 1024)),$cert,exit $rc" | tee -a "$csv"
done
rm -rf "$work"

#!/usr/bin/env bash
# Certified enclosures (issue 28's goal: relative width <= 1e-10 over 10^4 output points): `dcad simulate
# --certified` against the double dense route on the same deck, side by side, one process each.
# Families: a lossless LC tank over 10^4 periods (one row per 1.01 periods: the wrapping test), an RLC ladder
# with a PULSE at the dense model's limit (58 branches) and at 199 branches (the state-equation model of
# reference/pipeline/rlc_motion.hpp; its double twin is the sparse route), the mixed-scale deck of
# cases/waveforms, and an RC ladder driven by a SIN with a phase and a delay.  Width = the largest radius of a kind over the
# run / the largest |value| of that kind (charges, currents, flux linkages); the radius includes the
# rounding of the printed midpoint to double (so 1.1e-16 is the floor).
#   cmake -S . -B build && cmake --build build -j2 --target dcad
#   bash bench/enclosure.sh [build]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=$(mktemp -d)
csv=bench/results/enclosure.csv
echo "deck,branches,double_route,rows,certified_seconds,double_seconds,width_q,width_v,width_p,max_diff_vs_double" > "$csv"
printf 'LC tank, 10^4 periods\nL1 a 0 1u\nC1 a 0 1n IC=1\n.end\n' > "$work/tank.cir"
python3 - "$work" <<'PY'
import sys
w = sys.argv[1]
for n, name in ((19, "ladder"), (66, "ladder199")):
    lines = ["RLC ladder, %d sections" % n, "V1 n0 0 PULSE(0 1 1n 1n 1n 20n 50n)"]
    for k in range(n):
        lines += ["R%d n%d m%d 1" % (k, k, k), "L%d m%d n%d 10n" % (k, k, k + 1), "C%d n%d 0 1p" % (k, k + 1)]
    open(w + "/" + name + ".cir", "w").write("\n".join(lines + [".end"]) + "\n")
lines = ["RC ladder driven by a SIN with phase and delay", "V1 n0 0 SIN(0.5 1 10Meg 3n 1e6 90)"]
for k in range(20):
    lines += ["R%d n%d n%d 100" % (k, k, k + 1), "C%d n%d 0 10p" % (k, k + 1)]
open(w + "/rcsin.cir", "w").write("\n".join(lines + [".end"]) + "\n")
PY
cp cases/waveforms/mixed-scale-rlc.cir "$work/mixed.cir"
run() {  # name deck tstop step initial [double route]
  local name=$1 deck=$2 tstop=$3 step=$4 init=$5 route=${6:-dense}
  /usr/bin/time -f "%e" -o "$work/t_c" "$build/dcad" simulate "$deck" --tstop "$tstop" --step "$step" --initial "$init" --certified > "$work/c.csv" 2> /dev/null
  /usr/bin/time -f "%e" -o "$work/t_d" "$build/dcad" simulate "$deck" --tstop "$tstop" --step "$step" --initial "$init" --route "$route" > "$work/d.csv" 2> /dev/null
  local branches rows
  branches=$(tail -n +2 "$deck" | grep -cE '^[RLCVI]')
  rows=$(($(wc -l < "$work/c.csv") - 1))
  stats=$(paste -d, "$work/c.csv" "$work/d.csv" | awk -F, -v nb="$branches" 'NR > 1 {
      n = 3 * nb; for (i = 0; i < n; i++) { v = $(2 + i); a = v < 0 ? -v : v; k = int(i / nb); if (a > s[k]) s[k] = a;
        d = v - $(2 + n + 3 + 1 + i); d = d < 0 ? -d : d; if (d > dd[k]) dd[k] = d }
      for (k = 0; k < 3; k++) { r = $(2 + n + k); if (r > rad[k]) rad[k] = r } }
    END { for (k = 0; k < 3; k++) { w[k] = s[k] > 0 ? rad[k] / s[k] : 0; m = s[k] > 0 ? dd[k] / s[k] : 0; if (m > md) md = m }
      printf "%.2e,%.2e,%.2e,%.2e", w[0], w[1], w[2], md }')
  echo "$name,$branches,$route,$rows,$(cat "$work/t_c"),$(cat "$work/t_d"),$stats" | tee -a "$csv"
}
run "LC tank 10^4 periods" "$work/tank.cir" 2.0067868296908125e-3 2.0067868296908125e-7 uic
run "RLC ladder (PULSE)" "$work/ladder.cir" 100n 10p op
run "RLC ladder (PULSE), state equations" "$work/ladder199.cir" 100n 10p op sparse
run "mixed-scale RLC" "$work/mixed.cir" 100n 10p op
run "RC ladder (SIN, phase, delay)" "$work/rcsin.cir" 1u 100p op
rm -rf "$work"

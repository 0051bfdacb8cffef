#!/bin/bash
# Issue 28's verdict table: every deck of cases/waveforms x {ngspice, gnucap} x {default, tight settings}, one
# run at a time: the simulator (timeout 120 s) -> `dcad check --json` on the original deck (timeout 600 s) ->
# cases/waveforms/oracle.py (the independent derivation).  The table (bench/results/corpus_verdicts.md) holds
# dcad's verdict next to the oracle's for every run, with check times.
#   cmake -S . -B build && cmake --build build -j2 --target dcad      (ngspice and gnucap from .ci/setup)
#   bash bench/corpus_verdicts.sh [build] [DECK...]
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
W=$PWD/cases/waveforms
DCAD=$PWD/$build/dcad
ORACLE="/usr/bin/python3 $W/oracle.py"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# gnucap needs .print (before .tran): every node, every inductor current and the voltage source's current.
declare -A PRINT=(
  [rc-pulse]="v(in) v(out) i(V1)"
  [cap-triangle-inductor-cutset]="v(a) v(b) v(c) i(L1) i(L2) i(L3)"
  [lc-tank-1000-periods]="v(a) i(L1)"
  [lc-tank-10000-periods]="v(a) i(L1)"
  [mixed-scale-rlc]="v(in) v(x) v(a) v(b) i(V1) i(L1) i(L2)"
  [pwl-rlc]="v(in) v(a) v(b) i(L1) i(V1)"
  [transformer-k1]="v(a) v(b) i(L1) i(L2)"
)
NG_TIGHT=".options reltol=1e-7 abstol=1e-15 vntol=1e-12"
GC_TIGHT=".options reltol=1e-7 trtol=1 numdgt=12"   # trtol default 7; numdgt: print 12 digits instead of 5

# tight .tran: TSTEP TSTOP 0 TMAX=TSTEP/10 [uic] (the 4th positional is TMAX/dtmax in both simulators)
tight_tran() {  # reads the deck's .tran line on stdin
  awk '{ s=$2; m=s; sub(/[a-zA-Z]+$/, "", m); u=substr(s, length(m)+1);
         printf ".tran %s %s 0 %g%s", $2, $3, m/10, u; for (i=4;i<=NF;i++) printf " %s", $i; printf "\n" }'
}

make_deck() {  # deck sim setting -> edited deck on stdout
  local d=$1 sim=$2 set=$3 text="" tran
  tran=$(grep -i '^\.tran' "$W/$d.cir")
  [ "$set" = tight ] && { tran=$(echo "$tran" | tight_tran); [ "$sim" = ngspice ] && text="$NG_TIGHT" || text="$GC_TIGHT"; }
  [ "$sim" = gnucap ] && text="${text:+$text
}.print tran ${PRINT[$d]}"
  awk -v text="$text" -v tran="$tran" 'tolower($1)==".tran" { if (text != "") print text; print tran; next } { print }' "$W/$d.cir"
}

check_one() {  # waveform prefix deck: dcad check on the original deck (the edits are options/.print/TMAX only), then the oracle
  /usr/bin/time -f %e -o "$2.checktime" timeout 600 $DCAD check "$1" "$W/$3.cir" --json > "$2.json" 2> "$2.checkerr"
  echo $? > "$2.checkrc"
  /usr/bin/time -f %e -o "$2.oracletime" timeout 3600 $ORACLE "$W/$3.cir" "$1" > "$2.oracle" 2>&1
  echo $? > "$2.oraclerc"
}

DECKS=("$@")
[ ${#DECKS[@]} -eq 0 ] && DECKS=(rc-pulse cap-triangle-inductor-cutset lc-tank-1000-periods lc-tank-10000-periods mixed-scale-rlc pwl-rlc transformer-k1)

for d in "${DECKS[@]}"; do
  for sim in ngspice gnucap; do
    for set in default tight; do
      tag="$d.$sim.$set"; p="$OUT/$tag"
      rm -f "$p".*
      if [ $sim = ngspice ]; then
        make_deck $d $sim $set > "$p.cir"; wave="$p.raw"
        /usr/bin/time -f %e -o "$p.simtime" timeout 120 ngspice -b -r "$wave" "$p.cir" > "$p.simlog" 2>&1
      else
        make_deck $d $sim $set > "$p.ckt"; wave="$p.txt"
        /usr/bin/time -f %e -o "$p.simtime" timeout 120 gnucap -b "$p.ckt" > "$wave" 2> "$p.simlog"
      fi
      echo $? > "$p.simrc"
      if [ "$(cat "$p.simrc")" = 124 ]; then echo "$tag: simulator timed out"; continue; fi
      check_one "$wave" "$p" "$d"
      echo "$tag: sim rc=$(cat "$p.simrc") check rc=$(cat "$p.checkrc") ($(tail -1 "$p.checktime") s) oracle rc=$(cat "$p.oraclerc")"
    done
  done
done
/usr/bin/python3 bench/corpus_table.py "$OUT" > bench/results/corpus_verdicts.md
cat bench/results/corpus_verdicts.md

#!/usr/bin/env bash
# The speed-against-accuracy benchmark of issue 6, one command:
#   bash bench/run.sh [--quick]
# Installs what it needs (Debian packages), builds the benchmark targets in build/, runs
#   dcad_sweep (every family × method, progress bar)  -> bench/results/sweep.csv, instances.jsonl
#   peers/cad_peers.py (sympy, numpy, scipy on the same instances)  -> bench/results/peers.csv
#   peers/per_process.py (reference vs sympy, a process per case)     -> bench/results/per_process.csv
#   dcad_sweep --adversarial (certified against mpq, 10^5 instances)  -> bench/results/adversarial.txt
#   trajectory.py (dcad simulate vs ngspice vs the analytic 4-port)  -> bench/results/trajectory.csv
#   bench_kernels (Google Benchmark)                                 -> bench/results/kernels.csv
#   charts.py (gnuplot)                                              -> bench/charts/*.png, results/summary.md
# --quick (under 2 minutes once built): fewer instances, sympy up to N = 21, kernels up to N = 200.
# Full: about 3 minutes after the build; sympy up to N = 33.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=""
[ "${1:-}" = "--quick" ] && quick="--quick"
bash .ci/setup --bench
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDCAD_BUILD_BENCH=ON > /dev/null
cmake --build build -j2 --target dcad dcad_sweep bench_kernels
mkdir -p bench/results bench/charts
start=$(date +%s)
echo "== sweep (methods × families)"
build/dcad_sweep $quick --out bench/results
mv bench/results/instances.jsonl build/bench_instances.jsonl  # 3 MB of exact matrices: not committed
echo "== peers (sympy, numpy, scipy)"
if [ -n "$quick" ]; then sympy_max=21; else sympy_max=33; fi  # sympy takes minutes per instance at N = 41
/usr/bin/python3 bench/peers/cad_peers.py build/bench_instances.jsonl --sympy-max-n $sympy_max > bench/results/peers.csv
echo "== reference against sympy, one process per case (issue 14)"
if [ -n "$quick" ]; then pp="--per 1 --max-n 13 --reps 1"; else pp="--per 2 --max-n 21 --reps 3"; fi
/usr/bin/python3 bench/peers/per_process.py build/dcad build/bench_instances.jsonl $pp > bench/results/per_process.csv
echo "== certified on adversarial instances (issue 14)"
if [ -n "$quick" ]; then adv=5000; else adv=100000; fi
build/dcad_sweep --adversarial $adv > bench/results/adversarial.txt
echo "== trajectories (dcad simulate, ngspice)"
/usr/bin/python3 bench/trajectory.py build/dcad cases bench/results/trajectory.csv
echo "== RLC decks against closed forms and ngspice (issue 12)"
/usr/bin/python3 bench/rlc_peers.py build/dcad cases bench/results/rlc_peers.csv
echo "== kernels (Google Benchmark)"
if [ -n "$quick" ]; then filter='ColPivQR|FastCad/(100|200)/|Rref.*/(20|50)$'; else filter='.'; fi
build/bench_kernels --benchmark_filter="$filter" --benchmark_format=csv > bench/results/kernels.csv
echo "== charts"
/usr/bin/python3 bench/charts.py bench/results bench/charts
echo "bench/run.sh $quick: $(( $(date +%s) - start )) s after the build"

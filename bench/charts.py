#!/usr/bin/env python3
"""The four charts of issue 6 and the summary of ratios, from the CSVs of one run (bench/run.sh):
    python3 bench/charts.py RESULTS_DIR CHARTS_DIR
RESULTS_DIR holds sweep.csv (dcad_sweep), peers.csv (peers/cad_peers.py), trajectory.csv
(trajectory.py) and kernels.csv (bench_kernels, Google Benchmark CSV).  Writes CHARTS_DIR/*.png
with gnuplot (pngcairo if present, else png), the data behind them in RESULTS_DIR/plot/ and
RESULTS_DIR/summary.md.  Standard library only.
"""
import csv
import math
import os
import re
import subprocess
import sys
from collections import defaultdict

METHODS = ["reference", "certified", "bf100", "bf50", "naive", "fast", "sympy", "numpy", "scipy"]
LABEL = {"reference": "reference (words, fmpq)", "certified": "certified (words, fmpq)", "bf100": "bin\\\\_float\\\\_100 + tol",
         "bf50": "bin\\\\_float\\\\_50 + tol", "naive": "naive double + tol", "fast": "fast (SVD)", "sympy": "sympy (exact)",
         "numpy": "numpy (SVD)", "scipy": "scipy (pivoted QR)"}
PRESYMPLECTIC = {"graded", "perturbed", "tower"}


KERNEL_SIZES = (100, 200, 500, 1000, 2000)


def read_rows(path, header=None):
    with open(path) as f:
        return list(csv.DictReader(f, fieldnames=header))


def fit_exponent(points):
    pts = [(math.log(n), math.log(t)) for n, t in points if n > 0 and t > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx else float("nan")


def main():
    res, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    header = "family,param,n,method,instances,wrong,wrong_claimed_certain,uncertain,recomputed,max_angle,mean_seconds".split(",")
    rows = read_rows(os.path.join(res, "sweep.csv"))
    peers = os.path.join(res, "peers.csv")
    if os.path.exists(peers):
        rows += read_rows(peers, header)
    for r in rows:
        for k in ("param", "n", "instances", "wrong", "wrong_claimed_certain", "uncertain", "recomputed", "max_angle", "mean_seconds"):
            r[k] = float(r[k])
    data = os.path.join(res, "plot")  # the numbers behind each chart
    os.makedirs(data, exist_ok=True)

    # (1) Pareto: mean time per instance against the fraction of wrong answers, presymplectic families.
    agg = defaultdict(lambda: [0.0, 0.0, 0.0, 0.0])  # instances, wrong, seconds·instances, wrong_certain
    for r in rows:
        if r["family"] in PRESYMPLECTIC:
            a = agg[r["method"]]
            a[0] += r["instances"]
            a[1] += r["wrong"]
            a[2] += r["mean_seconds"] * r["instances"]
            a[3] += r["wrong_claimed_certain"]
    plot1 = []
    for i, m in enumerate(METHODS):
        if m in agg and agg[m][0]:
            n, w, s, _ = agg[m]
            fn = os.path.join(data, f"pareto_{m}.dat")
            with open(fn, "w") as f:
                f.write(f"{s / n:.6g} {w / n:.6g}\n")
            plot1.append(f"'{fn}' using 1:2 with points pt {i + 4} ps 2.5 lw 2 title \"{LABEL[m]}\"")

    # (2) wrong-answer rate against condition number (graded family), one file per method.
    graded = defaultdict(list)
    for r in rows:
        if r["family"] == "graded":
            graded[r["method"]].append((r["param"], r["wrong"] / r["instances"]))
    plot2 = []
    for i, m in enumerate(METHODS):
        if m in graded:
            fn = os.path.join(data, f"graded_{m}.dat")
            with open(fn, "w") as f:
                for k, w in sorted(graded[m]):
                    f.write(f"{k:g} {w:g}\n")
            plot2.append(f"'{fn}' using 1:2 with linespoints lw 2 pt {i + 1} title \"{LABEL[m]}\"")

    # (3) time against size (size family), log-log, fitted exponents.
    sizes = defaultdict(list)
    for r in rows:
        if r["family"] == "size":
            sizes[r["method"]].append((r["n"], r["mean_seconds"]))
    plot3, exponents = [], {}
    for i, m in enumerate(METHODS):
        if m in sizes:
            fn = os.path.join(data, f"size_{m}.dat")
            with open(fn, "w") as f:
                for n, t in sorted(sizes[m]):
                    f.write(f"{n:g} {t:g}\n")
            exponents[m] = fit_exponent(sizes[m])
            plot3.append(f"'{fn}' using 1:2 with linespoints lw 2 pt {i + 1} title \"{LABEL[m]}  N^{{{exponents[m]:.1f}}}\"")

    # (4) trajectory error against run time.
    traj = read_rows(os.path.join(res, "trajectory.csv"))
    for tool in ("dcad", "ngspice"):
        with open(os.path.join(data, f"traj_{tool}.dat"), "w") as f:
            for r in traj:
                if r["tool"] == tool and r["max_rel_error"] != "nan":
                    crowded = "tmax=100m" in r["setting"] and not r["setting"].startswith(("reltol=1e-3 ", "reltol=1e-10 "))
                    f.write(f'{r["seconds"]} {r["max_rel_error"]} "{"" if crowded else r["setting"]}"\n')

    # (5) RLC decks (issue 12): error against closed forms and time, dcad and ngspice side by side.
    rlc_path = os.path.join(res, "rlc_peers.csv")
    rlc = read_rows(rlc_path) if os.path.exists(rlc_path) else []
    for deck in ("rlc-series", "rl-step"):
        for tool in ("dcad", "ngspice"):
            with open(os.path.join(data, f"rlc_{deck}_{tool}.dat"), "w") as f:
                for r in rlc:
                    if r["family"] == "closed-form" and r["deck"] == deck and r["tool"] == tool and r["error"] != "nan":
                        f.write(f'{r["seconds"]} {max(float(r["error"]), 1e-17)} "{r["setting"]}"\n')

    # (6) fast CAD against one pivoted QR, time against N (bench_kernels), fitted exponents.
    k = {}
    kp = os.path.join(res, "kernels.csv")
    if os.path.exists(kp):
        with open(kp) as f:
            text = f.read()
        body = text[text.index("name,"):] if "name," in text else ""
        for r in csv.DictReader(body.splitlines()):
            # the benchmark's name without Google Benchmark's option suffixes (/min_time:1.000, /iterations:…)
            k[re.sub(r"/(min_time|iterations|repetitions)[^/]*", "", r["name"])] = float(r["real_time"]) * {"ms": 1e-3, "us": 1e-6, "ns": 1e-9, "s": 1.0}[r["time_unit"]]
    plot6, kexp = [], {}
    for i, m in enumerate(("FastCad", "ColPivQR", "JacobiSingularValues")):
        pts = [(n, k[f"{m}/{n}"]) for n in KERNEL_SIZES if f"{m}/{n}" in k]
        if len(pts) >= 2:
            fn = os.path.join(data, f"kernel_{m}.dat")
            with open(fn, "w") as f:
                f.writelines(f"{n} {t:g}\n" for n, t in pts)
            kexp[m] = fit_exponent(pts)
            plot6.append(f"'{fn}' using 1:2 with linespoints lw 2 pt {i + 5} title \"{m}  N^{{{kexp[m]:.2f}}}\"")

    term = "pngcairo size 720,460 font ',10'"
    if subprocess.run(["gnuplot", "-e", "set terminal pngcairo"], capture_output=True).returncode != 0:
        term = "png size 720,460"
    gp = f"""set terminal {term}
set key outside right
set grid
set output '{out}/pareto.png'
set title 'Speed against accuracy: presymplectic families (graded, perturbed, tower)'
set logscale x
set xlabel 'mean time per instance [s]'
set ylabel 'fraction of wrong discrete answers'
set yrange [-0.05:1.05]
plot {", ".join(plot1)}
set output '{out}/wrong_vs_condition.png'
set title 'Wrong answers against condition (graded tower, planted answer)'
set logscale x
set xlabel 'condition number of the data'
set ylabel 'fraction wrong'
set yrange [-0.05:1.05]
plot {", ".join(plot2)}
set output '{out}/time_vs_size.png'
set title 'Time against size (graded tower, condition 10^2)'
set logscale xy
set xlabel 'N'
set ylabel 'mean time per instance [s]'
set format y '10^{{%L}}'
set autoscale y
plot {", ".join(plot3)}
set output '{out}/trajectory.png'
set title '4-port (CEF Fig. 6.1): trajectory error against run time'
set logscale xy
set xlabel 'run time [s] (whole process)'
set ylabel 'max relative error of i_L vs analytic'
set format y '10^{{%L}}'
set format x '%g'
plot '{data}/traj_dcad.dat' using 1:2 with linespoints pt 7 lw 2 title 'dcad simulate (exact flow)', '' using 1:2:3 with labels offset 0,-1 font ',7' notitle, \\
     '{data}/traj_ngspice.dat' using 1:2 with linespoints pt 5 lw 2 title 'ngspice', '' using 1:2:3 with labels offset 0,1 font ',7' notitle
set output '{out}/rlc_trajectory.png'
set title 'RLC decks (series RLC, RL step): error against the closed form and run time'
set logscale xy
set xlabel 'run time [s] (whole process, best of 3)'
set ylabel 'max relative error of i_L'
set format y '10^{{%L}}'
set format x '%g'
plot '{data}/rlc_rlc-series_dcad.dat' using 1:2 with linespoints pt 7 lw 2 title 'dcad, series RLC', \
     '{data}/rlc_rlc-series_ngspice.dat' using 1:2 with linespoints pt 5 lw 2 title 'ngspice, series RLC', '' using 1:2:3 with labels offset 0,1 font ',7' notitle, \
     '{data}/rlc_rl-step_dcad.dat' using 1:2 with linespoints pt 9 lw 2 title 'dcad, RL step', \
     '{data}/rlc_rl-step_ngspice.dat' using 1:2 with linespoints pt 11 lw 2 title 'ngspice, RL step', '' using 1:2:3 with labels offset 0,-1 font ',7' notitle
"""
    if plot6:
        gp += f"""set output '{out}/fast_cad_vs_qr.png'
set title 'Fast CAD against one pivoted QR, one SVD (NxN)'
set logscale xy
set xlabel 'N'
set ylabel 'time [s]'
set format y '10^{{%L}}'
set format x '%g'
plot {", ".join(plot6)}
"""
    with open(os.path.join(data, "charts.gp"), "w") as f:
        f.write(gp)
    subprocess.run(["gnuplot", os.path.join(data, "charts.gp")], check=True)

    # Summary of the ratios the issue asks for, all from this run.
    lines = ["# dcad benchmark summary (one run; regenerate with `bash bench/run.sh`)\n"]
    for n in KERNEL_SIZES:
        if f"FastCad/{n}" in k and f"ColPivQR/{n}" in k:
            lines.append(f"- fast CAD at N = {n}: {k[f'FastCad/{n}']:.3g} s, one pivoted QR of an N×N matrix {k[f'ColPivQR/{n}']:.3g} s: "
                         f"ratio {k[f'FastCad/{n}'] / k[f'ColPivQR/{n}']:.1f}× (goal ≤ 4×)\n")
    if kexp:
        lines.append("- fitted exponents over N: " + ", ".join(f"{m} N^{e:.2f}" for m, e in sorted(kexp.items())) + "\n")
    beyond = [(n, k[f"CadBeyondWords/Mpq/{n}"] / k[f"CadBeyondWords/Fmpq/{n}"]) for n in (8, 16, 24)
              if f"CadBeyondWords/Mpq/{n}" in k and f"CadBeyondWords/Fmpq/{n}" in k]
    if beyond:
        lines.append("- the exact tier where the words overflow (bench_kernels CadBeyondWords, every entry beyond 128 bits): "
                     "mpq_rational takes " + ", ".join(f"{r:.1f}× (N = {n})" for n, r in beyond) + " as long as fmpq\n")
    grown = [(n, k[f"RrefExact/{n}"] / k[f"RrefFmpq/{n}"]) for n in (20, 50, 100) if f"RrefExact/{n}" in k and f"RrefFmpq/{n}" in k]
    if grown:
        lines.append("- RREF of a dense rank-deficient integer matrix (numbers grow to hundreds of digits: GMP's gcds either "
                     "way): mpq_rational takes " + ", ".join(f"{r:.2f}× (N = {n})" for n, r in grown) + " as long as fmpq\n")
    ref_t = {(r["family"], r["param"]): r["mean_seconds"] for r in rows if r["method"] == "reference"}
    ratios = [(fam, p, t / ref_t[(fam, p)]) for (fam, p, t) in
              ((r["family"], r["param"], r["mean_seconds"]) for r in rows if r["method"] == "sympy") if (fam, p) in ref_t]
    if ratios:
        lo, hi = min(x for *_, x in ratios), max(x for *_, x in ratios)
        lines.append(f"- reference against sympy in process, same instances, same steps: sympy takes {lo:.1f}× … {hi:.0f}× as long "
                     f"(median {sorted(x for *_, x in ratios)[len(ratios) // 2]:.0f}×; goal ≥ 50×)\n")
        lines.append("  - per family: " + ", ".join(f"{fam} {min(x for f2, _, x in ratios if f2 == fam):.0f}× … "
                                                   f"{max(x for f2, _, x in ratios if f2 == fam):.0f}×"
                                                   for fam in sorted({fam for fam, *_ in ratios})) + "\n")
    pp_path = os.path.join(res, "per_process.csv")
    if os.path.exists(pp_path):
        pp = read_rows(pp_path)
        per = [float(r["sympy_per_process"]) / float(r["dcad_per_process"]) for r in pp]
        one = [float(r["sympy_per_process"]) / float(r["dcad_one_process"]) for r in pp]
        if per:
            lines.append(f"- reference against sympy, one process per case (what a CI calling each tool per file pays; "
                         f"bench/peers/per_process.py): sympy takes {min(per):.0f}× … {max(per):.0f}× as long; against dcad's one "
                         f"process for the corpus (`solve --jsonl`): {min(one):.0f}× … {max(one):.0f}× (goal ≥ 20× per process)\n")
            fams = sorted({r["family"] for r in pp})
            lines.append("  - per family, per process: " + ", ".join(
                f"{fam} {min(float(r['sympy_per_process']) / float(r['dcad_per_process']) for r in pp if r['family'] == fam):.0f}× … "
                f"{max(float(r['sympy_per_process']) / float(r['dcad_per_process']) for r in pp if r['family'] == fam):.0f}×"
                for fam in fams) + "\n")
    # certified: how each instance was decided, per family, and its time against fast and reference
    fam_t = defaultdict(dict)
    for r in rows:
        fam_t[(r["family"], r["param"])][r["method"]] = r
    per_fam = defaultdict(lambda: [0, 0, 0, [], []])  # instances, machine words, recomputed, /fast, /reference
    for (fam, _), ms in fam_t.items():
        c = ms.get("certified")
        if not c or "fast" not in ms or "reference" not in ms:
            continue
        a = per_fam[fam]
        words = float(c.get("machine_words") or 0)
        a[0] += c["instances"]
        a[1] += words
        a[2] += c["recomputed"]
        a[3].append(c["mean_seconds"] / ms["fast"]["mean_seconds"])
        a[4].append(c["mean_seconds"] / ms["reference"]["mean_seconds"])
    if per_fam:
        lines.append("\n| certified, family | instances | exact in machine words (64, then 128 bits) | recomputed in fmpq | time / fast | time / reference |\n|---|---|---|---|---|---|\n")
        for fam, a in sorted(per_fam.items()):
            lines.append(f"| {fam} | {int(a[0])} | {int(a[1])} | {int(a[2])} | {min(a[3]):.1f}× … {max(a[3]):.1f}× | "
                         f"{min(a[4]):.2f}× … {max(a[4]):.2f}× |\n")
        lines.append("\n")
    # the exact tiers, each alone on every instance (issue 26): total time per family, and against the words
    tiers = [("reference", "words (64, 128 bits)"), ("tier_fmpq", "FLINT fmpq"), ("tier_flint", "fmpq + fmpq_mat_rref"),
             ("tier_mpq", "mpq_rational"), ("tier_ball", "dcad's balls (bench/ball.hpp)"), ("tier_arb", "Arb arb_t")]
    tier_t = defaultdict(lambda: defaultdict(float))
    for r in rows:
        if r["method"] in dict(tiers) or r["method"] == "certified":
            tier_t[r["family"]][r["method"]] += r["mean_seconds"] * r["instances"]
    if tier_t:
        lines.append("| exact tier alone, family: total [s] (× words) | certified as shipped | " + " | ".join(l for _, l in tiers)
                     + " |\n|---|" + "---|" * (len(tiers) + 1) + "\n")
        for fam, t in sorted(tier_t.items()):
            w = t.get("reference", 0) or float("nan")
            cells = [f"{t[m]:.3g} ({t[m] / w:.1f}×)" if m in t else "–" for m in ["certified"] + [m for m, _ in tiers]]
            lines.append(f"| {fam} | " + " | ".join(cells) + " |\n")
        rec = sum(r["recomputed"] for r in rows if r["method"] == "tier_ball")
        n_ball = sum(r["instances"] for r in rows if r["method"] == "tier_ball")
        lines.append(f"\nBalls and Arb alone are recomputed in fmpq when a zero test is undecidable, as the cascade does: "
                     f"{int(rec)} of {int(n_ball)} instances here.\n\n")
    adv_path = os.path.join(res, "adversarial.txt")
    if os.path.exists(adv_path):
        with open(adv_path) as f:
            lines.append("- " + f.readline().strip() + " (`build/dcad_sweep --adversarial 100000`)\n")
    for r in rlc:
        if r["family"] == "closed-form":
            lines.append(f"- RLC {r['deck']}, {r['tool']} {r['setting']}: error {float(r['error']):.2g} against the closed form, {float(r['seconds']):.3g} s\n")
    failed = [r for r in rlc if r["tool"] == "ngspice" and r["failure"]]
    if rlc:
        lines.append(f"- ngspice on {sum(1 for r in rlc if r['tool'] == 'ngspice' and r['family'] != 'closed-form')} random/hard RLC runs: "
                     + ("; ".join(f"{r['deck']} ({r['setting']}): {r['failure']}, then {float(r['error']):.2g} from dcad" for r in failed) or "no failures")
                     + "\n")
    dc = [r for r in traj if r["tool"] == "dcad" and r["setting"] == "step=0.001"]
    ng = [r for r in traj if r["tool"] == "ngspice" and r["max_rel_error"] != "nan"]
    if dc and ng:
        d = dc[0]
        best = min(ng, key=lambda r: float(r["max_rel_error"]))
        lines.append(f"- dcad simulate (10,001 points) {float(d['seconds']):.3g} s at error {d['max_rel_error']}; ngspice's most "
                     f"accurate run ({best['setting']}) {float(best['seconds']):.3g} s at error {best['max_rel_error']}: dcad "
                     f"{float(best['seconds']) / float(d['seconds']):.0f}× faster and more accurate (goal ≥ 10×)\n")
    cert = agg.get("certified")
    if cert:
        lines.append(f"- certified in this sweep: {int(cert[1])} wrong of {int(cert[0])} presymplectic instances\n")
    lines.append("\n| method | instances | wrong | wrong while claiming certain | mean time [s] | size exponent |\n|---|---|---|---|---|---|\n")
    for m in METHODS:
        if m in agg:
            n, w, s, wc = agg[m]
            lines.append(f"| {m} | {int(n)} | {int(w)} | {int(wc)} | {s / n:.3g} | {exponents.get(m, float('nan')):.2f} |\n")
    with open(os.path.join(res, "summary.md"), "w") as f:
        f.writelines(lines)
    sys.stdout.writelines(lines)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""`dcad simulate` on the expression form against scipy's DOP853 (issue 29's goal: median <= 3x scipy at
the same accuracy, the Cartesian double pendulum's 10 s of motion in <= 10 s).

Each scene in bench/scenes/ is a dcad case; its peer is an ODE derived by hand (in minimal coordinates
where the case has multipliers, so the peer does no index reduction at all: the easiest job for scipy).
Both run 10 s of motion with rows every 0.01 s.  Timing: dcad's whole process (start, the CAD at the
initial point, the chart, the integration, the CSV) against scipy's solve_ivp call alone (no interpreter
start), best of 3 each.  Accuracy: both against the peer's own tight run (DOP853, rtol 1e-13, atol
1e-15), on the coordinates the peer can express, max over the rows, relative to the coordinate's scale.

  /usr/bin/python3 bench/simulate_vs_scipy.py build/dcad > bench/results/simulate_vs_scipy.md
"""
import csv, io, math, statistics, subprocess, sys, time

import numpy as np
from scipy.integrate import solve_ivp

DCAD = sys.argv[1] if len(sys.argv) > 1 else "build/dcad"
SCENES = "bench/scenes/"
T, H = 10.0, 0.01
TIMES = np.linspace(0.0, T, int(round(T / H)) + 1)


def case(name):
    import json
    return json.load(open(SCENES + name + ".json"))


def init(name, key):
    return float(case(name)["initial"][key])


# ---- peers: (y0, rhs, observe(t, y) -> dict of dcad columns) -------------------------------------------

def pendulum():
    g, th0 = 9.81, math.atan2(init("pendulum-cartesian", "x"), -init("pendulum-cartesian", "y"))
    w0 = init("pendulum-cartesian", "v_x") / math.cos(th0)
    return [th0, w0], lambda t, y: [y[1], -g * math.sin(y[0])], lambda t, y: {"x": math.sin(y[0]), "y": -math.cos(y[0])}


def double_pendulum():
    g, n = 9.81, "double-pendulum-cartesian"
    x1, y1, x2, y2 = (init(n, k) for k in ("x1", "y1", "x2", "y2"))
    t1, t2 = math.atan2(x1, -y1), math.atan2(x2 - x1, -(y2 - y1))
    w1 = init(n, "v_x1") / math.cos(t1)
    w2 = (init(n, "v_x2") - init(n, "v_x1")) / math.cos(t2)

    def f(t, y):  # m1 = m2 = l1 = l2 = 1 (the standard angle form)
        a, b, p, q = y
        d = a - b
        den = 3 - math.cos(2 * d)
        pa = (-g * 3 * math.sin(a) - g * math.sin(a - 2 * b) - 2 * math.sin(d) * (q * q + p * p * math.cos(d))) / den
        pb = (2 * math.sin(d) * (p * p * 2 + g * 2 * math.cos(a) + q * q * math.cos(d))) / den
        return [p, q, pa, pb]

    def obs(t, y):
        return {"x1": math.sin(y[0]), "y1": -math.cos(y[0]), "x2": math.sin(y[0]) + math.sin(y[1]), "y2": -math.cos(y[0]) - math.cos(y[1])}
    return [t1, t2, w1, w2], f, obs


def rolling_disk():
    n, R = "rolling-disk", 0.5
    y0 = [0.0, 0.0, 0.0, init(n, "phi"), init(n, "v_theta"), init(n, "v_phi")]
    return y0, lambda t, y: [R * math.cos(y[3]) * y[4], R * math.sin(y[3]) * y[4], y[4], y[5], 0.0, 0.0], \
        lambda t, y: {"x": y[0], "y": y[1], "theta": y[2], "phi": y[3]}


def chaplygin():
    n, a, m, I = "chaplygin-sleigh", 0.5, 1.0, 1.0 / 3
    th, w = init(n, "theta"), init(n, "v_theta")
    u = init(n, "v_x") * math.cos(th) + init(n, "v_y") * math.sin(th)

    def f(t, y):
        x, yy, th, u, w = y
        return [u * math.cos(th) - a * w * math.sin(th), u * math.sin(th) + a * w * math.cos(th), w, a * w * w, -m * a * u * w / (I + m * a * a)]
    return [0.0, 0.0, th, u, w], f, lambda t, y: {"x": y[0], "y": y[1], "theta": y[2]}


def knife_edge():
    n = "knife-edge-incline"
    th, om = init(n, "theta"), init(n, "v_theta")
    v = init(n, "v_x") * math.cos(th) + init(n, "v_y") * math.sin(th)

    def f(t, y):
        x, yy, th, v = y
        return [v * math.cos(th), v * math.sin(th), om, 5 * math.cos(th)]
    return [0.0, 0.0, th, v], f, lambda t, y: {"x": y[0], "y": y[1], "theta": y[2]}


def bead():
    n, W, g = "bead-rotating-hoop", 5.0, 9.81
    th = math.atan2(init(n, "x"), -init(n, "z"))
    w = init(n, "v_x") / math.cos(th)

    def obs(t, y):
        rho = math.sin(y[0])
        return {"x": rho * math.cos(W * t), "y": rho * math.sin(W * t), "z": -math.cos(y[0])}
    return [th, w], lambda t, y: [y[1], W * W * math.sin(y[0]) * math.cos(y[0]) - g * math.sin(y[0])], obs


def josephson():
    n = "josephson-lc"
    return [init(n, "phi"), init(n, "v_phi")], lambda t, y: [y[1], -y[0] - 20 * math.sin(y[0])], lambda t, y: {"phi": y[0]}


def heisenberg():
    n = "heisenberg-particle"
    y0 = [init(n, "x"), init(n, "y"), 0.0, init(n, "v_x"), init(n, "v_y")]
    return y0, lambda t, y: [y[3], y[4], y[0] * y[4] - y[1] * y[3], -y[0], -y[1]], lambda t, y: {"x": y[0], "y": y[1], "z": y[2]}


def damper():
    return [1.0, 2.0], lambda t, y: [y[1], (-3 * y[0] - 0.5 * y[1] ** 3) / 2], lambda t, y: {"x": y[0]}


def spherical():
    n, g = "spherical-pendulum-cartesian", 9.81
    x, y, z = init(n, "x"), init(n, "y"), init(n, "z")
    th, ph = math.acos(-z), math.atan2(y, x)
    vz = init(n, "v_z")
    wt = vz / math.sin(th)
    wp = (init(n, "v_y") * math.cos(ph) - init(n, "v_x") * math.sin(ph)) / math.sin(th)

    def f(t, s):
        th, ph, wt, wp = s
        return [wt, wp, math.sin(th) * math.cos(th) * wp * wp - g * math.sin(th), -2 * wt * wp * math.cos(th) / math.sin(th)]

    def obs(t, s):
        return {"x": math.sin(s[0]) * math.cos(s[1]), "y": math.sin(s[0]) * math.sin(s[1]), "z": -math.cos(s[0])}
    return [th, ph, wt, wp], f, obs


PEERS = [("pendulum-cartesian", pendulum), ("double-pendulum-cartesian", double_pendulum), ("rolling-disk", rolling_disk),
         ("chaplygin-sleigh", chaplygin), ("knife-edge-incline", knife_edge), ("bead-rotating-hoop", bead), ("josephson-lc", josephson),
         ("heisenberg-particle", heisenberg), ("cubic-damper", damper), ("spherical-pendulum-cartesian", spherical)]


def peer_run(y0, f, rtol, atol):
    return solve_ivp(f, (0.0, T), y0, method="DOP853", t_eval=TIMES, rtol=rtol, atol=atol)


def observed(sol, obs):
    rows = [obs(t, sol.y[:, k]) for k, t in enumerate(sol.t)]
    return {key: np.array([r[key] for r in rows]) for key in rows[0]}


def main():
    print("| scene | dcad s | scipy DOP853 s | ratio | dcad error | scipy error | dcad's own estimate | charts | drift |")
    print("|---|---|---|---|---|---|---|---|---|")
    ratios = []
    for name, make in PEERS:
        y0, f, obs = make()
        truth = observed(peer_run(y0, f, 1e-13, 1e-15), obs)
        best_scipy = math.inf
        for _ in range(3):
            t0 = time.perf_counter()
            sol = peer_run(y0, f, 1e-9, 1e-12)
            best_scipy = min(best_scipy, time.perf_counter() - t0)
        mine = observed(sol, obs)
        best_dcad, out, log = math.inf, "", ""
        for _ in range(3):
            t0 = time.perf_counter()
            try:
                p = subprocess.run([DCAD, "simulate", SCENES + name + ".json", "--tstop", str(T), "--step", str(H)], capture_output=True, text=True, timeout=300)
            except subprocess.TimeoutExpired:
                p = subprocess.CompletedProcess([], 124, "", "timed out after 300 s")
            best_dcad = min(best_dcad, time.perf_counter() - t0)
            out, log = p.stdout, p.stderr
            if p.returncode != 0:
                break
        if p.returncode != 0:
            print(f"| {name} | exit {p.returncode}: {log.strip().splitlines()[-1][:120]} | {best_scipy:.3f} | – | – | – | – | – | – |")
            continue
        rows = list(csv.DictReader(io.StringIO(out)))
        err_d = err_s = 0.0
        for key, col in truth.items():
            d = np.array([float(r[key]) for r in rows])
            if len(d) != len(col):
                raise SystemExit(f"{name}: dcad wrote {len(d)} rows, expected {len(col)}")
            scale = max(1.0, float(np.max(np.abs(col))))
            err_d = max(err_d, float(np.max(np.abs(d - col))) / scale)
            err_s = max(err_s, float(np.max(np.abs(mine[key] - col))) / scale)
        summary = [l for l in log.splitlines() if l.startswith("simulate: ") and "rows" in l]
        est = summary[-1].split("estimated error ")[1].split(" ")[0] if summary and "estimated error" in summary[-1] else "?"
        charts = summary[-1].split("(")[1].split(")")[0] if summary and "chart" in summary[-1] else "pointwise"
        drift = summary[-1].split("largest drift from M_c ")[1].split(" ")[0] if summary and "drift from M_c" in summary[-1] else "?"
        ratio = best_dcad / best_scipy
        ratios.append(ratio)
        print(f"| {name} | {best_dcad:.3f} | {best_scipy:.3f} | {ratio:.2f} | {err_d:.1e} | {err_s:.1e} | {float(est):.1e} | {charts} | {float(drift):.1e} |")
    print()
    print(f"median ratio dcad / scipy over {len(ratios)} scenes: {statistics.median(ratios):.2f} (best of 3 each; dcad's whole process, scipy's solve_ivp call)")


if __name__ == "__main__":
    main()

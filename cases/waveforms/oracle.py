#!/usr/bin/python3
"""Independent verdicts on a simulator's waveform for the decks of cases/waveforms/ (issue 28).

Each deck's equations are written here by hand from Kirchhoff's laws (nodal analysis, eliminated by
hand to an ODE), solved in closed form with mpmath at 30 digits — no dcad code, no netlist reader.
Sources are piecewise linear (PULSE), so on each piece x(t) = e^{A tau}(x0 - p) + p + q tau exactly
(eigendecomposition of A).  Outputs that involve a source's derivative are two-sided at its corners;
either side is accepted there, as the CONTRACT says.

    /usr/bin/python3 cases/waveforms/oracle.py DECK.cir RAW [--rtol 1e-3] [--emit OUT.csv]
prints the verdict per vector and exits 0 (every vector agrees) or 3 (one does not), like `dcad check`;
1 when the file has no time point.  With --emit it writes its own values at RAW's times instead (30
digits, rounded to double): a waveform for `dcad check` to hold its enclosures against.
RAW is an ngspice raw file (binary or ASCII), gnucap's `.print tran` output, or CSV with a time column.
"""
import bisect
import math
import struct
import sys

from mpmath import mp, mpf, matrix, eig, exp, cos, sin, sqrt, inverse

mp.dps = 30


# ------------------------------------------------------------------ ngspice raw
def read_raw(path):
    data = open(path, "rb").read()
    names, npoints, pos, binary = [], 0, 0, False
    while True:
        end = data.index(b"\n", pos)
        line = data[pos:end].decode("latin-1")
        pos = end + 1
        key = line.split(":")[0].strip().lower()
        if key == "no. points":
            npoints = int(line.split(":")[1])
        elif key == "variables":
            while True:
                end = data.index(b"\n", pos)
                parts = data[pos:end].decode("latin-1").split()
                if not parts or not parts[0].isdigit():
                    break
                names.append(parts[1].lower())
                pos = end + 1
        if key in ("binary", "values"):
            binary = key == "binary"
            break
    n = len(names)
    rows = []
    if binary:
        if npoints == 0:  # ngspice writes the count when the run ends: an aborted run leaves 0, its points after it
            npoints = (len(data) - pos) // (8 * n)
        for p in range(npoints):
            rows.append(struct.unpack_from("<%dd" % n, data, pos + 8 * n * p))
    else:
        words = data[pos:].decode("latin-1").split()
        k = 0
        for p in range(npoints):
            k += 1  # the point's index
            rows.append([float(w) for w in words[k:k + n]])
            k += n
    return names, rows


SCALE = {"a": 1e-18, "f": 1e-15, "p": 1e-12, "n": 1e-9, "u": 1e-6, "m": 1e-3, "K": 1e3, "k": 1e3, "Meg": 1e6, "G": 1e9, "T": 1e12}


def scaled(w):
    for suffix in ("Meg", "a", "f", "p", "n", "u", "m", "K", "k", "G", "T"):
        if w.endswith(suffix):
            return float(w[:-len(suffix)]) * SCALE[suffix]
    return float(w)


def read_gnucap(path):
    """gnucap's `.print tran` table: '#Time name…' and rows of numbers with scale letters."""
    names, rows = None, []
    for line in open(path):
        w = line.split()
        if names is None:
            if w and w[0].lower() == "#time":
                names = ["time"] + [x.lower() for x in w[1:]]
            continue
        if not w:
            continue
        if w[0].startswith("#"):  # the next analysis's header
            break
        try:
            rows.append([scaled(x) for x in w])
        except (ValueError, IndexError):
            continue  # a message between rows ("zero time step", "newtime=..."): the table goes on
    return names, rows


def read_csv(path):
    """CSV whose first column is time (`dcad cases export --waveforms`)."""
    lines = open(path).read().split()
    names = [x.lower() for x in lines[0].split(",")]
    return names, [[float(x) for x in line.split(",")] for line in lines[1:]]


# ------------------------------------------------------------------ piecewise-linear sources
def pulse(v1, v2, td, tr, tf, pw, per):
    """(breakpoints, value(t), slope(t, left)) of SPICE's PULSE over its first periods."""
    def value(t):
        if t <= td:
            return mpf(v1)
        t = (t - td) % per
        if t < tr:
            return v1 + (v2 - v1) * t / tr
        if t <= tr + pw:
            return mpf(v2)
        if t < tr + pw + tf:
            return v2 + (v1 - v2) * (t - tr - pw) / tf
        return mpf(v1)

    def slope(t, left=False):
        # the slope on the piece that ends at t (left) or starts there: a corner's own value is ambiguous
        t = t - mpf("1e-25") if left else t + mpf("1e-25")
        if t < td:
            return mpf(0)
        s = (t - td) % per
        if s < tr:
            return (v2 - v1) / tr
        if tr + pw <= s < tr + pw + tf:
            return (v1 - v2) / tf
        return mpf(0)

    breaks = []
    for k in range(200):
        for b in (0, tr, tr + pw, tr + pw + tf):
            breaks.append(td + k * per + b)
    return sorted(set(breaks)), value, slope


def pwl(points):
    """(breakpoints, value(t), slope(t, left)) of SPICE's PWL: linear between the points, constant outside."""
    ts, vs = [mpf(t) for t, _ in points], [mpf(v) for _, v in points]

    def piece(t):
        for k in range(len(ts) - 1):
            if ts[k] <= t < ts[k + 1]:
                return k
        return None

    def value(t):
        if t <= ts[0]:
            return vs[0]
        k = piece(t)
        if k is None:
            return vs[-1]
        return vs[k] + (vs[k + 1] - vs[k]) * (t - ts[k]) / (ts[k + 1] - ts[k])

    def slope(t, left=False):
        t = t - mpf("1e-25") if left else t + mpf("1e-25")
        k = piece(t)
        return mpf(0) if k is None else (vs[k + 1] - vs[k]) / (ts[k + 1] - ts[k])
    return sorted(t for t in ts if t >= 0), value, slope  # 0 too: the source is held before it (a corner at 0)


# ------------------------------------------------------------------ x' = A x + B0 u + B1 u', exactly
class Linear:
    def __init__(self, A, B0, B1, source, x0):
        self.A, self.B0, self.B1 = A, B0, B1
        self.breaks, self.u, self.du = source
        self.Ainv = inverse(A)
        lam, V = eig(A)
        self.lam, self.V, self.Vinv = lam, V, inverse(V)
        self.n = A.rows
        self.t, self.x = mpf(0), x0
        self.piece = None

    def advance(self, t):
        """The state at t >= the last time asked (piece by piece between the source's corners): on a
        piece with u = u0 + s tau, x = p + q tau + V diag(e^{lambda tau}) V^-1 (x0 - p), with
        q = -A^-1 B0 s and p = A^-1 (q - B0 u0 - B1 s)."""
        while self.t < t:
            k = bisect.bisect_right(self.breaks, self.t)
            nxt = min(self.breaks[k], t) if k < len(self.breaks) else t
            if self.piece is None:  # the source on this piece, read at its middle (a corner's own value is ambiguous)
                end = self.breaks[k] if k < len(self.breaks) else self.t + 1
                mid = (self.t + end) / 2
                s = self.du(mid)
                u0 = self.u(mid) - s * (mid - self.t)
                q = -self.Ainv * (self.B0 * s)
                p = self.Ainv * (q - self.B0 * u0 - self.B1 * s)
                self.piece = (self.t, p, q, self.Vinv * (self.x - p))
            t0, p, q, w = self.piece
            tau = nxt - t0
            e = self.V * matrix([w[i] * exp(self.lam[i] * tau) for i in range(self.n)])
            self.x = matrix([(e[i] + p[i] + q[i] * tau).real for i in range(self.n)])
            self.t = nxt
            if nxt != t or nxt in self.breaks:
                self.piece = None  # a corner: the next piece starts here
        return self.x


def rc_pulse():
    R, C = mpf(1000), mpf("1e-9")
    src = pulse(0, 1, mpf("1e-6"), mpf("1e-9"), mpf("1e-9"), mpf("1e-5"), mpf("2e-5"))
    # v_out' = (V - v_out)/(R C); from the operating point at t = 0 (V = 0): v_out = 0
    sys_ = Linear(matrix([[-1 / (R * C)]]), matrix([[1 / (R * C)]]), matrix([[0]]), src, matrix([0]))
    u, du = src[1], src[2]

    def outputs(t, x, left):
        V = u(t)
        return {"v(in)": V, "v(out)": x[0], "i(v1)": -(V - x[0]) / R}
    return sys_, outputs


def cap_triangle():
    C1, C2, C3 = mpf("1e-9"), mpf("2e-9"), mpf("3e-9")
    L1, L2, L3 = mpf("1e-6"), mpf("2e-6"), mpf("3e-6")
    R = mpf(100)
    src = pulse(0, mpf("1e-3"), mpf("1e-8"), mpf("1e-9"), mpf("1e-9"), mpf("5e-8"), mpf("2e-7"))
    # node potentials e_a, e_b, e_c; x = e_a - e_c, y = e_b - e_c; inductor currents to ground i1, i2,
    # i3 = I - i1 - i2 (KCL over the triangle).  KCL at a and b:
    #   (C1 + C3) x' - C1 y' = I - i1,     -C1 x' + (C1 + C2) y' = -y/R - i2,
    # and L_k i_k' = e_k with the common potential e_c from d/dt (i1 + i2 + i3) = I':
    #   x/L1 + y/L2 + e_c (1/L1 + 1/L2 + 1/L3) = I'.
    S = 1 / L1 + 1 / L2 + 1 / L3
    M = matrix([[C1 + C3, -C1], [-C1, C1 + C2]])
    Mi = inverse(M)
    # state z = (x, y, i1, i2); e_c = (I' - x/L1 - y/L2)/S
    A = matrix(4, 4)
    B0 = matrix(4, 1)
    B1 = matrix(4, 1)
    # x', y' = Mi [I - i1; -y/R - i2]
    for r in range(2):
        A[r, 2] = -Mi[r, 0]
        A[r, 1] = -Mi[r, 1] / R
        A[r, 3] = -Mi[r, 1]
        B0[r, 0] = Mi[r, 0]
    # i1' = (x + e_c)/L1, i2' = (y + e_c)/L2, e_c = (I' - x/L1 - y/L2)/S
    for r, (own, L) in enumerate(((0, L1), (1, L2))):
        A[2 + r, own] += 1 / L
        A[2 + r, 0] += -1 / (L1 * S * L)
        A[2 + r, 1] += -1 / (L2 * S * L)
        B1[2 + r, 0] = 1 / (S * L)
    sys_ = Linear(A, B0, B1, src, matrix([0, 0, 0, 0]))
    u, du = src[1], src[2]

    def outputs(t, z, left):
        x, y, i1, i2 = z[0], z[1], z[2], z[3]
        ec = (du(t, left) - x / L1 - y / L2) / S
        return {"v(a)": x + ec, "v(b)": y + ec, "v(c)": ec, "i(l1)": i1, "i(l2)": i2, "i(l3)": u(t) - i1 - i2}
    return sys_, outputs


def mixed_scale():
    R1, L1, C1, R2, C2, L2 = mpf("1e-3"), mpf("1e-12"), mpf("1e-6"), mpf("1e6"), mpf("1e-15"), mpf("1e-3")
    src = pulse(0, 1, mpf("1e-9"), mpf("1e-9"), mpf("1e-9"), mpf("1e-8"), mpf("4e-8"))
    # x = (i1, v_a, v_b, i2): L1 i1' = V - R1 i1 - v_a, C1 v_a' = i1 - (v_a - v_b)/R2,
    # C2 v_b' = (v_a - v_b)/R2 - i2, L2 i2' = v_b
    A = matrix([[-R1 / L1, -1 / L1, 0, 0],
                [1 / C1, -1 / (R2 * C1), 1 / (R2 * C1), 0],
                [0, 1 / (R2 * C2), -1 / (R2 * C2), -1 / C2],
                [0, 0, 1 / L2, 0]])
    B0 = matrix([[1 / L1], [0], [0], [0]])
    sys_ = Linear(A, B0, matrix(4, 1), src, matrix([0, 0, 0, 0]))
    u = src[1]

    def outputs(t, x, left):
        V = u(t)
        return {"v(in)": V, "v(x)": V - R1 * x[0], "v(a)": x[1], "v(b)": x[2], "i(v1)": -x[0], "i(l1)": x[0], "i(l2)": x[3]}
    return sys_, outputs


def transformer_k1():
    w = sqrt(mpf("2e13"))

    class Closed:
        breaks = []
        jump = True  # the state jumps onto M_c at t = 0: a simulator shows it before at 0, then smears it over one step

        def advance(self, t):
            return t

    def outputs(t, _, left):
        # after the jump at t = 0 (flux kept): p1 = 1e-8 cos(w t), v(a) = p1', v(b) = 2 v(a);
        # KCL: i(L1) = -C1 v(a)' = 0.2m cos(w t), i(L2) = -C2 v(b)' = 0.4m cos(w t)
        va = -mpf("1e-8") * w * sin(w * t)
        return {"v(a)": va, "v(b)": 2 * va, "i(l1)": mpf("2e-4") * cos(w * t), "i(l2)": mpf("4e-4") * cos(w * t)}
    return Closed(), outputs


def pwl_rlc():
    R, L, C1, C2 = mpf(50), mpf("1e-7"), mpf("2e-11"), mpf("5e-12")
    src = pwl([(0, 0), ("1e-9", 1), ("3e-9", 1), ("3.5e-9", "-0.5"), ("6e-9", 0)])
    # x = (i, v_b): L i' = V - R i - v_b, C1 v_b' = i
    sys_ = Linear(matrix([[-R / L, -1 / L], [1 / C1, 0]]), matrix([[1 / L], [0]]), matrix(2, 1), src, matrix([0, 0]))
    u, du = src[1], src[2]

    def outputs(t, x, left):
        V = u(t)
        return {"v(in)": V, "v(a)": V - R * x[0], "v(b)": x[1], "i(l1)": x[0], "i(v1)": -(x[0] + C2 * du(t, left))}
    return sys_, outputs


def lc_tank():
    L, C = mpf("1e-6"), mpf("1e-9")
    w = 1 / sqrt(L * C)

    class Closed:
        breaks = []

        def advance(self, t):
            return t

    wf, cf = float(w), float(C)

    def outputs(t, _, left):
        # C v' = -i_L (the inductor's current leaves a), L i_L' = v: v = cos(w t), i_L = C w sin(w t);
        # in double (math): w t < 7e3 loses at most 1e-12, and 2e5 points at 30 digits take minutes;
        # at 30 digits with --emit (which is asked for few points)
        if EMIT:
            return {"v(a)": cos(w * t), "i(l1)": C * w * sin(w * t)}
        tf = float(t)
        return {"v(a)": math.cos(wf * tf), "i(l1)": cf * wf * math.sin(wf * tf)}
    return Closed(), outputs


EMIT = None  # --emit OUT.csv: write the exact values at the file's times instead of a verdict

DECKS = {"rc-pulse": rc_pulse, "cap-triangle-inductor-cutset": cap_triangle, "lc-tank-1000-periods": lc_tank, "lc-tank-10000-periods": lc_tank, "mixed-scale-rlc": mixed_scale, "transformer-k1": transformer_k1, "pwl-rlc": pwl_rlc}


def main():
    args = sys.argv[1:]
    rtol = mpf("1e-3")
    if "--rtol" in args:
        k = args.index("--rtol")
        rtol = mpf(args[k + 1])
        del args[k:k + 2]
    global EMIT
    if "--emit" in args:
        k = args.index("--emit")
        EMIT = args[k + 1]
        del args[k:k + 2]
    deck, raw = args
    name = deck.rsplit("/", 1)[-1].rsplit(".", 1)[0]
    system, outputs = DECKS[name]()
    head = open(raw, "rb").read(6).lower()
    names, rows = read_raw(raw) if head == b"title:" else read_csv(raw) if head.startswith(b"time,") else read_gnucap(raw)
    if not rows or not names:
        print("no time point in " + raw)
        sys.exit(1)
    breaks = sorted(getattr(system, "breaks", []))
    exact = {}  # name -> list of (right, left)
    for row in rows:
        t = mpf(abs(row[0]))
        x = system.advance(t)
        right = outputs(t, x, False)
        k = bisect.bisect_left(breaks, t * (1 - mpf("1e-12")))
        corner = [b for b in breaks[k:k + 2] if abs(t - b) <= mpf("1e-12") * t]
        if corner:  # either one-sided value: the sources' slopes just before and just after the corner
            right, left = outputs(corner[0], x, False), outputs(corner[0], x, True)
        else:
            left = right
        for k in right:
            exact.setdefault(k, []).append((right[k], left[k]))
    if EMIT:  # the right values at every time of the file, rounded to the nearest double, as CSV
        keys = sorted(exact)
        with open(EMIT, "w") as out:
            out.write(",".join(["time"] + keys) + "\n")
            for i, row in enumerate(rows):
                out.write(",".join([repr(float(row[0]))] + [repr(float(exact[k][i][0])) for k in keys]) + "\n")
        sys.exit(0)
    agree = True
    for j, n in enumerate(names[1:], start=1):
        if n not in exact:
            continue
        scale = max(max(abs(r), abs(l)) for r, l in exact[n])
        worst, at = mpf(0), 0
        first = min([row[0] for row in rows if row[0] > 0], default=0)
        for i, row in enumerate(rows):
            if getattr(system, "jump", False) and row[0] <= first:
                continue  # t = 0 and the first step, as dcad check skips them after a jump
            r, l = exact[n][i]
            err = min(abs(row[j] - r), abs(row[j] - l))
            if err > worst:
                worst, at = err, row[0]
        ok = worst <= rtol * scale
        agree = agree and ok
        print("%-9s %-8s largest error %.3e of %.3e at t = %.6e" % ("agrees" if ok else "DISAGREES", n, float(worst), float(scale), at))
    sys.exit(0 if agree else 3)


if __name__ == "__main__":
    main()

"""The machine's limit for a motoneuron pool's arithmetic: the reduced motoneuron's fixed-step update (the
equations of mn_soma and mn_pic with their tables, the leak, the common synaptic conductance, the implicit cable
solve of its four compartments and the spike threshold) written as one C loop over N cells (structure of arrays),
compiled with the system's C compiler (the one nrnivmodl uses) and timed in ns per cell-step on one core.

``neuromuscle bench pool`` runs it before and after its pools (:func:`probe_ns`), so that a pool's cost per
cell-step is read beside what the same arithmetic costs on the same host at the same time; a shared host's speed
changes from hour to hour.  ``docs/validation/motoneuron_limit.py`` checks the loop against NEURON on the same cells
(spike counts and first spikes) and times its vectorised build too.  Units: ms, uS, ns.
"""

from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path

#: The probe's pool: cells, simulated time (ms), step (ms) and each cell's constant synaptic conductance (uS).
PROBE = {"n": 800, "duration_ms": 200.0, "dt_ms": 0.025, "g_uS": 0.3}


C_SOURCE = r"""
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* the reduced motoneuron (neuromuscle.pool.motoneuron): soma + 3 dendritic compartments, fused channels */
#define VMIN (-120.0)
#define VMAX 80.0
#define NT 8000
#define XMIN (-60.0)
#define XMAX 60.0
#define NX 12000
#define FARADAY 96485.33212331001

static double vtrap(double x, double y) {
    return fabs(x / y) < 1e-6 ? y * (1 + x / y / 2) : x / (1 - exp(-x / y));
}
static void rates(double v, double dt, double *r) {   /* minf mfac hinf hfac ninf nfac pinf qinf */
    double a = 0.4 * vtrap(v + 49, 5), b = 0.4 * vtrap(-(v + 25), 5);
    double mtau = 1 / (a + b), htau = 30 / (exp((v + 60) / 15) + exp(-(v + 60) / 16));
    double ntau = 5 / (exp((v + 50) / 40) + exp(-(v + 50) / 50));
    r[0] = a / (a + b); r[1] = 1 - exp(-dt / mtau);
    r[2] = 1 / (1 + exp((v + 58) / 7)); r[3] = 1 - exp(-dt / htau);
    r[4] = 1 / (1 + exp(-(v + 31) / 15)); r[5] = 1 - exp(-dt / ntau);
    r[6] = 1 / (1 + exp(-(v + 25) / 5)); r[7] = 1 / (1 + exp((v + 43) / 5));
}
static double geo(double lo, double hi, double x) { return lo * exp(x * log(hi / lo)); }

int main(int argc, char **argv) {
    int N = atoi(argv[1]); double T = atof(argv[2]), dt = atof(argv[3]), gsyn = atof(argv[4]);
    const char *out = argc > 5 ? argv[5] : NULL;
    int steps = (int)(T / dt + 0.5);
    static double tab[NT + 1][8]; static double ltab[NX + 1];
    for (int i = 0; i <= NT; i++) rates(VMIN + i * (VMAX - VMIN) / NT, dt, tab[i]);
    for (int i = 0; i <= NX; i++) ltab[i] = 1 / (1 + exp(-(XMIN + i * (XMAX - XMIN) / NX)));
    /* per cell, structure of arrays: 4 compartments (0 soma, 1-3 dendrite) */
    double *v[4], *C[4], *gl[4], *gs[4], *area[4], *mp[4], *gpic[4], *G[3];
    double *m = malloc(N * 8), *h = malloc(N * 8), *n = malloc(N * 8), *p = malloc(N * 8), *q = malloc(N * 8);
    double *cai = malloc(N * 8), *ica = malloc(N * 8), *cfac = malloc(N * 8), *taur = malloc(N * 8);
    double *above = malloc(N * 8), *first = malloc(N * 8); long *count = calloc(N, sizeof(long));
    for (int k = 0; k < 4; k++) {
        v[k] = malloc(N * 8); C[k] = malloc(N * 8); gl[k] = malloc(N * 8); gs[k] = malloc(N * 8);
        area[k] = malloc(N * 8); mp[k] = malloc(N * 8); gpic[k] = malloc(N * 8);
        if (k < 3) G[k] = malloc(N * 8);
    }
    const double Ra = 70, cm = 1, el = -70, ena = 50, ek = -80, eca = 80, erev = 60, vhalf = -57, slope = 4;
    const double gnaf = 0.6, gkdr = 0.15, gcan = 0.01, gkca = 0.012, kd = 0.002, depth = 1;
    const double pfac = 1 - exp(-dt / 15), qfac = 1 - exp(-dt / 50), mfacp = 1 - exp(-dt / 60), gpicd = 0.6 * 6e-5;
    for (int c = 0; c < N; c++) {
        double x = N > 1 ? (double)c / (N - 1) : 0;
        double ds = geo(55, 80, x), L = geo(3500, 4200, x), dd = geo(25, 38, x);
        double rms = geo(600, 250, x), rmd = geo(8000, 4500, x);
        double seg = L / 3, tot;
        taur[c] = geo(45, 12, x); cfac[c] = 1 - exp(-dt / taur[c]);
        area[0][c] = M_PI * ds * ds;
        for (int k = 1; k < 4; k++) area[k][c] = M_PI * dd * seg;
        tot = area[0][c] + 3 * area[1][c];
        for (int k = 0; k < 4; k++) {
            C[k][c] = cm * area[k][c] * 1e-5;                       /* nF */
            gl[k][c] = (k ? 1 / rmd : 1 / rms) * area[k][c] * 1e-2;  /* uS */
            gs[k][c] = gsyn * area[k][c] / tot;                      /* uS */
            gpic[k][c] = k ? gpicd * area[k][c] * 1e-2 : 0;
            v[k][c] = el; mp[k][c] = 1 / (1 + exp(-(el - vhalf) / slope));
        }
        /* axial conductances (uS): soma centre to the first dendritic node through half of each */
        double rs = Ra * (ds / 2) * 1e-2 / (M_PI * ds * ds / 4), rd = Ra * (seg / 2) * 1e-2 / (M_PI * dd * dd / 4);
        G[0][c] = 1 / (rs + rd); G[1][c] = G[2][c] = 1 / (2 * rd);
        double r[8]; rates(el, dt, r);
        m[c] = r[0]; h[c] = r[2]; n[c] = r[4]; p[c] = r[6]; q[c] = r[7]; cai[c] = 0; ica[c] = 0;
        above[c] = 0; first[c] = -1;
    }
    struct timespec t0, t1; clock_gettime(CLOCK_MONOTONIC, &t0);
    for (int s = 0; s < steps; s++) {
        double t = (s + 1) * dt;
        #pragma GCC ivdep
        for (int c = 0; c < N; c++) {
            /* currents at v (nA) and their conductances (uS), then the 4-node implicit solve (dv) */
            double v0 = v[0][c], v1 = v[1][c], v2 = v[2][c], v3 = v[3][c], A0 = area[0][c] * 1e-2;
            double gna = gnaf * m[c] * m[c] * m[c] * h[c], n2 = n[c] * n[c];
            double gk = gkdr * n2 * n2 + gkca * cai[c] / (cai[c] + kd), gca = gcan * p[c] * p[c] * q[c];
            ica[c] = gca * (v0 - eca);
            double g0 = (gna + gk + gca) * A0 + gl[0][c] + gs[0][c];
            double i0 = (gna * (v0 - ena) + gk * (v0 - ek) + ica[c]) * A0 + gl[0][c] * (v0 - el) + gs[0][c] * v0;
            double gp1 = gpic[1][c] * mp[1][c], gp2 = gpic[2][c] * mp[2][c], gp3 = gpic[3][c] * mp[3][c];
            double g1 = gp1 + gl[1][c] + gs[1][c], g2 = gp2 + gl[2][c] + gs[2][c], g3 = gp3 + gl[3][c] + gs[3][c];
            double i1 = gp1 * (v1 - erev) + gl[1][c] * (v1 - el) + gs[1][c] * v1;
            double i2 = gp2 * (v2 - erev) + gl[2][c] * (v2 - el) + gs[2][c] * v2;
            double i3 = gp3 * (v3 - erev) + gl[3][c] * (v3 - el) + gs[3][c] * v3;
            double Ga = G[0][c], Gb = G[1][c], Gc = G[2][c];
            double b0 = -i0 - Ga * (v0 - v1), b1 = -i1 - Ga * (v1 - v0) - Gb * (v1 - v2);
            double b2 = -i2 - Gb * (v2 - v1) - Gc * (v2 - v3), b3 = -i3 - Gc * (v3 - v2);
            double d0 = C[0][c] / dt + g0 + Ga, d1 = C[1][c] / dt + g1 + Ga + Gb;
            double d2 = C[2][c] / dt + g2 + Gb + Gc, d3 = C[3][c] / dt + g3 + Gc;
            /* eliminate from the leaf (3) to the soma (0), then back */
            double f = Gc / d3; d2 -= f * Gc; b2 += f * b3;
            f = Gb / d2; d1 -= f * Gb; b1 += f * b2;
            f = Ga / d1; d0 -= f * Ga; b0 += f * b1;
            double x0 = b0 / d0, x1 = (b1 + Ga * x0) / d1, x2 = (b2 + Gb * x1) / d2, x3 = (b3 + Gc * x2) / d3;
            v0 += x0; v1 += x1; v2 += x2; v3 += x3;
            v[0][c] = v0; v[1][c] = v1; v[2][c] = v2; v[3][c] = v3;
            /* the states at the new v (tables, linear interpolation) */
            double xi = (v0 - VMIN) * (NT / (VMAX - VMIN));
            xi = xi < 0 ? 0 : (xi > NT - 1e-9 ? NT - 1e-9 : xi);
            int j = (int)xi; double th = xi - j;
            const double *a = tab[j], *b = tab[j + 1];
            double minf = a[0] + th * (b[0] - a[0]), mfac = a[1] + th * (b[1] - a[1]);
            double hinf = a[2] + th * (b[2] - a[2]), hfac = a[3] + th * (b[3] - a[3]);
            double ninf = a[4] + th * (b[4] - a[4]), nfac = a[5] + th * (b[5] - a[5]);
            double pinf = a[6] + th * (b[6] - a[6]), qinf = a[7] + th * (b[7] - a[7]);
            m[c] += mfac * (minf - m[c]); h[c] += hfac * (hinf - h[c]); n[c] += nfac * (ninf - n[c]);
            p[c] += pfac * (pinf - p[c]); q[c] += qfac * (qinf - q[c]);
            cai[c] += cfac[c] * (taur[c] * (-10000.0 * ica[c] / (2 * FARADAY * depth)) - cai[c]);
            double vv[3] = {v1, v2, v3};
            for (int k = 1; k < 4; k++) {
                double y = ((vv[k - 1] - vhalf) / slope - XMIN) * (NX / (XMAX - XMIN));
                y = y < 0 ? 0 : (y > NX - 1e-9 ? NX - 1e-9 : y);
                int jj = (int)y; double sinf = ltab[jj] + (y - jj) * (ltab[jj + 1] - ltab[jj]);
                mp[k][c] += mfacp * (sinf - mp[k][c]);
            }
            /* the spike threshold (-10 mV, upward) */
            double up = v0 >= -10.0;
            if (up > above[c]) { count[c]++; if (first[c] < 0) first[c] = t; }
            above[c] = up;
        }
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double s = (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec);
    long total = 0; for (int c = 0; c < N; c++) total += count[c];
    printf("%.9f %ld\n", s * 1e9 / ((double)N * steps), total);
    if (out) {
        FILE *fo = fopen(out, "w");
        for (int c = 0; c < N; c++) fprintf(fo, "%ld %.6f\n", count[c], first[c]);
        fclose(fo);
    }
    return 0;
}
"""

#: The two builds: (label, compiler flags).
BUILDS = [("C loop, -O3 (scalar)", ["-O3", "-fno-tree-vectorize"]),
          ("C loop, -O3 -march=native -ffast-math (vectorised)", ["-O3", "-march=native", "-ffast-math"])]


def compile_loop(folder: Path, flags: list[str], name: str) -> Path:
    """Compile C_SOURCE with ``flags`` into folder/name; returns the executable's path."""
    src = folder / "mn_loop.c"
    src.write_text(C_SOURCE)
    exe = folder / name
    subprocess.run([os.environ.get("CC", "cc"), *flags, "-o", str(exe), str(src), "-lm"], check=True)
    return exe


def run_loop(exe: Path, n: int, duration_ms: float, dt_ms: float, g_uS: float, out: Path) -> tuple[float, int]:
    """Run the compiled loop: (ns per cell-step, spikes); per-cell spike counts and first spikes (ms) to out."""
    text = subprocess.run([str(exe), str(n), str(duration_ms), str(dt_ms), str(g_uS), str(out)], check=True,
                          capture_output=True, text=True).stdout.split()
    return float(text[0]), int(text[1])


def probe_ns(n: int = PROBE["n"], duration_ms: float = PROBE["duration_ms"], dt_ms: float = PROBE["dt_ms"],
             g_uS: float = PROBE["g_uS"]) -> float | None:
    """ns per cell-step of the scalar C loop (BUILDS[0]) for n cells over duration_ms (ms) at dt_ms (ms), or None
    when it cannot be built or run here (no C compiler): the probe only annotates a benchmark, never stops it."""
    with tempfile.TemporaryDirectory(prefix="neuromuscle-limit.") as tmp:
        folder = Path(tmp)
        try:
            exe = compile_loop(folder, BUILDS[0][1], "loop")
            ns, _ = run_loop(exe, n, duration_ms, dt_ms, g_uS, folder / "out.txt")
        except (OSError, subprocess.CalledProcessError, ValueError, IndexError):
            return None
    return ns

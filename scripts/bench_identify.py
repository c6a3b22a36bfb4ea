#!/usr/bin/env python3
"""frfup identify against sdypy-EMA (LSCF + stabilisation + LSFD) on
campaigns with known modes, and speed on a GARTEUR-like campaign and a long
record. Usage: bench_identify.py FRFUP_BIN WORKDIR [--cases N] [--seed S]
[--garteur UFF]. Prints a Markdown report.

Cases: modal models synthesised exactly (real normal modes, viscous damping,
unit modal masses, accelerance, 1001 lines 0-250 Hz, one reference), 3-6
modes in 10-200 Hz, zeta 0.5-3 %, 10 outputs, complex Gaussian noise of
1-3 % of each channel's RMS; every third case adds a close pair (two modes
zeta f apart: within each other's half-power bandwidth), every third a weak mode
(shape scaled by 1/15). sdypy-EMA is used as its documentation shows:
Model(...).get_poles(), select_closest_poles(approx_nat_freq) (given the
TRUE frequencies: it has no automatic selection), get_constants(); frfup
gets nothing but the file.
"""
import argparse
import os
import subprocess
import sys
import time
import warnings

import numpy as np
import pyuff

warnings.filterwarnings("ignore")
TWO_PI = 2 * np.pi


def synthesise(freqs, zetas, shapes, f):
    w = TWO_PI * f
    h = np.zeros((shapes.shape[1], len(f)), complex)
    for r in range(len(freqs)):
        wr = TWO_PI * freqs[r]
        den = wr**2 - w**2 + 2j * zetas[r] * wr * w
        h += np.outer(shapes[r] * shapes[r][0], 1.0 / den)
    return h * (1j * w) ** 2


def make_case(rng, kind):
    n = rng.integers(3, 7)
    while True:
        freqs = np.sort(rng.uniform(10, 200, n))
        if np.all(np.diff(freqs) / freqs[1:] > 0.08):
            break
    zetas = rng.uniform(0.005, 0.03, n)
    n_out = 10
    shapes = rng.uniform(-1, 1, (n, n_out))
    shapes[:, 0] = np.sign(shapes[:, 0]) * rng.uniform(0.4, 1.0, n)
    if kind == "close":
        # A pair within each other's half-power bandwidth: 1 zeta f apart
        # (the bandwidth is 2 zeta f), at least 3 lines apart.
        fc, zc = rng.uniform(80, 180), rng.uniform(0.01, 0.025)
        keep = np.abs(freqs - fc) / fc > 0.08
        freqs, zetas, shapes = freqs[keep], zetas[keep], shapes[keep]
        freqs = np.append(freqs, [fc, fc * (1 + zc)])
        zetas = np.append(zetas, [zc, zc])
        pair = rng.uniform(-1, 1, (2, n_out))
        pair[:, 0] = [0.8, 0.6]
        shapes = np.vstack([shapes, pair])
    if kind == "weak":
        k = rng.integers(0, n)
        shapes[k] /= 15.0 ** 0.5
    order = np.argsort(freqs)
    return freqs[order], zetas[order], shapes[order]


def noisy(h, level, rng):
    out = h.copy()
    for c in range(h.shape[0]):
        rms = np.sqrt(np.mean(np.abs(h[c]) ** 2))
        s = level * rms / np.sqrt(2)
        out[c] += s * (rng.standard_normal(h.shape[1]) + 1j * rng.standard_normal(h.shape[1]))
    return out


def write_uff(path, f, h):
    if os.path.exists(path):
        os.remove(path)
    u = pyuff.UFF(path)
    sets = []
    for c in range(h.shape[0]):
        sets.append(pyuff.prepare_58(
            binary=0, id1="synthesised", func_type=4, rsp_node=c + 1, rsp_dir=3,
            ref_node=1, ref_dir=3, ord_data_type=6, data=h[c], x=f,
            abscissa_spacing=1, abscissa_spec_data_type=18, ordinate_spec_data_type=12,
            orddenom_spec_data_type=13))
    u.write_sets(sets, mode="add")


def run_frfup(binary, uff, out):
    t = time.perf_counter()
    subprocess.run([binary, "identify", uff, "--out", out, "--quiet"], check=True)
    dt = time.perf_counter() - t
    rows = [l.split(",") for l in open(os.path.join(out, "modes.csv")).read().splitlines()[1:]]
    freqs = np.array([float(r[1]) for r in rows])
    zetas = np.array([float(r[2]) for r in rows])
    sh = [l.split(",") for l in open(os.path.join(out, "shapes.csv")).read().splitlines()[1:]]
    nodes = [int(r[0]) for r in sh]
    shapes = np.zeros((len(freqs), len(nodes)))
    for o, r in enumerate(sh):
        for m in range(len(freqs)):
            # Synthesised cases number their outputs 1..n; others by row.
            col = nodes[o] - 1 if max(nodes) <= len(nodes) else o
            shapes[m, col] = float(r[3 + 3 * m])
    return freqs, zetas, shapes, dt


def run_sdypy(uff, approx, f_lo, f_hi, order=60):
    from sdypy import EMA
    t = time.perf_counter()
    sets = pyuff.UFF(uff).read_sets()
    sets = sets if isinstance(sets, list) else [sets]
    f = np.asarray(sets[0]["x"])
    h = np.array([s["data"] for s in sets])
    try:
        m = EMA.Model(frf=h, freq=f, lower=f_lo, upper=f_hi, pol_order_high=order,
                      frf_form="accelerance")
        m.get_poles(show_progress=False)
        m.select_closest_poles(approx)
        _, a = m.get_constants(whose_poles="own")
    except Exception as e:  # a failed fit counts its modes as missed
        print(f"sdypy-EMA failed: {e}", file=sys.stderr)
        return np.zeros(0), np.zeros(0), np.zeros((0, h.shape[0])), time.perf_counter() - t
    dt = time.perf_counter() - t
    shapes = np.real(a * np.exp(-1j * np.angle(a[np.argmax(np.abs(a), axis=0), range(a.shape[1])]))).T
    return np.asarray(m.nat_freq), np.asarray(m.nat_xi), shapes, dt


def mac(a, b):
    return abs(a @ b) ** 2 / ((a @ a) * (b @ b))


def score(truth, found):
    tf, tz, ts = truth
    ff, fz, fs = found[:3]
    used, errs = set(), []
    for r in range(len(tf)):
        best = None
        for k in range(len(ff)):
            if k in used:
                continue
            if abs(ff[k] - tf[r]) > 3 * tz[r] * tf[r]:
                continue
            m = mac(fs[k], ts[r])
            if best is None or m > best[1]:
                best = (k, m)
        if best is not None and best[1] > 0.5:
            used.add(best[0])
            k = best[0]
            errs.append((abs(ff[k] / tf[r] - 1), abs(fz[k] / tz[r] - 1), best[1]))
    missed = len(tf) - len(errs)
    spurious = len(ff) - len(used)
    return errs, missed, spurious


def accuracy(args, rng):
    stats = {"frfup": [], "sdypy-EMA": []}
    f = np.linspace(0, 250, 1001)[1:]
    for i in range(args.cases):
        kind = ["random", "close", "weak"][i % 3]
        truth = make_case(rng, kind)
        h = noisy(synthesise(*truth, f), rng.uniform(0.01, 0.03), rng)
        uff = os.path.join(args.workdir, f"case{i}.uff")
        write_uff(uff, f, h)
        res = {"frfup": run_frfup(args.frfup, uff, os.path.join(args.workdir, f"out{i}")),
               "sdypy-EMA": run_sdypy(uff, list(truth[0]), 5.0, 240.0)}
        print(f"case {i} ({kind}) done", file=sys.stderr)
        for k, v in res.items():
            errs, missed, spurious = score(truth, v)
            stats[k].append((kind, errs, missed, spurious, v[3]))
    return stats


def table(stats):
    print("| method | mean freq. error | mean damping error | mean MAC | cases within targets* | missed modes | spurious modes | mean time (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for k, rows in stats.items():
        errs = [e for r in rows for e in r[1]]
        ef = np.mean([e[0] for e in errs]) if errs else float("nan")
        ez = np.mean([e[1] for e in errs]) if errs else float("nan")
        em = np.mean([e[2] for e in errs]) if errs else float("nan")
        ok = sum(1 for r in rows if r[2] == 0 and r[3] == 0 and all(
            e[0] < 5e-4 and e[1] < 0.05 and e[2] >= 0.995 for e in r[1]))
        missed = sum(r[2] for r in rows)
        spur = sum(r[3] for r in rows)
        t = np.mean([r[4] for r in rows])
        print(f"| {k} | {100*ef:.4f} % | {100*ez:.2f} % | {em:.5f} | {ok}/{len(rows)} | {missed} | {spur} | {t:.3f} |")
    print("\n*within targets: every mode found, none spurious, each within 0.05 % in frequency, 5 % in damping, MAC >= 0.995.")


def median_time(run, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        run()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def sdypy_once(uff, freqs, out):
    """One whole sdypy-EMA job as a user's script runs it (the imports,
    reading, poles, selection at `freqs`, residues, a modes file): the peer's
    side of the whole-process figure."""
    from sdypy import EMA
    sets = pyuff.UFF(uff).read_sets()
    sets = sets if isinstance(sets, list) else [sets]
    f = np.asarray(sets[0]["x"])
    h = np.array([s["data"] for s in sets])
    m = EMA.Model(frf=h, freq=f, lower=max(f[0], f[1]), upper=f[-1], pol_order_high=60,
                  frf_form="accelerance")
    m.get_poles(show_progress=False)
    m.select_closest_poles(freqs)
    m.get_constants(whose_poles="own")
    np.savetxt(out, np.c_[m.nat_freq, m.nat_xi], delimiter=",")


def speed(args, rng):
    """Two figures per campaign, medians of `--repeats` runs each:
    whole process (a new process per run for both tools: frfup's binary, and
    a Python interpreter that imports pyuff and sdypy-EMA, reads, identifies
    and writes its modes) and, for sdypy-EMA, the warm in-process time (the
    same job in this interpreter after one warm-up run: what a notebook user
    waits for once the imports are paid)."""
    print("\n| campaign | frfup, whole process (s) | sdypy-EMA, whole process (s) | ratio "
          "| sdypy-EMA in a warm interpreter (s) | ratio |\n|---|---|---|---|---|---|")
    cases = []
    if args.garteur:
        cases.append(("GARTEUR-like fixture (26 channels x 801 lines)", args.garteur))
    f = np.linspace(0, 500, 50001)[1:]
    truth = make_case(rng, "random")
    h = noisy(synthesise(truth[0], truth[1], truth[2], f), 0.02, rng)
    long_uff = os.path.join(args.workdir, "long.uff")
    write_uff(long_uff, f, h)
    cases.append(("long record (10 channels x 50,000 lines)", long_uff))
    for name, uff in cases:
        out = os.path.join(args.workdir, "speed-" + os.path.basename(uff))
        ff = run_frfup(args.frfup, uff, out)[0]
        t1 = median_time(lambda: run_frfup(args.frfup, uff, out), args.repeats)
        approx = ",".join(f"{x:.6f}" for x in ff)
        modes = os.path.join(args.workdir, "sdypy-modes.csv")
        once = [sys.executable, os.path.abspath(__file__), "--sdypy-once", uff, approx, modes]
        t2 = median_time(lambda: subprocess.run(once, check=True, stderr=subprocess.DEVNULL),
                         args.repeats)
        sets = pyuff.UFF(uff).read_sets()
        x = np.asarray(sets[0]["x"])
        run_sdypy(uff, list(ff), max(x[0], x[1]), x[-1])
        t3 = median_time(lambda: run_sdypy(uff, list(ff), max(x[0], x[1]), x[-1]), args.repeats)
        print(f"| {name} | {t1:.3f} | {t2:.2f} | {t2 / t1:.0f}x | {t3:.3f} | {t3 / t1:.1f}x |")


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "--sdypy-once":
        sdypy_once(sys.argv[2], [float(v) for v in sys.argv[3].split(",")], sys.argv[4])
        return 0
    p = argparse.ArgumentParser()
    p.add_argument("frfup")
    p.add_argument("workdir")
    p.add_argument("--cases", type=int, default=30)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--garteur")
    p.add_argument("--speed-only", action="store_true")
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    rng = np.random.default_rng(args.seed)
    print(f"## frfup identify vs sdypy-EMA ({args.cases} cases, seed {args.seed})\n")
    if not args.speed_only:
        table(accuracy(args, rng))
    speed(args, rng)


if __name__ == "__main__":
    sys.exit(main())

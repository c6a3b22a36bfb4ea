#!/usr/bin/env python3
"""SciPy reference for bench_eigen.sh: eigsh(K, N, M, sigma=σ, which='LM') on
the K.mtx / M.mtx exported by `bench_eigen --export DIR`.

σ: `initial` (default) is DIR/shift0.txt, the σ₀ ≈ 0 below the spectrum that
frfup itself starts from, i.e. what a caller asking for the lowest modes
passes (SciPy's documented sigma=0 for modes near zero, here
−min(1e-8·max, 1e-4·median) of K_ii/M_ii); `final` is DIR/shift.txt, the shift frfup's probe moved to just
below the lowest ω², which hands SciPy the result of frfup's extra
factorisation for free.

Usage: bench_eigen_scipy.py DIR N [initial|final]
Prints one JSON line: seconds, peak RSS (MB) and the largest relative
difference between SciPy's and frfup's ω² (DIR/omega2.txt).
"""
import json
import resource
import sys
import time

import numpy as np
import scipy.io
import scipy.sparse.linalg as sla

d, n = sys.argv[1], int(sys.argv[2])
k = scipy.io.mmread(f"{d}/K.mtx").tocsc()
m = scipy.io.mmread(f"{d}/M.mtx").tocsc()
which = sys.argv[3] if len(sys.argv) > 3 else "initial"
sigma = float(open(f"{d}/{'shift0' if which == 'initial' else 'shift'}.txt").read())
ours = np.loadtxt(f"{d}/omega2.txt")
t = time.perf_counter()
w, _ = sla.eigsh(k, n, m, sigma=sigma, which="LM")
secs = time.perf_counter() - t
w = np.sort(w)
rel = float(np.max(np.abs(w - ours[: len(w)]) / np.abs(ours[: len(w)])))
print(json.dumps({
    "dir": d, "n": k.shape[0], "count": n, "shift": which, "sigma": sigma, "scipy_s": round(secs, 3),
    "scipy_peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024),
    "max_rel_diff_omega2_vs_frfup": rel,
}))

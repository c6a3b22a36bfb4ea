#!/usr/bin/env python3
"""SciPy reference for bench_eigen.sh: eigsh(K, N, M, sigma=σ, which='LM') on
the K.mtx / M.mtx / shift.txt exported by `bench_eigen --export DIR`.

Usage: bench_eigen_scipy.py DIR N
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
sigma = float(open(f"{d}/shift.txt").read())
ours = np.loadtxt(f"{d}/omega2.txt")
t = time.perf_counter()
w, _ = sla.eigsh(k, n, m, sigma=sigma, which="LM")
secs = time.perf_counter() - t
w = np.sort(w)
rel = float(np.max(np.abs(w - ours[: len(w)]) / np.abs(ours[: len(w)])))
print(json.dumps({
    "dir": d, "n": k.shape[0], "count": n, "sigma": sigma, "scipy_s": round(secs, 3),
    "scipy_peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024),
    "max_rel_diff_omega2_vs_frfup": rel,
}))

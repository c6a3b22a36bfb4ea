#!/usr/bin/env python3
"""Straightforward NumPy/SciPy implementation of the same FRF updating
iterations as frfup (Yan & Golinval Eq. 7-12, 29, 32-34, 40-41, 45-46, 49),
for speed and consistency comparison.

Reads the problem exported by `update_bench garteur` (examples/update_bench.rs):
K0, M0, dK_j, dM_j as COO triplets (.npy), measured DOF indices, updating
frequencies, measured signed real displacement FRFs h_test, options.

Each iteration: K = K0 + sum_j pbar_j dK_j (stiffness parameters are linear in
their property), dense scipy.linalg.eigh for the lowest modes, SEREP basis by
ordered Gram-Schmidt on the measured partition, H = Psi_m diag(1/(lam - w^2))
Psi_m^T, A_i = H * Psi_m^+T * (Psi^T dZ_j Psi) * Psi_m^+ * hbar_i, b_i = h_n - hbar,
SVD gap rule, frfup's damped least squares (--damping), Eq. 29 composition,
same stopping rules as frfup.

Usage: peer_update.py EXPORT_DIR [--repeat N]   prints JSON
"""
import json
import os
import sys
import time

try:
    import numpy as np
    import scipy.linalg
    import scipy.sparse
except ImportError:  # pip-install on first use
    import subprocess

    subprocess.check_call([sys.executable, "-m", "pip", "install", "--quiet", "numpy", "scipy"])
    import numpy as np
    import scipy.linalg
    import scipy.sparse


def load_sparse(d, name, n):
    r = np.load(os.path.join(d, f"{name}_rows.npy"))
    c = np.load(os.path.join(d, f"{name}_cols.npy"))
    v = np.load(os.path.join(d, f"{name}_vals.npy"))
    return scipy.sparse.csc_matrix((v, (r, c)), shape=(n, n))


def gap_solve(A, b, eps):
    """p = V1 S1^-1 U1^T b with the gap rule (Eq. 40-41); returns p and all s."""
    U, s, Vt = np.linalg.svd(A, full_matrices=False)
    rank = len(s)
    for k in range(len(s)):
        if s[k] < s[0] * 1e-13:
            rank = k
            break
        if k + 1 < len(s) and s[k + 1] < eps * s[k]:
            rank = k + 1
            break
    return Vt[:rank].T @ ((U[:, :rank].T @ b) / s[:rank]), s


def run(d):
    prob = json.load(open(os.path.join(d, "problem.json")))
    n = prob["n"]
    names = prob["parameters"]
    npar = len(names)
    K0 = load_sparse(d, "K0", n)
    M0 = load_sparse(d, "M0", n)
    dK = [load_sparse(d, f"dK_{j}", n) for j in range(npar)]
    dM = [load_sparse(d, f"dM_{j}", n) for j in range(npar)]
    meas = np.load(os.path.join(d, "measured.npy"))
    h_test = np.load(os.path.join(d, "h_test.npy"))
    omegas = 2 * np.pi * np.array(prob["updating_frequencies_hz"])
    k_dof = prob["excitation_dof"]
    n_md, n_eig = prob["modes"], prob["eigen_count"]
    eps, tol, max_iter = prob["svd_eps"], prob["tol"], prob["max_iter"]
    btol, pmax = prob["basis_tolerance"], prob["max_parameter"]

    damping = prob.get("damping", 0.0)
    damping_scale = 1.0
    pbar = np.zeros(npar)
    step = np.zeros(npar)
    records = []
    stop = "iteration limit"
    for it in range(max_iter + 1):
        K = (K0 + sum(pbar[j] * dK[j] for j in range(npar))).toarray()
        M = (M0 + sum(pbar[j] * dM[j] for j in range(npar))).toarray()
        lam, psi = scipy.linalg.eigh(K, M, subset_by_index=[0, n_eig - 1])
        # SEREP basis: ordered Gram-Schmidt on the measured partition.
        cols = psi[meas, :]
        maxn = np.linalg.norm(cols, axis=0).max()
        kept, Q = [], []
        for r in range(cols.shape[1]):
            if len(kept) == min(n_md, len(meas)):
                break
            v = cols[:, r].copy()
            for _ in range(2):
                for q in Q:
                    v -= (q @ v) * q
            nv = np.linalg.norm(v)
            if nv >= btol * maxn:
                Q.append(v / nv)
                kept.append(r)
        P = psi[:, kept]
        L = lam[kept]
        Pm = P[meas, :]
        Pm_pinv = np.linalg.pinv(Pm)
        # current derivatives about the current values: (1 + pbar_j) dK_j
        Kj = [(1 + pbar[j]) * (P.T @ (dK[j] @ P)) for j in range(npar)]
        Mj = [(1 + pbar[j]) * (P.T @ (dM[j] @ P)) for j in range(npar)]
        A_blocks, b_blocks, fe = [], [], []
        for i, w in enumerate(omegas):
            dfac = 1.0 / (L - w * w)
            H = (Pm * dfac) @ Pm.T
            u = Pm_pinv @ h_test[i]
            W = np.column_stack([Pm_pinv.T @ ((Kj[j] - w * w * Mj[j]) @ u) for j in range(npar)])
            A_blocks.append(H @ W)
            hn = (Pm * dfac) @ P[k_dof, :]
            fe.append(hn)
            b_blocks.append(hn - h_test[i])
        sf = []
        for hn, ht in zip(fe, h_test):
            x = hn @ ht
            den = (hn @ hn) * (ht @ ht)
            sf.append(x * abs(x) / den if den > 0 else 0.0)
        records.append({"index": it, "parameters": pbar.tolist(), "sfdac_mean": float(np.mean(sf))})
        if it > 0 and np.max(np.abs(step)) < tol:
            stop = "converged"
            break
        if it >= 2:
            m = [r["sfdac_mean"] for r in records[-3:]]
            if m[2] < m[1] - 1e-5 and m[1] < m[0] - 1e-5:
                stop = "diverged"
                break
        if it == max_iter:
            break
        A = np.vstack(A_blocks)
        b = np.concatenate(b_blocks)
        p, s = gap_solve(A, b, eps)
        # Damped least squares (frfup's --damping): rows mu I, mu = damping
        # * sigma_1, the damping scale halved after a step that raised the
        # mean SFDAC and quadrupled after one that lowered it.
        if it > 0:
            if records[it]["sfdac_mean"] >= records[it - 1]["sfdac_mean"]:
                damping_scale = max(damping_scale * 0.5, 0.01)
            else:
                damping_scale = min(damping_scale * 4.0, 16.0)
        mu = damping_scale * damping * s[0]
        if mu > 0:
            p, _ = gap_solve(np.vstack([A, mu * np.eye(npar)]), np.concatenate([b, np.zeros(npar)]), eps)
        if np.any(1 + p <= 0):
            scale = 1.0
            while np.any(1 + scale * p < 0.1) and scale > 1e-12:
                scale *= 0.5
            p = p * scale
        pbar = pbar + p + pbar * p
        step = p
        if np.any(~np.isfinite(pbar)) or np.any(np.abs(pbar) > pmax):
            stop = "parameter exploded"
            break
    return names, records, stop


def main():
    d = sys.argv[1]
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 3
    times = []
    for _ in range(max(1, repeat)):
        t = time.perf_counter()
        names, records, stop = run(d)
        times.append(time.perf_counter() - t)
    times.sort()
    print(json.dumps({
        "case": "peer",
        "update_s_best": times[0],
        "update_s_median": times[len(times) // 2],
        "iterations": len(records) - 1,
        "stop": stop,
        "sfdac_mean": [records[0]["sfdac_mean"], records[-1]["sfdac_mean"]],
        "parameters_last": dict(zip(names, records[-1]["parameters"])),
    }))


if __name__ == "__main__":
    main()

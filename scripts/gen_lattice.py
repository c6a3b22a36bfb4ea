#!/usr/bin/env python3
"""Write frame-lattice benchmark decks (deck format: docs/spec/deck.md).

  plate N : N x N grid of 6-DOF nodes (spacing 0.1 m, z = 0) with beams along x
            and y, every node on a vertical column (0.1 m) to a fixed node of a
            layer below -> 6 N^2 free DOFs (N = 130: 101,400).
  cube N  : N x N x N nodes (spacing 0.1 m) with beams along x, y and z; the
            base layer z = 0 is fixed -> 6 N^2 (N - 1) free DOFs (N = 26: 101,400).

Steel, solid 10 mm square section. Deterministic output.

Usage: gen_lattice.py plate 130 > plate.deck ; gen_lattice.py cube 26 > cube.deck
"""
import sys

H = 0.1
B = 0.01
A = B * B
I = B**4 / 12.0
J = 0.1406 * B**4


def header(out, title):
    out.append(f"title {title}")
    out.append("analysis space")
    out.append("material steel E=210e9 rho=7850 nu=0.3")
    out.append(f"section sq10 A={A:.6g} Iy={I:.6g} Iz={I:.6g} J={J:.6g}")


def plate(n):
    out = []
    header(out, f"plate-like frame lattice {n}x{n} over a fixed layer")
    nid = lambda i, j: 1 + i * n + j
    base = n * n
    for i in range(n):
        for j in range(n):
            out.append(f"node {nid(i, j)} {i * H:.6g} {j * H:.6g} 0")
    for i in range(n):
        for j in range(n):
            out.append(f"node {base + nid(i, j)} {i * H:.6g} {j * H:.6g} {-H:.6g}")
    e = 0
    for i in range(n):
        for j in range(n):
            if i + 1 < n:
                e += 1
                out.append(f"beam {e} {nid(i, j)} {nid(i + 1, j)} steel sq10")
            if j + 1 < n:
                e += 1
                out.append(f"beam {e} {nid(i, j)} {nid(i, j + 1)} steel sq10")
            e += 1
            out.append(f"beam {e} {base + nid(i, j)} {nid(i, j)} steel sq10")
    for i in range(n):
        for j in range(n):
            out.append(f"fix {base + nid(i, j)} all")
    return out


def cube(n):
    out = []
    header(out, f"cube frame lattice {n}x{n}x{n}, base fixed")
    nid = lambda i, j, k: 1 + (k * n + i) * n + j
    for k in range(n):
        for i in range(n):
            for j in range(n):
                out.append(f"node {nid(i, j, k)} {i * H:.6g} {j * H:.6g} {k * H:.6g}")
    e = 0
    for k in range(n):
        for i in range(n):
            for j in range(n):
                for (di, dj, dk) in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                    if i + di < n and j + dj < n and k + dk < n:
                        e += 1
                        out.append(f"beam {e} {nid(i, j, k)} {nid(i + di, j + dj, k + dk)} steel sq10")
    for i in range(n):
        for j in range(n):
            out.append(f"fix {nid(i, j, 0)} all")
    return out


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("plate", "cube"):
        sys.exit(__doc__)
    kind, n = sys.argv[1], int(sys.argv[2])
    lines = plate(n) if kind == "plate" else cube(n)
    sys.stdout.write("\n".join(lines) + "\n")

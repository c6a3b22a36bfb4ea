//! Unit tests of `src/solvers/nested_dissection.rs` through its public interface.

use frfup::solvers::nested_dissection::*;

/// Column pointers and row indices of a graph given by its edges.
pub fn pattern(n: usize, edges: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>) {
    let mut adj = vec![Vec::new(); n];
    for &(a, b) in edges {
        adj[a].push(b);
        adj[b].push(a);
    }
    let mut ptr = vec![0];
    let mut idx = Vec::new();
    for (v, mut list) in adj.into_iter().enumerate() {
        list.push(v);
        list.sort_unstable();
        idx.extend(list);
        ptr.push(idx.len());
    }
    (ptr, idx)
}

fn grid_edges(k: usize) -> Vec<(usize, usize)> {
    let id = |x: usize, y: usize, z: usize| (z * k + y) * k + x;
    let mut e = Vec::new();
    for z in 0..k {
        for y in 0..k {
            for x in 0..k {
                if x + 1 < k {
                    e.push((id(x, y, z), id(x + 1, y, z)));
                }
                if y + 1 < k {
                    e.push((id(x, y, z), id(x, y + 1, z)));
                }
                if z + 1 < k {
                    e.push((id(x, y, z), id(x, y, z + 1)));
                }
            }
        }
    }
    e
}

fn assert_permutation(fwd: &[usize], n: usize) {
    let mut seen = vec![false; n];
    assert_eq!(fwd.len(), n);
    for &f in fwd {
        assert!(f < n && !seen[f], "not a permutation");
        seen[f] = true;
    }
}

#[test]
fn orderings_are_permutations_and_deterministic() {
    let (p, i) = pattern(0, &[]);
    assert!(order(0, &p, &i).is_empty());
    let (p, i) = pattern(1, &[]);
    assert_eq!(order(1, &p, &i), vec![0]);
    // 3-D grid, a path, and two disconnected grids plus isolated vertices.
    let k = 11;
    let grid = grid_edges(k);
    let path: Vec<_> = (0..499).map(|v| (v, v + 1)).collect();
    let mut two = grid.clone();
    two.extend(grid.iter().map(|&(a, b)| (a + k * k * k, b + k * k * k)));
    for (n, edges) in [(k * k * k, &grid), (500, &path), (2 * k * k * k + 7, &two)] {
        let (p, i) = pattern(n, edges);
        let fwd = order(n, &p, &i);
        assert_permutation(&fwd, n);
        assert_eq!(fwd, order(n, &p, &i));
    }
    // Out-of-range indices are ignored, not a panic.
    let (p, mut i) = pattern(200, &path[..199]);
    i[3] = 10_000;
    assert_permutation(&order(200, &p, &i), 200);
}

#[test]
fn grid_separator_is_last_and_separates() {
    let k = 9;
    let n = k * k * k;
    let (p, i) = pattern(n, &grid_edges(k));
    let fwd = order(n, &p, &i);
    let mut pos = vec![0; n];
    for (new, &old) in fwd.iter().enumerate() {
        pos[old] = new;
    }
    // The top-level separator is a suffix; removing it leaves no edge
    // between the two halves that precede it.
    let set: Vec<usize> = (0..n).collect();
    let mut label = vec![0u32; n];
    let mut level = vec![u32::MAX; n];
    let adj = |v: usize| &i[p[v]..p[v + 1]];
    let levels = peripheral_levels(&set, 0, &label, &mut level, &adj);
    let kk = pick_separator(&levels, n).unwrap();
    let sep = levels[kk].len();
    let a: usize = levels[..kk].iter().map(Vec::len).sum();
    for v in 0..n {
        label[v] = if pos[v] < a {
            1
        } else if pos[v] < n - sep {
            2
        } else {
            3
        };
    }
    for v in 0..n {
        for &w in adj(v) {
            assert!(
                label[v] * label[w] != 2,
                "edge {v}-{w} crosses the separator"
            );
        }
    }
}

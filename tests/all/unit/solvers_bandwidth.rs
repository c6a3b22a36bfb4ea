//! Unit tests of `src/solvers/bandwidth.rs` through its public interface.

use crate::unit::solvers_nested_dissection::pattern;
use frfup::solvers::bandwidth::*;

/// A path 0–1–…–(n−1) numbered by a stride permutation has a wide
/// envelope; RCM numbers it along the path (profile n − 1, the minimum
/// for a connected graph) and keeps every unknown exactly once.
#[test]
fn a_scrambled_path_becomes_a_band() {
    let n = 101;
    let label = |k: usize| (k * 37) % n; // path position k → unknown label
    let edges: Vec<_> = (0..n - 1).map(|k| (label(k), label(k + 1))).collect();
    let (ptr, idx) = pattern(n, &edges);
    let identity: Vec<usize> = (0..n).collect();
    let order = reverse_cuthill_mckee(n, &ptr, &idx);
    let mut seen = order.clone();
    seen.sort_unstable();
    assert_eq!(seen, identity);
    assert!(profile(&ptr, &idx, &identity) > 20 * n);
    assert_eq!(profile(&ptr, &idx, &order), n - 1);
}

/// Two components and an isolated unknown are all numbered.
#[test]
fn every_component_is_numbered() {
    let (ptr, idx) = pattern(5, &[(0, 2), (3, 4)]);
    let mut order = reverse_cuthill_mckee(5, &ptr, &idx);
    order.sort_unstable();
    assert_eq!(order, vec![0, 1, 2, 3, 4]);
}

//! Automatic choice of the physical poles of a stabilisation diagram.
//!
//! The poles stable in frequency and in damping or shape are clustered across
//! orders, highest order first: a pole joins the cluster whose first pole λ_c
//! is nearest in d = |λ − λ_c| / max(−Re λ_c, Δω_line) (distance in units of
//! the half-power half-bandwidth, or of the line spacing when that is
//! coarser) when d ≤ `join_distance`, the shapes' MAC ≥ `join_mac` and the
//! cluster has no pole of that order yet. Two modes within each other's
//! half-power bandwidth lie about one unit apart and stay in two clusters.
//! A physical mode stays stable once the order can hold it, so its cluster
//! fills at least `min_fill` of the orders from its first to the highest;
//! noise poles and the computational poles of over-modelling do not; a
//! cluster also needs `min_orders` poles stable in all three. Each kept cluster gives its member
//! nearest the clusters' median pole.

use faer::c64;

use super::prepare::Prepared;
use super::stabilisation::{mac, Diagram, Stability};

/// Settings of the selection (and of the significance test of the fit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelectOptions {
    pub join_distance: f64,
    pub join_mac: f64,
    pub min_fill: f64,
    pub min_orders: usize,
    /// Least peak modal contribution ÷ fit residual RMS of a kept mode.
    pub min_significance: f64,
}

impl Default for SelectOptions {
    fn default() -> Self {
        SelectOptions {
            join_distance: 0.4,
            join_mac: 0.9,
            min_fill: 0.5,
            min_orders: 4,
            min_significance: 4.0,
        }
    }
}

/// A selected pole.
#[derive(Clone, Debug, PartialEq)]
pub struct Picked {
    pub pole: c64,
    pub vector: Vec<c64>,
    /// Poles in its cluster.
    pub stable_orders: usize,
    /// The cluster's poles (indices in [`Diagram::poles`]).
    pub cluster: Vec<usize>,
}

struct Cluster {
    first: c64,
    vector: Vec<c64>,
    /// (order, pole, index in the diagram).
    members: Vec<(usize, c64, usize)>,
}

/// The physical poles of `diagram`, ascending in frequency.
pub fn select(diagram: &Diagram, data: &Prepared, opts: &SelectOptions) -> Vec<Picked> {
    let line = if data.n_lines() > 1 {
        (data.omega[data.n_lines() - 1] - data.omega[0]) / (data.n_lines() - 1) as f64
    } else {
        1.0
    };
    let mut stable: Vec<usize> = (0..diagram.poles.len())
        .filter(|&k| {
            matches!(
                diagram.poles[k].stability,
                Stability::Stable | Stability::Damping | Stability::Vector
            )
        })
        .collect();
    stable.sort_by_key(|&k| std::cmp::Reverse(diagram.poles[k].order));
    let mut clusters: Vec<Cluster> = Vec::new();
    for k in stable {
        let p = &diagram.poles[k];
        let best = clusters
            .iter_mut()
            .filter(|c| c.members.iter().all(|m| m.0 != p.order))
            .map(|c| {
                let d = (p.pole - c.first).norm() / (-c.first.re).max(line);
                (d, c)
            })
            .filter(|(d, c)| *d <= opts.join_distance && mac(&c.vector, &p.vector) >= opts.join_mac)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((_, c)) => {
                c.members.push((p.order, p.pole, k));
                c.first = p.pole;
                c.vector = p.vector.clone();
            }
            None => clusters.push(Cluster {
                first: p.pole,
                vector: p.vector.clone(),
                members: vec![(p.order, p.pole, k)],
            }),
        }
    }
    let top = diagram.max_order;
    let mut picked: Vec<Picked> = clusters
        .into_iter()
        .filter(|c| {
            let low = c.members.iter().map(|m| m.0).min().unwrap_or(top);
            let span = (top - low + 1) as f64;
            let full = c
                .members
                .iter()
                .filter(|m| diagram.poles[m.2].stability == Stability::Stable)
                .count();
            full >= opts.min_orders && c.members.len() as f64 >= opts.min_fill * span
        })
        .map(|c| {
            let median = |f: &dyn Fn(&c64) -> f64| {
                let mut v: Vec<f64> = c.members.iter().map(|m| f(&m.1)).collect();
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            };
            let centre = c64::new(median(&|z| z.re), median(&|z| z.im));
            let rep = c
                .members
                .iter()
                .min_by(|a, b| (a.1 - centre).norm().total_cmp(&(b.1 - centre).norm()))
                .expect("a kept cluster has members");
            Picked {
                pole: rep.1,
                vector: diagram.poles[rep.2].vector.clone(),
                stable_orders: c.members.len(),
                cluster: c.members.iter().map(|m| m.2).collect(),
            }
        })
        .collect();
    picked.sort_by(|a, b| a.pole.norm().total_cmp(&b.pole.norm()));
    picked
}

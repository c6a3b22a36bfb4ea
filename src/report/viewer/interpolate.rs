//! A test shape at the nodes nobody measured, interpolated along the beams:
//! per direction, the measured values and the fixed translations (0) are
//! held, every other node takes the average of its beam neighbours weighted
//! by 1/length (a discrete harmonic function). Along a chain of beams this
//! is linear in arc length between measured nodes and constant beyond the
//! last one; nodes with no path to a held value stay at rest.

/// The beams as a weighted graph on the nodes.
pub struct Graph {
    /// [node] (neighbour, 1 / beam length).
    adjacent: Vec<Vec<(usize, f64)>>,
}

impl Graph {
    pub fn new(xyz: &[[f64; 3]], beams: &[[usize; 2]]) -> Graph {
        let mut adjacent = vec![Vec::new(); xyz.len()];
        for &[a, b] in beams {
            let l = (0..3)
                .map(|k| (xyz[a][k] - xyz[b][k]).powi(2))
                .sum::<f64>()
                .sqrt();
            if a != b && l > 0.0 {
                adjacent[a].push((b, 1.0 / l));
                adjacent[b].push((a, 1.0 / l));
            }
        }
        Graph { adjacent }
    }

    /// `values` with the unmeasured translations filled in, direction by
    /// direction; `measured` and `free` are per node and direction.
    pub fn fill(
        &self,
        values: &[[f64; 3]],
        measured: &[[bool; 3]],
        free: &[[bool; 3]],
    ) -> Vec<[f64; 3]> {
        let mut out = values.to_vec();
        for a in 0..3 {
            if !measured.iter().any(|m| m[a]) {
                continue;
            }
            let held: Vec<bool> = (0..values.len())
                .map(|i| measured[i][a] || !free[i][a])
                .collect();
            let known: Vec<f64> = (0..values.len())
                .map(|i| if measured[i][a] { values[i][a] } else { 0.0 })
                .collect();
            let x = self.harmonic(&held, &known);
            for (o, v) in out.iter_mut().zip(x) {
                o[a] = v;
            }
        }
        out
    }

    /// Nodes that reach a held node through beams.
    fn reached(&self, held: &[bool]) -> Vec<bool> {
        let mut seen = held.to_vec();
        let mut stack: Vec<usize> = (0..held.len()).filter(|&i| held[i]).collect();
        while let Some(i) = stack.pop() {
            for &(j, _) in &self.adjacent[i] {
                if !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        seen
    }

    /// Solve L_uu x_u = −L_uh x_h by conjugate gradients (L the weighted
    /// graph Laplacian, u the free nodes that reach a held one: L_uu is
    /// then positive definite); the others keep `known` (0 if not held).
    fn harmonic(&self, held: &[bool], known: &[f64]) -> Vec<f64> {
        let n = held.len();
        let reached = self.reached(held);
        let free: Vec<bool> = (0..n).map(|i| !held[i] && reached[i]).collect();
        let mut x = known.to_vec();
        // A u = L_uu u (zero outside the free set).
        let apply = |u: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|i| {
                    if !free[i] {
                        return 0.0;
                    }
                    self.adjacent[i]
                        .iter()
                        .map(|&(j, w)| w * (u[i] - if free[j] { u[j] } else { 0.0 }))
                        .sum()
                })
                .collect()
        };
        let b: Vec<f64> = (0..n)
            .map(|i| {
                if !free[i] {
                    return 0.0;
                }
                self.adjacent[i]
                    .iter()
                    .filter(|&&(j, _)| !free[j])
                    .map(|&(j, w)| w * known[j])
                    .sum()
            })
            .collect();
        let dot = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(a, b)| a * b).sum::<f64>();
        let mut u = vec![0.0; n];
        let mut r = b.clone();
        let mut p = r.clone();
        let mut rr = dot(&r, &r);
        let stop = 1e-24 * dot(&b, &b);
        for _ in 0..(2 * n + 10) {
            if rr <= stop || rr == 0.0 {
                break;
            }
            let ap = apply(&p);
            let alpha = rr / dot(&p, &ap);
            for i in 0..n {
                u[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
            }
            let next = dot(&r, &r);
            for i in 0..n {
                p[i] = r[i] + next / rr * p[i];
            }
            rr = next;
        }
        for i in (0..n).filter(|&i| free[i]) {
            x[i] = u[i];
        }
        x
    }
}

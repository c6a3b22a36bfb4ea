//! Bounds and priors of the deck's parameters (`param NAME … min= max=
//! sd=`): the hard bounds of a relative change p̄ and the prior rows
//! √J₀·p̄_j/s_j of the maximum a posteriori objective of
//! [`super::estimate`], shared by every fit of the deck's parameters (the
//! update's estimate, the diagnosis's polish and joint fits).

use faer::Mat;
use frfup_parsers::deck::Deck;

/// Default hard bounds of a relative change p̄ (a property between 0.1× and
/// 11× its deck value).
pub const DEFAULT_MIN: f64 = -0.9;
pub const DEFAULT_MAX: f64 = 10.0;

/// Bounds and prior of one parameter (relative change p̄).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterPrior {
    pub min: f64,
    pub max: f64,
    /// Prior standard deviation (None: no prior).
    pub sd: Option<f64>,
    /// Prior mean of p̄: 0 for a deck as written; the written value for a
    /// deck updated in memory ([`frfup_parsers::deck::Param::prior_centre`]).
    pub centre: f64,
}

impl ParameterPrior {
    /// The deck's `param` bounds and priors, in deck order. On a deck
    /// updated in memory by v the prior keeps its physical meaning: centred
    /// on the written value, c = −v/(1 + v), with sd s/(1 + v) = s(1 + c).
    pub fn of_deck(deck: &Deck) -> Vec<ParameterPrior> {
        deck.params
            .iter()
            .map(|p| ParameterPrior {
                min: p.min.unwrap_or(DEFAULT_MIN),
                max: p.max.unwrap_or(DEFAULT_MAX),
                sd: p.sd.map(|s| s * (1.0 + p.prior_centre)),
                centre: p.prior_centre,
            })
            .collect()
    }

    /// The prior rows of the objective F of [`super::estimate`], appended to the
    /// residuals `r`: √J₀·(p̄_j − c_j)/s_j (`scale` = √J₀) for each
    /// parameter j with a prior, in order; `p` holds p̄ in the order of
    /// `priors`.
    pub fn push_rows(priors: &[ParameterPrior], p: &[f64], scale: f64, r: &mut Vec<f64>) {
        for (pr, &pj) in priors.iter().zip(p) {
            if let Some(sd) = pr.sd {
                r.push(scale * (pj - pr.centre) / sd);
            }
        }
    }

    /// √J₀, the scale of a prior row, for a noise level `j0` (floored, so
    /// that a noise-free campaign keeps its priors).
    pub fn row_scale(j0: f64) -> f64 {
        j0.max(1e-12).sqrt()
    }

    /// The derivatives of those rows, ∂/∂p̄_j = scale/s_j, written into
    /// `jac` from row `first` on (column j of parameter j).
    pub fn fill_rows(priors: &[ParameterPrior], scale: f64, jac: &mut Mat<f64>, first: usize) {
        let mut row = first;
        for (j, pr) in priors.iter().enumerate() {
            if let Some(sd) = pr.sd {
                jac[(row, j)] = scale / sd;
                row += 1;
            }
        }
    }

    /// Number of prior rows [`Self::push_rows`] appends.
    pub fn rows(priors: &[ParameterPrior]) -> usize {
        priors.iter().filter(|p| p.sd.is_some()).count()
    }
}

//! Bad input and hard cases of `update` (issue: "Bad input and hard cases"):
//! each is an error or a warning that names what is wrong.

use frfup::model::ParameterValues;
use frfup::parsers::deck::{parse, Deck};
use frfup::simulate::simulate;
use frfup::testdata::MeasuredFrfs;
use frfup::updating::{update, UpdateOptions, UpdateWarning};

use crate::campaign_support::{band, z_campaign};

fn cantilever(extra: &str) -> Deck {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/paper/cantilever.deck");
    parse(&(std::fs::read_to_string(path).unwrap() + extra)).unwrap()
}

fn measure(deck: &Deck, truth: &[(&str, f64)], nodes: &[u32]) -> MeasuredFrfs {
    let truth: ParameterValues = truth.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    simulate(deck, &truth, &z_campaign(16, nodes, band(250.0, 5001))).unwrap()
}

/// The cantilever (with `extra` deck lines) and its test at nodes 2..=`last`
/// for the true relative changes `truth`.
fn case(extra: &str, truth: &[(&str, f64)], last: u32) -> (Deck, MeasuredFrfs) {
    let d = cantilever(extra);
    let nodes: Vec<u32> = (2..=last).collect();
    let test = measure(&d, truth, &nodes);
    (d, test)
}

fn opts() -> UpdateOptions {
    UpdateOptions {
        resonances: Some(6),
        ..UpdateOptions::paper()
    }
}

/// A fixed exciter whose driving point was not measured (tip node 16
/// driven, nodes 2–15 measured): the model's mode shapes at the excitation
/// stand in for it (SEREP expansion), the run says so, and the paper's
/// method still recovers p3 = 1 (exact data: 1e-3, as with the driving
/// point in `channels_matching_no_dof_are_listed_and_ignored`).
#[test]
fn excitation_not_measured_is_a_warning_and_the_update_still_recovers_the_change() {
    let (d, test) = case("", &[("p3", 1.0)], 15);
    let r = update(&d, &test, &opts()).unwrap();
    let said = r.warnings.iter().any(|w| {
        matches!(w, UpdateWarning::DrivingPointNotMeasured { excitation } if excitation.contains("16"))
    });
    assert!(said, "{:?}", r.warnings);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.to_string().contains("not measured")),
        "{:?}",
        r.warnings
    );
    let p = r.parameters();
    assert!((p[2] - 1.0).abs() < 1e-3, "{p:?}");
    for (j, v) in p.iter().enumerate().filter(|&(j, _)| j != 2) {
        assert!(v.abs() < 1e-3, "p{} = {v}", j + 1);
    }
}

#[test]
fn channels_matching_no_dof_are_listed_and_ignored() {
    let (d, mut test) = case("", &[("p3", 1.0)], 16);
    let mut stray = test.channels[0].clone();
    stray.response_node = 99;
    test.channels.push(stray);
    let r = update(&d, &test, &opts()).unwrap();
    let listed = r.warnings.iter().any(|w| {
        matches!(w, UpdateWarning::UnmatchedChannels { labels } if labels.len() == 1 && labels[0].contains("99"))
    });
    assert!(listed, "{:?}", r.warnings);
    // The other channels still update the model: p3 → 1 (exact 1.0), as
    // in updating_paper::cantilever_table1 (measured 1.1e-4 from exact).
    assert!(
        (r.parameters()[2] - 1.0).abs() < 1e-3,
        "{:?}",
        r.parameters()
    );
}

#[test]
fn parameters_the_equations_cannot_tell_apart_are_named() {
    // p3b acts on the same elements and quantity as p3: only p3 + p3b is seen.
    let (d, test) = case("param p3b Iy 7-9\n", &[("p3", 1.0)], 16);
    let r = update(&d, &test, &opts()).unwrap();
    let named = r.warnings.iter().find_map(|w| match w {
        UpdateWarning::Indistinguishable { combinations, .. } => Some(combinations.clone()),
        _ => None,
    });
    let combos = named.expect("an Indistinguishable warning");
    assert!(
        combos.iter().any(|c| {
            let names: Vec<&str> = c.iter().map(|(n, _)| n.as_str()).collect();
            names.contains(&"p3") && names.contains(&"p3b")
        }),
        "{combos:?}"
    );
    // The combination the data do see is recovered: (1 + p3)(1 + p3b) = 2
    // (measured 1.99989, as 1 + p3 alone in cantilever_table1).
    let p = r.parameters();
    assert!(((1.0 + p[2]) * (1.0 + p[5]) - 2.0).abs() < 1e-3, "{p:?}");
}

#[test]
fn a_step_that_would_make_a_stiffness_negative_is_limited_and_reported() {
    // Elements 1-3 and 7-9 are 100 times softer than the deck says: the first
    // linearised step overshoots below -1 (a negative stiffness). It is
    // scaled back, reported, and the iteration still reaches the truth.
    let (d, test) = case("", &[("p3", -0.99), ("p1", -0.99)], 16);
    let r = update(&d, &test, &opts()).unwrap();
    let limited = r.warnings.iter().find_map(|w| match w {
        UpdateWarning::StepLimited {
            parameters, scale, ..
        } => Some((parameters.clone(), *scale)),
        _ => None,
    });
    let (names, scale) = limited.expect("a StepLimited warning");
    assert!(!names.is_empty() && scale < 1.0, "{names:?} {scale}");
    let p = r.parameters();
    assert!(p.iter().all(|&x| 1.0 + x > 0.0), "{p:?}");
    // Measured 2e-10 and 3e-9 from the truth; 1e-7 leaves room for rounding.
    assert!(
        (p[0] + 0.99).abs() < 1e-7 && (p[2] + 0.99).abs() < 1e-7,
        "{p:?}"
    );
}

#[test]
fn divergence_stops_keeps_the_best_iteration_and_says_so() {
    // The plain method on the GARTEUR-like campaign (5-11 % off, close modes,
    // suspension the free-free deck lacks) does not converge.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/garteur");
    let d = parse(&std::fs::read_to_string(root.join("garteur.deck")).unwrap()).unwrap();
    let test = frfup::testdata::load(&root.join("campaign.uff")).unwrap();
    let r = update(&d, &test, &UpdateOptions::paper()).unwrap();
    assert!(!r.converged);
    let said = r.warnings.iter().find_map(|w| match w {
        UpdateWarning::Diverged { best, .. } | UpdateWarning::ParameterExploded { best, .. } => {
            Some(*best)
        }
        _ => None,
    });
    let best = said.expect("a Diverged or ParameterExploded warning");
    assert_eq!(r.final_iteration, best);
    let top = r
        .iterations
        .iter()
        .map(|i| i.sfdac.mean)
        .fold(f64::MIN, f64::max);
    assert_eq!(r.iterations[best].sfdac.mean, top);
    assert!(r
        .warnings
        .iter()
        .any(|w| w.to_string().contains("iteration")));
}

/// The GARTEUR deck without its bungees cannot explain its test (about 23×
/// the noise level): every parameter the data do not identify keeps the
/// deck's value in the result and in `updated.deck` (fus_J once came out
/// "not identified" at +9.04), and the identified ones stay within bounds.
#[test]
fn parameters_not_identified_keep_the_decks_value() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/garteur");
    let deck = parse(&std::fs::read_to_string(root.join("garteur.deck")).unwrap()).unwrap();
    let test = frfup::testdata::load(&root.join("campaign.uff")).unwrap();
    let r = update(&deck, &test, &UpdateOptions::default()).unwrap();
    let est = r.estimate.as_ref().expect("the robust pipeline's estimate");
    let values = r.parameter_values();
    let unidentified: Vec<&str> = est
        .parameters
        .iter()
        .filter(|p| !p.identified && !p.at_bound)
        .map(|p| p.name.as_str())
        .collect();
    assert!(unidentified.contains(&"fus_J"), "{unidentified:?}");
    for p in est
        .parameters
        .iter()
        .filter(|p| !p.identified && !p.at_bound)
    {
        assert_eq!(p.value, 0.0, "{}", p.name);
        assert_eq!(
            values.get(&p.name).copied().unwrap_or(0.0),
            0.0,
            "{}",
            p.name
        );
    }
    assert!(est.misfit > 4.0, "misfit {}", est.misfit);
}

#[test]
fn coarse_stage_ignores_resonances_the_model_cannot_pair() {
    // Case 54 of the randomised update benchmark (seed 1): a T-frame tested
    // by roving hammer on a log-spaced axis from 3.2 Hz. Peak picking finds
    // 35 noise peaks in 3-33 Hz, where the accelerance is at the noise, and
    // 4 resonances. Starting near the truth (a first stage's result: every
    // parameter within 0.032 of it), the coarse frequency stage must not
    // run: the unpaired peaks (capped at ln 2 each) made the mean deviation
    // 0.62 and the stage moved Iy_m3s1 from -0.383 to -0.526 (truth -0.384),
    // a basin the full-band estimate did not leave.
    use frfup::benchmark::{case_seed, generate, GenOptions};
    use frfup::updating::fullband::{coarse, data::TestData, fit, prior::ParameterPrior};
    let case = generate(case_seed(1, 54), &GenOptions::default()).unwrap();
    let truth: Vec<f64> = case.params.iter().map(|p| p.value).collect();
    assert!(
        (truth[0] + 0.3839).abs() < 1e-4,
        "the generator drew another case: {truth:?}"
    );
    let deck = parse(&case.model_deck).unwrap();
    let file = frfup::parsers::uff::parse(&case.uff_bytes().unwrap()).unwrap();
    let test = frfup::testdata::from_uff(&file, std::path::Path::new("test.uff")).unwrap();
    let (column, _) = frfup::testdata::layout::as_column(&test);
    let data = TestData::new(&column).unwrap();
    let names = frfup::model::parameter_names(&deck);
    assert!(names.iter().zip(&case.params).all(|(n, p)| *n == p.name));
    let priors = ParameterPrior::of_deck(&deck);
    let start = vec![-0.383, -0.263, 0.338, 0.143, -0.132, -0.38];
    let mut p = start.clone();
    let mut damp = fit::start_damping(frfup::model::Damping::of_deck(&deck), &data);
    let (kept, _) = coarse::coarse_frequencies(&deck, &data, &names, &priors, &mut p, &mut damp);
    assert!(!kept && p == start, "coarse stage moved the start to {p:?}");
}

/// Case `i` of the update benchmark's seed-1 set, updated with the
/// defaults: the case (its truth) and the update's result.
fn benchmark_case_updated(i: u64) -> (frfup::benchmark::Case, frfup::updating::UpdateResult) {
    benchmark_case_of_seed_updated(1, i)
}

/// Case `i` of the update benchmark of seed `seed`, updated as above.
fn benchmark_case_of_seed_updated(
    seed: u64,
    i: u64,
) -> (frfup::benchmark::Case, frfup::updating::UpdateResult) {
    let (case, model, test) = benchmark_campaign(seed, i);
    let r = update(&model, &test, &UpdateOptions::default()).expect("update runs");
    (case, r)
}

/// Case `i` of the update benchmark of seed `seed`: the case, its deck and
/// its test as read from its UFF bytes.
fn benchmark_campaign(seed: u64, i: u64) -> (frfup::benchmark::Case, Deck, MeasuredFrfs) {
    use frfup::benchmark::{case_seed, generate, GenOptions};
    let case = generate(case_seed(seed, i), &GenOptions::default()).expect("generate");
    let model = parse(&case.model_deck).unwrap();
    let file = frfup::parsers::uff::parse(&case.uff_bytes().unwrap()).unwrap();
    let test = frfup::testdata::from_uff(&file, std::path::Path::new("test.uff")).unwrap();
    (case, model, test)
}

/// Every parameter of the truth identified and within `tol` of it.
fn every_parameter_within(
    case: &frfup::benchmark::Case,
    r: &frfup::updating::UpdateResult,
    tol: f64,
) {
    let est = r.estimate.as_ref().expect("full-band estimate");
    for p in &case.params {
        let e = est.parameters.iter().find(|e| e.name == p.name).unwrap();
        assert!(
            e.identified && (e.value - p.value).abs() < tol,
            "{}: {} ± {} vs {}",
            p.name,
            e.value,
            e.sd,
            p.value
        );
    }
}

/// A local minimum every ordinary start falls into: the update benchmark's
/// case 040 of seed 1 (clamped space frame, z only, the driving point not
/// measured, 6 parameters, two of its four modes nearly invisible). From
/// the deck, the first stage's result and its best iterate the estimate
/// ended at 60.6× the noise level with A_m6s1 on its bound (−0.9) and
/// exit 1; a start spread over the plausible range reaches 0.94× with every
/// parameter within 0.004 of the truth (measured). Tolerance 0.01: the
/// parameters' standard deviations are 0.0002–0.003.
#[test]
fn a_local_minimum_is_left_from_a_spread_start() {
    let (case, r) = from_a_spread_start(1, 40, 1.5, 0.01);
    assert!(!case.driving_point_measured());
    assert!(r.converged);
}

/// Case `i` of seed `seed` updated with the defaults: its estimate must
/// come from a spread start, end below `misfit` × the noise level and have
/// every parameter identified within `tol` of the truth.
fn from_a_spread_start(
    seed: u64,
    i: u64,
    misfit: f64,
    tol: f64,
) -> (frfup::benchmark::Case, frfup::updating::UpdateResult) {
    use frfup::updating::fullband::estimate::SPREAD_START;
    let (case, r) = benchmark_case_of_seed_updated(seed, i);
    let est = r.estimate.as_ref().expect("full-band estimate");
    assert!(est.start >= SPREAD_START, "start {}", est.start);
    assert!(est.misfit < misfit, "misfit {}", est.misfit);
    every_parameter_within(&case, &r, tol);
    (case, r)
}

/// A local minimum close above the noise level: the update benchmark's
/// case 058 of seed 11 (free-free T-frame, roving hammer over 15 points,
/// sensors in x alone, the crossbar arms' Iy changed +0.35 and −0.25).
/// From the deck and the first stage the estimate ended at 1.31× the noise
/// level with the two arms' Iy at −0.17 and +0.11, standard deviations
/// 0.0005 and 0.0003, exit 0: a false certainty. Spread starts are taken
/// whenever the fit ends above 1.1× (no fit at the truth of the 600 cases
/// of seeds 1, 2 and 11 does); one reaches 0.90× with every parameter
/// within 0.0003 of the truth (measured). Tolerance 0.003: ten of the
/// largest standard deviation (0.0003).
#[test]
fn a_fit_just_above_the_noise_level_is_left_from_a_spread_start() {
    from_a_spread_start(11, 58, 1.0, 0.003);
}

/// A deck whose Rayleigh damping is proportional to the stiffness alone
/// (α = 0, β = 4.651e-5): the update benchmark's case 082 of seed 12, a
/// free-free space frame on springs, suspension modes at 1.6–10 Hz (ζ from
/// 2e-4) and elastic ones at 53–98 Hz (ζ 0.8–1.4 %). The estimate took the
/// deck for one without damping and fitted a constant modal ζ (0.0083):
/// 48.7× the noise level, both parameters 0.01–0.02 from the truth. With
/// the deck's form kept: 0.78×, both within 0.0004 (measured). Tolerance
/// 0.003: four standard deviations of the larger (0.0008).
#[test]
fn a_stiffness_proportional_deck_damping_keeps_its_form_in_the_estimate() {
    let (case, r) = benchmark_case_of_seed_updated(12, 82);
    let est = r.estimate.as_ref().expect("full-band estimate");
    assert!(
        matches!(est.damping, frfup::model::Damping::Rayleigh { .. }),
        "{:?}",
        est.damping
    );
    assert!(est.misfit < 1.0, "misfit {}", est.misfit);
    every_parameter_within(&case, &r, 0.003);
}

/// The further starts run on the pool's threads, taken in their order as if
/// one after the other: case 040 above (ordinary starts, then spread starts
/// until one reaches 1.1× the noise) gives the same estimate, bit for bit,
/// the same start and the same count of model solutions (the starts after
/// the one that stopped the spread are not counted) on one thread and on
/// three (batches of three spread starts: the stop falls inside a batch).
#[test]
fn further_starts_on_several_threads_give_the_same_estimate() {
    let (_, model, test) = benchmark_campaign(1, 40);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let r = pool.install(|| update(&model, &test, &UpdateOptions::default()).unwrap());
        let e = r.estimate.expect("full-band estimate");
        let bits: Vec<u64> = e.parameters.iter().map(|p| p.value.to_bits()).collect();
        (bits, e.start, e.model_solutions, e.misfit.to_bits())
    };
    let one = on(1);
    assert!(one.1 >= frfup::updating::fullband::estimate::SPREAD_START);
    assert_eq!(one, on(3));
}

/// Parameters the resonance frequencies do not see are held near the start
/// by the coarse stage: the update benchmark's case 125 of seed 1 (pinned
/// portal, roving hammer at 6 points, z only, 5 elastic modes; three of its
/// four parameters share one member's mass and axial stiffness and move its
/// frequencies by 0.4–1.6 % each). A fit to the frequencies alone took them
/// to −63 %, +112 %, +199 % from every start, a minimum at 0.99× the noise
/// level with standard deviations of 0.0005–0.002 (false certainty: the
/// truth fits at 0.94×). Held near the start (sd 0.3), the estimate reaches
/// the truth: every parameter within 7e-4 (measured), standard deviations
/// 0.00002–0.0008. Tolerance 0.005 (six of the largest sd).
#[test]
fn a_frequency_fit_leaves_the_parameters_it_cannot_see_near_the_start() {
    let (case, r) = benchmark_case_updated(125);
    assert!(
        (case.params[2].value - 0.2383).abs() < 1e-4,
        "the generator drew another case"
    );
    let est = r.estimate.as_ref().expect("full-band estimate");
    assert!(r.converged && est.misfit < 1.0, "misfit {}", est.misfit);
    every_parameter_within(&case, &r, 0.005);
}

/// A minimum just above the noise level is not taken for the one the data
/// support: the update benchmark's case 147 of seed 1 (10 channels, five
/// Young's moduli and second moments). From the first stage's result the
/// estimate ended at 1.017× the noise level with `Iy_m2s3` and `E_m1s1`
/// 0.07 from the truth (100 standard deviations); from the deck it reaches
/// the truth at 0.955× (measured: every parameter within 4e-4). Tolerance
/// 0.005: the standard deviations are 0.0001–0.002.
#[test]
fn a_minimum_just_above_the_noise_level_sends_the_estimate_to_the_other_starts() {
    let (case, r) = benchmark_case_updated(147);
    assert!(
        (case.params[0].value + 0.2711).abs() < 1e-4,
        "the generator drew another case"
    );
    let est = r.estimate.as_ref().expect("full-band estimate");
    assert!(r.converged && est.misfit < 1.0, "misfit {}", est.misfit);
    assert_eq!(est.start, 0, "the deck's start");
    every_parameter_within(&case, &r, 0.005);
}

/// Channels the excitation does not reach: case 035 of the update
/// benchmark's seed 2 (a pinned straight space beam excited at 52+y, 24
/// channels in x, y and z at 8 nodes). Its x channels are exact zeros, its
/// z channels rounding (1e-26 of the y ones), and their noise was taken
/// from themselves: the z channels' rounding dominated the fit (3·10⁶× the
/// noise level, rho_m1s1 at +9.29 "identified"). Below 1e-9 of the largest
/// channel they now lie under the noise floor, are named in a warning, and
/// the fit reaches the noise level (0.81× measured) with every parameter
/// within 0.003 of the truth; tolerance 0.01 as for the cases above.
#[test]
fn channels_the_excitation_does_not_reach_are_left_out_and_named() {
    let (case, r) = benchmark_case_of_seed_updated(2, 35);
    let silent = r
        .warnings
        .iter()
        .find_map(|w| match w {
            frfup::updating::UpdateWarning::SilentChannels { channels } => Some(channels.clone()),
            _ => None,
        })
        .expect("the silent channels named");
    assert_eq!(silent.len(), 16, "{silent:?}");
    assert!(silent
        .iter()
        .all(|c| c.ends_with("+x") || c.ends_with("+z")));
    let est = r.estimate.as_ref().unwrap();
    assert!(est.misfit < 1.2, "misfit {}", est.misfit);
    every_parameter_within(&case, &r, 0.01);
}

/// Seed 2, case 122: a free-free plane T-frame measured in x only, whose
/// two top-bar halves (Iy of members 1 and 2, truth +0.321 and +0.077)
/// the data cannot tell apart at the deck (symmetric there: only their
/// sum shows). Holding both at the deck's value left the fit at 386× the
/// noise level; the first pass's optimum and its mirror image (the two
/// values swapped) are both fitted instead, fit alike, and the pair is
/// reported not identified, not held, with half their distance as its
/// standard deviation and the direction named, while every other
/// parameter is found (within 0.002) at the noise level.
#[test]
fn two_like_members_whose_mirror_fits_as_well_are_not_identified_but_fitted() {
    let (case, r) = benchmark_case_of_seed_updated(2, 122);
    let est = r.estimate.as_ref().unwrap();
    assert!(est.misfit < 1.2, "misfit {}", est.misfit);
    let pair = ["Iy_m1s1", "Iy_m2s1"];
    for p in &case.params {
        let e = est.parameters.iter().find(|e| e.name == p.name).unwrap();
        if pair.contains(&p.name.as_str()) {
            assert!(!e.identified && !e.held, "{e:?}");
            // Either value: the truth of one member or of the other.
            let other = case
                .params
                .iter()
                .find(|q| pair.contains(&q.name.as_str()) && q.name != p.name)
                .unwrap();
            let near = (e.value - p.value).abs().min((e.value - other.value).abs());
            assert!(
                near < 0.002,
                "{}: {} vs {} or {}",
                p.name,
                e.value,
                p.value,
                other.value
            );
            assert!(
                (e.sd - 0.5 * (p.value - other.value).abs()).abs() < 0.005,
                "{e:?}"
            );
        } else {
            assert!(
                e.identified && (e.value - p.value).abs() < 0.002,
                "{e:?} vs {}",
                p.value
            );
        }
    }
    let named = est
        .missing_directions
        .iter()
        .any(|(d, _)| d.len() == 2 && d.iter().all(|(n, _)| pair.contains(&n.as_str())));
    assert!(named, "{:?}", est.missing_directions);
}

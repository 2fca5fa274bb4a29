//! A deterministic global search for least squares over piecewise objectives.
//!
//! A steady state of a switching model is piecewise smooth in its parameters, and its
//! best fit often lies on a *face* of the feasible set rather than inside it: a contact
//! whose kinetic friction equals its breakaway force (`F_C = F_S`) is where a model with a
//! small viscous coefficient fits measured growth best, and a local search started inside
//! (`F_C < F_S`) slides into another basin (`F_C = 0` with a huge viscous coefficient) and
//! stays there. Local descent cannot step onto the face either: beyond it the model cannot be
//! evaluated at all.
//!
//! So the search works face by face. Each ordering `lower <= upper` between two fitted
//! parameters (a contact's Coulomb force and its breakaway force) gives a face where the
//! two are tied. For the interior and every face with up to three orderings tied, it
//! 1. *screens* the face's box with a Halton sequence (deterministic, evenly spread: the
//!    same points every run) and keeps the best few points as starts, besides the caller's
//!    own starts projected onto the face;
//! 2. runs [`calibrate::least_squares`] on the face's reduced parameters from each start:
//!    first from the best start of all, then from the others, each knowing where that
//!    first fit ended, so that a descent crawling above it stops early;
//!
//! and keeps the best face's optimum, which is then *polished* on all parameters (so that a
//! threshold the data does not pin, the breakaway force above the tied Coulomb force, gets
//! its interval, and standard errors come from the full Jacobian). Nothing is random: a fit
//! is a function of its data. The faces, and the local fits on each, run side by side
//! (each with a residual function of its own, as an evaluator caches the modes it has
//! derived), and their outcomes are taken in order, so threads change only the time.

use bondgraph_core::linear::Var;
use bondgraph_core::model::{ElementKind, Friction, Model};
use bondgraph_core::symbolic::RatFunc;

use rayon::prelude::*;

use crate::calibrate::{self, CalibrationError, Ending, Fit, Settings};

/// How widely a fit searches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Search {
    /// Halton points screened on each face.
    pub screened: usize,
    /// The best screened points of each face that start a local fit.
    pub local_fits: usize,
    /// Search every face (up to three orderings tied); otherwise only the faces the
    /// caller's starts lie on (a fold's refit, started from the full data's optimum).
    pub every_face: bool,
}

impl Search {
    /// The full search: what a model's first fit on its data uses.
    pub const GLOBAL: Self = Self {
        screened: 64,
        local_fits: 2,
        every_face: true,
    };

    /// Local fits from the caller's starts only, each on the face it lies on.
    pub const LOCAL: Self = Self {
        screened: 0,
        local_fits: 0,
        every_face: false,
    };
}

impl Default for Search {
    fn default() -> Self {
        Self::GLOBAL
    }
}

/// `values[lower] <= values[upper]` must hold (outside it the model cannot be evaluated).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ordering {
    /// The parameter that must not exceed the other.
    pub lower: usize,
    /// The parameter it must not exceed.
    pub upper: usize,
}

/// The orderings among the fitted parameters `names` that the model's friction contacts
/// impose: a contact whose breakaway force exceeds its Coulomb force by exactly the
/// difference of two fitted parameters (`F_S - F_C`, or `F_S + mu P - (F_C + mu P)` where
/// both grow with an input) needs the one not to exceed the other.
pub fn orderings(model: &Model, names: &[String]) -> Vec<Ordering> {
    model
        .element_ids()
        .filter_map(|id| match &model.element(id).kind {
            ElementKind::Friction(friction) => gap_between(model, names, friction),
            _ => None,
        })
        .collect()
}

/// The fitted parameters `(lower, upper)` whose difference `upper - lower` is exactly the
/// contact's breakaway force less its Coulomb force, if it is such a difference: no input,
/// no other parameter, no constant, checked at the model's values and at a second point.
fn gap_between(model: &Model, names: &[String], friction: &Friction) -> Option<Ordering> {
    let mut gap = friction.breakaway.value.clone();
    gap.add_scaled(&friction.coulomb.value, &RatFunc::integer(-1));
    if gap.mentions(|v| v != Var::Constant) {
        return None;
    }
    let gap = gap.coefficient(Var::Constant);
    let slots: Vec<usize> = names
        .iter()
        .map(|n| {
            model
                .parameters()
                .iter()
                .find(|p| &p.name == n)
                .map(|p| p.symbol.index())
        })
        .collect::<Option<_>>()?;
    let (mut lower, mut upper) = (None, None);
    for (j, &slot) in slots.iter().enumerate() {
        let mut moved = model.values().to_vec();
        moved[slot] += 1.0;
        let slope = gap.eval(&moved) - gap.eval(model.values());
        if (slope - 1.0).abs() < 1e-9 && upper.is_none() {
            upper = Some(j);
        } else if (slope + 1.0).abs() < 1e-9 && lower.is_none() {
            lower = Some(j);
        } else if slope.abs() > 1e-9 {
            return None;
        }
    }
    let ordering = Ordering {
        lower: lower?,
        upper: upper?,
    };
    // Exactly the difference (nothing else in it), here and at another point.
    let second: Vec<f64> = model.values().iter().map(|v| 1.7 * v + 0.3).collect();
    for values in [model.values(), &second] {
        let difference = values[slots[ordering.upper]] - values[slots[ordering.lower]];
        if (gap.eval(values) - difference).abs() > 1e-9 * (1.0 + difference.abs()) {
            return None;
        }
    }
    Some(ordering)
}

/// Faces searched with every face on: the interior, then every set of up to this many
/// orderings tied.
const MAX_TIED: usize = 3;

/// What a search found: the best fit, and the distinct local optima it met on the way.
#[derive(Clone, Debug)]
pub struct Searched {
    /// The best fit, polished on every parameter.
    pub fit: Fit,
    /// The distinct local optima of the local fits (full parameter vectors), best first, at
    /// most [`BASINS_KEPT`], the polished optimum first: where a refit on part of the data
    /// starts, so that it may change basin as the whole search would, without searching
    /// again.
    pub basins: Vec<Vec<f64>>,
}

/// Local optima a search keeps as [`Searched::basins`].
pub const BASINS_KEPT: usize = 2;

/// Two local optima closer than this in every parameter, in units of its bounds' width,
/// are one basin.
const SAME_BASIN: f64 = 1e-3;

/// A search's objective on a face, in the face's reduced parameters.
struct OnFace<'o, 'r> {
    objective: &'o mut dyn calibrate::ResidualFunction,
    reduced: &'r Reduced,
}

impl calibrate::ResidualFunction for OnFace<'_, '_> {
    fn residuals(&mut self, u: &[f64]) -> Option<Vec<f64>> {
        self.objective.residuals(&self.reduced.expand(u))
    }

    fn differenced(&mut self, u: &[f64], from: &[f64]) -> Option<Vec<f64>> {
        let (x, from) = (self.reduced.expand(u), self.reduced.expand(from));
        self.objective.differenced(&x, &from)
    }

    fn sum_of_squares(&mut self, u: &[f64], limit: f64) -> Option<f64> {
        self.objective
            .sum_of_squares(&self.reduced.expand(u), limit)
    }
}

/// A search's own residuals (each search running side by side makes one).
pub type Residuals<'a> = Box<dyn calibrate::ResidualFunction + 'a>;

/// Minimises the sum of squared residuals over the box `bounds` subject to `orderings`,
/// searching as `search` says from `starts` (every start is tried, on the face it lies on).
///
/// The faces, and the local fits on each, are searched side by side, each with its own
/// residual function from `residuals`; their outcomes are taken in order, so the result
/// is the same however many threads run them.
///
/// # Errors
/// When no start and no screened point can be evaluated, or a bound is not a finite interval.
pub fn least_squares<'a>(
    residuals: &(dyn Fn() -> Residuals<'a> + Sync),
    starts: &[&[f64]],
    bounds: &[(f64, f64)],
    orderings: &[Ordering],
    search: &Search,
    settings: &Settings,
) -> Result<Searched, CalibrationError> {
    let mut faces: Vec<Vec<Ordering>> = if search.every_face {
        subsets(orderings, MAX_TIED)
    } else {
        Vec::new()
    };
    for start in starts {
        let face = face_of(start, bounds, orderings);
        if !faces.contains(&face) {
            faces.push(face);
        }
    }
    // Each face screened and its starts evaluated, face by face side by side; then the local
    // fits ([`local_fits`]).
    let screened: Vec<Screened> = faces
        .par_iter()
        .filter_map(|face| {
            // None: the tied parameters' bounds do not overlap.
            let reduced = Reduced::new(bounds, face)?;
            let mut screening = residuals();
            let mut face_starts: Vec<(Option<f64>, Vec<f64>)> = starts
                .iter()
                .filter(|s| face_of(s, bounds, orderings) == *face)
                .map(|s| {
                    let start = reduced.project(s);
                    let sse = screening.sum_of_squares(&reduced.expand(&start), f64::INFINITY);
                    (sse, start)
                })
                .collect();
            let given = face_starts.len();
            face_starts.extend(
                screen(
                    &mut |u: &[f64], limit: f64| {
                        screening.sum_of_squares(&reduced.expand(u), limit)
                    },
                    &reduced.bounds,
                    search,
                )
                .into_iter()
                .map(|(sse, x)| (Some(sse), x)),
            );
            Some((reduced, face_starts, given))
        })
        .collect();
    let searched = local_fits(residuals, &screened, settings);
    let mut evaluations = 0;
    let mut best: Option<(Fit, Ending, Reduced)> = None;
    let mut optima: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut failure = None;
    for (reduced, fits, given) in searched {
        // The evaluations of the caller's starts, and the screening's.
        evaluations += given + search.screened;
        for result in fits {
            match result {
                Ok((fit, ending)) => {
                    evaluations += fit.evaluations;
                    optima.push((fit.sse, reduced.expand(&fit.values)));
                    if best.as_ref().is_none_or(|(b, _, _)| fit.sse < b.sse) {
                        best = Some((fit, ending, reduced.clone()));
                    }
                }
                Err(e) => {
                    evaluations += 1;
                    failure = Some(e);
                }
            }
        }
    }
    let Some((face_fit, ending, reduced)) = best else {
        return Err(failure.unwrap_or_else(|| {
            CalibrationError("no start and no screened point could be evaluated".into())
        }));
    };
    // A best fit that tied no parameters and converged is the polish's own end: a polish
    // from it would difference every column again, try the Gauss–Newton step and scan the
    // flat parameters again, a dozen predictions of every row, to stay where it is.
    if ending == Ending::Converged && reduced.is_whole() {
        let mut fit = face_fit;
        fit.evaluations = evaluations;
        let basins = distinct_basins(optima, bounds);
        return Ok(Searched { fit, basins });
    }
    // Polish on every parameter from the face's optimum: the tied parameters part where the
    // data allows it, and the errors come from the full Jacobian.
    let start = reduced.expand(&face_fit.values);
    let mut polish = residuals();
    let mut fit = calibrate::least_squares(&mut *polish, &start, bounds, settings)?;
    fit.evaluations += evaluations;
    errors_on_the_face(&mut fit, &face_fit, &reduced);
    optima.push((f64::NEG_INFINITY, fit.values.clone()));
    let basins = distinct_basins(optima, bounds);
    Ok(Searched { fit, basins })
}

/// A face screened: its reduced parameters, its starts (with their sums of squares, `None`
/// where the model cannot be evaluated), and how many of them are the caller's.
type Screened = (Reduced, Vec<(Option<f64>, Vec<f64>)>, usize);

/// A face's reduced parameters, its local fits (one per start, in order), and how many
/// starts were the caller's.
type Fitted<'r> = (
    &'r Reduced,
    Vec<Result<(Fit, Ending), CalibrationError>>,
    usize,
);

/// A local fit from every start of every face, in two waves: first from the best start of
/// all, then from the others side by side, each knowing the lower of the best start's sum
/// of squares and where that first fit ended (a bar some local fit ends at or below), so
/// that a descent crawling above it, too slowly to reach it, ends its round early
/// ([`calibrate::least_squares_toward`]). The waves and the bars are fixed before any fit
/// runs, so the search is the same however the threads interleave.
fn local_fits<'r, 'a>(
    residuals: &(dyn Fn() -> Residuals<'a> + Sync),
    screened: &'r [Screened],
    settings: &Settings,
) -> Vec<Fitted<'r>> {
    let local = |reduced: &Reduced, start: &[f64], bar: f64| {
        let mut local = residuals();
        calibrate::least_squares_toward(
            &mut OnFace {
                objective: &mut *local,
                reduced,
            },
            start,
            &reduced.bounds,
            settings,
            bar,
        )
    };
    let sse_of = |(face, k): (usize, usize)| screened[face].1[k].0.unwrap_or(f64::INFINITY);
    let every = screened
        .iter()
        .enumerate()
        .flat_map(|(face, (_, face_starts, _))| (0..face_starts.len()).map(move |k| (face, k)));
    let bar = every.clone().map(sse_of).fold(f64::INFINITY, f64::min);
    let lead = every.min_by(|&a, &b| sse_of(a).total_cmp(&sse_of(b)));
    let mut first = lead.map(|(face, k)| local(&screened[face].0, &screened[face].1[k].1, bar));
    let second_bar = match &first {
        Some(Ok((fit, _))) => bar.min(fit.sse),
        _ => bar,
    };
    let rest: Vec<Vec<Option<_>>> = screened
        .par_iter()
        .enumerate()
        .map(|(face, (reduced, face_starts, _))| {
            face_starts
                .par_iter()
                .enumerate()
                .map(|(k, (_, start))| {
                    (Some((face, k)) != lead).then(|| local(reduced, start, second_bar))
                })
                .collect()
        })
        .collect();
    screened
        .iter()
        .zip(rest)
        .map(|((reduced, _, given), fits)| {
            let fits = fits
                .into_iter()
                .map(|fit| {
                    fit.or_else(|| first.take())
                        .expect("each start fitted once")
                })
                .collect();
            (reduced, fits, *given)
        })
        .collect()
}

/// The best [`BASINS_KEPT`] of `optima` (`(sse, values)`), one per basin: an optimum within
/// [`SAME_BASIN`] of a better one in every parameter is that one's.
fn distinct_basins(mut optima: Vec<(f64, Vec<f64>)>, bounds: &[(f64, f64)]) -> Vec<Vec<f64>> {
    optima.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut basins: Vec<Vec<f64>> = Vec::new();
    for (_, values) in optima {
        let same = |kept: &Vec<f64>| {
            kept.iter()
                .zip(&values)
                .zip(bounds)
                .all(|((a, b), (lo, hi))| (a - b).abs() <= SAME_BASIN * (hi - lo))
        };
        if basins.len() < BASINS_KEPT && !basins.iter().any(same) {
            basins.push(values);
        }
    }
    basins
}

/// Where the polish stays on the face (no better point off it) and the full Jacobian leaves
/// parameters without errors (a tied Coulomb and breakaway force move the residuals alike,
/// which makes the normal matrix singular and costs every parameter its error), the errors
/// of the fit constrained to the face: those of its reduced parameters, a tied pair sharing
/// its lower side's. A threshold's interval is kept.
fn errors_on_the_face(fit: &mut Fit, face_fit: &Fit, reduced: &Reduced) {
    let on_face = reduced
        .expand(&face_fit.values)
        .iter()
        .zip(&fit.values)
        .zip(&reduced.widths())
        .all(|((a, b), w)| (a - b).abs() <= 1e-9 * w);
    if !on_face {
        return;
    }
    for (j, &r) in reduced.source.iter().enumerate() {
        if fit.std_errors[j].is_none() && fit.intervals[j].is_none() && !fit.at_bound[j] {
            fit.std_errors[j] = face_fit.std_errors[r];
        }
    }
}

/// Every set of at most `most` orderings, the empty one first.
fn subsets(orderings: &[Ordering], most: usize) -> Vec<Vec<Ordering>> {
    let mut all = vec![Vec::new()];
    for ordering in orderings {
        let grown: Vec<Vec<Ordering>> = all
            .iter()
            .filter(|s| s.len() < most)
            .map(|s| {
                let mut s = s.clone();
                s.push(*ordering);
                s
            })
            .collect();
        all.extend(grown);
    }
    all.sort_by_key(Vec::len);
    all
}

/// The orderings a point holds with equality (within a billionth of the bounds' width): the
/// face it lies on.
fn face_of(x: &[f64], bounds: &[(f64, f64)], orderings: &[Ordering]) -> Vec<Ordering> {
    orderings
        .iter()
        .filter(|o| {
            let width =
                (bounds[o.lower].1 - bounds[o.lower].0).max(bounds[o.upper].1 - bounds[o.upper].0);
            x[o.lower] >= x[o.upper] - 1e-9 * width
        })
        .copied()
        .collect()
}

/// The best `search.local_fits` of `search.screened` Halton points in `bounds`, best
/// first, with their sums of squares.
fn screen(
    sum_of_squares: &mut dyn FnMut(&[f64], f64) -> Option<f64>,
    bounds: &[(f64, f64)],
    search: &Search,
) -> Vec<(f64, Vec<f64>)> {
    // The best `local_fits` so far, best first. A point is evaluated only as far as it can
    // still join them (partial sums of squares only grow), so the points kept are those a
    // full evaluation of every point would keep.
    let mut best: Vec<(f64, Vec<f64>)> = Vec::with_capacity(search.local_fits + 1);
    for k in 1..=search.screened {
        let x: Vec<f64> = bounds
            .iter()
            .enumerate()
            .map(|(d, &(lo, hi))| lo + halton(k, PRIMES[d % PRIMES.len()]) * (hi - lo))
            .collect();
        let limit = if best.len() < search.local_fits {
            f64::INFINITY
        } else {
            best.last().map_or(f64::INFINITY, |(worst, _)| *worst)
        };
        let Some(sse) = sum_of_squares(&x, limit) else {
            continue;
        };
        // Ties keep the earlier point, as a stable sort of every point would.
        let at = best.partition_point(|(b, _)| b.total_cmp(&sse).is_le());
        if at < search.local_fits {
            best.insert(at, (sse, x));
            best.truncate(search.local_fits);
        }
    }
    best
}

/// Bases of the Halton sequence, one per dimension.
const PRIMES: [usize; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// The `k`-th element of the van der Corput sequence in `base`: `k`'s digits mirrored
/// about the radix point.
fn halton(mut k: usize, base: usize) -> f64 {
    let mut value = 0.0;
    let mut scale = 1.0 / base as f64;
    while k > 0 {
        value += (k % base) as f64 * scale;
        k /= base;
        scale /= base as f64;
    }
    value
}

/// The parameters of one face: the full set less the upper side of each tied ordering,
/// which takes its lower side's value.
#[derive(Clone, Debug)]
struct Reduced {
    /// The full index of each reduced parameter.
    kept: Vec<usize>,
    /// For every full parameter, the reduced one that gives its value.
    source: Vec<usize>,
    /// The reduced parameters' bounds (a tied pair's is the overlap of both).
    bounds: Vec<(f64, f64)>,
}

impl Reduced {
    /// Whether no parameter is tied: the reduced parameters are the full ones.
    fn is_whole(&self) -> bool {
        self.kept.len() == self.source.len()
    }

    /// `None` when a tied pair's bounds do not overlap, or the orderings chain (a parameter
    /// tied on both sides), which the face search does not handle.
    fn new(bounds: &[(f64, f64)], tied: &[Ordering]) -> Option<Self> {
        let mut uses = vec![0usize; bounds.len()];
        for o in tied {
            uses[o.lower] += 1;
            uses[o.upper] += 1;
        }
        if uses.iter().any(|&n| n > 1) {
            return None;
        }
        let upper_of = |j: usize| tied.iter().find(|o| o.lower == j).map(|o| o.upper);
        let is_upper = |j: usize| tied.iter().any(|o| o.upper == j);
        let kept: Vec<usize> = (0..bounds.len()).filter(|&j| !is_upper(j)).collect();
        let mut reduced_bounds = Vec::with_capacity(kept.len());
        for &j in &kept {
            let (mut lo, mut hi) = bounds[j];
            if let Some(u) = upper_of(j) {
                lo = lo.max(bounds[u].0);
                hi = hi.min(bounds[u].1);
                if lo >= hi {
                    return None;
                }
            }
            reduced_bounds.push((lo, hi));
        }
        let source = (0..bounds.len())
            .map(|j| {
                let giver = tied.iter().find(|o| o.upper == j).map_or(j, |o| o.lower);
                kept.iter().position(|&k| k == giver).expect("kept")
            })
            .collect();
        Some(Self {
            kept,
            source,
            bounds: reduced_bounds,
        })
    }

    /// The width of each full parameter's bounds, through the reduced one that gives it.
    fn widths(&self) -> Vec<f64> {
        self.source
            .iter()
            .map(|&r| self.bounds[r].1 - self.bounds[r].0)
            .collect()
    }

    /// The full parameter vector of a reduced one.
    fn expand(&self, reduced: &[f64]) -> Vec<f64> {
        self.source.iter().map(|&s| reduced[s]).collect()
    }

    /// A full vector's reduced one (a tied pair takes the lower side's value), clamped to
    /// the face's bounds.
    fn project(&self, full: &[f64]) -> Vec<f64> {
        self.kept
            .iter()
            .zip(&self.bounds)
            .map(|(&j, &(lo, hi))| full[j].clamp(lo, hi))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screening_keeps_the_points_a_full_evaluation_keeps_and_stops_rows_early() {
        // Twenty "rows" alike, each with residuals x0 - 0.3 and x1 - 0.7 (the sums of
        // squares then tie only where the points do); a failure where x0 > 0.95. Sorting every screened point by its
        // whole sum of squares (ties in order) is the reference.
        let bounds = [(0.0, 1.0), (0.0, 1.0)];
        let search = Search {
            screened: 64,
            local_fits: 3,
            every_face: true,
        };
        let row = |x: &[f64], _r: usize| (x[0] - 0.3).powi(2) + (x[1] - 0.7).powi(2);
        let mut reference: Vec<(f64, Vec<f64>)> = (1..=search.screened)
            .map(|k| vec![halton(k, 2), halton(k, 3)])
            .filter(|x| x[0] <= 0.95)
            .map(|x| ((0..20).map(|r| row(&x, r)).sum(), x))
            .collect();
        reference.sort_by(|a, b| a.0.total_cmp(&b.0));
        // The points kept, with their whole sums of squares (the bar of the local fits).
        let expected: Vec<(f64, Vec<f64>)> = reference.into_iter().take(3).collect();

        let mut rows_predicted = 0;
        let mut bounded = |x: &[f64], limit: f64| {
            if x[0] > 0.95 {
                return None;
            }
            let mut sum = 0.0;
            for r in 0..20 {
                rows_predicted += 1;
                sum += row(x, r);
                if sum > limit {
                    break;
                }
            }
            Some(sum)
        };
        assert_eq!(screen(&mut bounded, &bounds, &search), expected);
        // Evaluated whole, the 61 points that do not fail would cost 20 rows each; most are
        // put out of the best three after a few of their rows.
        let whole = 20 * 61;
        assert!(
            rows_predicted < whole / 2,
            "{rows_predicted} rows of {whole}"
        );
    }

    #[test]
    fn basins_keep_the_best_optimum_of_each_and_the_best_basins() {
        // Bounds 10 wide: optima within a hundredth (1e-3 of the width) are one basin.
        let bounds = [(0.0, 10.0), (0.0, 10.0)];
        let optima = vec![
            (3.0, vec![5.0, 5.0]),
            (1.0, vec![1.0, 1.0]),
            (1.5, vec![1.005, 0.995]), // the basin of (1, 1)
            (2.0, vec![9.0, 1.0]),
            (2.5, vec![1.0, 9.0]),
        ];
        // The best of each basin, best first, at most BASINS_KEPT.
        let expected = [
            vec![1.0, 1.0],
            vec![9.0, 1.0],
            vec![1.0, 9.0],
            vec![5.0, 5.0],
        ];
        assert_eq!(
            distinct_basins(optima, &bounds),
            expected[..BASINS_KEPT].to_vec()
        );
    }

    #[test]
    fn halton_points_are_the_mirrored_digits() {
        // 1, 2, 3 in base 2 are 1, 10, 11: mirrored 0.1, 0.01, 0.11 = 1/2, 1/4, 3/4.
        assert_eq!(halton(1, 2), 0.5);
        assert_eq!(halton(2, 2), 0.25);
        assert_eq!(halton(3, 2), 0.75);
        // 5 in base 3 is 12: mirrored 0.21 = 2/3 + 1/9.
        assert!((halton(5, 3) - (2.0 / 3.0 + 1.0 / 9.0)).abs() < 1e-15);
    }

    #[test]
    fn faces_are_every_set_of_at_most_three_orderings() {
        let o = |k: usize| Ordering {
            lower: 2 * k,
            upper: 2 * k + 1,
        };
        let four = [o(0), o(1), o(2), o(3)];
        let faces = subsets(&four, 3);
        // C(4,0) + C(4,1) + C(4,2) + C(4,3) = 1 + 4 + 6 + 4.
        assert_eq!(faces.len(), 15);
        assert!(faces[0].is_empty());
        assert!(faces.iter().all(|f| f.len() <= 3));
    }

    #[test]
    fn a_tied_pair_shares_one_value_within_both_bounds() {
        let bounds = [(0.0, 30.0), (0.0, 5000.0), (5.0, 40.0)];
        let tied = [Ordering { lower: 0, upper: 2 }];
        let reduced = Reduced::new(&bounds, &tied).unwrap();
        assert_eq!(reduced.bounds, vec![(5.0, 30.0), (0.0, 5000.0)]);
        assert_eq!(reduced.expand(&[11.0, 100.0]), vec![11.0, 100.0, 11.0]);
        assert_eq!(reduced.project(&[2.0, 100.0, 12.0]), vec![5.0, 100.0]);
        // Disjoint bounds: no face.
        assert!(
            Reduced::new(
                &[(0.0, 1.0), (2.0, 3.0)],
                &[Ordering { lower: 0, upper: 1 }]
            )
            .is_none()
        );
    }

    /// A contact pushed by forces `1..=20` N: stuck (velocity 0) up to its breakaway force
    /// `x[2]`, sliding above it at `(P - F_C)/b` with `F_C = x[0]`, `b = x[1]`; it cannot be
    /// evaluated with `F_C > F_S`. The data were made with `F_C = F_S = 9`, `b = 2`.
    fn contact(x: &[f64]) -> Option<Vec<f64>> {
        let velocity = |p: f64, f_c: f64, b: f64, f_s: f64| {
            if p <= f_s { 0.0 } else { (p - f_c) / b }
        };
        (x[0] <= x[2]).then(|| {
            (1..=20)
                .map(|p| {
                    let p = f64::from(p);
                    velocity(p, x[0], x[1], x[2]) - velocity(p, 9.0, 2.0, 9.0)
                })
                .collect()
        })
    }

    #[test]
    fn the_optimum_on_the_face_is_found_from_a_start_inside() {
        let bounds = [(0.0, 30.0), (0.1, 50.0), (0.0, 30.0)];
        let start = [0.0, 25.0, 15.0];
        let ties = [Ordering { lower: 0, upper: 2 }];
        let global = least_squares(
            &|| Box::new(contact),
            &[&start],
            &bounds,
            &ties,
            &Search::GLOBAL,
            &Settings::default(),
        )
        .unwrap()
        .fit;
        assert!(global.sse < 1e-12, "{global:?}");
        // The data pin F_C and b exactly; F_S only to a window: at least 9 (F_C) and below
        // 10 (the first row that slides in the data, P = 10, must slide).
        assert!((global.values[0] - 9.0).abs() < 1e-6, "{:?}", global.values);
        assert!((global.values[1] - 2.0).abs() < 1e-6, "{:?}", global.values);
        assert!(global.values[2] >= 9.0 && global.values[2] < 10.0);
        let (lo, hi) = global.intervals[2].expect("a threshold's interval");
        assert!(
            (lo - 9.0).abs() < 0.01 && (hi - 10.0).abs() < 0.01,
            "{lo} {hi}"
        );
    }

    #[test]
    fn a_local_fit_that_converged_with_nothing_tied_is_not_polished_again() {
        // y = 3 exp(-0.7 t) at 20 times, fitted as a exp(-k t) from (1, 0.2): the one local
        // fit converges on the whole parameter space, and the search returns it as it is,
        // having evaluated its start once and then only what that fit evaluated (a polish
        // would evaluate the start again, difference both columns and try a step).
        let t: Vec<f64> = (0..20).map(|k| f64::from(k) * 0.25).collect();
        let decay = |p: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .map(|&t| p[0] * (-p[1] * t).exp() - 3.0 * (-0.7 * t).exp())
                    .collect(),
            )
        };
        let bounds = [(0.0, 10.0), (0.0, 5.0)];
        let start = [1.0, 0.2];
        let counted = std::sync::atomic::AtomicUsize::new(0);
        let counting = |p: &[f64]| {
            counted.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            decay(p)
        };
        let searched = least_squares(
            &|| Box::new(counting),
            &[&start],
            &bounds,
            &[],
            &Search::LOCAL,
            &Settings::default(),
        )
        .unwrap();
        let (local, ending) = calibrate::least_squares_toward(
            &mut { decay },
            &start,
            &bounds,
            &Settings::default(),
            f64::INFINITY,
        )
        .unwrap();
        assert_eq!(ending, Ending::Converged);
        assert_eq!(searched.fit.values, local.values);
        assert!(
            (searched.fit.values[1] - 0.7).abs() < 1e-6,
            "{:?}",
            local.values
        );
        let made = counted.load(std::sync::atomic::Ordering::Relaxed);
        assert_eq!(made, 1 + local.evaluations);
        assert_eq!(searched.fit.evaluations, made);
    }

    #[test]
    fn a_crawl_above_where_the_best_start_ended_stops_early() {
        // Above x1 = 2 a bowl with its minimum of 1 at (1, 2.5); below, a valley where x1
        // falls to 0.5 in a step and x0 crawls (the Gauss–Newton curvature a thousand times
        // the true one) at a sum of squares near 100. The bowl's start is the better one
        // (157.5 against 200) and its fit ends at 1; the valley's fit, crawling far above
        // that, ends its descent after a few steps, where against the starts' bar of 157.5
        // alone it crawled through all its iterations.
        let objective = |x: &[f64]| -> Option<Vec<f64>> {
            let e = x[0] - 1.0;
            Some(if x[1] >= 2.0 {
                vec![e, 1.0, 25.0 * (x[1] - 2.5)]
            } else {
                vec![e, 10.0 - 0.04995 * e * e, 20.0 * (x[1] - 0.5)]
            })
        };
        let bounds = [(0.0, 3.0), (0.0, 3.0)];
        let (bowl, valley) = ([1.5, 3.0], [2.0, 1.0]);
        let settings = Settings::default();
        let alone = |start: &[f64], bar: f64| {
            calibrate::least_squares_toward(&mut { objective }, start, &bounds, &settings, bar)
                .unwrap()
        };
        let (bowl_fit, _) = alone(&bowl, 157.5);
        assert!((bowl_fit.sse - 1.0).abs() < 1e-9, "{}", bowl_fit.sse);
        let (crawled, _) = alone(&valley, 157.5);
        let (stopped, ending) = alone(&valley, bowl_fit.sse);
        assert_eq!(ending, Ending::Crawled);
        assert!(crawled.evaluations > 100, "{}", crawled.evaluations);
        assert!(stopped.evaluations < 40, "{}", stopped.evaluations);
        let counted = std::sync::atomic::AtomicUsize::new(0);
        let counting = |x: &[f64]| {
            counted.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            objective(x)
        };
        let searched = least_squares(
            &|| Box::new(counting),
            &[&valley, &bowl],
            &bounds,
            &[],
            &Search::LOCAL,
            &settings,
        )
        .unwrap();
        assert_eq!(searched.fit.values, bowl_fit.values);
        // The two starts once each, then the two fits, and no polish of a converged fit.
        let made = counted.load(std::sync::atomic::Ordering::Relaxed);
        assert_eq!(made, 2 + bowl_fit.evaluations + stopped.evaluations);
    }

    #[test]
    fn the_search_is_the_same_on_one_thread_and_on_several() {
        // Faces and local fits run side by side; their outcomes are taken in order, so the
        // optimum, the basins and the count of evaluations cannot depend on the threads.
        let bounds = [(0.0, 30.0), (0.1, 50.0), (0.0, 30.0)];
        let starts: [&[f64]; 2] = [&[0.0, 25.0, 15.0], &[20.0, 1.0, 20.0]];
        let ties = [Ordering { lower: 0, upper: 2 }];
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    least_squares(
                        &|| Box::new(contact),
                        &starts,
                        &bounds,
                        &ties,
                        &Search::GLOBAL,
                        &Settings::default(),
                    )
                    .unwrap()
                })
        };
        let (one, four) = (on(1), on(4));
        // The data's own optimum, on either thread count: F_C = 9, b = 2 (the data were
        // made with them), F_S in [9, 10).
        assert!(one.fit.sse < 1e-12, "{:?}", one.fit);
        assert!(
            (one.fit.values[0] - 9.0).abs() < 1e-6,
            "{:?}",
            one.fit.values
        );
        assert!(
            (one.fit.values[1] - 2.0).abs() < 1e-6,
            "{:?}",
            one.fit.values
        );
        assert_eq!(one.fit.values, four.fit.values);
        assert_eq!(one.fit.sse.to_bits(), four.fit.sse.to_bits());
        assert_eq!(one.fit.evaluations, four.fit.evaluations);
        assert_eq!(one.basins, four.basins);
        assert_eq!(one.basins.len(), 2, "{:?}", one.basins);
    }

    #[test]
    fn contacts_order_their_coulomb_and_breakaway_parameters() {
        let model = bondgraph_ron::model::load_str(
            "contacts.ron",
            r#"Model(
                name: "contacts",
                parameters: {
                    "m": (value: 1.0), "dv": (value: 1.0e-6), "mu": (value: 0.1),
                    "F_S": (value: 2.0), "F_C": (value: 1.0),
                    "G_S": (value: 2.0), "G_C": (value: 1.0),
                    "H_S": (value: 2.0), "H_C": (value: 1.0),
                },
                inputs: { "P": () },
                elements: {
                    "push": Se(effort: "P"), "v": One, "body": I(inertance: "m"),
                    "plain": Friction(breakaway: "F_S", coulomb: "F_C", dead_band: "dv"),
                    "loaded": Friction(breakaway: "G_S + mu*P", coulomb: "G_C + mu*P", dead_band: "dv"),
                    "scaled": Friction(breakaway: "2*H_S", coulomb: "H_C", dead_band: "dv"),
                },
                bonds: [("push", "v"), ("v", "body"), ("v", "plain"), ("v", "loaded"), ("v", "scaled")],
            )"#,
        )
        .unwrap();
        let names: Vec<String> = ["F_C", "G_S", "F_S", "G_C", "H_C", "H_S", "mu"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        // `plain`: F_C <= F_S; `loaded`: the input terms cancel, G_C <= G_S; `scaled`: the gap
        // 2 H_S - H_C is not a difference of two parameters.
        assert_eq!(
            orderings(&model, &names),
            vec![
                Ordering { lower: 0, upper: 2 },
                Ordering { lower: 3, upper: 1 }
            ]
        );
        // A contact with a parameter that is not fitted gives no ordering.
        assert_eq!(orderings(&model, &names[..2]), vec![]);
    }

    #[test]
    fn a_local_search_keeps_each_start_on_its_own_face() {
        // From the data's own optimum (on the face F_C = F_S), a local search stays there;
        // from inside, it does not jump onto the face.
        let bounds = [(0.0, 30.0), (0.1, 50.0), (0.0, 30.0)];
        let ties = [Ordering { lower: 0, upper: 2 }];
        let on_face = [9.0, 2.0, 9.0];
        let fit = least_squares(
            &|| Box::new(contact),
            &[&on_face],
            &bounds,
            &ties,
            &Search::LOCAL,
            &Settings::default(),
        )
        .unwrap()
        .fit;
        assert!(fit.sse < 1e-12, "{fit:?}");
        assert_eq!(face_of(&on_face, &bounds, &ties), ties.to_vec());
        assert!(face_of(&[0.0, 25.0, 15.0], &bounds, &ties).is_empty());
    }
}

//! Event location: the first time a guard function reaches zero from below.
//!
//! Within a segment every guard is a closed-form function of local time (a sum of complex
//! exponentials times polynomials, through [`Segment`]), so an event is found by bracketing
//! and then refined to machine precision; no step size limits the accuracy. The bracketing
//! samples follow the mode's own time scales: geometrically from a fraction of the fastest
//! time constant (a stiff tip settles in 1e-17 s), and finely enough to resolve every
//! oscillation while it lasts.
//!
//! A guard is *armed* once its function has been seen negative: a guard that is already
//! satisfied when a mode is entered (a velocity guard of a contact that just started to slip
//! from zero) only fires after it has been left and is reached again.
//!
//! An oscillation is followed for at most [`OSCILLATION_SAMPLES`] samples (625 periods) per
//! segment: a longer segment is cut there ([`Located::Clear`] before its end), after passing
//! over any stretch where a bound of every guard (`events/envelope.rs`) shows that none can
//! reach zero.
//!
//! The samples stop early once a bound of every guard clears the rest of the stretch: looked
//! at before the first sample, then at doubling multiples of the slowest decaying time
//! constant. A segment that settles away from every guard (a contact sliding on, a string
//! taut under a steady pull) then costs a few samples of its start instead of every time
//! scale across the whole segment: what a steady-state search spends most of its time on.
//!
//! # Complexity
//! `O(s · (n² + g))` for `s` samples (typically a hundred, at most 10,000 per oscillation),
//! `n` states and `g` guards, plus a few dozen evaluations per refinement.

mod envelope;

use num_complex::Complex64;

use crate::numeric::{NumericMode, dot};
use crate::propagate::Segment;
use envelope::{Coordinate, Envelope};

/// A guard reaching zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The guard's index in the mode.
    pub guard: usize,
    /// Local time of the crossing.
    pub tau: f64,
}

/// What the locator found in a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Located {
    /// A guard reaches zero.
    Crossing(Crossing),
    /// No guard reaches zero up to this local time: the segment's length, or less where
    /// the samples stopped following an oscillation (the segment is to end there).
    Clear(f64),
}

/// Samples of one oscillation the bracketing may take in a segment: sixteen a period for
/// 625 periods.
pub const OSCILLATION_SAMPLES: usize = 10_000;

/// How far into a segment of `length` the bracketing samples can follow every oscillation
/// of a mode with these eigenvalues, sixteen samples a period for as long as it lasts (40
/// time constants, or the whole segment if undamped): `length`, or less where that would
/// take more than [`OSCILLATION_SAMPLES`] samples of one oscillation.
///
/// A segment is cut there, not sampled more sparsely beyond: a guard creeping up to zero
/// under a fast swing (a slack string whose tug draws away at 1 mm/s while its cart swings
/// ±1 cm at 9.7 rad/s) crosses zero back and forth for dozens of periods, and samples
/// hundreds of periods apart bracket some later zero, or none, instead of the first.
pub fn sampled_horizon(values: &[Complex64], length: f64) -> f64 {
    let mut horizon = length;
    for v in values {
        let rate = v.norm();
        if v.im == 0.0 || !rate.is_finite() {
            continue;
        }
        let spacing = oscillation_spacing(*v);
        let lasts = if v.re < 0.0 {
            (40.0 / -v.re).min(length)
        } else {
            length
        };
        if lasts / spacing > OSCILLATION_SAMPLES as f64 {
            horizon = horizon.min(OSCILLATION_SAMPLES as f64 * spacing);
        }
    }
    horizon
}

/// Sixteen samples a period of the oscillation at `value`.
fn oscillation_spacing(value: Complex64) -> f64 {
    2.0 * std::f64::consts::PI / value.im.abs() / 16.0
}

/// Bracketing samples over `(from, to]` for a mode with these eigenvalues: each decaying
/// time scale `1/|λ|` sampled geometrically while it is active (from 0.02 to 40 time
/// constants after the segment's start), each growing one likewise until it has grown by
/// `e^700`, every oscillation sixteen times a period while it
/// lasts, and the stretch uniformly (sixteen intervals). An oscillation is sampled for at
/// most [`OSCILLATION_SAMPLES`]: a stretch longer than its [`sampled_horizon`] is for the
/// caller to cut.
pub fn sample_times(values: &[Complex64], from: f64, to: f64) -> Vec<f64> {
    let mut buffers = SampleBuffers::default();
    sample_times_into(values, from, to, &mut buffers);
    buffers.times
}

/// The buffers [`sample_times`] fills, kept from one stretch to the next.
#[derive(Debug, Default)]
struct SampleBuffers {
    /// The times, once merged.
    times: Vec<f64>,
    /// Where each increasing run of `times` ends, before merging.
    runs: Vec<usize>,
    /// A merging round's output and its runs' ends.
    merged: Vec<f64>,
    ends: Vec<usize>,
}

/// [`sample_times`] into `buffers.times`.
fn sample_times_into(values: &[Complex64], from: f64, to: f64, buffers: &mut SampleBuffers) {
    let times = &mut buffers.times;
    times.clear();
    // Each time scale gives an increasing run of times; `runs` marks where each ends, and
    // the runs are merged rather than sorted.
    let runs = &mut buffers.runs;
    runs.clear();
    runs.push(0);
    let inside = |t: &f64| *t > from && *t <= to;
    for v in values {
        let rate = v.norm();
        if rate == 0.0 || !rate.is_finite() {
            continue;
        }
        let lasts = if v.re < 0.0 {
            (40.0 / -v.re).min(to)
        } else {
            to
        };
        // A decaying scale is sampled while it lasts; a growing one until it has grown by
        // e^700, close to the largest double: a guard it drives crosses zero on its own time
        // scale (a contact's creep that runs away at 1e17/s reaches the slip speed within
        // attoseconds), and a sample of the uniform stretch beyond would read infinity.
        let active = if v.re > 0.0 {
            (700.0 / v.re).min(to)
        } else {
            lasts
        };
        if v.re != 0.0 {
            let mut t = 0.02 / rate;
            while t < active {
                if inside(&t) {
                    times.push(t);
                }
                t *= 1.8;
            }
            runs.push(times.len());
        }
        if v.im != 0.0 && lasts > from {
            let spacing = oscillation_spacing(*v);
            let count = (((lasts - from) / spacing) as usize).min(OSCILLATION_SAMPLES);
            times.extend(
                (1..=count)
                    .map(|k| from + k as f64 * spacing)
                    .filter(inside),
            );
            runs.push(times.len());
        }
    }
    let uniform = (to - from) / 16.0;
    times.extend((1..16).map(|k| from + k as f64 * uniform).filter(inside));
    times.push(to);
    runs.push(times.len());
    merge_runs(buffers);
    buffers.times.dedup();
}

/// The increasing runs `times[runs[k]..runs[k + 1]]` of `buffers` merged into one
/// increasing sequence, pairwise, in `buffers.times`.
fn merge_runs(buffers: &mut SampleBuffers) {
    let SampleBuffers {
        times,
        runs,
        merged,
        ends,
    } = buffers;
    runs.dedup();
    while runs.len() > 2 {
        merged.clear();
        ends.clear();
        ends.push(0);
        for pair in runs.windows(3).step_by(2) {
            let (left, right) = (&times[pair[0]..pair[1]], &times[pair[1]..pair[2]]);
            let (mut i, mut j) = (0, 0);
            while i < left.len() && j < right.len() {
                if left[i] <= right[j] {
                    merged.push(left[i]);
                    i += 1;
                } else {
                    merged.push(right[j]);
                    j += 1;
                }
            }
            merged.extend_from_slice(&left[i..]);
            merged.extend_from_slice(&right[j..]);
            ends.push(merged.len());
        }
        // An odd run out stays as it is.
        if runs.len().is_multiple_of(2) {
            let last = runs[runs.len() - 2];
            merged.extend_from_slice(&times[last..]);
            ends.push(merged.len());
        }
        std::mem::swap(times, merged);
        std::mem::swap(runs, ends);
    }
}

/// Buffers event location reuses from segment to segment: a steady-state search locates
/// events in thousands of short segments, and allocating them for each was a tenth of its
/// time. Keep one per simulation (it holds no state between calls).
#[derive(Debug, Default)]
pub struct Scratch {
    previous: Vec<f64>,
    current: Vec<f64>,
    previous_slopes: Vec<f64>,
    current_slopes: Vec<f64>,
    /// The guards' values or rates at a refinement's trial point.
    probe: Vec<f64>,
    /// The levels below which each guard is armed in this segment.
    levels: Vec<f64>,
    /// The levels above which each guard fires in this segment.
    fires: Vec<f64>,
    from_zero: Vec<bool>,
    offsets: Vec<(f64, f64)>,
    envelopes: Vec<Envelope>,
    terms: Vec<[Complex64; 4]>,
    coordinates: Vec<Coordinate>,
    stretches: Vec<(f64, f64)>,
    samples: SampleBuffers,
    /// The state at the segment's start.
    start_state: Vec<f64>,
    /// The state and inputs at a sample, and at a rate's, for a segment that is not modal.
    x: Vec<f64>,
    u: Vec<f64>,
    x_rate: Vec<f64>,
    u_rate: Vec<f64>,
}

/// The first crossing of an armed guard in `(0, length]`, arming guards seen below their
/// `arm_below` level (zero, or minus a rounding tolerance for a guard whose switch was just
/// declined, so that rounding noise about zero cannot fire it again and again; over a modal
/// segment, at least 1e-9 of the guard's modal terms at its start). Each guard
/// is taken less its `fire_above` level (zero, or the rounding of its terms for a guard at
/// rest on its threshold, which fires only once clearly past it).
///
/// # Arguments
/// The inputs are `u₀ + u₁ τ` over the segment. `window` is how long a stretch the samples
/// may follow ([`sampled_horizon`], or `length` where the segment must not be cut).
///
/// Each bracketing sample taken is counted in `samples`; `scratch` lends the buffers.
///
/// # Returns
/// The crossing, or how far no guard reaches zero: `length`, or, when `window < length`,
/// the end of the sampled stretch. That stretch starts where some guard may first reach
/// zero by a bound of each guard over a modal segment (`events/envelope.rs`), or at zero.
///
/// (Over the size budget, and listed in `tests/architecture.rs`: its evaluation and slope
/// closures share the scratch buffers across the arming at the start, the bracketing over
/// the samples, the search for a guard touching zero between two and the refinement, and
/// cutting it means threading those buffers through each step.)
#[allow(clippy::too_many_arguments)]
pub fn first_crossing(
    mode: &NumericMode,
    segment: &mut Segment<'_>,
    u0: &[f64],
    u1: &[f64],
    length: f64,
    window: f64,
    armed: &mut [bool],
    arm_below: &[f64],
    fire_above: &[f64],
    samples: &mut u64,
    scratch: &mut Scratch,
) -> Located {
    if mode.guards.is_empty() || length <= 0.0 {
        return Located::Clear(length);
    }
    let Scratch {
        previous,
        current,
        previous_slopes,
        current_slopes,
        probe,
        levels,
        fires,
        from_zero,
        offsets,
        envelopes,
        terms,
        coordinates,
        stretches,
        samples: times,
        start_state,
        x,
        u,
        x_rate,
        u_rate,
    } = scratch;
    let n = segment.dimension();
    resting_levels(mode, segment, fire_above, fires);
    let fire_above = &fires[..];
    // In eigen-coordinates each guard is Re(Σ_j c_j z_j(τ)) + a + b τ with c = G V,
    // a = H u₀ + R u₁ + k and b = H u₁: no change of coordinates per evaluation.
    let modal = segment
        .vectors()
        .is_some()
        .then(|| ModalGuards::new(mode, n, u0, u1, fire_above, offsets));
    // The state and inputs at `τ`, for a segment that is not modal.
    if modal.is_none() {
        x.resize(n, 0.0);
        u.resize(u0.len(), 0.0);
        x_rate.resize(n, 0.0);
        u_rate.resize(u0.len(), 0.0);
    }
    let mut evaluate = |segment: &mut Segment<'_>, tau: f64, values: &mut Vec<f64>| {
        values.clear();
        if let Some(guards) = &modal
            && let Some(z) = segment.modal_state(tau)
        {
            guards.values(z, tau, values);
            return;
        }
        segment.state_into(tau, x);
        for (k, slot) in u.iter_mut().enumerate() {
            *slot = u0[k] + u1[k] * tau;
        }
        values.extend(
            mode.guards
                .iter()
                .zip(fire_above)
                .map(|(g, level)| g.row.eval(x, u, u1) - level),
        );
    };
    evaluate(segment, 0.0, previous);
    // An armed guard already at zero fires at once (an event exactly at a breakpoint).
    if let Some(i) = (0..previous.len()).find(|&i| armed[i] && previous[i] >= 0.0) {
        return Located::Crossing(Crossing { guard: i, tau: 0.0 });
    }
    // A guard resting after a declined switch (its level below zero: static friction could
    // not hold) is armed again once below the rounding of its terms. In eigen-coordinates
    // those are the modal terms, which cancel where the guard is zero: a carriage's speed
    // at rest read -1.1e-19 m/s, the rounding of terms of 5e-4 m/s, far below 1e-9 of its
    // own one term (1e-19), so the guard was armed again at each segment's start and found
    // crossing first, an ulp of time later, again and again.
    levels.clear();
    levels.extend_from_slice(arm_below);
    if let Some(guards) = &modal
        && levels.iter().any(|level| *level < 0.0)
        && let Some(z) = segment.modal_state(0.0)
    {
        for (i, level) in levels.iter_mut().enumerate() {
            if *level < 0.0 {
                *level = level.min(-1e-9 * guards.magnitude(i, z, 0.0));
            }
        }
    }
    for (i, value) in previous.iter().enumerate() {
        if *value < levels[i] {
            armed[i] = true;
        }
    }
    // The guards' rates of change at `tau`, for a guard that rises above zero and falls back
    // between two samples (a contact's relative velocity touching zero for a few
    // milliseconds of a long swing, when the belt is fast): negative at both samples, it has
    // a maximum between them where its rate changes sign from rising to falling.
    let mut slopes = |segment: &mut Segment<'_>, tau: f64, out: &mut Vec<f64>| {
        out.clear();
        if let Some(guards) = &modal
            && let Some(rates) = segment.modal_rate(tau)
        {
            guards.rates(rates, out);
            return;
        }
        segment.state_into(tau, x_rate);
        for (k, slot) in u_rate.iter_mut().enumerate() {
            *slot = u0[k] + u1[k] * tau;
        }
        out.extend(
            mode.guards
                .iter()
                .map(|g| mode.row_rate(&g.row, x_rate, u_rate, u1)),
        );
    };
    previous_slopes.clear();
    current_slopes.clear();
    // A guard at zero (to rounding) that is falling is left at once: armed now, as if seen
    // below zero, or a dip shorter than the first sample (a string that goes slack and is
    // pulled taut again within milliseconds) would never arm it.
    from_zero.clear();
    from_zero.resize(previous.len(), false);
    if (0..previous.len()).any(|i| !armed[i] && arm_below[i] >= 0.0) {
        slopes(segment, 0.0, previous_slopes);
        start_state.resize(n, 0.0);
        segment.state_into(0.0, start_state);
        // Zero to the rounding of the guard's terms: in the state, and in eigen-coordinates
        // where the segment is modal (a string's stretch at the switch read 4.4e-16 m
        // there, the rounding of its coordinates' terms of 0.07 m, so a state-only level of
        // 4e-25 m left it unarmed and its return, pulled taut within 75 ms, unseen).
        let start_coordinates = modal.as_ref().and_then(|_| segment.modal_state(0.0));
        for i in 0..previous.len() {
            let mut magnitude = mode.guards[i].row.magnitude(start_state, u0, u1);
            if let (Some(guards), Some(z)) = (&modal, start_coordinates) {
                magnitude = magnitude.max(guards.magnitude(i, z, 0.0));
            }
            let level = 1e-9 * magnitude;
            if !armed[i] && arm_below[i] >= 0.0 && previous[i] <= level && previous_slopes[i] < 0.0
            {
                armed[i] = true;
                from_zero[i] = true;
                previous[i] = previous[i].min(-f64::MIN_POSITIVE);
            }
        }
    }
    // Bounds of each guard over stretches of a modal segment.
    let bounded = match &modal {
        Some(guards) if segment.modal_terms_into(terms) => {
            coordinates.clear();
            coordinates.extend(terms.iter().map(|t| Coordinate::of(*t)));
            envelopes.truncate(guards.offsets.len());
            for i in 0..guards.offsets.len() {
                let (a, b) = guards.offsets[i];
                let c = guards.coefficients(i);
                match envelopes.get_mut(i) {
                    Some(envelope) => envelope.reset(c, a, b, coordinates),
                    None => envelopes.push(Envelope::new(c, a, b, coordinates)),
                }
            }
            true
        }
        _ => false,
    };
    let envelopes: Option<&[Envelope]> = bounded.then_some(envelopes.as_slice());
    // Where the samples start: at zero, or past the stretches where no guard can reach
    // zero, in strides that double while they stay clear.
    let mut from = 0.0;
    if window < length
        && let Some(envelopes) = envelopes
    {
        let mut stride = window;
        while from < length {
            let to = (from + stride).min(length);
            if envelopes.iter().all(|e| e.upper_bound(from, to) < 0.0) {
                from = to;
                stride *= 2.0;
                evaluate(segment, from, current);
                for i in 0..current.len() {
                    if current[i] < levels[i] {
                        armed[i] = true;
                    }
                }
            } else if stride > window {
                stride = window;
            } else {
                break;
            }
        }
        if from >= length {
            return Located::Clear(length);
        }
        if from > 0.0 {
            evaluate(segment, from, previous);
            previous_slopes.clear();
        }
    }
    let to = (from + window).min(length);
    // A cut segment's samples are taken in stretches that double from 1/256 of it, so
    // that a crossing early in it does not cost all 10,000 samples of its oscillation.
    stretches.clear();
    let mut end = from;
    let mut piece = if window < length {
        (to - from) / 256.0
    } else {
        to - from
    };
    while end < to {
        let start = end;
        end = if end + piece < to { end + piece } else { to };
        stretches.push((start, end));
        piece *= 2.0;
    }
    let mut previous_tau = from;
    let values = mode.propagator.eigenvalues();
    // The rest of the stretch is passed over once a bound shows that no guard can reach
    // zero in it: looked at first, then at doubling multiples of the slowest decaying time
    // constant (where the transients that kept the bound above zero have died down).
    let mut look_every = first_look_interval(values, from, to);
    // The first look, before any sample time is placed: most segments of a run driven by
    // a measured signal (one per sample of it) end there.
    if let Some(envelopes) = envelopes
        && rest_is_clear(envelopes, from, to, armed, arm_below)
    {
        arm_the_rest(armed, arm_below);
        return Located::Clear(to);
    }
    let mut next_look = from + look_every;
    look_every *= 2.0;
    for &(start, end) in stretches.iter() {
        sample_times_into(values, start, end, times);
        for &tau in &times.times {
            if previous_tau >= next_look {
                if let Some(envelopes) = envelopes
                    && rest_is_clear(envelopes, previous_tau, to, armed, arm_below)
                {
                    arm_the_rest(armed, arm_below);
                    return Located::Clear(to);
                }
                next_look = from + look_every;
                look_every *= 2.0;
            }
            *samples += 1;
            let dipping = (0..previous.len()).any(|i| armed[i] && previous[i] < 0.0);
            if dipping
                && let Some(guards) = &modal
                && let Some((z, rates)) = segment.modal_state_and_rate(tau)
            {
                // Both at once, from one evaluation of the exponentials.
                current.clear();
                guards.values(z, tau, current);
                current_slopes.clear();
                guards.rates(rates, current_slopes);
                if previous_slopes.is_empty() {
                    slopes(segment, previous_tau, previous_slopes);
                }
            } else if dipping {
                evaluate(segment, tau, current);
                if previous_slopes.is_empty() {
                    slopes(segment, previous_tau, previous_slopes);
                }
                slopes(segment, tau, current_slopes);
            } else {
                evaluate(segment, tau, current);
                current_slopes.clear();
            }
            let mut best: Option<Crossing> = None;
            for i in 0..current.len() {
                if !(armed[i] && previous[i] < 0.0) {
                    continue;
                }
                // Rising at the first sample and falling at the second, the guard peaks
                // between them: its first zero, if any, is before the peak (a bracket that
                // ends at or above zero would otherwise give Brent's method two roots to
                // choose from).
                let mut bracket = (current[i] >= 0.0).then_some((tau, current[i]));
                if previous_slopes[i] > 0.0 && current_slopes[i] < 0.0 {
                    let peak = refine(
                        previous_tau,
                        tau,
                        -previous_slopes[i],
                        -current_slopes[i],
                        |t| {
                            slopes(segment, t, probe);
                            -probe[i]
                        },
                    );
                    evaluate(segment, peak, probe);
                    if probe[i] >= 0.0 {
                        bracket = Some((peak, probe[i]));
                    }
                    // A peak below zero is not the last: the rates found one of several
                    // extrema, and a guard at or above zero at the second sample still
                    // crossed.
                }
                if let Some((end, value)) = bracket {
                    let (mut start, mut f_start) = (previous_tau, previous[i]);
                    if from_zero[i] && previous_tau == 0.0 {
                        // Armed at zero: start the bracket where the guard is below zero, or
                        // Brent's method would find the zero it starts from.
                        let mut at = end;
                        loop {
                            at *= 0.5;
                            evaluate(segment, at, probe);
                            if probe[i] < 0.0 || at < f64::MIN_POSITIVE {
                                break;
                            }
                        }
                        if probe[i] >= 0.0 {
                            continue;
                        }
                        (start, f_start) = (at, probe[i]);
                    }
                    let root = refine(start, end, f_start, value, |t| {
                        evaluate(segment, t, probe);
                        probe[i]
                    });
                    if best.is_none_or(|b| root < b.tau) {
                        best = Some(Crossing {
                            guard: i,
                            tau: root,
                        });
                    }
                }
            }
            if let Some(crossing) = best {
                return Located::Crossing(crossing);
            }
            std::mem::swap(previous_slopes, current_slopes);
            for i in 0..current.len() {
                if current[i] < levels[i] {
                    armed[i] = true;
                }
            }
            std::mem::swap(previous, current);
            previous_tau = tau;
        }
    }
    Located::Clear(to)
}

/// A mode's guards in the eigen-coordinates of one segment: guard `i` is
/// `Re(Σ_j c_ij z_j(τ)) + a_i + b_i τ` with `c = G V`, `a = H u₀ + R u₁ + k`, `b = H u₁`.
struct ModalGuards<'m> {
    /// `c`, a guard's coefficients after another's (`n` each).
    c: &'m [Complex64],
    /// `(a_i, b_i)`.
    offsets: &'m [(f64, f64)],
    n: usize,
}

impl<'m> ModalGuards<'m> {
    /// The guards of `mode` over a segment with inputs `u₀ + u₁ τ`, less the levels they
    /// must rise to before they fire, their offsets in the buffer `offsets`.
    fn new(
        mode: &'m NumericMode,
        n: usize,
        u0: &[f64],
        u1: &[f64],
        fire_above: &[f64],
        offsets: &'m mut Vec<(f64, f64)>,
    ) -> Self {
        offsets.clear();
        offsets.extend(mode.guards.iter().zip(fire_above).map(|(g, level)| {
            let a = dot(&g.row.input, u0) + dot(&g.row.rate, u1) + g.row.constant - level;
            (a, dot(&g.row.input, u1))
        }));
        ModalGuards {
            c: &mode.modal_guards,
            offsets,
            n,
        }
    }

    /// Guard `i`'s coefficients `c_i`.
    fn coefficients(&self, i: usize) -> &[Complex64] {
        &self.c[i * self.n..(i + 1) * self.n]
    }

    /// The guards' values at `τ` from the coordinates `z(τ)`, appended to `out`.
    fn values(&self, z: &[Complex64], tau: f64, out: &mut Vec<f64>) {
        out.extend(self.offsets.iter().enumerate().map(|(i, (a, b))| {
            let mut sum = a + b * tau;
            for (cj, zj) in self.coefficients(i).iter().zip(z) {
                sum += cj.re * zj.re - cj.im * zj.im;
            }
            sum
        }));
    }

    /// The magnitude of guard `i`'s terms at `τ` from the coordinates `z(τ)`: its value's
    /// scale, which rounding is judged against.
    fn magnitude(&self, i: usize, z: &[Complex64], tau: f64) -> f64 {
        let (a, b) = self.offsets[i];
        let terms: f64 = self
            .coefficients(i)
            .iter()
            .zip(z)
            .map(|(cj, zj)| cj.norm() * zj.norm())
            .sum();
        a.abs() + (b * tau).abs() + terms
    }

    /// The guards' rates from the coordinates' rates `ż(τ)`, appended to `out`.
    fn rates(&self, rates: &[Complex64], out: &mut Vec<f64>) {
        out.extend(self.offsets.iter().enumerate().map(|(i, (_, b))| {
            let mut sum = *b;
            for (cj, rj) in self.coefficients(i).iter().zip(rates) {
                sum += cj.re * rj.re - cj.im * rj.im;
            }
            sum
        }));
    }
}

/// How long after the first look at the bounds of a stretch `[from, to]` the next is taken
/// (each later one twice as long after): a quarter of the slowest decaying time constant,
/// where the transients that kept the bound above zero have died down, or a sixteenth of
/// the stretch when nothing decays.
fn first_look_interval(values: &[Complex64], from: f64, to: f64) -> f64 {
    let slowest = values
        .iter()
        .filter(|v| v.re < 0.0 && v.re.is_finite())
        .map(|v| -v.re)
        .fold(f64::INFINITY, f64::min);
    if slowest.is_finite() {
        0.25 / slowest
    } else {
        (to - from) / 16.0
    }
}

/// The levels above which each guard fires over `segment`, in `fires`: `fire_above`, and
/// for a guard resting on its threshold (a level above zero), at least the rounding of its
/// modal terms at the segment's start, which cancel where the guard is zero. A contact
/// entering its creep at zero relative velocity and zero acceleration read a rounding below
/// zero an instant later, stuck, and broke away again, 200 times at one instant.
fn resting_levels(
    mode: &NumericMode,
    segment: &mut Segment<'_>,
    fire_above: &[f64],
    fires: &mut Vec<f64>,
) {
    fires.clear();
    fires.extend_from_slice(fire_above);
    let n = segment.dimension();
    if segment.vectors().is_none() || fire_above.iter().all(|level| *level <= 0.0) {
        return;
    }
    let Some(z) = segment.modal_state(0.0) else {
        return;
    };
    for (i, fire) in fires.iter_mut().enumerate() {
        if *fire > 0.0 {
            let terms: f64 = mode.modal_guards[i * n..(i + 1) * n]
                .iter()
                .zip(z)
                .map(|(c, z)| c.norm() * z.norm())
                .sum();
            *fire = fire.max(1e-9 * terms);
        }
    }
}

/// Arms every guard whose level is zero, at the end of a stretch [`rest_is_clear`] passed
/// over (each was below zero there, by its bound).
fn arm_the_rest(armed: &mut [bool], arm_below: &[f64]) {
    for (i, below) in arm_below.iter().enumerate() {
        if *below >= 0.0 {
            armed[i] = true;
        }
    }
}

/// Whether no guard can reach zero over `[t0, t1]` by its bound, and every guard not yet
/// armed will be armed by then (its level is zero, so a value below zero arms it): the
/// samples of that stretch cannot change what is found.
fn rest_is_clear(
    envelopes: &[Envelope],
    t0: f64,
    t1: f64,
    armed: &[bool],
    arm_below: &[f64],
) -> bool {
    t0 < t1
        && armed
            .iter()
            .zip(arm_below)
            .all(|(armed, below)| *armed || *below >= 0.0)
        && envelopes.iter().all(|e| e.upper_bound(t0, t1) < 0.0)
}

/// Refines a bracket `[a, b]` with `f(a) < 0 <= f(b)` by Brent's method (inverse quadratic
/// interpolation, secant steps and bisection, as in Brent's `zeroin`); returns a `τ` with
/// `f(τ) >= 0` within a few ulps of the root.
pub(crate) fn refine(a: f64, b: f64, fa: f64, fb: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    // `low` keeps f < 0, `high` keeps f >= 0: the answer is `high`.
    let (mut low, mut high, mut f_low, mut f_high) = (a, b, fa, fb);
    // Brent's state: b the best estimate, a the previous, c the contrapoint.
    let (mut xa, mut xb, mut fxa, mut fxb) = (a, b, fa, fb);
    let (mut xc, mut fxc) = (xa, fxa);
    let mut d = xb - xa;
    let mut e = d;
    for _ in 0..100 {
        if high - low <= 4.0 * f64::EPSILON * high.abs().max(f64::MIN_POSITIVE) {
            break;
        }
        if fxb.signum() == fxc.signum() {
            xc = xa;
            fxc = fxa;
            d = xb - xa;
            e = d;
        }
        if fxc.abs() < fxb.abs() {
            xa = xb;
            xb = xc;
            xc = xa;
            fxa = fxb;
            fxb = fxc;
            fxc = fxa;
        }
        let tolerance = 2.0 * f64::EPSILON * xb.abs();
        let m = 0.5 * (xc - xb);
        if m.abs() <= tolerance || fxb == 0.0 {
            break;
        }
        if e.abs() >= tolerance && fxa.abs() > fxb.abs() {
            let s = fxb / fxa;
            let (mut p, mut q);
            if xa == xc {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fxa / fxc;
                let r = fxb / fxc;
                p = s * (2.0 * m * qa * (qa - r) - (xb - xa) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tolerance * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        xa = xb;
        fxa = fxb;
        xb += if d.abs() > tolerance {
            d
        } else {
            tolerance.copysign(m)
        };
        fxb = f(xb);
        if !fxb.is_finite() {
            // Fall back to bisection of the sign bracket.
            xb = 0.5 * (low + high);
            fxb = f(xb);
        }
        if fxb >= 0.0 {
            if xb < high {
                high = xb;
                f_high = fxb;
            }
        } else if xb > low {
            low = xb;
            f_low = fxb;
        }
    }
    let _ = (f_low, f_high);
    high
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refine_finds_a_root_to_machine_precision() {
        // e^{-t} - 0.3 = 0 at t = ln(1/0.3), written as a rising function.
        let f = |t: f64| 0.3 - (-t).exp();
        let root = refine(0.0, 5.0, f(0.0), f(5.0), f);
        assert!((root - (1.0f64 / 0.3).ln()).abs() < 1e-15);
        assert!(f(root) >= 0.0);
    }

    #[test]
    fn merged_runs_are_the_sorted_times() {
        // Five increasing runs of different lengths, one empty, overlapping and tied.
        let runs: [&[f64]; 5] = [
            &[0.1, 0.4, 0.9],
            &[],
            &[0.05, 0.4, 0.5, 2.0, 3.0],
            &[1.0],
            &[0.2, 0.3, 0.35, 0.9],
        ];
        let mut times = Vec::new();
        let mut ends = vec![0];
        for run in runs {
            times.extend_from_slice(run);
            ends.push(times.len());
        }
        let mut sorted = times.clone();
        sorted.sort_by(f64::total_cmp);
        let mut buffers = SampleBuffers {
            times,
            runs: ends,
            ..SampleBuffers::default()
        };
        merge_runs(&mut buffers);
        assert_eq!(buffers.times, sorted);
    }

    #[test]
    fn samples_cover_stiff_and_oscillating_scales() {
        let times = sample_times(
            &[Complex64::new(-2.5e17, 0.0), Complex64::new(-0.1, 10.0)],
            0.0,
            1.0,
        );
        assert!(times[0] <= 0.05 / 2.5e17);
        // The stiff scale is sampled from 0.02 to 40 time constants, then left alone.
        let stiff = times.iter().filter(|t| **t < 1e-15).count();
        assert!((8..=16).contains(&stiff), "{stiff}");
        assert_eq!(*times.last().unwrap(), 1.0);
        // An oscillation of period 2π/10 is sampled at least sixteen times a period.
        let period = 2.0 * std::f64::consts::PI / 10.0;
        let gaps = times
            .windows(2)
            .filter(|w| w[0] > 1e-3)
            .map(|w| w[1] - w[0]);
        assert!(gaps.fold(0.0, f64::max) <= period / 16.0 + 1e-12);
    }
}

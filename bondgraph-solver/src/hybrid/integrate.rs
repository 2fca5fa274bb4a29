//! Segments of nonlinear modes: integrated numerically ([`crate::ode`]: DOP853, handing
//! over to Radau IIA if the mode proves stiff) instead of propagated in closed form, with
//! the same events, samples, integrals and energy books.
//!
//! Within a segment the inputs are linear in time, so the mode is the ODE
//! `dx/dτ = f(x, u₀ + u₁τ)`; the energy books and integral outputs ride along as quadrature
//! components that never set the step size, so keeping the books does not change the
//! trajectory. After each accepted step the guards are checked on the step's dense output
//! ([`super::step_guards`], which also finds a guard's brief excursion above zero between
//! two looks and a guard falling from zero at the segment's start); a crossing is
//! bracketed there, located by Brent's method, and then refined by Newton's method on the
//! guard along exact steps from the step's start (each a full step of the same method
//! landing on the candidate time, the guard's rate `∇g·f` from its symbolic derivative),
//! so the event is where the integrated solution crosses, not where its interpolant does,
//! and on the far side of the zero by rounding. Samples come from the dense output, which
//! DOP853 builds (three more evaluations of `f`) only for steps with a sample or a guard
//! to check.

// The kernels index stages and components as the method's formulas do.
#![allow(clippy::needless_range_loop)]

use bondgraph_core::modes::Mode;
use bondgraph_core::symbolic::expr::Sym;

use super::stall;
use super::step_guards::{self, Look};
use super::{SimError, Simulator, Stepper, TimeScale};
use crate::events::Crossing;
use std::sync::Arc;

use crate::nonlinear::{NonlinearForms, NonlinearNumeric};
use crate::numeric::NumericMode;
use crate::ode::{Method, StepOutcome, Switching, System};

/// The numeric form of a mode of a nonlinear model.
pub(super) fn numeric_mode(
    simulator: &mut Simulator<'_>,
    mode: &Mode,
) -> Result<NumericMode, SimError> {
    let derived = simulator
        .symbolic
        .get_nonlinear(mode)
        .map_err(SimError::Derivation)?;
    let forms = match simulator.nonlinear_forms.get(mode) {
        Some(forms) => forms.clone(),
        None => {
            let outputs: Vec<Sym> = simulator
                .outputs
                .iter()
                .map(|o| derived.equations.output(&o.spec).value)
                .collect();
            let forms = Arc::new(NonlinearForms::new(simulator.model, &derived, &outputs));
            simulator
                .nonlinear_forms
                .insert(mode.clone(), forms.clone());
            forms
        }
    };
    Ok(NumericMode::from_nonlinear(
        simulator.model,
        &simulator.values,
        &simulator.storage,
        &derived,
        &forms,
    ))
}

/// The buffers a segment of one nonlinear mode evaluates its tapes in (their registers,
/// holding the constants folded in, and their outputs), kept from segment to segment in the
/// simulator: a recorded input makes a segment of every sample, and building them for each
/// was about a tenth of a run of the actuator with a nonlinear brush drop. They are made for
/// one mode's tapes (`tapes`) and reused only with those.
pub(super) struct Workspace {
    tapes: Arc<NonlinearNumeric>,
    segment: SegmentBuffers,
    /// The guards' buffers: one for the looks at each step's start, one for the looks
    /// inside and at the end of a step.
    guards: [GuardBuffers; 2],
}

impl Workspace {
    fn for_tapes(kept: Option<Workspace>, tapes: &Arc<NonlinearNumeric>) -> Workspace {
        match kept {
            Some(kept) if Arc::ptr_eq(&kept.tapes, tapes) => kept,
            _ => Workspace {
                tapes: tapes.clone(),
                segment: SegmentBuffers::new(tapes),
                guards: [GuardBuffers::new(tapes), GuardBuffers::new(tapes)],
            },
        }
    }
}

/// Writes a nonlinear mode's tapes' input `[x, u₀ + u₁τ, u₁]` (its `n` states, its `m`
/// inputs and their rates over the segment) into the first registers of `registers`, where
/// [`Tape::eval_in_place`](bondgraph_core::symbolic::expr::Tape::eval_in_place) reads it,
/// with no copy of its own.
fn load_input(
    registers: &mut [f64],
    (n, m): (usize, usize),
    (x, u0, u1): (&[f64], &[f64], &[f64]),
    tau: f64,
) {
    // Element by element: a copy of a few values through `copy_from_slice` is a call to
    // `memcpy`, at every evaluation of `f` (about 4 % of a run of a nonlinear mode).
    #[allow(clippy::manual_memcpy)]
    for r in 0..n {
        registers[r] = x[r];
    }
    for k in 0..m {
        registers[n + k] = u0[k] + u1[k] * tau;
        registers[n + m + k] = u1[k];
    }
}

/// What [`Segment`] evaluates its tapes in.
struct SegmentBuffers {
    /// `f`'s registers, its inputs `[x, u, u̇]` first: where every tape of the segment
    /// reads them from (`f`'s evaluation leaves them as they are).
    f_scratch: Vec<f64>,
    fj_scratch: Vec<f64>,
    fj_out: Vec<f64>,
    port_scratch: Vec<f64>,
    port_out: Vec<f64>,
    output_scratch: Vec<f64>,
    output_out: Vec<f64>,
}

impl SegmentBuffers {
    fn new(nl: &NonlinearNumeric) -> Self {
        Self {
            f_scratch: nl.f.scratch(),
            fj_scratch: nl.f_and_jacobian.scratch(),
            fj_out: vec![0.0; nl.n + nl.n * nl.n],
            port_scratch: nl.ports.scratch(),
            port_out: vec![0.0; nl.ports.output_count()],
            output_scratch: nl.outputs.scratch(),
            output_out: vec![0.0; nl.outputs.output_count()],
        }
    }
}

/// A nonlinear mode over one segment, with its quadratures: the energy supplied and
/// dissipated (when kept) and the integral outputs.
struct Segment<'a> {
    nl: &'a NonlinearNumeric,
    u0: &'a [f64],
    u1: &'a [f64],
    buffers: SegmentBuffers,
    energy: bool,
    /// The outputs integrated, by index.
    integrals: Vec<usize>,
}

impl<'a> Segment<'a> {
    fn new(
        nl: &'a NonlinearNumeric,
        (u0, u1): (&'a [f64], &'a [f64]),
        buffers: SegmentBuffers,
        energy: bool,
        integrals: Vec<usize>,
    ) -> Self {
        Self {
            nl,
            u0,
            u1,
            buffers,
            energy,
            integrals,
        }
    }

    fn quadratures(&self) -> usize {
        usize::from(self.energy) * 2 + self.integrals.len()
    }

    /// Writes the tapes' input `[x, u, u̇]` at `(tau, x)` into `f`'s input registers.
    fn load(&mut self, tau: f64, x: &[f64]) {
        let sizes = (self.nl.n, self.nl.m);
        load_input(
            &mut self.buffers.f_scratch,
            sizes,
            (x, self.u0, self.u1),
            tau,
        );
    }

    /// The tapes' input, as [`Segment::load`] left it.
    fn input_len(&self) -> usize {
        self.nl.n + 2 * self.nl.m
    }

    /// The requested outputs at `(tau, x)` (integrals excluded) into `output_out`.
    fn outputs(&mut self, tau: f64, x: &[f64]) {
        self.load(tau, x);
        let inputs = self.input_len();
        self.nl.outputs.eval(
            &self.buffers.f_scratch[..inputs],
            &mut self.buffers.output_scratch,
            &mut self.buffers.output_out,
        );
    }
}

impl System for Segment<'_> {
    fn dimension(&self) -> usize {
        self.nl.n + self.quadratures()
    }

    fn controlled(&self) -> usize {
        self.nl.n
    }

    fn rhs(&mut self, tau: f64, x: &[f64], dx: &mut [f64]) {
        let n = self.nl.n;
        self.load(tau, x);
        self.nl
            .f
            .eval_in_place(&mut self.buffers.f_scratch, &mut dx[..n]);
        let inputs = self.input_len();
        let mut next = n;
        if self.energy {
            self.nl.ports.eval(
                &self.buffers.f_scratch[..inputs],
                &mut self.buffers.port_scratch,
                &mut self.buffers.port_out,
            );
            let (mut supplied, mut dissipated) = (0.0, 0.0);
            for (k, source) in self.nl.port_sources.iter().enumerate() {
                let power = self.buffers.port_out[2 * k] * self.buffers.port_out[2 * k + 1];
                if *source {
                    supplied -= power;
                } else {
                    dissipated += power;
                }
            }
            dx[n] = supplied;
            dx[n + 1] = dissipated;
            next += 2;
        }
        if !self.integrals.is_empty() {
            self.nl.outputs.eval(
                &self.buffers.f_scratch[..inputs],
                &mut self.buffers.output_scratch,
                &mut self.buffers.output_out,
            );
            for (slot, &k) in self.integrals.iter().enumerate() {
                dx[next + slot] = self.buffers.output_out[k];
            }
        }
    }

    fn jacobian(&mut self, tau: f64, x: &[f64], jacobian: &mut [f64]) {
        let n = self.nl.n;
        let size = self.dimension();
        self.load(tau, x);
        let inputs = self.input_len();
        self.nl.f_and_jacobian.eval(
            &self.buffers.f_scratch[..inputs],
            &mut self.buffers.fj_scratch,
            &mut self.buffers.fj_out,
        );
        jacobian.fill(0.0);
        for r in 0..n {
            jacobian[r * size..r * size + n]
                .copy_from_slice(&self.buffers.fj_out[n + r * n..n + (r + 1) * n]);
        }
    }
}

/// The guards' values (less the levels they must rise to before they fire), magnitudes and
/// rates at a point, evaluated without allocating.
struct Guards<'a> {
    nl: &'a NonlinearNumeric,
    buffers: GuardBuffers,
}

/// What [`Guards`] evaluates the guards' tape in.
struct GuardBuffers {
    /// The guards' tape's registers, its inputs first.
    scratch: Vec<f64>,
    out: Vec<f64>,
    fire_above: Vec<f64>,
}

impl GuardBuffers {
    fn new(nl: &NonlinearNumeric) -> Self {
        Self {
            scratch: nl.guards.scratch(),
            out: vec![0.0; nl.guards.output_count()],
            fire_above: Vec::new(),
        }
    }
}

impl<'a> Guards<'a> {
    fn new(nl: &'a NonlinearNumeric, mut buffers: GuardBuffers, fire_above: &[f64]) -> Self {
        buffers.fire_above.clear();
        buffers.fire_above.extend_from_slice(fire_above);
        Self { nl, buffers }
    }

    fn count(&self) -> usize {
        self.buffers.out.len() / 3
    }

    fn at(&mut self, tau: f64, x: &[f64], u0: &[f64], u1: &[f64]) {
        load_input(
            &mut self.buffers.scratch,
            (self.nl.n, self.nl.m),
            (x, u0, u1),
            tau,
        );
        self.nl
            .guards
            .eval_in_place(&mut self.buffers.scratch, &mut self.buffers.out);
    }

    fn value(&self, k: usize) -> f64 {
        self.buffers.out[3 * k] - self.buffers.fire_above[k]
    }

    fn rate(&self, k: usize) -> f64 {
        self.buffers.out[3 * k + 2]
    }

    fn magnitude(&self, k: usize) -> f64 {
        self.buffers.out[3 * k + 1]
    }

    /// The values and rates of the last point, into `look`.
    fn look_into(&self, look: &mut Look) {
        look.values.clear();
        look.values.extend((0..self.count()).map(|k| self.value(k)));
        look.rates.clear();
        look.rates.extend((0..self.count()).map(|k| self.rate(k)));
    }
}

/// The buffers of a step's looks at its guards: the guards' tapes, a point of the dense
/// output, the look at the step's end.
struct Looks<'a> {
    guards: Guards<'a>,
    point: Vec<f64>,
    end: Look,
}

impl<'a> Looks<'a> {
    /// Looks with `guards`, for a system of `size` variables.
    fn new(guards: Guards<'a>, size: usize) -> Self {
        Self {
            guards,
            point: vec![0.0; size],
            end: Look::default(),
        }
    }
}

/// Steps held to a few spacings of doubles at `t` (the clock's `resolution`) in `mode`,
/// with no guard met: the motion stalled.
fn stalled(t: f64, mode: &NumericMode, step: f64, resolution: f64) -> SimError {
    SimError::Stalled {
        t,
        mode: mode.spec.clone(),
        cause: super::Stall::Steps { step, resolution },
    }
}

/// A step just taken, as its looks at the guards need it.
struct TakenStep<'a> {
    /// Its start in the segment's time, and its size.
    tau: f64,
    step: f64,
    /// The state at its end.
    end: &'a [f64],
    /// The segment's inputs `u₀ + u₁τ`.
    inputs: (&'a [f64], &'a [f64]),
    /// The guards armed at zero at its start ([`step_guards::arm_at_zero`]).
    from_zero: &'a [bool],
}

/// Where a step that crosses a guard starts, and which guard.
struct Landing<'a> {
    /// The step's start, in time.
    start: f64,
    /// The step's start, in the segment's local time.
    tau: f64,
    /// The state at the step's start.
    before: &'a [f64],
    /// The step's size.
    step: f64,
    /// The guard crossed.
    guard: usize,
    u0: &'a [f64],
    u1: &'a [f64],
}

/// The state `hit` into the step into `point`: by an exact step, or on the dense output
/// where Radau's Newton iteration does not converge. Each is a step's work, counted in
/// `steps`.
fn place(
    integrator: &mut Switching,
    system: &mut Segment<'_>,
    at: &Landing<'_>,
    hit: f64,
    reuse: bool,
    point: &mut [f64],
    steps: &mut u64,
) {
    *steps += 1;
    if !integrator.step_exact(system, at.tau, at.before, hit, reuse, point) {
        integrator.dense(hit / at.step, point);
    }
}

/// Lands exactly on a crossing found near `hit` into the step on its dense output: Newton on
/// the guard along exact steps from the step's start (the guard's rate `∇g·f` from its
/// symbolic derivative), so the event is where the integrated solution crosses, not where
/// its interpolant does. Newton's last iterate may stop a rounding error short of the zero
/// (an extension of -1.2e-21 m, still slack), which the modes judged at the event would read
/// as the crossing not made (taut and slack each sending the string to the other); as
/// Brent's method does on the closed-form path, the landing then moves on by a few ulps
/// until the guard is at or above zero. Returns the time into the step, the state there in
/// `point`, and counts the exact steps taken in `steps`.
fn land_on_crossing(
    integrator: &mut Switching,
    system: &mut Segment<'_>,
    guards: &mut Guards<'_>,
    at: Landing<'_>,
    mut hit: f64,
    point: &mut [f64],
    steps: &mut u64,
) -> f64 {
    let k = at.guard;
    let resolution = |hit: f64| 4.0 * f64::EPSILON * (at.start + hit).abs().max(1e-300);
    let mut placed = None;
    for _ in 0..8 {
        place(integrator, system, &at, hit, placed.is_some(), point, steps);
        placed = Some(hit);
        guards.at(at.tau + hit, point, at.u0, at.u1);
        let (g, rate) = (guards.value(k), guards.rate(k));
        if rate <= 0.0 || !rate.is_finite() {
            break;
        }
        let next = (hit - g / rate).clamp(0.0, at.step);
        let converged = (next - hit).abs() <= resolution(hit);
        hit = next;
        if converged {
            break;
        }
    }
    if placed != Some(hit) {
        place(integrator, system, &at, hit, true, point, steps);
        guards.at(at.tau + hit, point, at.u0, at.u1);
    }
    let mut nudge = resolution(hit);
    for _ in 0..64 {
        if guards.value(k) >= 0.0 || hit >= at.step {
            break;
        }
        hit = (hit + nudge).min(at.step);
        place(integrator, system, &at, hit, true, point, steps);
        guards.at(at.tau + hit, point, at.u0, at.u1);
        nudge *= 2.0;
    }
    hit
}

impl Stepper<'_, '_> {
    /// Integrates the current (nonlinear) mode to `end` or to its first guard crossing.
    pub(super) fn integrated_segment(&mut self, end: f64) -> Result<Option<Crossing>, SimError> {
        let current = self.mode.clone();
        let nl = current
            .nonlinear
            .clone()
            .expect("an integrated segment is of a nonlinear mode");
        let length = end - self.t;
        let (u0, u1) = self.inputs_at(self.t);
        self.stats.segments += 1;
        let integral_outputs = self.integral_outputs();
        let Workspace {
            tapes,
            segment: segment_buffers,
            guards: [start_buffers, look_buffers],
        } = Workspace::for_tapes(self.simulator.workspace.take(), &nl);
        let mut system = Segment::new(
            &nl,
            (&u0, &u1),
            segment_buffers,
            self.energy.is_some(),
            integral_outputs.clone(),
        );
        let n = nl.n;
        let size = system.dimension();
        let mut z = vec![0.0; size];
        z[..n].copy_from_slice(&self.x);
        let mut guards = Guards::new(&nl, start_buffers, &self.fire_above);
        let mode_index = self.sample.map(|_| self.recorder.mode_index(&current.spec));
        let start = self.t;

        // Guards at the start: an armed guard already at zero fires at once.
        let armed = self.arm_at_start(&mut guards, &z, (&u0, &u1));
        self.sample_until(&mut system, start, &z, None, start, mode_index);
        let Ok((mut previous, from_zero)) = armed else {
            return Ok(armed.err().map(|k| Crossing { guard: k, tau: 0.0 }));
        };
        let not_from_zero = vec![false; guards.count()];

        let (mut integrator, mut h) = self.integrator_for(&mut system, &z, length);
        let mut tau = 0.0;
        let mut before = vec![0.0; size];
        let mut point = vec![0.0; size];
        let mut crossing: Option<Crossing> = None;
        let mut looks = Looks::new(Guards::new(&nl, look_buffers, &self.fire_above), size);
        while tau < length {
            let step = h.min(length - tau);
            // A step held to a few spacings of doubles at `t` makes no progress, unless it is
            // all that is left of the segment (a table's last point an ulp before the end).
            let resolution = stall::resolution_at(start + tau);
            let held = step <= stall::HELD_RESOLUTIONS * resolution && step < length - tau;
            if held && integrator.method() == Method::Explicit {
                // Explicit steps held below the clock's resolution: stiff beyond doubt.
                integrator.force_implicit();
                h = integrator.initial_step(&mut system, tau, &z, length - tau);
                continue;
            }
            if held {
                // Steps collapse where the motion reaches a guard tangentially (a tank
                // emptying as (t_e - t)², its law's slope infinite there): the guard is met.
                if let Some(k) = self.touching(&mut guards, tau, &z, (&u0, &u1), &from_zero) {
                    crossing = Some(Crossing { guard: k, tau });
                    break;
                }
                return Err(stalled(start + tau, &current, step, resolution));
            }
            before.copy_from_slice(&z);
            if self.over_step_limit(1) {
                return Err(self.too_many_steps_at(&mut system, start + tau, &z, step, &current));
            }
            match integrator.step(&mut system, tau, &mut z, step) {
                StepOutcome::Rejected { h_next } => {
                    h = h_next;
                    continue;
                }
                StepOutcome::Accepted { h_next } => h = h_next,
            }
            if z[..n].iter().any(|v| !v.is_finite()) {
                return Err(self
                    .simulator
                    .non_finite(start + tau + step, &current, &z[..n]));
            }
            // The step's end in time: exactly the segment's at its last step.
            let step_end = if tau + step >= length {
                end
            } else {
                start + tau + step
            };
            let from_zero = if tau == 0.0 {
                &from_zero
            } else {
                &not_from_zero
            };
            let (found, dense_ready) = self.crossing_in_step(
                (&mut integrator, &mut system),
                &mut previous,
                &mut looks,
                TakenStep {
                    tau,
                    step,
                    end: &z,
                    inputs: (&u0, &u1),
                    from_zero,
                },
            );
            if let Some((k, theta)) = found {
                let landing = Landing {
                    start: start + tau,
                    tau,
                    before: &before,
                    step,
                    guard: k,
                    u0: &u0,
                    u1: &u1,
                };
                let hit = self.land(
                    (&mut integrator, &mut system),
                    &mut guards,
                    landing,
                    (theta * step, dense_ready),
                    &mut point,
                    (mode_index, &current),
                )?;
                z.copy_from_slice(&point);
                tau += hit;
                crossing = Some(Crossing { guard: k, tau });
                break;
            }
            if !dense_ready && self.sample_before(step_end, mode_index) {
                integrator.prepare_dense(&mut system);
            }
            self.sample_until(
                &mut system,
                start + tau,
                &before,
                Some((&integrator, step, &z)),
                step_end,
                mode_index,
            );
            tau += step;
        }
        self.add_quadratures(&z, n, &integral_outputs);
        self.finish_integrated(start, end, crossing, &z[..n]);
        self.simulator.integrator = Some(integrator);
        self.simulator.workspace = Some(Workspace {
            tapes,
            segment: system.buffers,
            guards: [guards.buffers, looks.guards.buffers],
        });
        Ok(crossing)
    }

    /// The armed guard the state `z` at `tau` touches, if any: at its threshold to rounding.
    /// (A guard armed at zero as it falls from the segment's start is not met.)
    fn touching(
        &self,
        guards: &mut Guards<'_>,
        tau: f64,
        z: &[f64],
        (u0, u1): (&[f64], &[f64]),
        from_zero: &[bool],
    ) -> Option<usize> {
        guards.at(tau, z, u0, u1);
        (0..guards.count()).find(|&k| {
            let tolerance = 1e-9 * guards.magnitude(k) + f64::MIN_POSITIVE;
            self.armed[k] && guards.value(k) >= -tolerance && !(tau == 0.0 && from_zero[k])
        })
    }

    /// The indices of the outputs recorded as time integrals.
    fn integral_outputs(&self) -> Vec<usize> {
        self.simulator
            .outputs
            .iter()
            .enumerate()
            .filter(|(_, o)| o.integral)
            .map(|(k, _)| k)
            .collect()
    }

    /// Ends an integrated segment that started at `start` and was to reach `end`: at its
    /// crossing's event time or at `end`, in state `x`.
    fn finish_integrated(&mut self, start: f64, end: f64, crossing: Option<Crossing>, x: &[f64]) {
        self.t = match crossing {
            Some(crossing) => super::event_time(start, crossing.tau, end),
            None => end,
        };
        self.x = x.to_vec();
    }

    /// Arms the guards at a segment's start (state `z`, inputs `u0 + u1 τ`): their first
    /// look and which are armed at zero as they fall from it, or `Err` with the armed guard
    /// already at its threshold, which fires at once.
    fn arm_at_start(
        &mut self,
        guards: &mut Guards<'_>,
        z: &[f64],
        (u0, u1): (&[f64], &[f64]),
    ) -> Result<(Look, Vec<bool>), usize> {
        let guard_count = guards.count();
        guards.at(0.0, z, u0, u1);
        let mut previous = Look::default();
        guards.look_into(&mut previous);
        if let Some(k) = (0..guard_count).find(|&k| self.armed[k] && previous.values[k] >= 0.0) {
            return Err(k);
        }
        let magnitudes: Vec<f64> = (0..guard_count).map(|k| guards.magnitude(k)).collect();
        let from_zero =
            step_guards::arm_at_zero(&mut previous, &magnitudes, &mut self.armed, &self.arm_below);
        for (k, value) in previous.values.iter().enumerate() {
            if *value < self.arm_below[k] {
                self.armed[k] = true;
            }
        }
        Ok((previous, from_zero))
    }

    /// Lands the step `landing` on its guard's crossing, first seen at `at` into the step,
    /// and samples up to it: how far into the step the crossing is, its state in `point`.
    fn land(
        &mut self,
        (integrator, system): (&mut Switching, &mut Segment<'_>),
        guards: &mut Guards<'_>,
        landing: Landing<'_>,
        (at, dense_ready): (f64, bool),
        point: &mut [f64],
        (mode_index, current): (Option<usize>, &NumericMode),
    ) -> Result<f64, SimError> {
        let (start, step, before) = (landing.start, landing.step, landing.before);
        let mut landing_steps = 0;
        let hit = land_on_crossing(
            integrator,
            system,
            guards,
            landing,
            at,
            point,
            &mut landing_steps,
        );
        if self.over_step_limit(landing_steps) {
            return Err(self.too_many_steps_at(system, start + hit, point, step, current));
        }
        if !dense_ready && self.sample_before(start + hit, mode_index) {
            integrator.prepare_dense(system);
        }
        self.sample_until(
            system,
            start,
            before,
            Some((integrator, step, point)),
            start + hit,
            mode_index,
        );
        Ok(hit)
    }

    /// Adds a segment's quadratures (after its `n` states in `z`: the energy books when
    /// kept, then the integral outputs `integral_outputs`) to the run's.
    fn add_quadratures(&mut self, z: &[f64], n: usize, integral_outputs: &[usize]) {
        let mut next = n;
        if let Some(energy) = &mut self.energy {
            energy.supplied += z[n];
            energy.dissipated += z[n + 1];
            next += 2;
        }
        for (slot, &k) in integral_outputs.iter().enumerate() {
            self.integrals[k] += z[next + slot];
        }
    }

    /// The first crossing of an armed guard in the step just `taken`, `(guard, θ)`, from the
    /// look at its start (`previous`, replaced by the last look taken): the guards are looked
    /// at at its end, from its end state, and inside it, unless every guard stays clear of
    /// zero ([`step_guards::clear_of_zero`]), on its dense output, built when first read.
    /// Also whether the dense output was built.
    fn crossing_in_step(
        &mut self,
        (integrator, system): (&mut Switching, &mut Segment<'_>),
        previous: &mut Look,
        looks: &mut Looks<'_>,
        taken: TakenStep<'_>,
    ) -> (Option<(usize, f64)>, bool) {
        if looks.guards.count() == 0 {
            return (None, false);
        }
        let TakenStep {
            tau,
            step,
            end,
            inputs: (u0, u1),
            from_zero,
        } = taken;
        looks.guards.at(tau + step, end, u0, u1);
        looks.guards.look_into(&mut looks.end);
        let clear = step_guards::clear_of_zero(previous, &looks.end, step);
        let mut dense_ready = false;
        let found = step_guards::first_crossing(
            previous,
            if clear {
                &[1.0]
            } else {
                &[0.25, 0.5, 0.75, 1.0]
            },
            &mut self.armed,
            &self.arm_below,
            from_zero,
            |theta, look| {
                if theta == 1.0 {
                    look.clone_from(&looks.end);
                    return;
                }
                if !dense_ready {
                    integrator.prepare_dense(system);
                    dense_ready = true;
                }
                integrator.dense(theta, &mut looks.point);
                looks.guards.at(tau + theta * step, &looks.point, u0, u1);
                looks.guards.look_into(look);
            },
        );
        (found, dense_ready)
    }

    /// The integrator of a segment of the current mode, `length` long, at state `z` (the
    /// simulator's, reset: its buffers reused from segment to segment, as a recorded input
    /// makes a segment of every sample), and its first step, estimated.
    fn integrator_for(
        &mut self,
        system: &mut Segment<'_>,
        z: &[f64],
        length: f64,
    ) -> (Box<Switching>, f64) {
        let (size, n) = (system.dimension(), system.nl.n);
        let tolerances = self.simulator.settings.tolerances;
        let mut integrator = match self.simulator.integrator.take() {
            Some(mut kept) if kept.made_for(size, n, tolerances) => {
                kept.reset();
                kept
            }
            _ => Box::new(Switching::new(size, n, tolerances)),
        };
        let h = if length > 0.0 {
            integrator.initial_step(system, 0.0, z, length)
        } else {
            0.0
        };
        (integrator, h)
    }

    /// The error of a run past its limit of steps at `time`, in state `z` of `mode`, its last
    /// step `step` long: with the fastest time scale its Jacobian shows there.
    fn too_many_steps_at(
        &self,
        system: &mut Segment<'_>,
        time: f64,
        z: &[f64],
        step: f64,
        mode: &NumericMode,
    ) -> SimError {
        let size = system.dimension();
        let mut jacobian = vec![0.0; size * size];
        system.jacobian(time - self.t, z, &mut jacobian);
        let scale = TimeScale::of_jacobian(&jacobian, system.nl.n, size, &mode.state_names);
        self.too_many_steps(time, Some(step), scale)
    }

    /// Whether a sample is due at or before `time`.
    fn sample_due(&self, time: f64, mode_index: Option<usize>) -> bool {
        match (self.sample, mode_index) {
            (Some(times), Some(_)) => times.time(self.next_sample) <= time,
            _ => false,
        }
    }

    /// Whether a sample is due before `time` (not at it).
    fn sample_before(&self, time: f64, mode_index: Option<usize>) -> bool {
        match (self.sample, mode_index) {
            (Some(times), Some(_)) => times.time(self.next_sample) < time,
            _ => false,
        }
    }

    /// Records the samples due at or before `through` (a time) in a step that starts at
    /// `step_start` (time) from `before`: at `through` itself from the state there, before
    /// it from the dense output of the integrator's last step (of size `step`, prepared if
    /// a sample is due before `through`); with no integrator, the samples due at
    /// `step_start` itself.
    fn sample_until(
        &mut self,
        system: &mut Segment<'_>,
        step_start: f64,
        before: &[f64],
        integrator: Option<(&Switching, f64, &[f64])>,
        through: f64,
        mode_index: Option<usize>,
    ) {
        if !self.sample_due(through, mode_index) {
            return;
        }
        let (Some(times), Some(mode_index)) = (self.sample, mode_index) else {
            return;
        };
        let segment_start = self.t;
        let n = system.nl.n;
        let integrals_offset = n + if system.energy { 2 } else { 0 };
        let mut point = before.to_vec();
        loop {
            let time = times.time(self.next_sample);
            if time > through {
                break;
            }
            match integrator {
                Some((_, _, there)) if time == through => point.copy_from_slice(there),
                Some((integrator, step, _)) => {
                    let theta = ((time - step_start) / step).clamp(0.0, 1.0);
                    integrator.dense(theta, &mut point);
                }
                None => {}
            }
            let tau = time - segment_start;
            system.outputs(tau, &point);
            let mut integral_slot = 0;
            let values: Vec<f64> = self
                .simulator
                .outputs
                .iter()
                .enumerate()
                .map(|(k, output)| {
                    if output.integral {
                        let value = self.integrals[k] + point[integrals_offset + integral_slot];
                        integral_slot += 1;
                        value
                    } else {
                        system.buffers.output_out[k]
                    }
                })
                .collect();
            let mut values = values;
            if !self.simulator.energy_columns.is_empty() {
                let u: Vec<f64> = (0..system.nl.m)
                    .map(|k| system.u0[k] + system.u1[k] * tau)
                    .collect();
                let (mut supplied, mut dissipated) = self.books();
                if system.energy {
                    supplied += point[n];
                    dissipated += point[n + 1];
                }
                values.extend(self.simulator.energy_values(
                    &self.mode,
                    &point[..n],
                    &u,
                    (supplied, dissipated),
                ));
            }
            self.recorder.sample_in(time, mode_index, values);
            self.next_sample += 1;
        }
    }
}

//! The numbers of `bondgraph analyze` against closed forms: roots, time scales, step-response
//! metrics of first- and second-order systems, the frequency response.

use bondgraph_core::symbolic::Scaled;
use bondgraph_solver::analysis::{
    AnalysisError, Complex64, Scale, StepSystem, bode, roots, step_metrics,
};

fn close(what: &str, actual: f64, expected: f64, relative: f64) {
    assert!(
        (actual - expected).abs() <= relative * expected.abs().max(1e-300),
        "{what}: {actual} against {expected}"
    );
}

/// `dx/dt = -x/τ + u/τ`, `y = x`: unit DC gain, pole `-1/τ`.
fn first_order(tau: f64) -> StepSystem {
    StepSystem {
        a: vec![vec![-1.0 / tau]],
        b: vec![1.0 / tau],
        e: vec![0.0],
        c: vec![1.0],
        d: 0.0,
        f: 0.0,
        integral: false,
    }
}

/// A mass on a spring and damper driven by a force, output the spring's displacement:
/// `m x'' + b x' + k x = F`, states (p, q).
fn mass_spring_damper(m: f64, b: f64, k: f64) -> StepSystem {
    StepSystem {
        a: vec![vec![-b / m, -k], vec![1.0 / m, 0.0]],
        b: vec![1.0, 0.0],
        e: vec![0.0, 0.0],
        c: vec![0.0, 1.0],
        d: 0.0,
        f: 0.0,
        integral: false,
    }
}

#[test]
fn roots_of_a_cubic_and_a_quadratic_with_complex_roots() {
    // (s + 1)(s + 2)(s + 3) = s³ + 6 s² + 11 s + 6.
    let r = roots(&[1.0, 6.0, 11.0, 6.0]).unwrap();
    for (root, expected) in r.iter().zip([-3.0, -2.0, -1.0]) {
        close("real root", root.re, expected, 1e-12);
        assert!(root.im.abs() < 1e-12);
    }
    // s² + 2 s + 100: -1 ± sqrt(99) i.
    let r = roots(&[1.0, 2.0, 100.0]).unwrap();
    close("re", r[0].re, -1.0, 1e-15);
    close("im", r[1].im, 99f64.sqrt(), 1e-15);
    // A trailing zero is an exact root at the origin; a leading zero drops the degree.
    let r = roots(&[0.0, 2.0, 4.0, 0.0]).unwrap();
    assert_eq!(r, [Complex64::new(-2.0, 0.0), Complex64::new(0.0, 0.0)]);
}

#[test]
fn time_scales_of_an_underdamped_pair() {
    // m = 2, b = 4, k = 200: wn = sqrt(k/m) = 10, zeta = b/(2 sqrt(k m)) = 0.1.
    let (m, b, k): (f64, f64, f64) = (2.0, 4.0, 200.0);
    let wn = (k / m).sqrt();
    let zeta = b / (2.0 * (k * m).sqrt());
    let r = roots(&[1.0, b / m, k / m]).unwrap();
    let s = Scale::of(r[1]);
    close("natural frequency", s.natural_frequency, wn, 1e-14);
    close("damping ratio", s.damping_ratio.unwrap(), zeta, 1e-14);
    close(
        "time constant",
        s.time_constant.unwrap(),
        1.0 / (zeta * wn),
        1e-14,
    );
}

#[test]
fn first_order_step_metrics_are_tau_ln9_and_tau_ln50() {
    // y = 1 - exp(-t/τ): 10 % at τ ln(10/9), 90 % at τ ln 10, within 2 % after τ ln 50.
    let tau = 0.37;
    let m = step_metrics(
        &first_order(tau),
        &[Complex64::new(-1.0 / tau, 0.0)],
        Some(1.0),
    )
    .unwrap();
    close("final value", m.final_value.unwrap(), 1.0, 0.0);
    close("rise time", m.rise_time.unwrap(), tau * 9f64.ln(), 1e-9);
    close(
        "settling time",
        m.settling_time.unwrap(),
        tau * 50f64.ln(),
        1e-9,
    );
    assert_eq!(m.overshoot_percent, Some(0.0));
    assert_eq!(m.initial_value, 0.0);
}

#[test]
fn second_order_overshoot_peak_and_rise_against_the_closed_form() {
    let (m, b, k): (f64, f64, f64) = (2.0, 4.0, 200.0);
    let wn = (k / m).sqrt();
    let zeta = b / (2.0 * (k * m).sqrt());
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let poles = roots(&[1.0, b / m, k / m]).unwrap();
    let metrics = step_metrics(&mass_spring_damper(m, b, k), &poles, Some(1.0 / k)).unwrap();
    // Final value F/k; overshoot exp(-zeta pi / sqrt(1 - zeta^2)) at t = pi/wd.
    close("final value", metrics.final_value.unwrap(), 1.0 / k, 1e-15);
    let overshoot = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
    close(
        "overshoot",
        metrics.overshoot_percent.unwrap(),
        100.0 * overshoot,
        1e-9,
    );
    close(
        "peak time",
        metrics.peak_time.unwrap(),
        std::f64::consts::PI / wd,
        1e-6,
    );
    // Rise time: the closed form y/y_final = 1 - e^(-zeta wn t)(cos wd t + zeta wn/wd sin wd t)
    // solved for 0.1 and 0.9 by bisection here, independently of the solver.
    let r =
        |t: f64| 1.0 - (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin());
    let solve = |level: f64| {
        let (mut lo, mut hi) = (0.0, std::f64::consts::PI / wd);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if r(mid) < level { lo = mid } else { hi = mid }
        }
        lo
    };
    close(
        "rise time",
        metrics.rise_time.unwrap(),
        solve(0.9) - solve(0.1),
        1e-9,
    );
    // Settling: the envelope 1 + e^(-zeta wn t)/sqrt(1 - zeta^2) bounds it from above, and
    // the response is outside the band at the last extremum before it.
    let envelope = (50.0 / (1.0 - zeta * zeta).sqrt()).ln() / (zeta * wn);
    let settling = metrics.settling_time.unwrap();
    assert!(settling <= envelope && settling > envelope - std::f64::consts::PI / wd);
    assert!((r(settling) - 1.0).abs() - 0.02 < 1e-9);
}

#[test]
fn an_input_rate_term_makes_the_state_jump() {
    // dx/dt = -x + du/dt, y = x: the high-pass G = s/(s + 1); a step gives y = e^(-t).
    let system = StepSystem {
        e: vec![1.0],
        b: vec![0.0],
        ..first_order(1.0)
    };
    let response = system.response().at(&[0.0, 1.0, 2.0]);
    close("y(0+)", response[0], 1.0, 1e-15);
    close("y(1)", response[1], (-1.0f64).exp(), 1e-14);
    close("y(2)", response[2], (-2.0f64).exp(), 1e-14);
    // Its final value is 0: no rise time or overshoot to speak of.
    let m = step_metrics(&system, &[Complex64::new(-1.0, 0.0)], Some(0.0)).unwrap();
    assert_eq!(m.rise_time, None);
    assert_eq!(m.overshoot_percent, None);
}

#[test]
fn an_integral_output_of_a_first_order_lag_ramps() {
    // ∫ (1 - e^(-t)) dt = t - 1 + e^(-t).
    let system = StepSystem {
        integral: true,
        ..first_order(1.0)
    };
    let y = system.response().at(&[3.0])[0];
    close("integral", y, 3.0 - 1.0 + (-3.0f64).exp(), 1e-13);
    // A pole at the origin: no final value.
    let poles = [Complex64::new(-1.0, 0.0), Complex64::new(0.0, 0.0)];
    assert_eq!(
        step_metrics(&system, &poles, None).unwrap().final_value,
        None
    );
}

#[test]
fn bode_of_a_first_order_lag_at_its_corner() {
    // 1/(τ s + 1), monic (1/τ)/(s + 1/τ): at ω = 1/τ, -10 log10 2 dB and -45 degrees.
    let tau = 0.5;
    let points = bode(
        &[1.0 / tau],
        &[1.0, 1.0 / tau],
        &[Complex64::new(-1.0 / tau, 0.0)],
    );
    let corner = points
        .iter()
        .min_by(|a, b| {
            (a.omega * tau - 1.0)
                .abs()
                .total_cmp(&(b.omega * tau - 1.0).abs())
        })
        .unwrap();
    let x = corner.omega * tau;
    close(
        "magnitude",
        corner.magnitude_db,
        -10.0 * (1.0 + x * x).log10(),
        1e-12,
    );
    close("phase", corner.phase_deg, -x.atan().to_degrees(), 1e-12);
    assert!((x - 1.0).abs() < 0.05);
    // Two decades either side of the corner.
    close(
        "lowest frequency",
        points.first().unwrap().omega,
        0.01 / tau,
        1e-12,
    );
    close(
        "highest frequency",
        points.last().unwrap().omega,
        100.0 / tau,
        1e-12,
    );
}

#[test]
fn roots_beside_huge_coefficients_keep_their_digits() {
    // (s + 0.5)(s² + 5e301) = s³ + 0.5 s² + 5e301 s + 2.5e301: the coefficients span 5e301
    // (a 1e-300 kg mass on a spring), the roots are -0.5 and ±sqrt(5e301) i.
    let r = roots(&[1.0, 0.5, 5e301, 2.5e301]).unwrap();
    assert_eq!(r.len(), 3, "{r:?}");
    let real: Vec<_> = r.iter().filter(|z| z.im == 0.0).collect();
    assert_eq!(real.len(), 1, "{r:?}");
    close("slow root", real[0].re, -0.5, 1e-14);
    for z in r.iter().filter(|z| z.im != 0.0) {
        close("fast pair", z.norm(), 5e301f64.sqrt(), 1e-14);
    }
    // (s + 1e200)(s + 1e-200) = s² + (1e200 + 1e-200) s + 1: the discriminant 1e400
    // overflows, the roots do not.
    let r = roots(&[1.0, 1e200, 1.0]).unwrap();
    close("large root", r[0].re, -1e200, 1e-15);
    close("small root", r[1].re, -1e-200, 1e-15);
}

#[test]
fn a_response_slower_than_any_double_time_still_returns() {
    // τ = 1e308 s: the horizon 8τ is beyond the largest double (1.8e308). The metrics
    // return promptly: with metrics whose horizon is finite, or with the error that the
    // closed form is not finite there (the propagator's e^(λt) with λ = -1e-308, a
    // subnormal), never with NaN metrics or an unbounded grid.
    let tau = 1e308;
    match step_metrics(
        &first_order(tau),
        &[Complex64::new(-1.0 / tau, 0.0)],
        Some(1.0),
    ) {
        Ok(m) => {
            assert_eq!(m.final_value, Some(1.0));
            assert!(m.horizon.is_finite(), "{m:?}");
            assert!(m.initial_value.is_finite(), "{m:?}");
        }
        Err(error) => assert_eq!(error, AnalysisError::NonFinite),
    }
}

#[test]
fn bode_beside_huge_coefficients() {
    // 1/((s + 0.5)(s² + 5e301)): at ω = 1, |G| = 1/(|i + 0.5| · (5e301 - 1)), that is
    // -20 log10(sqrt(1.25) · 5e301) dB; the phase is -atan(2) (the quadratic is real and
    // positive there). Evaluating s³ at ω ~ 1e152 must not overflow either.
    let points = bode(
        &[1.0],
        &[1.0, 0.5, 5e301, 2.5e301],
        &[
            Complex64::new(-0.5, 0.0),
            Complex64::new(0.0, 5e301f64.sqrt()),
        ],
    );
    assert!(
        points
            .iter()
            .all(|p| p.magnitude_db.is_finite() && p.phase_deg.is_finite()),
        "{:?}",
        points.iter().find(|p| !p.magnitude_db.is_finite())
    );
    let one = points
        .iter()
        .min_by(|a, b| (a.omega.ln()).abs().total_cmp(&(b.omega.ln()).abs()))
        .unwrap();
    let w = one.omega;
    let expected = -20.0 * ((0.25 + w * w).sqrt() * (5e301 - w * w)).log10();
    close("magnitude", one.magnitude_db, expected, 1e-12);
}

#[test]
fn poles_are_the_eigenvalues_the_transfer_function_keeps() {
    let scaled = |p: &[f64]| -> Vec<Scaled> { p.iter().map(|c| Scaled::from_f64(*c)).collect() };
    let real = |values: &[f64]| -> Vec<Complex64> {
        values.iter().map(|v| Complex64::new(*v, 0.0)).collect()
    };
    // Eigenvalues -1, -2, -3; the factor s + 2 cancelled, leaving (s + 1)(s + 3).
    let poles = bondgraph_solver::analysis::poles(
        &real(&[-3.0, -2.0, -1.0]),
        &scaled(&[1.0, 2.0]),
        &scaled(&[1.0, 4.0, 3.0]),
    );
    assert_eq!(poles, real(&[-3.0, -1.0]));
    // A double eigenvalue -1 of which one copy cancelled, beside -2: (s + 1)(s + 2) stays.
    let poles = bondgraph_solver::analysis::poles(
        &real(&[-2.0, -1.0, -1.0]),
        &scaled(&[1.0, 1.0]),
        &scaled(&[1.0, 3.0, 2.0]),
    );
    assert_eq!(poles, real(&[-2.0, -1.0]));
    // Nothing cancelled, and an eigenvalue the matrix gives as 0 polished on the
    // denominator s³ + 2.5e-308 s² + 50 s + 1.25e-306 = (s + 2.5e-308)(s² + 50): the root
    // -2.5e-308 (a 1e308 kg mass behind a 2.5 N s/m damper) is below the matrix's
    // precision, not the polynomial's.
    let poles = bondgraph_solver::analysis::poles(
        &[
            Complex64::new(0.0, -50f64.sqrt()),
            Complex64::new(0.0, 0.0),
            Complex64::new(0.0, 50f64.sqrt()),
        ],
        &scaled(&[1.0]),
        &scaled(&[1.0, 2.5e-308, 50.0, 1.25e-306]),
    );
    // Sorted by real part: the slow pole first, then the pair.
    assert_eq!(poles[0].im, 0.0);
    close("slow pole", poles[0].re, -2.5e-308, 1e-14);
    close("pair", poles[2].im, 50f64.sqrt(), 1e-15);
}

#[test]
fn roots_of_coefficients_beyond_doubles() {
    // (s + 1e200)(s + 2e200) = s² + 3e200 s + 2e400: the constant is beyond f64.
    let coefficients = [
        Scaled::ONE,
        Scaled::from_f64(3e200),
        Scaled::from_f64(2e200) * Scaled::from_f64(1e200),
    ];
    let r = bondgraph_solver::analysis::roots_scaled(&coefficients).unwrap();
    close("first", r[0].re, -2e200, 1e-15);
    close("second", r[1].re, -1e200, 1e-15);
    // An infinite coefficient is an error, not a root.
    assert_eq!(
        roots(&[1.0, f64::INFINITY, 1.0]),
        Err(AnalysisError::NonFinite)
    );
}

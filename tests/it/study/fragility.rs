//! The collapse-fragility fits of `fem2rbd study collect` (`src/study/fragility.rs`)
//! against closed forms and known answers.
use fem2rbd::study::fragility::{fit_ida, fit_stripes, phi, phi_inv};
use fem2rbd::study::StudyError;

/// Standard normal values (Abramowitz & Stegun, table 26.1; R's pnorm/qnorm).
#[test]
fn normal_cdf_and_inverse_match_tables() {
    let table = [
        (0.0, 0.5),
        (0.5, 0.691_462_461_274_013_1),
        (1.0, 0.841_344_746_068_542_9),
        (-1.644_853_626_951_472_2, 0.05),
        (2.326_347_874_040_841, 0.99),
        (-3.0, 0.001_349_898_031_630_094_6),
        (4.0, 0.999_968_328_758_166_9),
    ];
    for (z, p) in table {
        assert!((phi(z) - p).abs() < 1e-14, "Φ({z}) = {} ≠ {p}", phi(z));
        assert!(
            (phi_inv(p) - z).abs() < 1e-10,
            "Φ⁻¹({p}) = {} ≠ {z}",
            phi_inv(p)
        );
    }
    // Lower tail in relative terms: Φ(−6) = 9.865876450377e-10.
    assert!((phi(-6.0) / 9.865_876_450_377e-10 - 1.0).abs() < 1e-10);
}

/// Without censoring the MLE is closed-form: μ = mean ln x, β² = mean (ln x − μ)².
#[test]
fn ida_fit_without_censoring_is_the_closed_form() {
    let x = [
        0.62, 0.75, 0.81, 0.88, 0.95, 1.02, 1.10, 1.15, 1.21, 1.33, 1.48, 1.60,
    ];
    let n = x.len() as f64;
    let mu = x.iter().map(|v: &f64| v.ln()).sum::<f64>() / n;
    let beta = (x.iter().map(|v| (v.ln() - mu).powi(2)).sum::<f64>() / n).sqrt();
    let f = fit_ida(&x, &[]).unwrap();
    assert!((f.median_g - mu.exp()).abs() < 1e-14, "{f:?}");
    assert!((f.beta - beta).abs() < 1e-14, "{f:?}");
    // ℓ at the optimum: −n/2 (ln 2π + 1) − n ln β − Σ ln x.
    let ll = -n / 2.0 * ((2.0 * std::f64::consts::PI).ln() + 1.0)
        - n * beta.ln()
        - x.iter().map(|v| v.ln()).sum::<f64>();
    assert!(
        (f.log_likelihood - ll).abs() < 1e-10,
        "{} vs {ll}",
        f.log_likelihood
    );
}

/// Censored IDA data drawn as exact quantiles of a known lognormal (θ = 1.2 g,
/// β = 0.45), every record above c = θ·e^(0.5β) censored at c (31 % of them): the MLE
/// recovers θ and β (the naive fit of the observed collapses alone does not).
#[test]
fn ida_fit_with_censoring_recovers_a_known_lognormal() {
    let (theta, beta) = (1.2f64, 0.45f64);
    let n = 4000;
    let c = theta * (0.5 * beta).exp();
    let (mut obs, mut cen) = (Vec::new(), Vec::new());
    for i in 0..n {
        let x = theta * (beta * phi_inv((i as f64 + 0.5) / n as f64)).exp();
        if x < c {
            obs.push(x);
        } else {
            cen.push(c);
        }
    }
    let share = cen.len() as f64 / n as f64;
    assert!((share - (1.0 - phi(0.5))).abs() < 1e-3, "{share}");
    let f = fit_ida(&obs, &cen).unwrap();
    assert!((f.median_g / theta - 1.0).abs() < 2e-3, "{f:?}");
    assert!((f.beta / beta - 1.0).abs() < 5e-3, "{f:?}");
    let naive = fit_ida(&obs, &[]).unwrap();
    assert!(
        naive.median_g < 0.9 * theta && naive.beta < 0.8 * beta,
        "{naive:?}"
    );
}

/// Two stripes fit exactly: Φ((ln x₁ − μ)/β) = p₁ and Φ((ln x₂ − μ)/β) = p₂ give
/// β = (ln x₂ − ln x₁)/(Φ⁻¹(p₂) − Φ⁻¹(p₁)), μ = ln x₁ − β Φ⁻¹(p₁) (the binomial
/// likelihood is maximal where the fitted probabilities equal the observed fractions).
#[test]
fn stripe_fit_with_two_stripes_matches_the_observed_fractions() {
    let (x1, n1, z1) = (0.6f64, 20, 3);
    let (x2, n2, z2) = (1.4f64, 20, 15);
    let (p1, p2) = (z1 as f64 / n1 as f64, z2 as f64 / n2 as f64);
    let beta = f64::ln(x2) - f64::ln(x1);
    let beta = beta / (phi_inv(p2) - phi_inv(p1));
    let mu = f64::ln(x1) - beta * phi_inv(p1);
    let f = fit_stripes(&[(x1, n1, z1), (x2, n2, z2)]).unwrap();
    assert!(
        (f.median_g / mu.exp() - 1.0).abs() < 1e-7,
        "{f:?} vs θ = {}",
        mu.exp()
    );
    assert!((f.beta / beta - 1.0).abs() < 1e-7, "{f:?} vs β = {beta}");
}

/// Data that cannot bound a fit are errors, not numbers.
#[test]
fn degenerate_data_are_errors() {
    let unfit = |r: Result<_, StudyError>| matches!(r, Err(StudyError::Fit(_)));
    assert!(unfit(fit_ida(&[1.0], &[2.0, 2.0])));
    assert!(unfit(fit_ida(&[], &[2.0])));
    assert!(unfit(fit_stripes(&[(0.5, 10, 0), (1.0, 10, 0)])));
    assert!(unfit(fit_stripes(&[(0.5, 10, 10)])));
}

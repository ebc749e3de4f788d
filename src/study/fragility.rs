//! Collapse fragility: a lognormal fit by maximum likelihood.
//!
//! The fragility P(collapse | IM = x) = Φ((ln x − ln θ)/β), θ the median collapse
//! intensity (g) and β the dispersion (FEMA P-695 §6–7 practice; Baker, "Efficient
//! analytical fragility function fitting using dynamic structural analysis", Earthquake
//! Spectra 31(1), 2015).
//!
//! * **IDA** ([`fit_ida`]): each record's collapse intensity x_i is observed (the lowest
//!   collapsing intensity of its bisection), or right-censored at c_j when it did not
//!   collapse up to `max_g`. Log-likelihood
//!   ℓ(μ, β) = Σ_i [ln φ((ln x_i − μ)/β) − ln β − ln x_i] + Σ_j ln(1 − Φ((ln c_j − μ)/β)),
//!   μ = ln θ. Without censoring the maximum is closed-form: μ = mean(ln x_i),
//!   β² = mean((ln x_i − μ)²) (the 1/n variance).
//! * **Stripes** ([`fit_stripes`]): at intensity x_j, z_j of n_j runs collapsed; binomial
//!   log-likelihood ℓ = Σ_j [z_j ln Φ_j + (n_j − z_j) ln(1 − Φ_j)], Φ_j = Φ((ln x_j − μ)/β)
//!   (Baker 2015, eq. 11). n_j counts each (model, record, mode) once per intensity, not
//!   each ensemble member: collapse is decided by the FE stage the members share.
//!
//! Both are maximised over (μ, ln β) by Nelder–Mead from a deterministic start, so the
//! same data give the same bits.
use super::error::{Result, StudyError};

/// A fitted lognormal fragility.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit {
    /// Median θ, g.
    pub median_g: f64,
    /// Dispersion β (standard deviation of ln IM).
    pub beta: f64,
    /// Log-likelihood at the optimum.
    pub log_likelihood: f64,
}

/// erf(x): the Maclaurin series for |x| < 2, else 1 − erfc by the continued fraction
/// (Lentz); both to about 1e-15.
pub(crate) fn erf(x: f64) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    if x.abs() < 2.0 {
        // erf x = 2/√π Σ (−1)^n x^(2n+1) / (n! (2n+1))
        let mut term = x;
        let mut sum = x;
        let x2 = x * x;
        let mut n = 0.0;
        loop {
            n += 1.0;
            term *= -x2 / n;
            let add = term / (2.0 * n + 1.0);
            sum += add;
            if add.abs() <= 1e-17 * sum.abs() || n > 200.0 {
                break;
            }
        }
        sum * 2.0 / std::f64::consts::PI.sqrt()
    } else {
        x.signum() * (1.0 - erfc_cf(x.abs()))
    }
}

/// erfc(x) for x ≥ 2: e^(−x²)/√π · 1/(x + (1/2)/(x + 1/(x + (3/2)/(x + …)))), modified
/// Lentz.
fn erfc_cf(x: f64) -> f64 {
    let tiny = 1e-300;
    let mut f = x;
    let mut c = x;
    let mut d = 0.0;
    for k in 1..5000 {
        let a = k as f64 / 2.0;
        d = x + a * d;
        d = if d.abs() < tiny { tiny } else { d };
        c = x + a / c;
        c = if c.abs() < tiny { tiny } else { c };
        d = 1.0 / d;
        let delta = c * d;
        f *= delta;
        if (delta - 1.0).abs() < 1e-16 {
            break;
        }
    }
    (-x * x).exp() / std::f64::consts::PI.sqrt() / f
}

/// erfc(x) = 1 − erf(x), accurate in both tails.
pub(crate) fn erfc(x: f64) -> f64 {
    if x >= 2.0 {
        erfc_cf(x)
    } else if x <= -2.0 {
        2.0 - erfc_cf(-x)
    } else {
        1.0 - erf(x)
    }
}

/// Standard normal CDF Φ(z) = erfc(−z/√2)/2.
pub fn phi(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// ln Φ(z), accurate far in the lower tail.
pub(crate) fn ln_phi(z: f64) -> f64 {
    phi(z).max(1e-300).ln()
}

/// Inverse of [`phi`] for 0 < p < 1: bisection to a bracket, then Newton.
pub fn phi_inv(p: f64) -> f64 {
    assert!(p > 0.0 && p < 1.0, "phi_inv: p = {p} not in (0, 1)");
    let (mut lo, mut hi) = (-40.0, 40.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if phi(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut z = 0.5 * (lo + hi);
    for _ in 0..5 {
        let pdf = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
        if pdf < 1e-300 {
            break;
        }
        z -= (phi(z) - p) / pdf;
    }
    z
}

/// Minimises `f` over 2 parameters by Nelder–Mead from `x0` with initial steps `step`.
fn nelder_mead(f: &dyn Fn([f64; 2]) -> f64, x0: [f64; 2], step: [f64; 2]) -> [f64; 2] {
    let mut s = [x0, [x0[0] + step[0], x0[1]], [x0[0], x0[1] + step[1]]];
    let mut v = s.map(f);
    for _ in 0..20_000 {
        // order
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        s = idx.map(|i| s[i]);
        v = idx.map(|i| v[i]);
        let spread = (v[2] - v[0]).abs();
        let size = (s[2][0] - s[0][0])
            .abs()
            .max((s[2][1] - s[0][1]).abs())
            .max((s[1][0] - s[0][0]).abs())
            .max((s[1][1] - s[0][1]).abs());
        if size < 1e-11 || spread <= 1e-16 * (1.0 + v[0].abs()) && size < 1e-8 {
            break;
        }
        let c = [(s[0][0] + s[1][0]) / 2.0, (s[0][1] + s[1][1]) / 2.0];
        let at = |t: f64| [c[0] + t * (s[2][0] - c[0]), c[1] + t * (s[2][1] - c[1])];
        let r = at(-1.0);
        let fr = f(r);
        if fr < v[0] {
            let e = at(-2.0);
            let fe = f(e);
            if fe < fr {
                s[2] = e;
                v[2] = fe;
            } else {
                s[2] = r;
                v[2] = fr;
            }
        } else if fr < v[1] {
            s[2] = r;
            v[2] = fr;
        } else {
            let k = if fr < v[2] { at(-0.5) } else { at(0.5) };
            let fk = f(k);
            if fk < v[2].min(fr) {
                s[2] = k;
                v[2] = fk;
            } else {
                for i in 1..3 {
                    s[i] = [
                        s[0][0] + 0.5 * (s[i][0] - s[0][0]),
                        s[0][1] + 0.5 * (s[i][1] - s[0][1]),
                    ];
                    v[i] = f(s[i]);
                }
            }
        }
    }
    let best = (0..3).min_by(|&a, &b| v[a].total_cmp(&v[b])).expect("3");
    s[best]
}

/// IDA fit (module docs): `collapse_g` observed collapse intensities, `censored_g`
/// intensities reached without collapse. Needs at least two observed collapses with
/// different intensities.
pub fn fit_ida(collapse_g: &[f64], censored_g: &[f64]) -> Result<Fit> {
    if collapse_g
        .iter()
        .chain(censored_g)
        .any(|x| !(x.is_finite() && *x > 0.0))
    {
        return Err(StudyError::Fit("intensities must be positive".into()));
    }
    let ln: Vec<f64> = collapse_g.iter().map(|x| x.ln()).collect();
    let n = ln.len() as f64;
    if ln.len() < 2 || ln.iter().all(|l| (l - ln[0]).abs() < 1e-12) {
        return Err(StudyError::Fit(format!(
            "{} collapse intensities (need at least two different ones)",
            ln.len()
        )));
    }
    let mu0 = ln.iter().sum::<f64>() / n;
    let b0 = (ln.iter().map(|l| (l - mu0).powi(2)).sum::<f64>() / n).sqrt();
    let lnc: Vec<f64> = censored_g.iter().map(|x| x.ln()).collect();
    let ll = |mu: f64, beta: f64| -> f64 {
        let half_ln_2pi = 0.5 * (2.0 * std::f64::consts::PI).ln();
        let mut s = 0.0;
        for l in &ln {
            let z = (l - mu) / beta;
            s += -0.5 * z * z - half_ln_2pi - beta.ln() - l;
        }
        for c in &lnc {
            s += ln_phi(-(c - mu) / beta);
        }
        s
    };
    let (mu, beta) = if lnc.is_empty() {
        (mu0, b0)
    } else {
        let x = nelder_mead(&|p| -ll(p[0], p[1].exp()), [mu0, b0.ln()], [0.1, 0.1]);
        (x[0], x[1].exp())
    };
    Ok(Fit {
        median_g: mu.exp(),
        beta,
        log_likelihood: ll(mu, beta),
    })
}

/// Stripe fit (module docs): `(x_g, n, z)` per intensity. Needs a stripe with some but not
/// all collapsing, or collapses and non-collapses at different intensities in the right
/// order to bound the fit.
pub fn fit_stripes(stripes: &[(f64, usize, usize)]) -> Result<Fit> {
    let total: usize = stripes.iter().map(|s| s.1).sum();
    let coll: usize = stripes.iter().map(|s| s.2).sum();
    if stripes
        .iter()
        .any(|s| !(s.0 > 0.0 && s.0.is_finite()) || s.2 > s.1)
    {
        return Err(StudyError::Fit("bad stripe data".into()));
    }
    if coll == 0 || coll == total {
        return Err(StudyError::Fit(format!(
            "{coll} of {total} runs collapsed; a fit needs both outcomes"
        )));
    }
    let ll = |mu: f64, beta: f64| -> f64 {
        let mut s = 0.0;
        for &(x, n, z) in stripes {
            let u = (x.ln() - mu) / beta;
            if z > 0 {
                s += z as f64 * ln_phi(u);
            }
            if n > z {
                s += (n - z) as f64 * ln_phi(-u);
            }
        }
        s
    };
    // Start: μ at the count-weighted mean of ln x, β = 0.4 (a typical record-to-record
    // dispersion).
    let mu0 = stripes.iter().map(|s| s.1 as f64 * s.0.ln()).sum::<f64>() / total as f64;
    let x = nelder_mead(&|p| -ll(p[0], p[1].exp()), [mu0, 0.4f64.ln()], [0.2, 0.2]);
    let (mu, beta) = (x[0], x[1].exp());
    if !(1e-6..=50.0).contains(&beta) {
        return Err(StudyError::Fit(format!("the data do not bound the fit (β → {beta:.3e}); separate outcomes overlap or are perfectly split")));
    }
    Ok(Fit {
        median_g: mu.exp(),
        beta,
        log_likelihood: ll(mu, beta),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phi_matches_tabulated_values() {
        // Abramowitz & Stegun table 26.1 / standard values.
        assert!((phi(0.0) - 0.5).abs() < 1e-15);
        assert!((phi(1.0) - 0.841_344_746_068_542_9).abs() < 1e-14);
        assert!((phi(-1.96) - 0.024_997_895_148_220_43).abs() < 1e-14);
        assert!((phi(3.5) - 0.999_767_370_920_964_2).abs() < 1e-14);
        assert!((phi(-5.0) - 2.866_515_718_791_939e-7).abs() < 1e-19);
        assert!((erf(0.5) - 0.520_499_877_813_046_5).abs() < 1e-15);
        assert!((phi_inv(0.975) - 1.959_963_984_540_054).abs() < 1e-12);
    }
}

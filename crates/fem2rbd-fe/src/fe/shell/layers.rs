//! Layer laws of a layered shell section (plate fibres: `[ε11 ε22 γ12 γ23 γ31]` →
//! `[σ11 σ22 σ12 σ23 σ31]`, Pa) and the layered section that integrates them through the
//! thickness (OpenSees `LayeredShellFiberSection`, Huang & Lu; see [`super`]).
//!
//! - [`ElasticFiber`]: isotropic plane stress plus transverse shear (OpenSees `PlateFiber`
//!   of `ElasticIsotropic`).
//! - [`RebarFiber`]: smeared bars, a uniaxial law along the bar direction θ (OpenSees
//!   `PlateRebar`): ε = c² ε11 + s² ε22 + c s γ12, σ = σ_bar [c², s², c s, 0, 0].
//! - [`DamageConcreteFiber`]: OpenSees `PlasticDamageConcretePlaneStress` (Wu, Li & Faria
//!   2006 plastic-damage model in the explicit form of its OpenSees implementation by
//!   T. Do, 2016) wrapped by `PlateFromPlaneStress` (elastic transverse shear G).

use nalgebra::{Matrix2x3, Matrix3, SVector, Vector2, Vector3};

use super::{isotropic_plate_fiber, rebar_plate_fiber, Mat5, Mat8};
use crate::fe::material::UniaxialMaterial;

/// 5-component plate-fibre strain or stress.
pub type Vec5 = SVector<f64, 5>;
/// 8-component generalized section strain or stress.
pub type Vec8 = SVector<f64, 8>;

/// A plate-fibre law (one layer at one Gauss point), with the commit/revert protocol of
/// [`UniaxialMaterial`].
pub trait PlateFiber: std::fmt::Debug + Send + Sync {
    /// Sets the trial strain `[ε11 ε22 γ12 γ23 γ31]` from the last committed state.
    fn set_trial_strain(&mut self, strain: &Vec5);
    /// Trial stress (Pa).
    fn stress(&self) -> Vec5;
    /// Trial tangent dσ/dε (Pa).
    fn tangent(&self) -> Mat5;
    /// Initial tangent (Pa).
    fn initial_tangent(&self) -> Mat5;
    /// The time increment Δt (s) of the step about to be iterated, for laws that
    /// extrapolate their internal variables in time (IMPL-EX). Default: ignored.
    fn set_time_increment(&mut self, _dt: f64) {}
    /// Accepts the trial state.
    fn commit_state(&mut self);
    /// Returns to the last committed state.
    fn revert_to_last_commit(&mut self);
    /// A copy with its own state.
    fn boxed_clone(&self) -> Box<dyn PlateFiber>;
    /// (yielded, ruptured): steel yielded / concrete past its peak; steel ruptured.
    fn damage(&self) -> (bool, bool) {
        (false, false)
    }
    /// Whether the layer has lost its load path (committed state): `None` for layers that
    /// do not count (elastic), `Some(true)` for a crushed concrete layer (d⁻ ≥ 0.9) or a
    /// ruptured bar layer. See [`LayeredSection::load_path_lost`].
    fn load_path_lost(&self) -> Option<bool> {
        None
    }
    /// Whether this is a concrete layer (for [`LayeredSection::load_path_lost`]).
    fn is_concrete(&self) -> bool {
        false
    }
}

/// Linear elastic isotropic plate fibre.
#[derive(Debug, Clone)]
pub struct ElasticFiber {
    d: Mat5,
    strain: Vec5,
}

impl ElasticFiber {
    /// E (Pa) and ν; transverse shear G = E / (2 (1 + ν)).
    pub fn new(e: f64, nu: f64) -> Self {
        Self {
            d: isotropic_plate_fiber(e, nu),
            strain: Vec5::zeros(),
        }
    }
}

impl PlateFiber for ElasticFiber {
    fn set_trial_strain(&mut self, strain: &Vec5) {
        self.strain = *strain;
    }
    fn stress(&self) -> Vec5 {
        self.d * self.strain
    }
    fn tangent(&self) -> Mat5 {
        self.d
    }
    fn initial_tangent(&self) -> Mat5 {
        self.d
    }
    fn commit_state(&mut self) {}
    fn revert_to_last_commit(&mut self) {}
    fn boxed_clone(&self) -> Box<dyn PlateFiber> {
        Box::new(self.clone())
    }
}

/// Smeared bars at `angle` degrees from the section's x axis.
#[derive(Debug)]
pub struct RebarFiber {
    bar: Box<dyn UniaxialMaterial>,
    angle: f64,
}

impl RebarFiber {
    /// A uniaxial law along the direction `angle` (degrees from local x).
    pub fn new(bar: Box<dyn UniaxialMaterial>, angle: f64) -> Self {
        Self { bar, angle }
    }
    /// (c², s², c s) of the bar direction, with OpenSees' exact 0° and 90° cases.
    fn dir(&self) -> [f64; 3] {
        if self.angle == 0.0 {
            [1.0, 0.0, 0.0]
        } else if self.angle == 90.0 {
            [0.0, 1.0, 0.0]
        } else {
            let r = self.angle * 4.0 * 1f64.asin() / 360.0;
            let (c, s) = (r.cos(), r.sin());
            [c * c, s * s, c * s]
        }
    }
}

impl PlateFiber for RebarFiber {
    fn set_trial_strain(&mut self, e: &Vec5) {
        let [a, b, c] = self.dir();
        self.bar.set_trial_strain(a * e[0] + b * e[1] + c * e[2]);
    }
    fn stress(&self) -> Vec5 {
        let [a, b, c] = self.dir();
        let s = self.bar.stress();
        Vec5::new(a * s, b * s, c * s, 0.0, 0.0)
    }
    fn tangent(&self) -> Mat5 {
        rebar_plate_fiber(self.bar.tangent(), self.angle)
    }
    fn initial_tangent(&self) -> Mat5 {
        rebar_plate_fiber(self.bar.initial_tangent(), self.angle)
    }
    fn commit_state(&mut self) {
        self.bar.commit_state();
    }
    fn revert_to_last_commit(&mut self) {
        self.bar.revert_to_last_commit();
    }
    fn boxed_clone(&self) -> Box<dyn PlateFiber> {
        Box::new(Self {
            bar: self.bar.boxed_clone(),
            angle: self.angle,
        })
    }
    fn damage(&self) -> (bool, bool) {
        let d = self.bar.damage();
        (d.yielded, d.ruptured)
    }
    fn load_path_lost(&self) -> Option<bool> {
        Some(self.bar.damage().ruptured)
    }
}

/// How [`DamageConcreteFiber`] integrates its internal variables (damage thresholds r⁺,
/// r⁻ and plastic strain εᵖ) over a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ConcreteIntegration {
    /// OpenSees' `PlasticDamageConcretePlaneStress`: the internal variables follow the
    /// trial strain of every iteration (from the last committed state), with the
    /// consistent tangent of that map. Equal to OpenSees; Newton can cycle between a
    /// loading and an unloading state of a softening layer (docs/shell-verification.md
    /// §10).
    #[default]
    Implicit,
    /// IMPL-EX (Oliver, Huespe & Cante 2008, Comput. Methods Appl. Mech. Engrg 197,
    /// 1865–1889): during the iterations of step n+1 the internal variables are the
    /// linear extrapolation of the last two committed ones,
    /// x̃ₙ₊₁ = xₙ + (Δtₙ₊₁/Δtₙ)(xₙ − xₙ₋₁), so the stress is a fixed-damage function of
    /// the strain, σ = (1 − d̃⁻) σ̄⁻ + (1 − d̃⁺) σ̄⁺ with σ̄ = C (ε − ε̃ᵖ), whose tangent
    /// has no loading/unloading switch; at the commit the implicit update of the
    /// converged strain gives xₙ₊₁. First-order accurate in Δt (the error vanishes as the
    /// step shrinks); the same idea as OpenSees' `ASDConcrete3D -implex`.
    Implex,
}

/// History variables of [`DamageConcreteFiber`].
#[derive(Debug, Clone, Copy, PartialEq)]
struct DamageState {
    /// Total in-plane strain `[ε11 ε22 γ12]`.
    eps: Vector3<f64>,
    /// Plastic strain.
    eps_p: Vector3<f64>,
    /// Damage thresholds (Pa): compression r⁻, tension r⁺.
    rn: f64,
    rp: f64,
    /// Damage variables d⁻ (compression) and d⁺ (tension).
    dn: f64,
    dp: f64,
}

/// Plane-stress plastic-damage concrete, OpenSees `PlasticDamageConcretePlaneStress E ν
/// ft fc β Ap An Bn` inside `PlateFromPlaneStress` (transverse shear G = E / (2 (1 + ν))).
///
/// State determination (explicit, no return-mapping iterations; OpenSees 3.7.1
/// `PlasticDamageConcretePlaneStress::setTrialStrain`): with C the plane-stress elastic
/// matrix, the trial effective stress σ̄ = C (ε − εᵖ) is split in principal directions
/// (angle φ = ½ atan(2 σ̄12 / (σ̄11 − σ̄22))) into positive and negative parts σ̄⁺, σ̄⁻;
/// the equivalent stresses are τ⁻ = √3 (k σ_oct + τ_oct) of σ̄⁻ (k = √2 (f2c − fc) /
/// (2 f2c − fc), f2c = 1.16 fc) and τ⁺ = √(σ̄₁⁺² + σ̄₂⁺² − 2 ν σ̄₁⁺ σ̄₂⁺). If τ⁻ exceeds the
/// threshold r⁻ and the strain increment since the last commit loads (L·Δε > 0,
/// L = σ̄ / ‖σ̄‖), the effective stress is scaled by λ = 1 − β E L·Δε / ‖σ̄‖ and the plastic
/// strain grows by β E (L·Δε) C⁻¹ L. Damage: d⁺ = 1 − (ft / r⁺) exp(A⁺ (1 − r⁺ / ft)),
/// d⁻ = 1 − √(r⁻₀ / r⁻) (1 − A⁻) − A⁻ exp(B⁻ (1 − √(r⁻ / r⁻₀))), r⁻₀ = (√2 − k) fc / √3,
/// r⁺₀ = ft; σ = (1 − d⁻) σ̄⁻ + (1 − d⁺) σ̄⁺ rotated back. The tangent is the derivative
/// of this map (the same chain of derivatives as OpenSees, times C, plus 1e-12 C).
///
/// That is the default, [`ConcreteIntegration::Implicit`]. With
/// [`ConcreteIntegration::Implex`] ([`Self::with_integration`]) the iterations use r⁺, r⁻
/// and εᵖ extrapolated from the last two commits and the map above runs once per step, at
/// the commit, on the converged strain.
#[derive(Debug, Clone)]
pub struct DamageConcreteFiber {
    e: f64,
    nu: f64,
    ft: f64,
    fc: f64,
    beta: f64,
    ap: f64,
    an: f64,
    bn: f64,
    g_shear: f64,
    c0: Matrix3<f64>,
    committed: DamageState,
    trial: DamageState,
    sig: Vector3<f64>,
    ct: Matrix3<f64>,
    ct_committed: Matrix3<f64>,
    sig_committed: Vector3<f64>,
    shear: Vector2<f64>,
    shear_committed: Vector2<f64>,
    integration: ConcreteIntegration,
    /// IMPL-EX: the committed (implicit) state before the last one, and the time
    /// increments of the last committed step and of the current one (s; pseudo-time 1
    /// in static analyses that do not set it).
    previous: DamageState,
    dt_committed: f64,
    dt_trial: f64,
}

const TOL: f64 = 1.0e-14;
const SQRT2: f64 = std::f64::consts::SQRT_2;
const SQRT3: f64 = 1.7320508075688772;

impl DamageConcreteFiber {
    /// OpenSees' defaults β = 0.6, A⁺ = 0.5, A⁻ = 2.0, B⁻ = 0.75. `fc`, `ft` positive (Pa).
    pub fn new(e: f64, nu: f64, ft: f64, fc: f64) -> Self {
        Self::with_parameters(e, nu, ft, fc, 0.6, 0.5, 2.0, 0.75)
    }

    /// All parameters (see the type docs).
    #[allow(clippy::too_many_arguments)]
    pub fn with_parameters(
        e: f64,
        nu: f64,
        ft: f64,
        fc: f64,
        beta: f64,
        ap: f64,
        an: f64,
        bn: f64,
    ) -> Self {
        let g = e / 2.0 / (1.0 + nu);
        let c = e / (1.0 - nu * nu);
        let c0 = Matrix3::new(c, nu * c, 0.0, nu * c, c, 0.0, 0.0, 0.0, g);
        let state = DamageState {
            eps: Vector3::zeros(),
            eps_p: Vector3::zeros(),
            rn: Self::rn0_of(fc),
            rp: ft,
            dn: 0.0,
            dp: 0.0,
        };
        Self {
            e,
            nu,
            ft,
            fc,
            beta,
            ap,
            an,
            bn,
            g_shear: g,
            c0,
            committed: state,
            trial: state,
            sig: Vector3::zeros(),
            ct: c0,
            ct_committed: c0,
            sig_committed: Vector3::zeros(),
            shear: Vector2::zeros(),
            shear_committed: Vector2::zeros(),
            integration: ConcreteIntegration::Implicit,
            previous: state,
            dt_committed: 1.0,
            dt_trial: 1.0,
        }
    }

    fn k_of(fc: f64) -> f64 {
        let f2c = 1.16 * fc;
        SQRT2 * (f2c - fc) / (2.0 * f2c - fc)
    }

    fn rn0_of(fc: f64) -> f64 {
        (SQRT2 - Self::k_of(fc)) * fc / SQRT3
    }

    /// Damage variables (d⁻, d⁺) of the trial state.
    pub fn damage_variables(&self) -> (f64, f64) {
        (self.trial.dn, self.trial.dp)
    }

    /// Plane-stress state determination of `eps` from the state `from`: the new state,
    /// the stress and the tangent. With `evolve` the damage thresholds and the plastic
    /// strain evolve (the law of the type docs); without, they are held at `from`'s
    /// values, so σ = (1 − d⁻) σ̄⁻ + (1 − d⁺) σ̄⁺ with σ̄ = C (ε − εᵖ) and the tangent is
    /// that of the principal split alone (the IMPL-EX stress, [`ConcreteIntegration`]).
    fn response(
        &self,
        from: &DamageState,
        eps: Vector3<f64>,
        evolve: bool,
    ) -> (DamageState, Vector3<f64>, Matrix3<f64>) {
        let (e, nu, beta) = (self.e, self.nu, self.beta);
        let k = Self::k_of(self.fc);
        let rn0 = Self::rn0_of(self.fc);
        let g = self.g_shear;
        let inv_c = Matrix3::new(
            1.0 / e,
            -nu / e,
            0.0,
            -nu / e,
            1.0 / e,
            0.0,
            0.0,
            0.0,
            1.0 / g,
        );
        let mut st = *from;
        st.eps = eps;
        let deps = eps - from.eps;
        let s = self.c0 * (eps - st.eps_p);
        // principal directions of the trial effective stress
        let mut fi = if (s[0] - s[1]).abs() > TOL {
            0.5 * (2.0 * s[2] / (s[0] - s[1])).atan()
        } else if s[2].abs() > TOL {
            std::f64::consts::FRAC_PI_4
        } else {
            0.0
        };
        if fi.abs() < TOL {
            fi = 0.0;
        }
        let (c, sn) = (fi.cos(), fi.sin());
        let sigpe = [
            s[0] * c * c + s[1] * sn * sn + 2.0 * s[2] * c * sn,
            s[0] * sn * sn + s[1] * c * c - 2.0 * s[2] * c * sn,
        ];
        let neg = sigpe.map(|x| (x - x.abs()) / 2.0);
        let pos = sigpe.map(|x| (x + x.abs()) / 2.0);
        let sigoct = (neg[0] + neg[1]) / 3.0;
        let a = neg[0] - neg[1];
        let tauoct = (a * a + neg[1] * neg[1] + neg[0] * neg[0]).sqrt() / 3.0;
        let taunt = SQRT3 * (k * sigoct + tauoct);
        let taupt = (pos[0] * pos[0] + pos[1] * pos[1] - 2.0 * nu * pos[0] * pos[1]).sqrt();
        let (mut taun, mut taup) = (taunt, taupt);
        // Held internal variables: no threshold is ever exceeded.
        let gnegt = if evolve {
            taunt - st.rn
        } else {
            f64::NEG_INFINITY
        };
        // plasticity
        let mut nrm = 0.0;
        let mut l_tr = Vector3::zeros();
        let mut ldeps = 0.0;
        let (mut gp, mut gn) = (0.0, 0.0);
        let mut lam = 0.0;
        if gnegt > TOL {
            nrm = (s[0] * s[0] + s[1] * s[1] + 2.0 * s[2] * s[2]).sqrt();
            if nrm.abs() >= TOL {
                l_tr = s / nrm;
                ldeps = l_tr.dot(&deps);
            }
            if ldeps > 0.0 {
                lam = 1.0 - beta * e * ldeps / nrm;
                taun = taunt * lam;
                taup = taupt * lam;
                gp = taup - st.rp;
                gn = taun - st.rn;
                if gp > TOL || gn > TOL {
                    st.eps_p += inv_c * l_tr * (beta * e * ldeps);
                } else {
                    lam = 0.0;
                }
            }
        }
        // damage
        let (gpos, gneg) = if evolve {
            (taup - st.rp, taun - st.rn)
        } else {
            (f64::NEG_INFINITY, f64::NEG_INFINITY)
        };
        let mut ddp_drp = 0.0;
        if gpos > TOL {
            st.rp = taup;
            let ex = (self.ap * (1.0 - st.rp / self.ft)).exp();
            st.dp = 1.0 - (self.ft / st.rp) * ex;
            ddp_drp = (self.ft / (st.rp * st.rp) + self.ap / st.rp) * ex;
            if st.dp > 0.99999999999999 {
                st.dp = 0.99999999999999;
                ddp_drp = 0.0;
            }
        }
        let mut ddn_drn = 0.0;
        if gneg > TOL {
            st.rn = taun;
            let rn = st.rn;
            let ex = (self.bn * (1.0 - (rn / rn0).sqrt())).exp();
            st.dn = (1.0 - (rn0 / rn).sqrt() * (1.0 - self.an)) - self.an * ex;
            ddn_drn = (1.0 - self.an) * rn0.sqrt() / (2.0 * rn.powf(1.5))
                + self.an * self.bn * ex / (2.0 * (rn * rn0).sqrt());
            if st.dn > 0.99999999999999 {
                st.dn = 0.99999999999999;
                ddn_drn = 0.0;
            }
        }
        let scale = if lam > 0.0 { lam } else { 1.0 };
        let dpp = pos.map(|x| x * scale);
        let dnp = neg.map(|x| x * scale);
        let sigp = [0, 1].map(|i| (1.0 - st.dn) * dnp[i] + (1.0 - st.dp) * dpp[i]);
        let sig = Vector3::new(
            sigp[0] * c * c + sigp[1] * sn * sn,
            sigp[0] * sn * sn + sigp[1] * c * c,
            (sigp[0] - sigp[1]) * c * sn,
        );

        // ---- tangent: dσ/dσ̄ (chain of the map above) times C
        let mut dfi = Vector3::zeros();
        if (s[0] - s[1]).abs() > TOL {
            let a = s[0] - s[1];
            let y = a * a + 4.0 * s[2] * s[2];
            dfi = Vector3::new(-s[2] / y, s[2] / y, a / y);
        } else if s[2].abs() > TOL {
            let y = 4.0 * s[2];
            dfi = Vector3::new(-1.0 / y, 1.0 / y, 0.0);
        }
        if fi.abs() < TOL {
            dfi = Vector3::zeros();
        }
        let mut dsigp = Matrix2x3::new(c * c, sn * sn, 2.0 * c * sn, sn * sn, c * c, -2.0 * c * sn);
        let dsigp_dfi = Vector2::new(
            2.0 * (s[1] - s[0]) * c * sn + 2.0 * s[2] * (c * c - sn * sn),
            2.0 * (s[0] - s[1]) * c * sn + 2.0 * s[2] * (sn * sn - c * c),
        );
        dsigp += dsigp_dfi * dfi.transpose();
        let mut dpos = Matrix2x3::zeros();
        let mut dneg = Matrix2x3::zeros();
        for (i, sp) in sigpe.iter().enumerate() {
            if *sp >= 0.0 {
                dpos.set_row(i, &dsigp.row(i));
            } else {
                dneg.set_row(i, &dsigp.row(i));
            }
        }
        // OpenSees writes 1/3 as 0.333333333 here.
        let dsigoct = (dneg.row(0) + dneg.row(1)).transpose() * 0.333333333;
        let dtauoct_dn = if tauoct > 0.0 {
            let y = 9.0 * tauoct;
            Vector2::new((2.0 * neg[0] - neg[1]) / y, (2.0 * neg[1] - neg[0]) / y)
        } else {
            Vector2::zeros()
        };
        let dtauoct = dneg.transpose() * dtauoct_dn;
        let dtaunt = if taunt > 0.0 {
            dsigoct * (SQRT3 * k) + dtauoct * SQRT3
        } else {
            Vector3::zeros()
        };
        let dtaupt = if taupt > 0.0 {
            dpos.transpose()
                * Vector2::new(
                    (pos[0] - nu * pos[1]) / taupt,
                    (pos[1] - nu * pos[0]) / taupt,
                )
        } else {
            Vector3::zeros()
        };
        let mut dlam = Vector3::zeros();
        let mut dtaun = dtaunt;
        let mut dtaup = dtaupt;
        if gnegt > TOL && ldeps > 0.0 {
            let dnrm = Vector3::new(s[0], s[1], 2.0 * s[2]) / nrm;
            let dl = Matrix3::identity() / nrm - s * dnrm.transpose() / (nrm * nrm);
            let dldeps = dl.transpose() * deps + inv_c.transpose() * l_tr;
            let dlam_dldeps = -beta * e / nrm;
            let dlam_dnrm = beta * e * ldeps / (nrm * nrm);
            dlam = dldeps * dlam_dldeps + dnrm * dlam_dnrm;
            if lam != 0.0 {
                dtaun = dtaunt * lam + dlam * (taun / lam);
                dtaup = dtaupt * lam + dlam * (taup / lam);
            }
            if gp <= TOL && gn <= TOL {
                dlam = Vector3::zeros();
            }
        }
        let ddp = if gpos > TOL {
            dtaup * ddp_drp
        } else {
            Vector3::zeros()
        };
        let ddn = if gneg > TOL {
            dtaun * ddn_drn
        } else {
            Vector3::zeros()
        };
        let (ddpp, ddnp) = if lam > 0.0 {
            (
                dpos * lam + Vector2::new(pos[0], pos[1]) * dlam.transpose(),
                dneg * lam + Vector2::new(neg[0], neg[1]) * dlam.transpose(),
            )
        } else {
            (dpos, dneg)
        };
        let dsn = -Vector2::new(dnp[0], dnp[1]) * ddn.transpose()
            - Vector2::new(dpp[0], dpp[1]) * ddp.transpose()
            + ddnp * (1.0 - st.dn)
            + ddpp * (1.0 - st.dp);
        let mut dsig = Matrix3::zeros();
        for j in 0..3 {
            dsig[(0, j)] = c * c * dsn[(0, j)]
                + sn * sn * dsn[(1, j)]
                + 2.0 * (sigp[1] - sigp[0]) * sn * c * dfi[j];
            dsig[(1, j)] = sn * sn * dsn[(0, j)]
                + c * c * dsn[(1, j)]
                + 2.0 * (sigp[0] - sigp[1]) * sn * c * dfi[j];
            dsig[(2, j)] = if s[2].abs() < 10e-14 {
                if j == 2 {
                    1.0
                } else {
                    0.0
                }
            } else {
                sn * c * (dsn[(0, j)] - dsn[(1, j)])
                    + (sigp[0] - sigp[1]) * (c * c - sn * sn) * dfi[j]
            };
        }
        (st, sig, dsig * self.c0 + self.c0 * 1.0e-12)
    }

    /// The IMPL-EX internal variables of the step (Oliver, Huespe & Cante 2008, eq. 20):
    /// each of r⁺, r⁻ and εᵖ linearly extrapolated from the last two committed (implicit)
    /// values, x̃ₙ₊₁ = xₙ + (Δtₙ₊₁/Δtₙ)(xₙ − xₙ₋₁), and d⁺, d⁻ the laws' functions of
    /// the extrapolated thresholds.
    fn extrapolated(&self) -> DamageState {
        let (n, m) = (&self.committed, &self.previous);
        let ratio = if self.dt_committed > 0.0 {
            self.dt_trial / self.dt_committed
        } else {
            1.0
        };
        let mut st = *n;
        st.rp = n.rp + ratio * (n.rp - m.rp);
        st.rn = n.rn + ratio * (n.rn - m.rn);
        st.eps_p = n.eps_p + (n.eps_p - m.eps_p) * ratio;
        st.dp = self.tension_damage(st.rp);
        st.dn = self.compression_damage(st.rn);
        st
    }

    /// d⁺(r⁺) = 1 − (ft / r⁺) exp(A⁺ (1 − r⁺ / ft)) for r⁺ > ft, else 0; at most
    /// 1 − 1e-14 (OpenSees' cap).
    fn tension_damage(&self, rp: f64) -> f64 {
        if rp <= self.ft {
            return 0.0;
        }
        let d = 1.0 - (self.ft / rp) * (self.ap * (1.0 - rp / self.ft)).exp();
        d.min(0.99999999999999)
    }

    /// d⁻(r⁻) = 1 − √(r⁻₀ / r⁻) (1 − A⁻) − A⁻ exp(B⁻ (1 − √(r⁻ / r⁻₀))) for r⁻ > r⁻₀,
    /// else 0; at most 1 − 1e-14.
    fn compression_damage(&self, rn: f64) -> f64 {
        let rn0 = Self::rn0_of(self.fc);
        if rn <= rn0 {
            return 0.0;
        }
        let d = (1.0 - (rn0 / rn).sqrt() * (1.0 - self.an))
            - self.an * (self.bn * (1.0 - (rn / rn0).sqrt())).exp();
        d.min(0.99999999999999)
    }

    /// Integration of the internal variables (default [`ConcreteIntegration::Implicit`]).
    pub fn with_integration(mut self, integration: ConcreteIntegration) -> Self {
        self.integration = integration;
        self
    }
}

impl PlateFiber for DamageConcreteFiber {
    fn set_trial_strain(&mut self, e: &Vec5) {
        let eps = Vector3::new(e[0], e[1], e[2]);
        let (st, sig, ct) = match self.integration {
            ConcreteIntegration::Implicit => self.response(&self.committed, eps, true),
            ConcreteIntegration::Implex => {
                let (mut st, sig, ct) = self.response(&self.extrapolated(), eps, false);
                st.eps = eps;
                (st, sig, ct)
            }
        };
        self.trial = st;
        self.sig = sig;
        self.ct = ct;
        self.shear = Vector2::new(e[3], e[4]) * self.g_shear;
    }
    fn set_time_increment(&mut self, dt: f64) {
        self.dt_trial = dt;
    }
    fn stress(&self) -> Vec5 {
        Vec5::new(
            self.sig[0],
            self.sig[1],
            self.sig[2],
            self.shear[0],
            self.shear[1],
        )
    }
    fn tangent(&self) -> Mat5 {
        let mut d = Mat5::zeros();
        d.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.ct);
        d[(3, 3)] = self.g_shear;
        d[(4, 4)] = self.g_shear;
        d
    }
    fn initial_tangent(&self) -> Mat5 {
        isotropic_plate_fiber(self.e, self.nu)
    }
    fn commit_state(&mut self) {
        match self.integration {
            ConcreteIntegration::Implicit => self.committed = self.trial,
            ConcreteIntegration::Implex => {
                // The implicit (explicit-law) update of the converged strain from the last
                // committed state; the stress of the step stays the extrapolated one that
                // equilibrium used.
                let (st, _, _) = self.response(&self.committed, self.trial.eps, true);
                self.previous = self.committed;
                self.committed = st;
                self.dt_committed = self.dt_trial;
            }
        }
        self.ct_committed = self.ct;
        self.sig_committed = self.sig;
        self.shear_committed = self.shear;
    }
    fn revert_to_last_commit(&mut self) {
        self.trial = self.committed;
        self.ct = self.ct_committed;
        self.sig = self.sig_committed;
        self.shear = self.shear_committed;
    }
    fn boxed_clone(&self) -> Box<dyn PlateFiber> {
        Box::new(self.clone())
    }
    fn damage(&self) -> (bool, bool) {
        // Past the compressive peak: d⁻ grows past the value at the peak of the uniaxial
        // curve only after crushing starts; report any compressive damage as "yielded"
        // and d⁻ ≥ 0.9 (crushed to a tenth of the effective stress) as "ruptured".
        (self.committed.dn > 0.0, self.committed.dn >= 0.9)
    }
    fn load_path_lost(&self) -> Option<bool> {
        Some(self.committed.dn >= 0.9)
    }
    fn is_concrete(&self) -> bool {
        true
    }
}

/// One layer: thickness (m), mid-thickness coordinate z (m) and its law.
#[derive(Debug)]
struct Layer {
    t: f64,
    z: f64,
    fiber: Box<dyn PlateFiber>,
}

/// A layered shell section: generalized strains `[ε11 ε22 γ12 κ11 κ22 κ12 γ23 γ31]` →
/// resultants `[N11 N22 N12 M11 M22 M12 V23 V31]` with layer strains e − z κ (membrane),
/// γ (shear), N = Σ tᵢ σᵢ, M = Σ tᵢ zᵢ σᵢ, V = Σ tᵢ τᵢ (OpenSees
/// `LayeredShellFiberSection`, midpoint rule).
#[derive(Debug)]
pub struct LayeredSection {
    layers: Vec<Layer>,
    stress: Vec8,
    tangent: Mat8,
    initial: Mat8,
}

impl LayeredSection {
    /// Layers bottom to top as (thickness, law).
    pub fn new(layers: Vec<(f64, Box<dyn PlateFiber>)>) -> Self {
        let h: f64 = layers.iter().map(|l| l.0).sum();
        let mut cur = 0.0;
        let layers: Vec<Layer> = layers
            .into_iter()
            .map(|(t, fiber)| {
                cur += t;
                let sg = cur / h - 1.0;
                cur += t;
                Layer {
                    t,
                    z: 0.5 * h * sg,
                    fiber,
                }
            })
            .collect();
        let tangents: Vec<(f64, Mat5)> = layers
            .iter()
            .map(|l| (l.t, l.fiber.initial_tangent()))
            .collect();
        let initial = super::layered_section_tangent(&tangents);
        Self {
            layers,
            stress: Vec8::zeros(),
            tangent: initial,
            initial,
        }
    }

    /// A copy with its own state.
    pub fn boxed_clone(&self) -> Self {
        Self {
            layers: self
                .layers
                .iter()
                .map(|l| Layer {
                    t: l.t,
                    z: l.z,
                    fiber: l.fiber.boxed_clone(),
                })
                .collect(),
            stress: self.stress,
            tangent: self.tangent,
            initial: self.initial,
        }
    }

    /// Sets the trial generalized strains; updates resultants and tangent.
    pub fn set_trial(&mut self, e: &Vec8) {
        let mut s = Vec8::zeros();
        let mut tangents = Vec::with_capacity(self.layers.len());
        for l in &mut self.layers {
            let z = l.z;
            let eps = Vec5::new(
                e[0] - z * e[3],
                e[1] - z * e[4],
                e[2] - z * e[5],
                e[6],
                e[7],
            );
            l.fiber.set_trial_strain(&eps);
            let sig = l.fiber.stress();
            for i in 0..3 {
                s[i] += l.t * sig[i];
                s[3 + i] += l.t * z * sig[i];
            }
            s[6] += l.t * sig[3];
            s[7] += l.t * sig[4];
            tangents.push((l.t, l.fiber.tangent()));
        }
        self.stress = s;
        self.tangent = super::layered_section_tangent(&tangents);
    }

    /// Resultants of the trial state (N/m, N·m/m).
    pub fn stress(&self) -> Vec8 {
        self.stress
    }
    /// Tangent of the trial state.
    pub fn tangent(&self) -> Mat8 {
        self.tangent
    }
    /// Initial tangent.
    pub fn initial_tangent(&self) -> Mat8 {
        self.initial
    }
    /// The time increment of the step about to be iterated (s), passed to every layer
    /// ([`PlateFiber::set_time_increment`]).
    pub fn set_time_increment(&mut self, dt: f64) {
        for l in &mut self.layers {
            l.fiber.set_time_increment(dt);
        }
    }
    /// Accepts the trial state.
    pub fn commit_state(&mut self) {
        for l in &mut self.layers {
            l.fiber.commit_state();
        }
    }
    /// Returns to the last committed state (resultants and tangent are those of the
    /// committed layer states).
    pub fn revert_to_last_commit(&mut self) {
        for l in &mut self.layers {
            l.fiber.revert_to_last_commit();
        }
        let mut s = Vec8::zeros();
        let mut tangents = Vec::with_capacity(self.layers.len());
        for l in &self.layers {
            let sig = l.fiber.stress();
            for i in 0..3 {
                s[i] += l.t * sig[i];
                s[3 + i] += l.t * l.z * sig[i];
            }
            s[6] += l.t * sig[3];
            s[7] += l.t * sig[4];
            tangents.push((l.t, l.fiber.tangent()));
        }
        self.stress = s;
        self.tangent = super::layered_section_tangent(&tangents);
    }
    /// (yielded, ruptured) over the layers (committed).
    pub fn damage(&self) -> (bool, bool) {
        self.layers.iter().fold((false, false), |(y, r), l| {
            let (a, b) = l.fiber.damage();
            (y || a, r || b)
        })
    }

    /// Whether the section has lost its load path (the wall hand-off rule,
    /// docs/handoff.md §3): a bar layer (one smeared curtain in one direction) has
    /// ruptured, or every concrete layer is crushed (d⁻ ≥ 0.9: crushed through the
    /// thickness). Cracking (d⁺) and a crushed cover layer alone never count. Steel laws
    /// without a rupture strain (Steel02) never rupture; bar buckling is not modelled.
    pub fn load_path_lost(&self) -> bool {
        let mut concrete = 0;
        let mut crushed = 0;
        for l in &self.layers {
            match (l.fiber.is_concrete(), l.fiber.load_path_lost()) {
                (true, Some(lost)) => {
                    concrete += 1;
                    crushed += usize::from(lost);
                }
                (false, Some(true)) => return true,
                _ => {}
            }
        }
        concrete > 0 && crushed == concrete
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall() -> LayeredSection {
        let c = || Box::new(DamageConcreteFiber::new(30e9, 0.2, 3e6, 30e6)) as Box<dyn PlateFiber>;
        LayeredSection::new(vec![(0.02, c()), (0.06, c()), (0.02, c())])
    }

    const E: f64 = 30e9;
    const NU: f64 = 0.2;
    const FT: f64 = 3e6;
    const FC: f64 = 30e6;

    /// Uniaxial tension (σ22 = σ12 = 0: ε = [x, −ν x, 0], σ̄ = [E x, 0, 0]) of the law's
    /// tension branch: σ = E x up to ft, then (1 − d⁺) E x = ft exp(A⁺ (1 − E x / ft))
    /// with A⁺ = 0.5 on a monotonic path (r⁺ = E x).
    fn closed_form(x: f64) -> f64 {
        let r = E * x;
        if r <= FT {
            r
        } else {
            FT * (0.5 * (1.0 - r / FT)).exp()
        }
    }

    /// Drives one fibre along ε = [x, −ν x, 0] through the strains `xs` with the time
    /// increments `dts`; returns σ11 of every step.
    fn uniaxial(integration: ConcreteIntegration, xs: &[f64], dts: &[f64]) -> Vec<f64> {
        let mut f = DamageConcreteFiber::new(E, NU, FT, FC).with_integration(integration);
        xs.iter()
            .zip(dts)
            .map(|(&x, &dt)| {
                f.set_time_increment(dt);
                f.set_trial_strain(&Vec5::new(x, -NU * x, 0.0, 0.0, 0.0));
                let s = f.stress();
                assert!(s[1].abs() < 1e-6 * FT && s[2].abs() < 1e-6 * FT, "{s:?}");
                f.commit_state();
                s[0]
            })
            .collect()
    }

    /// The implicit law equals the closed form along a monotonic tension path into
    /// softening (to 10 εt: σ falls to ft e^−4.5).
    #[test]
    fn implicit_uniaxial_tension_follows_the_closed_form() {
        let et = FT / E;
        let xs: Vec<f64> = (1..=100).map(|k| k as f64 * 0.1 * et).collect();
        let s = uniaxial(ConcreteIntegration::Implicit, &xs, &[1.0; 100]);
        for (x, s) in xs.iter().zip(&s) {
            assert!(
                (s - closed_form(*x)).abs() < 1e-9 * FT,
                "x {x}: {s} vs {}",
                closed_form(*x)
            );
        }
    }

    /// IMPL-EX on a path linear in time (steps of varying Δt, strain rate constant):
    /// the extrapolated threshold r̃ₙ₊₁ = rₙ + (Δtₙ₊₁/Δtₙ)(rₙ − rₙ₋₁) is exact once two
    /// committed steps have cracked, so σ equals the closed form from then on; at the
    /// first cracked step the damage lags one step (σ = E x > ft, the method's overshoot).
    /// With the time ratio ignored (all Δt reported as 1) the same path is off.
    #[test]
    fn implex_is_exact_on_a_path_linear_in_time() {
        let et = FT / E;
        let rate = 0.37 * et; // strain per unit time
        let dts: Vec<f64> = (0..60).map(|k| [1.0, 0.5, 2.0][k % 3]).collect();
        let mut t = 0.0;
        let xs: Vec<f64> = dts
            .iter()
            .map(|dt| {
                t += dt;
                rate * t
            })
            .collect();
        let s = uniaxial(ConcreteIntegration::Implex, &xs, &dts);
        let first = xs.iter().position(|&x| E * x > FT).unwrap();
        assert!((s[first] - E * xs[first]).abs() < 1e-9 * FT, "one-step lag");
        assert!(s[first] > FT);
        for k in 0..first {
            assert!((s[k] - E * xs[k]).abs() < 1e-9 * FT);
        }
        for k in first + 2..xs.len() {
            let c = closed_form(xs[k]);
            assert!((s[k] - c).abs() < 1e-9 * FT, "step {k}: {} vs {c}", s[k]);
        }
        let wrong = uniaxial(ConcreteIntegration::Implex, &xs, &[1.0; 60]);
        let worst = (first + 2..xs.len())
            .map(|k| (wrong[k] - closed_form(xs[k])).abs())
            .fold(0.0, f64::max);
        assert!(worst > 0.05 * FT, "the time ratio matters: {worst}");
    }

    /// IMPL-EX converges to the closed form at first order in Δt on a path not linear in
    /// time, x(t) = 8 εt sin(π t / 2), t ∈ [0, 1] in N equal steps: the largest error over
    /// the path halves as N doubles (measured ratios in the assertion message).
    #[test]
    fn implex_converges_at_first_order_to_the_closed_form() {
        let et = FT / E;
        let err = |n: usize| {
            let dt = 1.0 / n as f64;
            let xs: Vec<f64> = (1..=n)
                .map(|k| 8.0 * et * (std::f64::consts::FRAC_PI_2 * k as f64 * dt).sin())
                .collect();
            let s = uniaxial(ConcreteIntegration::Implex, &xs, &vec![dt; n]);
            xs.iter()
                .zip(&s)
                .map(|(x, s)| (s - closed_form(*x)).abs())
                .fold(0.0, f64::max)
                / FT
        };
        let e: Vec<f64> = [50, 100, 200, 400].into_iter().map(err).collect();
        let ratios: Vec<f64> = e.windows(2).map(|w| w[0] / w[1]).collect();
        eprintln!("IMPL-EX largest error / ft at N = 50, 100, 200, 400: {e:?}, ratios {ratios:?}");
        for r in &ratios {
            assert!((1.6..2.5).contains(r), "errors {e:?}, ratios {ratios:?}");
        }
        assert!(e[3] < 0.05, "errors {e:?}");
    }

    /// The wall hand-off rule: crushing through the thickness loses the load path, a
    /// crushed cover layer (bending: top face at ε = −0.02, core at 0) or cracking does not.
    #[test]
    fn load_path_is_lost_only_when_crushed_through_the_thickness() {
        // A path of 20 committed steps to `e` (section strains).
        let push = |e: [f64; 8]| {
            let mut s = wall();
            for k in 1..=20 {
                let f = k as f64 / 20.0;
                s.set_trial(&Vec8::from_iterator(e.iter().map(|x| x * f)));
                s.commit_state();
            }
            s
        };
        // Uniform ε11 = −0.05: every layer crushed (d⁻ → 1; at −0.02 it is 0.87).
        let s = push([-0.05, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(s.load_path_lost());
        // ε = e − zκ: κ11 = 1.25 1/m gives +0.05 at z = −0.04 (cracked), 0 in the core and
        // −0.05 at z = +0.04 (crushed cover).
        let s = push([0.0, 0.0, 0.0, 1.25, 0.0, 0.0, 0.0, 0.0]);
        assert!(s.damage().1, "the cover layer is crushed");
        assert!(!s.load_path_lost());
    }
}

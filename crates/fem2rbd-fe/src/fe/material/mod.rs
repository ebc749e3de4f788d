//! Uniaxial materials with OpenSees' laws, parameter meanings and trial/commit protocol.
//! Sign convention as in OpenSees: tension positive, compression negative.
//!
//! One file per law: [`elastic`], [`steel01`], [`steel02`], [`concrete01`],
//! [`concrete02`]. [`build`] makes any of them from its OpenSees type name and
//! OpenSees parameter names.
//!
//! Every law reproduces the corresponding OpenSees class branch for branch (checked
//! against openseespy 3.7.1 on cyclic strain histories by `crates/fem2rbd-fe/tests/it/fe/material/opensees.rs`).
//! The few deliberate differences are documented on the type: parameters of the wrong
//! sign are rejected instead of silently flipped, a trial at the committed strain returns
//! the committed state, and Steel01/Steel02 accept an optional rupture strain.
//!
//! References:
//! - Kent, D. C. & Park, R. (1971). Flexural members with confined concrete. J. Struct.
//!   Div. ASCE 97(ST7), 1969–1990.
//! - Scott, B. D., Park, R. & Priestley, M. J. N. (1982). Stress–strain behavior of
//!   concrete confined by overlapping hoops at low and high strain rates. ACI J. 79(1).
//! - Karsan, I. D. & Jirsa, J. O. (1969). Behavior of concrete under compressive
//!   loadings. J. Struct. Div. ASCE 95(ST12).
//! - Yassin, M. H. M. (1994). Nonlinear analysis of prestressed concrete structures under
//!   monotonic and cyclic loads. PhD thesis, University of California, Berkeley.
//! - Menegotto, M. & Pinto, P. E. (1973). Method of analysis for cyclically loaded R.C.
//!   plane frames including changes in geometry and non-elastic behaviour of elements
//!   under combined normal force and bending. IABSE Symposium, Lisbon.
//! - Filippou, F. C., Popov, E. P. & Bertero, V. V. (1983). Effects of bond deterioration
//!   on hysteretic behavior of reinforced concrete joints. Report EERC 83/19, UC Berkeley.
//! - OpenSees source, `SRC/material/uniaxial/{ElasticMaterial,Steel01,Steel02,Concrete01,
//!   Concrete02}.cpp`, and the OpenSees command manual.

pub mod concrete01;
pub mod concrete02;
pub mod elastic;
pub mod steel01;
pub mod steel02;

pub use concrete01::Concrete01;
pub use concrete02::{Concrete02, Concrete02Params};
pub use elastic::Elastic;
pub use steel01::{Steel01, Steel01Params};
pub use steel02::{Steel02, Steel02Params};

use std::collections::{BTreeMap, BTreeSet};

/// Damage flags a material reports, used by the collapse criteria and the hand-off.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MaterialDamage {
    /// Steel has yielded / concrete has passed its peak compressive strength at least once.
    pub yielded: bool,
    /// Steel has ruptured / concrete is crushed to its residual strength.
    pub ruptured: bool,
}

/// A uniaxial stress–strain law (strain in –, stress and moduli in Pa).
///
/// Protocol (as OpenSees `UniaxialMaterial`): [`set_trial_strain`](Self::set_trial_strain)
/// any number of times, then either [`commit_state`](Self::commit_state) when the global
/// step converged or [`revert_to_last_commit`](Self::revert_to_last_commit) when it failed.
pub trait UniaxialMaterial: std::fmt::Debug + Send + Sync {
    /// Sets the trial strain and updates the trial stress and tangent from the last
    /// committed state.
    fn set_trial_strain(&mut self, strain: f64);
    /// [`Self::set_trial_strain`], then the trial stress and tangent `(σ, E_t)` (Pa):
    /// one dynamic call per fibre in the section's hot loop instead of three (the default
    /// is compiled for each law, so its three calls are static).
    fn set_trial_strain_response(&mut self, strain: f64) -> (f64, f64) {
        self.set_trial_strain(strain);
        (self.stress(), self.tangent())
    }
    /// Trial strain (–).
    fn strain(&self) -> f64;
    /// Trial stress (Pa).
    fn stress(&self) -> f64;
    /// Trial tangent modulus dσ/dε (Pa).
    fn tangent(&self) -> f64;
    /// Initial tangent modulus (Pa).
    fn initial_tangent(&self) -> f64;
    /// Accepts the trial state as the new committed state.
    fn commit_state(&mut self);
    /// Discards the trial state.
    fn revert_to_last_commit(&mut self);
    /// Returns to the virgin state.
    fn revert_to_start(&mut self);
    /// A boxed copy (each fiber owns its own material state).
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial>;
    /// Damage reached so far (committed history).
    fn damage(&self) -> MaterialDamage {
        MaterialDamage::default()
    }
}

/// A uniaxial material that cannot be built: unknown type, a missing, repeated, unknown
/// or non-finite parameter, or a value outside the law's range. Messages name the law and
/// the parameter.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// A value outside its law's range, e.g. "Steel02: Fy must be > 0 (Pa), got -1".
    #[error("{0}")]
    Parameter(String),
    /// Not one of the known laws.
    #[error(
        "unknown uniaxial material type '{0}' (known: Elastic, Steel01, Steel02, \
         Concrete01, Concrete02)"
    )]
    UnknownType(String),
    /// A parameter given under two of its names.
    #[error("{law}: parameter '{name}' given twice (as '{first}' and '{second}')")]
    Repeated {
        /// The law.
        law: String,
        /// Canonical parameter name.
        name: String,
        /// First name used.
        first: String,
        /// Second name used.
        second: String,
    },
    /// A parameter that is NaN or infinite.
    #[error("{law}: parameter '{name}' is not finite ({value})")]
    NotFinite {
        /// The law.
        law: String,
        /// Parameter name as given.
        name: String,
        /// The value.
        value: f64,
    },
    /// A required parameter absent.
    #[error("{law}: missing parameter '{name}'")]
    Missing {
        /// The law.
        law: String,
        /// Canonical parameter name.
        name: String,
    },
    /// Part of a group of parameters that go together.
    #[error("{law}: parameters {} go together; missing {}", group.join(", "), missing.join(", "))]
    PartialGroup {
        /// The law.
        law: String,
        /// The group.
        group: Vec<String>,
        /// The ones not given.
        missing: Vec<String>,
    },
    /// Parameter names the law does not know.
    #[error("{law}: unknown parameter(s) {}", names.join(", "))]
    UnknownParameters {
        /// The law.
        law: String,
        /// The unknown names.
        names: Vec<String>,
    },
}

/// Builds a material from its OpenSees type name and a map of OpenSees parameter names
/// to values (SI units: Pa for stresses and moduli).
///
/// | `kind`       | required                      | optional (all of a group or none)                    |
/// |--------------|-------------------------------|------------------------------------------------------|
/// | `Elastic`    | `E`                           | `eta` (ignored, rate independent), `Eneg` (default E) |
/// | `Steel01`    | `Fy`, `E0`, `b`               | {`a1`,`a2`,`a3`,`a4`}; `eps_rupture`                 |
/// | `Steel02`    | `Fy`, `E0`, `b`               | {`R0`,`cR1`,`cR2`}; {`a1`,`a2`,`a3`,`a4`}; `sigInit`; `eps_rupture` |
/// | `Concrete01` | `fpc`, `epsc0`, `fpcu`, `epscu` |                                                    |
/// | `Concrete02` | `fpc`, `epsc0`, `fpcu`, `epscu` | {`lambda`,`ft`,`Ets`}                              |
///
/// Aliases: `epscU` for `epscu`, `fy` for `Fy`, `sig0` for `sigInit`. Omitted groups take
/// OpenSees' defaults. `eps_rupture` is a fem2rbd extension (tensile rupture strain).
/// Unknown or duplicated names, missing or partial groups and invalid values are errors.
pub fn build(
    kind: &str,
    params: &BTreeMap<String, f64>,
) -> Result<Box<dyn UniaxialMaterial>, MaterialError> {
    let mut r = ParamReader::new(kind, params);
    let m: Box<dyn UniaxialMaterial> = match kind {
        "Elastic" => {
            let e = r.req(&["E"])?;
            r.opt(&["eta"])?;
            let e_neg = r.opt(&["Eneg"])?.unwrap_or(e);
            r.finish()?;
            Box::new(Elastic::new(e, e_neg)?)
        }
        "Steel01" => {
            let mut p = Steel01Params::new(r.req(&["Fy", "fy"])?, r.req(&["E0"])?, r.req(&["b"])?);
            if let Some([a1, a2, a3, a4]) = r.group(&[&["a1"], &["a2"], &["a3"], &["a4"]])? {
                (p.a1, p.a2, p.a3, p.a4) = (a1, a2, a3, a4);
            }
            p.eps_rupture = r.opt(&["eps_rupture"])?;
            r.finish()?;
            Box::new(Steel01::new(p)?)
        }
        "Steel02" => {
            let mut p = Steel02Params::new(r.req(&["Fy", "fy"])?, r.req(&["E0"])?, r.req(&["b"])?);
            if let Some([r0, c1, c2]) = r.group(&[&["R0"], &["cR1"], &["cR2"]])? {
                (p.r0, p.c_r1, p.c_r2) = (r0, c1, c2);
            }
            if let Some([a1, a2, a3, a4]) = r.group(&[&["a1"], &["a2"], &["a3"], &["a4"]])? {
                (p.a1, p.a2, p.a3, p.a4) = (a1, a2, a3, a4);
            }
            if let Some(s) = r.opt(&["sigInit", "sig0"])? {
                p.sig_init = s;
            }
            p.eps_rupture = r.opt(&["eps_rupture"])?;
            r.finish()?;
            Box::new(Steel02::new(p)?)
        }
        "Concrete01" => {
            let fpc = r.req(&["fpc"])?;
            let epsc0 = r.req(&["epsc0"])?;
            let fpcu = r.req(&["fpcu"])?;
            let epscu = r.req(&["epscu", "epscU"])?;
            r.finish()?;
            Box::new(Concrete01::new(fpc, epsc0, fpcu, epscu)?)
        }
        "Concrete02" => {
            let mut p = Concrete02Params::new(
                r.req(&["fpc"])?,
                r.req(&["epsc0"])?,
                r.req(&["fpcu"])?,
                r.req(&["epscu", "epscU"])?,
            );
            if let Some([l, ft, ets]) = r.group(&[&["lambda"], &["ft"], &["Ets"]])? {
                (p.lambda, p.ft, p.ets) = (l, ft, ets);
            }
            r.finish()?;
            Box::new(Concrete02::new(p)?)
        }
        other => return Err(MaterialError::UnknownType(other.to_string())),
    };
    Ok(m)
}

/// Reads named parameters for `build`, remembering which were used.
struct ParamReader<'a> {
    kind: &'a str,
    map: &'a BTreeMap<String, f64>,
    used: BTreeSet<&'a str>,
}

impl<'a> ParamReader<'a> {
    fn new(kind: &'a str, map: &'a BTreeMap<String, f64>) -> Self {
        Self {
            kind,
            map,
            used: BTreeSet::new(),
        }
    }

    /// The value under the first of `names` (a canonical name and its aliases) present.
    fn opt(&mut self, names: &[&str]) -> Result<Option<f64>, MaterialError> {
        let mut found: Option<(&'a str, f64)> = None;
        for (k, v) in self.map {
            if names.contains(&k.as_str()) {
                if let Some((prev, _)) = found {
                    return Err(MaterialError::Repeated {
                        law: self.kind.to_string(),
                        name: names[0].to_string(),
                        first: prev.to_string(),
                        second: k.clone(),
                    });
                }
                found = Some((k.as_str(), *v));
            }
        }
        match found {
            None => Ok(None),
            Some((k, v)) => {
                self.used.insert(k);
                if !v.is_finite() {
                    return Err(MaterialError::NotFinite {
                        law: self.kind.to_string(),
                        name: k.to_string(),
                        value: v,
                    });
                }
                Ok(Some(v))
            }
        }
    }

    fn req(&mut self, names: &[&str]) -> Result<f64, MaterialError> {
        self.opt(names)?.ok_or_else(|| MaterialError::Missing {
            law: self.kind.to_string(),
            name: names[0].to_string(),
        })
    }

    /// All parameters of a group, or none of them.
    fn group<const N: usize>(
        &mut self,
        names: &[&[&str]; N],
    ) -> Result<Option<[f64; N]>, MaterialError> {
        let mut vals = [0.0; N];
        let mut missing = Vec::new();
        for (i, n) in names.iter().enumerate() {
            match self.opt(n)? {
                Some(v) => vals[i] = v,
                None => missing.push(n[0]),
            }
        }
        if missing.is_empty() {
            Ok(Some(vals))
        } else if missing.len() == N {
            Ok(None)
        } else {
            Err(MaterialError::PartialGroup {
                law: self.kind.to_string(),
                group: names.iter().map(|n| n[0].to_string()).collect(),
                missing: missing.iter().map(|n| n.to_string()).collect(),
            })
        }
    }

    /// Errors on any parameter name that was not read.
    fn finish(self) -> Result<(), MaterialError> {
        let unknown: Vec<&str> = self
            .map
            .keys()
            .map(String::as_str)
            .filter(|k| !self.used.contains(k))
            .collect();
        if unknown.is_empty() {
            Ok(())
        } else {
            Err(MaterialError::UnknownParameters {
                law: self.kind.to_string(),
                names: unknown.iter().map(|n| n.to_string()).collect(),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(kv: &[(&str, f64)]) -> BTreeMap<String, f64> {
        kv.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    #[test]
    fn builds_each_kind_from_opensees_names() {
        let m = build("Elastic", &map(&[("E", 2e11), ("Eneg", 1e11)])).unwrap();
        assert_eq!(m.initial_tangent(), 2e11);
        let steel = [("Fy", 4e8), ("E0", 2e11), ("b", 0.01)];
        assert_eq!(
            build("Steel01", &map(&steel)).unwrap().initial_tangent(),
            2e11
        );
        let mut s2 = steel.to_vec();
        s2.extend([("R0", 18.0), ("cR1", 0.925), ("cR2", 0.15)]);
        assert_eq!(build("Steel02", &map(&s2)).unwrap().initial_tangent(), 2e11);
        let c = [
            ("fpc", -30e6),
            ("epsc0", -0.002),
            ("fpcu", -6e6),
            ("epscU", -0.006),
        ];
        assert_eq!(
            build("Concrete01", &map(&c)).unwrap().initial_tangent(),
            3e10
        );
        let mut c2 = c.to_vec();
        c2.extend([("lambda", 0.1), ("ft", 3e6), ("Ets", 1.5e9)]);
        assert_eq!(
            build("Concrete02", &map(&c2)).unwrap().initial_tangent(),
            3e10
        );
        assert_eq!(
            build("Concrete02", &map(&c)).unwrap().initial_tangent(),
            3e10
        );
    }

    #[test]
    fn clear_errors() {
        let e = build("Steel03", &map(&[])).unwrap_err();
        assert!(
            matches!(&e, MaterialError::UnknownType(t) if t == "Steel03"),
            "{e}"
        );
        assert!(
            e.to_string()
                .contains("unknown uniaxial material type 'Steel03'"),
            "{e}"
        );
        let e = build("Steel02", &map(&[("Fy", 4e8), ("E0", 2e11)])).unwrap_err();
        assert!(
            matches!(&e, MaterialError::Missing { name, .. } if name == "b"),
            "{e}"
        );
        let e = build(
            "Steel02",
            &map(&[("Fy", 4e8), ("E0", 2e11), ("b", 0.01), ("R0", 18.0)]),
        )
        .unwrap_err();
        assert!(
            matches!(&e, MaterialError::PartialGroup { missing, .. } if missing == &["cR1", "cR2"]),
            "{e}"
        );
        let e = build("Elastic", &map(&[("E", 2e11), ("Fy", 1.0)])).unwrap_err();
        assert!(
            matches!(&e, MaterialError::UnknownParameters { names, .. } if names == &["Fy"]),
            "{e}"
        );
        let e = build(
            "Concrete01",
            &map(&[
                ("fpc", -3e7),
                ("epsc0", -0.002),
                ("fpcu", 0.0),
                ("epscu", -0.004),
                ("epscU", -0.004),
            ]),
        )
        .unwrap_err();
        assert!(
            matches!(&e, MaterialError::Repeated { name, .. } if name == "epscu"),
            "{e}"
        );
        let e = build(
            "Concrete01",
            &map(&[
                ("fpc", 3e7),
                ("epsc0", -0.002),
                ("fpcu", 0.0),
                ("epscu", -0.004),
            ]),
        )
        .unwrap_err();
        assert!(
            matches!(&e, MaterialError::Parameter(m) if m.contains("fpc must be < 0")),
            "{e}"
        );
    }
}

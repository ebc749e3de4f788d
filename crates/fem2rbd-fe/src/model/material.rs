//! Uniaxial materials of the model file, with OpenSees' parameter names and meanings
//! (OpenSees command manual, `uniaxialMaterial Elastic | Concrete01 | Concrete02 |
//! Steel01 | Steel02`). Stresses in Pa, strains dimensionless, density in kg/m³.
//! Compression is negative for the concrete laws, as in OpenSees.
use super::InvalidValue;
use serde::{Deserialize, Serialize};

/// One uniaxial material: a tag, an optional name, a mass density and the law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Unique material tag (referenced by fibers and RC sections).
    pub tag: u32,
    /// Optional human name, e.g. "core_F1".
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub name: String,
    /// Mass density ρ (kg/m³) used for element self-weight (ρ × area per unit length).
    /// Default 0 (no self-weight).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub density: f64,
    /// The stress-strain law and its parameters.
    #[serde(flatten)]
    pub law: MaterialLaw,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// The uniaxial laws; the `type` key selects one. Field names are OpenSees' argument names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", deny_unknown_fields)]
pub enum MaterialLaw {
    /// Linear elastic: σ = E ε (`uniaxialMaterial Elastic tag E <eta> <Eneg>`).
    Elastic {
        /// Young's modulus E (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Damping tangent η (Pa·s); default 0.
        #[serde(default)]
        eta: f64,
        /// Modulus in compression (Pa); default = E.
        #[serde(rename = "Eneg", default, skip_serializing_if = "Option::is_none")]
        e_neg: Option<f64>,
    },
    /// Kent-Scott-Park concrete, no tension (`Concrete01 fpc epsc0 fpcu epscU`).
    Concrete01 {
        /// Compressive strength f'c (Pa, negative).
        fpc: f64,
        /// Strain at f'c (negative).
        epsc0: f64,
        /// Crushing (residual) strength (Pa, negative).
        fpcu: f64,
        /// Strain at crushing strength (negative).
        #[serde(rename = "epscU")]
        epscu: f64,
    },
    /// Concrete with linear tension softening
    /// (`Concrete02 fpc epsc0 fpcu epscu lambda ft Ets`). Initial tangent = 2 fpc/epsc0.
    Concrete02 {
        /// Compressive strength (Pa, negative).
        fpc: f64,
        /// Strain at compressive strength (negative).
        epsc0: f64,
        /// Crushing strength (Pa, negative).
        fpcu: f64,
        /// Strain at crushing strength (negative).
        epscu: f64,
        /// Ratio of unloading slope at epscu to the initial slope.
        lambda: f64,
        /// Tensile strength (Pa, positive).
        ft: f64,
        /// Tension softening stiffness (Pa, positive).
        #[serde(rename = "Ets")]
        ets: f64,
    },
    /// Bilinear steel with kinematic hardening (`Steel01 Fy E0 b`).
    Steel01 {
        /// Yield strength (Pa).
        #[serde(rename = "Fy")]
        fy: f64,
        /// Initial elastic tangent (Pa).
        #[serde(rename = "E0")]
        e0: f64,
        /// Strain-hardening ratio (post-yield / initial tangent).
        b: f64,
    },
    /// Giuffré-Menegotto-Pinto steel (`Steel02 Fy E0 b R0 cR1 cR2 <a1 a2 a3 a4>`).
    Steel02 {
        /// Yield strength (Pa).
        #[serde(rename = "Fy")]
        fy: f64,
        /// Initial elastic tangent (Pa).
        #[serde(rename = "E0")]
        e0: f64,
        /// Strain-hardening ratio.
        b: f64,
        /// Transition-curve parameter R0 (10..20 typical).
        #[serde(rename = "R0")]
        r0: f64,
        /// cR1 (0.925 typical).
        #[serde(rename = "cR1")]
        cr1: f64,
        /// cR2 (0.15 typical).
        #[serde(rename = "cR2")]
        cr2: f64,
        /// Isotropic hardening parameters a1..a4 (all four or none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        a: Option<[f64; 4]>,
    },
}

impl Material {
    /// The law's name as in the file (`"Concrete02"`, ...).
    pub fn type_name(&self) -> &'static str {
        match self.law {
            MaterialLaw::Elastic { .. } => "Elastic",
            MaterialLaw::Concrete01 { .. } => "Concrete01",
            MaterialLaw::Concrete02 { .. } => "Concrete02",
            MaterialLaw::Steel01 { .. } => "Steel01",
            MaterialLaw::Steel02 { .. } => "Steel02",
        }
    }

    /// Initial tangent modulus (Pa): E, 2·fpc/epsc0 for the concrete laws (OpenSees
    /// Concrete01/02 source: `Ec0 = 2 fpc / epsc0`), E0 for steel.
    pub fn initial_tangent(&self) -> f64 {
        match self.law {
            MaterialLaw::Elastic { e, .. } => e,
            MaterialLaw::Concrete01 { fpc, epsc0, .. } => 2.0 * fpc / epsc0,
            MaterialLaw::Concrete02 { fpc, epsc0, .. } => 2.0 * fpc / epsc0,
            MaterialLaw::Steel01 { e0, .. } => e0,
            MaterialLaw::Steel02 { e0, .. } => e0,
        }
    }

    /// All parameters with their names, for validation and export (in OpenSees order).
    pub fn parameters(&self) -> Vec<(&'static str, f64)> {
        let mut p = match &self.law {
            MaterialLaw::Elastic { e, eta, e_neg } => {
                let mut v = vec![("E", *e), ("eta", *eta)];
                if let Some(en) = e_neg {
                    v.push(("Eneg", *en));
                }
                v
            }
            MaterialLaw::Concrete01 {
                fpc,
                epsc0,
                fpcu,
                epscu,
            } => vec![
                ("fpc", *fpc),
                ("epsc0", *epsc0),
                ("fpcu", *fpcu),
                ("epscU", *epscu),
            ],
            MaterialLaw::Concrete02 {
                fpc,
                epsc0,
                fpcu,
                epscu,
                lambda,
                ft,
                ets,
            } => vec![
                ("fpc", *fpc),
                ("epsc0", *epsc0),
                ("fpcu", *fpcu),
                ("epscu", *epscu),
                ("lambda", *lambda),
                ("ft", *ft),
                ("Ets", *ets),
            ],
            MaterialLaw::Steel01 { fy, e0, b } => vec![("Fy", *fy), ("E0", *e0), ("b", *b)],
            MaterialLaw::Steel02 {
                fy,
                e0,
                b,
                r0,
                cr1,
                cr2,
                a,
            } => {
                let mut v = vec![
                    ("Fy", *fy),
                    ("E0", *e0),
                    ("b", *b),
                    ("R0", *r0),
                    ("cR1", *cr1),
                    ("cR2", *cr2),
                ];
                if let Some(a) = a {
                    v.extend([("a1", a[0]), ("a2", a[1]), ("a3", a[2]), ("a4", a[3])]);
                }
                v
            }
        };
        p.push(("density", self.density));
        p
    }

    /// Checks signs and ranges; returns a message for the first violation.
    pub fn check(&self) -> Result<(), InvalidValue> {
        for (name, v) in self.parameters() {
            if !v.is_finite() {
                return Err(InvalidValue(format!(
                    "parameter {name} is not finite ({v})"
                )));
            }
        }
        if self.density < 0.0 {
            return Err(InvalidValue(format!(
                "density {} kg/m3 is negative",
                self.density
            )));
        }
        let neg = |name: &str, v: f64| -> Result<(), InvalidValue> {
            if v < 0.0 {
                Ok(())
            } else {
                Err(InvalidValue(format!(
                    "{name} = {v} must be negative (compression is negative)"
                )))
            }
        };
        let pos = |name: &str, v: f64| -> Result<(), InvalidValue> {
            if v > 0.0 {
                Ok(())
            } else {
                Err(InvalidValue(format!("{name} = {v} must be positive")))
            }
        };
        match &self.law {
            MaterialLaw::Elastic { e, eta, e_neg } => {
                pos("E", *e)?;
                if *eta < 0.0 {
                    return Err(InvalidValue(format!("eta = {eta} must not be negative")));
                }
                if let Some(en) = e_neg {
                    pos("Eneg", *en)?;
                }
            }
            MaterialLaw::Concrete01 {
                fpc,
                epsc0,
                fpcu,
                epscu,
            } => {
                neg("fpc", *fpc)?;
                neg("epsc0", *epsc0)?;
                if *fpcu > 0.0 {
                    return Err(InvalidValue(format!("fpcu = {fpcu} must not be positive")));
                }
                neg("epscU", *epscu)?;
            }
            MaterialLaw::Concrete02 {
                fpc,
                epsc0,
                fpcu,
                epscu,
                lambda,
                ft,
                ets,
            } => {
                neg("fpc", *fpc)?;
                neg("epsc0", *epsc0)?;
                if *fpcu > 0.0 {
                    return Err(InvalidValue(format!("fpcu = {fpcu} must not be positive")));
                }
                neg("epscu", *epscu)?;
                if !(0.0..=1.0).contains(lambda) {
                    return Err(InvalidValue(format!("lambda = {lambda} must be in [0, 1]")));
                }
                if *ft < 0.0 {
                    return Err(InvalidValue(format!("ft = {ft} must not be negative")));
                }
                pos("Ets", *ets)?;
            }
            MaterialLaw::Steel01 { fy, e0, b } | MaterialLaw::Steel02 { fy, e0, b, .. } => {
                pos("Fy", *fy)?;
                pos("E0", *e0)?;
                if !(0.0..1.0).contains(b) {
                    return Err(InvalidValue(format!("b = {b} must be in [0, 1)")));
                }
            }
        }
        if let MaterialLaw::Steel02 { r0, .. } = &self.law {
            pos("R0", *r0)?;
        }
        Ok(())
    }
}

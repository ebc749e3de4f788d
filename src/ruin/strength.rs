//! Reinforced-concrete connection strengths: BCB's "Formula Assistant".
//!
//! Source: Bullet Constraints Builder (BCB, K. Kostack), `global_vars.py`
//! (`formulaAssistants`, ids `con_rei_beam` and `con_rei_wall`) and `formula.py`
//! (`combineExpressions`), read at HEAD 8972ecf and checked against the 2020 version;
//! written up in `docs/bcb.md` §3.2. Re-implemented here, not copied.
//!
//! Inputs are in BCB's units: lengths in **mm**, stresses in **N/mm²** (MPa), densities in
//! kg/m³. The section capacities of a reference section `h × w` are
//!
//! * ρ  = n·π·(dl/2)² / (h·w)                          (longitudinal reinforcement ratio)
//! * d  = h − c − dl/2 (beams/columns) or h/2 (walls/slabs)
//! * y  = [2·π·(ds/2)²/100 · 1000/s] · 10/d             (stirrup ratio as a "%" number)
//! * e1 = (h − 2c − dl)/h
//! * N⁻ = (fc(1−ρ) + fs·ρ)·h·w                          compression, N
//! * N⁺ = fs·ρ·h·w                                      tension, N
//! * V  = fs·y·e1·h²·1.2 (beams) or 0.15·k·(100·ρ·fc)^(1/3)·h·w (walls), N
//! * M  = (fc(1−ρ) + 4.5·fs·ρ·e1)·h²·w/12/1000          bending, N·m
//! * Sp = fsu·ρ·h·w/4                                   plastic (spring) capacity, N
//!
//! and every capacity is divided by h·w to give a strength **per mm² of contact area**.
//! The "90°" values S90 and B90 are the same formulas with h and w swapped.
//!
//! **Flagged, reproduced faithfully:** the beam shear formula uses the stirrup ratio y as a
//! percentage number, which with BCB's defaults gives 201 N/mm² of shear strength — far
//! above the concrete's compressive strength (34.9 N/mm²). We keep it because it is the
//! model the paper ran; a user who distrusts it can give per-area strengths directly
//! ([`StrengthSource::PerArea`]).
//!
//! Differences from BCB, all below the printed precision of BCB's own numbers:
//! BCB builds the per-mm² values as text, rounding every number to 4 decimals on the way;
//! we evaluate in `f64`. BCB's formulas use `pi = 3.1416`; so do we ([`FA_PI`]).

use serde::{Deserialize, Serialize};

/// The value of π that BCB's Formula Assistant uses (`global_vars.py`: `pi = 3.1416`),
/// deliberately not `std::f64::consts::PI`.
#[allow(clippy::approx_constant)]
pub const FA_PI: f64 = 3.1416;

/// Which Formula Assistant: beams & columns (`con_rei_beam`) or walls & slabs
/// (`con_rei_wall`). They differ only in the effective depth d and the shear formula.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FormulaKind {
    /// `con_rei_beam`: d = h − c − dl/2, V = fs·y·e1·h²·1.2.
    BeamColumn,
    /// `con_rei_wall`: d = h/2, V = 0.15·k·(100·ρ·fc)^(1/3)·h·w.
    WallSlab,
}

/// The Formula Assistant's inputs, with BCB's defaults (both assistants share them).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FormulaInputs {
    /// Which formula set.
    pub kind: FormulaKind,
    /// Reference section height h, mm (default 250). 0 = use the contact's h.
    pub h_mm: f64,
    /// Reference section width w, mm (default 150). 0 = use the contact's w.
    pub w_mm: f64,
    /// Concrete compressive strength fc, N/mm² (30).
    pub fc: f64,
    /// Steel yield strength fs, N/mm² (500).
    pub fs: f64,
    /// Steel ultimate strength fsu, N/mm² (650).
    pub fsu: f64,
    /// Steel ultimate elongation elu, % (12).
    pub elu: f64,
    /// Concrete density, kg/m³ (2400).
    pub densc: f64,
    /// Steel density, kg/m³ (7800).
    pub denss: f64,
    /// Concrete cover c, mm (20).
    pub c: f64,
    /// Stirrup spacing s, mm (100).
    pub s: f64,
    /// Stirrup bar diameter ds, mm (6).
    pub ds: f64,
    /// Longitudinal bar diameter dl, mm (10).
    pub dl: f64,
    /// Number of longitudinal bars n (5).
    pub n: f64,
    /// Shear coefficient k of the wall formula (1.9).
    pub k: f64,
}

impl Default for FormulaInputs {
    fn default() -> Self {
        FormulaInputs {
            kind: FormulaKind::BeamColumn,
            h_mm: 250.0,
            w_mm: 150.0,
            fc: 30.0,
            fs: 500.0,
            fsu: 650.0,
            elu: 12.0,
            densc: 2400.0,
            denss: 7800.0,
            c: 20.0,
            s: 100.0,
            ds: 6.0,
            dl: 10.0,
            n: 5.0,
            k: 1.9,
        }
    }
}

/// Capacities of one section (not per area): N⁻, N⁺, V, Sp in N and M in N·m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionCapacities {
    /// Compression N⁻, N.
    pub compression_n: f64,
    /// Tension N⁺, N.
    pub tension_n: f64,
    /// Shear V, N.
    pub shear_n: f64,
    /// Bending M, N·m.
    pub bending_nm: f64,
    /// Plastic (spring) capacity Sp, N.
    pub plastic_n: f64,
}

/// Strengths per mm² of contact area, as BCB's element-group strings hold them:
/// C, T, S, S90, P in N/mm², B, B90 in N·m/mm².
/// `s90`/`b90` are `None` where BCB leaves the 90° string empty (swapped section gives the
/// same value); `p` is `None` where there is no plastic value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrengthPerArea {
    /// Compressive strength C, N/mm².
    pub c: f64,
    /// Tensile strength T, N/mm².
    pub t: f64,
    /// Shear strength S, N/mm².
    pub s: f64,
    /// Shear strength with h and w swapped, N/mm².
    #[serde(default)]
    pub s90: Option<f64>,
    /// Bending strength B, N·m/mm².
    pub b: f64,
    /// Bending strength with h and w swapped, N·m/mm².
    #[serde(default)]
    pub b90: Option<f64>,
    /// Plastic (spring) strength P, N/mm².
    #[serde(default)]
    pub p: Option<f64>,
}

impl StrengthPerArea {
    /// BCB's default element-group preset ("" / "RC Columns", docs/bcb.md §8):
    /// 35 / 5.2 / 155 / 1.0 / 1.3, no 90° values.
    pub fn bcb_default_preset() -> Self {
        StrengthPerArea {
            c: 35.0,
            t: 5.2,
            s: 155.0,
            s90: None,
            b: 1.0,
            b90: None,
            p: Some(1.3),
        }
    }
}

impl FormulaInputs {
    /// Longitudinal reinforcement ratio ρ = n·π·(dl/2)²/(h·w) for a section h × w (mm).
    pub fn rho(&self, h_mm: f64, w_mm: f64) -> f64 {
        (self.dl / 2.0).powi(2) * FA_PI * self.n / (h_mm * w_mm)
    }

    /// Section capacities of an h × w section (mm), BCB's formulas (module docs).
    pub fn section_capacities(&self, h: f64, w: f64) -> SectionCapacities {
        let rho = self.rho(h, w);
        let d = match self.kind {
            FormulaKind::BeamColumn => h - self.c - self.dl / 2.0,
            FormulaKind::WallSlab => h / 2.0,
        };
        // Stirrup ratio as a percentage number (BCB's "Exp:y").
        let y = ((self.ds / 2.0).powi(2) * FA_PI * 2.0 / 100.0 * 1000.0 / self.s) * 10.0 / d;
        let e1 = (h - 2.0 * self.c - self.dl) / h;
        let area = h * w;
        let compression_n = (self.fc * (1.0 - rho) + self.fs * rho) * area;
        let tension_n = self.fs * rho * area;
        let shear_n = match self.kind {
            FormulaKind::BeamColumn => self.fs * y * e1 * h * h * 1.2,
            FormulaKind::WallSlab => 0.15 * self.k * (100.0 * rho * self.fc).powf(1.0 / 3.0) * area,
        };
        let bending_nm =
            (self.fc * (1.0 - rho) + self.fs * rho * e1 * 4.5) * h * h * w / 12.0 / 1000.0;
        let plastic_n = self.fsu * rho * area / 4.0;
        SectionCapacities {
            compression_n,
            tension_n,
            shear_n,
            bending_nm,
            plastic_n,
        }
    }

    /// The per-mm² strengths ("Evaluate" in BCB). The section is the reference section
    /// (`h_mm`, `w_mm`); a zero dimension is replaced by the contact's dimension
    /// (`contact_h_mm`, `contact_w_mm`), as BCB keeps it symbolic and evaluates it per
    /// connection. S90/B90 come from the section with h and w swapped and are `None`
    /// when they equal S/B (BCB leaves the string empty then).
    pub fn per_area(&self, contact_h_mm: f64, contact_w_mm: f64) -> StrengthPerArea {
        let h = if self.h_mm == 0.0 {
            contact_h_mm
        } else {
            self.h_mm
        };
        let w = if self.w_mm == 0.0 {
            contact_w_mm
        } else {
            self.w_mm
        };
        let area = h * w;
        let cap = self.section_capacities(h, w);
        let cap90 = self.section_capacities(w, h);
        let s = cap.shear_n / area;
        let s90 = cap90.shear_n / area;
        let b = cap.bending_nm / area;
        let b90 = cap90.bending_nm / area;
        StrengthPerArea {
            c: cap.compression_n / area,
            t: cap.tension_n / area,
            s,
            s90: (s90 != s).then_some(s90),
            b,
            b90: (b90 != b).then_some(b90),
            p: Some(cap.plastic_n / area),
        }
    }

    /// Element density ρ·denss + (1−ρ)·densc, kg/m³ (BCB sets it on Evaluate). With a
    /// symbolic section (a zero dimension) BCB cannot evaluate it; we then use the
    /// given contact dimensions like [`Self::per_area`].
    pub fn density(&self, contact_h_mm: f64, contact_w_mm: f64) -> f64 {
        let h = if self.h_mm == 0.0 {
            contact_h_mm
        } else {
            self.h_mm
        };
        let w = if self.w_mm == 0.0 {
            contact_w_mm
        } else {
            self.w_mm
        };
        let rho = self.rho(h, w);
        rho * self.denss + (1.0 - rho) * self.densc
    }

    /// 2nd distance tolerance from the Formula Assistant: tol2D = elu/100 (docs/bcb.md §4).
    pub fn tol2_dist(&self) -> f64 {
        self.elu / 100.0
    }

    /// 2nd rotation tolerance from the Formula Assistant (docs/bcb.md §4, `builder_setc.py`):
    /// tol2R = atan((elu/100)·L / (h_contact/2)), L = centre distance in m, h in m.
    pub fn tol2_rot(&self, centre_distance_m: f64, contact_h_m: f64) -> f64 {
        ((self.elu / 100.0) * centre_distance_m / (contact_h_m / 2.0)).atan()
    }

    /// Checks that every input is finite and that the formulas are defined (positive
    /// section where given, positive spacing, etc.). The message names the field.
    pub fn validate(&self) -> Result<(), FormulaInputError> {
        let fields = [
            ("h", self.h_mm),
            ("w", self.w_mm),
            ("fc", self.fc),
            ("fs", self.fs),
            ("fsu", self.fsu),
            ("elu", self.elu),
            ("densc", self.densc),
            ("denss", self.denss),
            ("c", self.c),
            ("s", self.s),
            ("ds", self.ds),
            ("dl", self.dl),
            ("n", self.n),
            ("k", self.k),
        ];
        for (name, v) in fields {
            if !v.is_finite() || v < 0.0 {
                return Err(FormulaInputError::Negative {
                    field: name,
                    value: v,
                });
            }
        }
        if self.s <= 0.0 {
            return Err(FormulaInputError::Spacing);
        }
        if self.h_mm > 0.0 && self.h_mm <= 2.0 * self.c + self.dl {
            return Err(FormulaInputError::NoCore {
                field: "h",
                value: self.h_mm,
                min: 2.0 * self.c + self.dl,
            });
        }
        if self.w_mm > 0.0 && self.w_mm <= 2.0 * self.c + self.dl {
            return Err(FormulaInputError::NoCore {
                field: "w",
                value: self.w_mm,
                min: 2.0 * self.c + self.dl,
            });
        }
        Ok(())
    }
}

/// A Formula Assistant input that makes the formulas undefined (the field named).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FormulaInputError {
    /// An input is not finite or negative.
    #[error("formula input {field} = {value} must be finite and >= 0")]
    Negative {
        /// The input's name (`h`, `fc`, …).
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The stirrup spacing is zero.
    #[error("formula input s (stirrup spacing) must be > 0")]
    Spacing,
    /// The section leaves no core inside the covers and bars.
    #[error(
        "formula input {field} = {value} mm leaves no core: it must exceed 2·c + dl = {min} mm"
    )]
    NoCore {
        /// `h` or `w`.
        field: &'static str,
        /// Its value, mm.
        value: f64,
        /// 2·c + dl, mm.
        min: f64,
    },
}

/// Where a group's strengths come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrengthSource {
    /// BCB's Formula Assistant (sets CT 22 and the FA tolerances in BCB).
    Formula(FormulaInputs),
    /// Per-mm² strengths given directly (BCB's element-group strings as numbers).
    PerArea(StrengthPerArea),
}

impl StrengthSource {
    /// Per-mm² strengths for a contact of h × w mm.
    pub fn per_area(&self, contact_h_mm: f64, contact_w_mm: f64) -> StrengthPerArea {
        match self {
            StrengthSource::Formula(f) => f.per_area(contact_h_mm, contact_w_mm),
            StrengthSource::PerArea(p) => *p,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_to(x: f64, decimals: i32) -> f64 {
        let m = 10f64.powi(decimals);
        (x * m).round() / m
    }

    /// docs/bcb.md §3.2 table, beams/columns with BCB's defaults, at the printed precision.
    #[test]
    fn beam_column_table() {
        let f = FormulaInputs::default();
        let p = f.per_area(0.0, 0.0);
        assert_eq!(round_to(p.c, 2), 34.92);
        assert_eq!(round_to(p.t, 3), 5.236);
        assert_eq!(round_to(p.s, 2), 201.06);
        assert_eq!(round_to(p.s90.unwrap(), 2), 108.57);
        assert_eq!(round_to(p.b, 4), 1.0112);
        assert_eq!(round_to(p.b90.unwrap(), 4), 0.5674);
        assert_eq!(round_to(p.p.unwrap(), 4), 1.7017);
        assert_eq!(round_to(f.density(0.0, 0.0), 1), 2456.5);
    }

    /// Walls/slabs: same as beams except the shear 0.899 (and no 90° shear: symmetric).
    #[test]
    fn wall_slab_table() {
        let f = FormulaInputs {
            kind: FormulaKind::WallSlab,
            ..FormulaInputs::default()
        };
        let p = f.per_area(0.0, 0.0);
        assert_eq!(round_to(p.c, 2), 34.92);
        assert_eq!(round_to(p.t, 3), 5.236);
        assert_eq!(round_to(p.s, 3), 0.899);
        // The wall shear formula is symmetric in h and w: same value, BCB leaves S90 empty.
        assert!(p.s90.is_none() || round_to(p.s90.unwrap(), 3) == 0.899);
        assert_eq!(round_to(p.b, 4), 1.0112);
        assert_eq!(round_to(p.b90.unwrap(), 4), 0.5674);
        assert_eq!(round_to(p.p.unwrap(), 4), 1.7017);
        assert_eq!(round_to(f.density(0.0, 0.0), 1), 2456.5);
    }

    /// The beam shear: V = fs·y·e1·h²·1.2 by hand, y = 0.251327 "%" for d = 225 mm.
    #[test]
    fn beam_shear_by_hand() {
        let f = FormulaInputs::default();
        let cap = f.section_capacities(250.0, 150.0);
        let y = (9.0 * FA_PI * 2.0 / 100.0 * 10.0) * 10.0 / 225.0;
        assert!((y - 0.2513280).abs() < 1e-6);
        let v = 500.0 * y * 0.8 * 250.0 * 250.0 * 1.2;
        assert!((cap.shear_n - v).abs() < 1e-6 * v);
    }

    /// Symbolic section (h = w = 0): the contact dimensions are used, and a square
    /// contact has no distinct 90° values.
    #[test]
    fn symbolic_section_uses_contact() {
        let f = FormulaInputs {
            h_mm: 0.0,
            w_mm: 0.0,
            ..FormulaInputs::default()
        };
        let sym = f.per_area(250.0, 150.0);
        let fixed = FormulaInputs::default().per_area(0.0, 0.0);
        assert_eq!(sym, fixed);
        let sq = f.per_area(100.0, 100.0);
        assert!(sq.s90.is_none() && sq.b90.is_none());
    }

    /// tol2R from the FA: L = 3 m, h = 0.25 m → 1.237 rad (docs/bcb.md §4).
    #[test]
    fn formula_rotation_tolerance() {
        let f = FormulaInputs::default();
        assert_eq!(f.tol2_dist(), 0.12);
        assert_eq!(round_to(f.tol2_rot(3.0, 0.25), 3), 1.237);
    }

    #[test]
    fn validation_names_the_field() {
        let f = FormulaInputs {
            s: 0.0,
            ..FormulaInputs::default()
        };
        assert_eq!(f.validate(), Err(FormulaInputError::Spacing));
        let f = FormulaInputs {
            fc: f64::NAN,
            ..FormulaInputs::default()
        };
        assert!(matches!(
            f.validate(),
            Err(FormulaInputError::Negative { field: "fc", .. })
        ));
        let f = FormulaInputs {
            h_mm: 40.0,
            ..FormulaInputs::default()
        };
        let e = f.validate().unwrap_err();
        assert!(
            matches!(e, FormulaInputError::NoCore { field: "h", value, .. } if value == 40.0),
            "{e:?}"
        );
        // The message names the field and its value.
        assert!(e.to_string().contains("h = 40"), "{e}");
        assert!(FormulaInputs::default().validate().is_ok());
    }
}

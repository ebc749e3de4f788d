//! What a run found, measured from the bodies' poses: the ruin's footprint, extent, height,
//! floors and slab overlap at the end ([`ruin_measures`]), the moment the FE alone stops
//! describing the building and the floors' shape as they come down ([`first_contact`],
//! [`floors_down`]), the energy ledger's summary ([`energy_summary`]) and the bodies still
//! moving at the end ([`unsettled`], [`instantaneous_at_end`]). Each is returned as its part
//! of `summary.json` ([`crate::output::summary`], the schema), numbers rounded by
//! [`crate::output::summary::r6`]; plan areas come from [`crate::plan_geometry`].
//!
//! * the **original footprint** is the plan AABB of the undeformed active bodies;
//! * the **floors** are the slab bodies grouped by their undeformed centre height (mm);
//!   a floor's centroid is the mass-weighted mean of its slab centres;
//! * the **pancake measure** (paper §4: stacked vs offset slabs) of two consecutive
//!   floors is the area of the intersection of their final slab projections divided by
//!   the upper floor's undeformed slab area (1 = fully stacked, 0 = no overlap).
mod debris;
pub(crate) mod energy;
pub(crate) mod floors;
mod rest;

pub(crate) use debris::ruin_measures;
pub(crate) use energy::energy_summary;
pub(crate) use floors::{first_contact, floors_down};
pub(crate) use rest::{instantaneous_at_end, unsettled};

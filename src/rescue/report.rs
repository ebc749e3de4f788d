//! The analysis of a ruin end to end and its files:
//!
//! * `voids.csv`: one row per void, largest first (columns in docs/rescue.md §5);
//! * `voids.json`: the sizes used, the grid, the counts, the rubble measures and the
//!   same voids, each with its cells as disjoint boxes of whole cells (`boxes`:
//!   `[i0, j0, k0, i1, j1, k1]`, cell indices of the grid, upper bounds excluded;
//!   [`super::boxes`]) and the rescuer's and the camera's routes as lines (`path_m`,
//!   simplified to within `route_tolerance_m`; [`super::route`]);
//! * `rubble_height.csv`: the height map, one row per grid column (`x,y,height_m`: the
//!   column's centre and the pile surface above the ground).
//!
//! Lengths are at the model's scale (the run folder's coordinates), to 6 decimals.
use super::access::{self, Access, Breach};
use super::boxes::cell_boxes;
use super::grid::{grid_over, ground_level, Grid};
use super::input::Ruin;
use super::occupancy::occupancy;
use super::pattern::{classify, slabs, Classified};
use super::person::{Scaled, Sizes, LYING_M, SITTING_M, SOLID_FRACTION};
use super::rubble::{height_map, rubble, Rubble, PLANNING_REACH_OVER_HEIGHT};
use super::stories::{standing_shelter, story_losses_from, StoryLoss};
use super::voids::{find_voids, Field, Throat, Void};
use super::Result;
use crate::output::csv_text::field as csv_field;
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The files a rescue analysis writes into a run folder.
pub const FILES: [&str; 3] = ["voids.csv", "voids.json", "rubble_height.csv"];

/// One void with everything found about it.
#[derive(Debug, Clone, PartialEq)]
pub struct VoidReport {
    /// The measures.
    pub void: Void,
    /// The pattern.
    pub pattern: Classified,
    /// Rescuer access.
    pub rescuer: Option<Access>,
    /// Camera access.
    pub camera: Option<Access>,
    /// The least breach.
    pub breach: Breach,
}

/// A ruin's rescue analysis.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// The sizes asked for (full scale).
    pub sizes: Sizes,
    /// The model's scale.
    pub scale: f64,
    /// The sizes at the model's scale.
    pub scaled: Scaled,
    /// The ground level, m (`None`: no bodies).
    pub ground_z: Option<f64>,
    /// The grid and its classified cells (`None`: no debris above the ground).
    pub field: Option<Field>,
    /// The voids (chambers), largest first.
    pub voids: Vec<VoidReport>,
    /// Where adjoining voids meet (indices into `voids`).
    pub throats: Vec<Throat>,
    /// The rubble measures (`None` without debris).
    pub rubble: Option<Rubble>,
    /// Each story's volume loss (empty without debris or slabs).
    pub stories: Vec<StoryLoss>,
    /// The box names, in body order.
    pub names: Vec<String>,
}

/// Analyses `ruin` with `sizes` (full scale; checked before any work).
pub fn analyse(ruin: &Ruin, sizes: Sizes) -> Result<Analysis> {
    let scaled = sizes.scaled(ruin.scale)?;
    let names: Vec<String> = ruin.boxes.iter().map(|b| b.id.name()).collect();
    let ground_z = ground_level(ruin);
    let margin = scaled.rescuer.max(scaled.sitting[0]);
    let Some(grid) = grid_over(ruin, scaled.cell, margin, sizes.cell_m)? else {
        return Ok(Analysis {
            sizes,
            scale: ruin.scale,
            scaled,
            ground_z,
            field: None,
            voids: Vec::new(),
            throats: Vec::new(),
            rubble: None,
            stories: Vec::new(),
            names,
        });
    };
    // The ruin's occupancy beside the standing building's (for the story losses).
    let (occupied, before) = std::thread::scope(|s| {
        let standing = s.spawn(|| standing_shelter(ruin, grid.h, sizes.cell_m));
        let occupied = occupancy(&grid, &ruin.boxes);
        let before = standing
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        (occupied, before)
    });
    let before = before?;
    let field = Field::new(grid, occupied);
    // Two threads: the rescuer's and the camera's searches on one, the chambers, the
    // story losses and the breach search on the other. Each reads the field only and
    // writes its own result, so the outcome is the same whatever the scheduling.
    let (chambers, stories, breach, (rescuer, camera)) = std::thread::scope(|s| {
        let searches = s.spawn(|| {
            let rescuer = access::routes(&field, scaled.rescuer);
            let camera = access::routes(&field, scaled.camera);
            (rescuer, camera)
        });
        let chambers = find_voids(&field, &scaled);
        let stories = story_losses_from(ruin, &field, &before);
        let breach = access::breach_field(&field);
        let searches = searches
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        (chambers, stories, breach, searches)
    });
    let (voids, _, throats) = chambers;
    let slab_of = slabs(ruin);
    let reports = voids
        .into_iter()
        .map(|v| VoidReport {
            pattern: classify(ruin, &field, &v, &slab_of),
            rescuer: access::access(&field, &rescuer, &v),
            camera: access::access(&field, &camera, &v),
            breach: access::breach(&field, &breach, &v),
            void: v,
        })
        .collect();
    let rubble = rubble(ruin, &field, grid.origin[2]);
    Ok(Analysis {
        sizes,
        scale: ruin.scale,
        scaled,
        ground_z,
        field: Some(field),
        voids: reports,
        throats,
        rubble: Some(rubble),
        stories,
        names,
    })
}

/// Rounded to 6 decimals (−0 as 0).
fn r6(x: f64) -> f64 {
    let r = (x * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// `voids.csv` header.
pub const VOIDS_HEADER: &str =
    "void,volume_m3,clear_height_m,inscribed_radius_m,widest_x,widest_y,widest_z,\
floor_area_lying_m2,floor_area_sitting_m2,lying_fits,sitting_fits,survivable,enclosed,\
centroid_x,centroid_y,centroid_z,min_x,min_y,min_z,max_x,max_y,max_z,cover_depth_m,\
pattern,roof_tilt_deg,held_by,roof_bodies,floor_bodies,rescuer_access,rescuer_route_m,\
rescuer_entry,camera_access,camera_route_m,camera_entry,breach_m,breach_x,breach_y,breach_z,\
breach_side,region,neighbours";

impl Analysis {
    fn grid(&self) -> Option<&Grid> {
        self.field.as_ref().map(|f| &f.grid)
    }

    fn body_list(&self, list: &[(usize, usize)]) -> String {
        list.iter()
            .map(|(b, _)| {
                if *b == usize::MAX {
                    "ground".to_string()
                } else {
                    self.names[*b].clone()
                }
            })
            .collect::<Vec<_>>()
            .join(";")
    }

    /// The throats of void `n` (index): (the other void's index, the throat), by the
    /// other's index.
    pub fn neighbours(&self, n: usize) -> Vec<(usize, &Throat)> {
        let mut v: Vec<(usize, &Throat)> = self
            .throats
            .iter()
            .filter_map(|t| {
                if t.a == n {
                    Some((t.b, t))
                } else if t.b == n {
                    Some((t.a, t))
                } else {
                    None
                }
            })
            .collect();
        v.sort_by_key(|(o, _)| *o);
        v
    }

    fn widest(&self, v: &Void) -> [f64; 3] {
        let g = self.grid().expect("voids have a grid");
        g.centre(g.ijk(v.widest_cell))
    }

    /// The `voids.csv` text.
    pub fn voids_csv(&self) -> String {
        let mut s = String::from(VOIDS_HEADER);
        s.push('\n');
        let f = |x: f64| format!("{:.6}", r6(x));
        let b = |x: bool| if x { "1" } else { "0" };
        for (n, r) in self.voids.iter().enumerate() {
            let v = &r.void;
            let w = self.widest(v);
            let acc = |a: &Option<Access>| match a {
                Some(a) => format!("1,{},{}", f(a.route_m), a.entry),
                None => "0,,".to_string(),
            };
            let at = r.breach.at_m.map_or(",,".to_string(), |p| {
                format!("{},{},{}", f(p[0]), f(p[1]), f(p[2]))
            });
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                n + 1,
                f(v.volume_m3),
                f(v.clear_height_m),
                f(v.inscribed_radius_m),
                f(w[0]),
                f(w[1]),
                f(w[2]),
                f(v.floor_area_lying_m2),
                f(v.floor_area_sitting_m2),
                b(v.lying_fits),
                b(v.sitting_fits),
                b(v.survivable()),
                b(v.enclosed),
                f(v.centroid_m[0]),
                f(v.centroid_m[1]),
                f(v.centroid_m[2]),
                f(v.bounds_m[0][0]),
                f(v.bounds_m[0][1]),
                f(v.bounds_m[0][2]),
                f(v.bounds_m[1][0]),
                f(v.bounds_m[1][1]),
                f(v.bounds_m[1][2]),
                f(v.cover_depth_m),
                r.pattern.pattern.name(),
                r.pattern.roof_tilt_deg.map_or(String::new(), |t| format!("{:.2}", t)),
                csv_field(&r.pattern.held_by),
                csv_field(&self.body_list(&v.roof)),
                csv_field(&self.body_list(&v.floor)),
                acc(&r.rescuer),
                acc(&r.camera),
                f(r.breach.thickness_m),
                at,
                r.breach.side,
                v.region + 1,
                self.neighbours(n)
                    .iter()
                    .map(|(o, t)| format!("{}:{}", o + 1, f(t.clearance_m)))
                    .collect::<Vec<_>>()
                    .join(";"),
            );
        }
        s
    }

    /// The `rubble_height.csv` text.
    pub fn height_csv(&self) -> String {
        let mut s = String::from("x,y,height_m\n");
        if let Some(field) = &self.field {
            let g = &field.grid;
            let hm = height_map(field);
            for j in 0..g.n[1] {
                for i in 0..g.n[0] {
                    let c = g.centre([i, j, 0]);
                    let _ = writeln!(
                        s,
                        "{:.6},{:.6},{:.6}",
                        r6(c[0]),
                        r6(c[1]),
                        r6(hm[g.column(i, j)])
                    );
                }
            }
        }
        s
    }

    fn void_json(&self, n: usize, r: &VoidReport) -> Value {
        let v = &r.void;
        let acc = |a: &Option<Access>| match a {
            Some(a) => json!({
                "reached": true,
                "route_m": r6(a.route_m),
                "entry": a.entry,
                "path_m": a.path_m.iter().map(|p| p.map(r6)).collect::<Vec<_>>(),
            }),
            None => json!({"reached": false}),
        };
        let w = self.widest(v);
        json!({
            "void": n + 1,
            "volume_m3": r6(v.volume_m3),
            "clear_height_m": r6(v.clear_height_m),
            "inscribed_radius_m": r6(v.inscribed_radius_m),
            "widest_m": w.map(r6),
            "floor_area_lying_m2": r6(v.floor_area_lying_m2),
            "floor_area_sitting_m2": r6(v.floor_area_sitting_m2),
            "lying_fits": v.lying_fits,
            "sitting_fits": v.sitting_fits,
            "survivable": v.survivable(),
            "enclosed": v.enclosed,
            "centroid_m": v.centroid_m.map(r6),
            "bounds_m": [v.bounds_m[0].map(r6), v.bounds_m[1].map(r6)],
            "cover_depth_m": r6(v.cover_depth_m),
            "pattern": r.pattern.pattern.name(),
            "roof_tilt_deg": r.pattern.roof_tilt_deg.map(|t| (t * 100.0).round() / 100.0),
            "held_by": r.pattern.held_by,
            "roof_bodies": self.body_list(&v.roof).split(';').filter(|s| !s.is_empty()).collect::<Vec<_>>(),
            "floor_bodies": self.body_list(&v.floor).split(';').filter(|s| !s.is_empty()).collect::<Vec<_>>(),
            "rescuer": acc(&r.rescuer),
            "camera": acc(&r.camera),
            "breach": {
                "thickness_m": r6(r.breach.thickness_m),
                "at_m": r.breach.at_m.map(|p| p.map(r6)),
                "side": r.breach.side,
            },
            "region": v.region + 1,
            "boxes": self.grid().map_or(Vec::new(), |g| cell_boxes(g, &v.cells)),
            "neighbours": self.neighbours(n).iter().map(|(o, t)| json!({
                "void": o + 1,
                "throat_clearance_m": r6(t.clearance_m),
                "throat_area_m2": r6(t.area_m2),
            })).collect::<Vec<_>>(),
        })
    }

    /// The `voids.json` value.
    pub fn json(&self) -> Value {
        let survivable: Vec<&VoidReport> =
            self.voids.iter().filter(|r| r.void.survivable()).collect();
        let rubble = self.rubble.as_ref().map(|r| {
            json!({
                "max_height_m": r6(r.max_height_m),
                "mean_height_m": r6(r.mean_height_m),
                "footprint_area_m2": r6(r.footprint_area_m2),
                "building_height_m": r6(r.building_height_m),
                "extent_m": {"x_minus": r6(r.extent_m[0]), "x_plus": r6(r.extent_m[1]),
                             "y_minus": r6(r.extent_m[2]), "y_plus": r6(r.extent_m[3])},
                "extent_over_height": {"x_minus": r6(r.extent_over_height[0]),
                                       "x_plus": r6(r.extent_over_height[1]),
                                       "y_minus": r6(r.extent_over_height[2]),
                                       "y_plus": r6(r.extent_over_height[3])},
                "planning_reach_over_height": r6(PLANNING_REACH_OVER_HEIGHT),
                "porosity": r6(r.porosity),
                "debris_volume_m3": r6(r.debris_volume_m3),
                "envelope_volume_m3": r6(r.envelope_volume_m3),
            })
        });
        json!({
            "scale": self.scale,
            "sizes_full_scale_m": {
                "cell": self.sizes.cell_m,
                "rescuer": self.sizes.rescuer_m,
                "camera": self.sizes.camera_m,
                "lying_adult": LYING_M,
                "sitting_adult": SITTING_M,
            },
            "solid_fraction": SOLID_FRACTION,
            "ground_z_m": self.ground_z.map(r6),
            "grid": self.grid().map(|g| json!({
                "origin_m": g.origin.map(r6),
                "cell_m": r6(g.h),
                "cells": g.n,
            })),
            "route_tolerance_m": self.grid().map(|g| r6(super::route::TOLERANCE_CELLS * g.h)),
            "voids_count": self.voids.len(),
            "regions_count": self.voids.iter().map(|r| r.void.region + 1).max().unwrap_or(0),
            "survivable_count": survivable.len(),
            "survivable_volume_m3": r6(survivable.iter().map(|r| r.void.volume_m3).sum()),
            "rescuer_reachable_survivable": survivable.iter().filter(|r| r.rescuer.is_some()).count(),
            "camera_reachable_survivable": survivable.iter().filter(|r| r.camera.is_some()).count(),
            "rubble": rubble,
            "stories": self.stories.iter().map(|s| json!({
                "story": s.story,
                "ceiling_z_m": r6(s.ceiling_z_m),
                "free_volume_before_m3": r6(s.before_m3),
                "free_volume_after_m3": r6(s.after_m3),
                "volume_loss": r6(s.loss),
            })).collect::<Vec<_>>(),
            "voids": self.voids.iter().enumerate().map(|(n, r)| self.void_json(n, r)).collect::<Vec<_>>(),
        })
    }

    /// The `rescue` section of `summary.json`: the void and survivable counts, the
    /// survivable volume, the largest survivable void (volume, pattern, access), the
    /// pile's height and its extent per side, all as in `voids.json` (the same numbers,
    /// so the two never disagree).
    pub fn summary(&self) -> Value {
        let js = self.json();
        // The voids are largest first.
        let largest = self
            .voids
            .iter()
            .enumerate()
            .find(|(_, r)| r.void.survivable())
            .map(|(n, r)| {
                json!({
                    "void": n + 1,
                    "volume_m3": r6(r.void.volume_m3),
                    "pattern": r.pattern.pattern.name(),
                    "rescuer_access": r.rescuer.is_some(),
                    "camera_access": r.camera.is_some(),
                    "breach_m": r6(r.breach.thickness_m),
                })
            });
        let rubble = &js["rubble"];
        json!({
            "sizes_full_scale_m": js["sizes_full_scale_m"],
            "voids_count": js["voids_count"],
            "survivable_count": js["survivable_count"],
            "survivable_volume_m3": js["survivable_volume_m3"],
            "largest_survivable": largest,
            "pile_max_height_m": rubble.get("max_height_m"),
            "pile_mean_height_m": rubble.get("mean_height_m"),
            "extent_m": rubble.get("extent_m"),
            "extent_over_height": rubble.get("extent_over_height"),
        })
    }

    /// The three files (name, bytes), in [`FILES`] order.
    pub fn files(&self) -> Vec<(&'static str, Vec<u8>)> {
        let js = serde_json::to_string_pretty(&self.json()).expect("a JSON value") + "\n";
        vec![
            (FILES[0], self.voids_csv().into_bytes()),
            (FILES[1], js.into_bytes()),
            (FILES[2], self.height_csv().into_bytes()),
        ]
    }

    /// Writes the files into `dir`, each atomically (all are built before the first is
    /// written); returns their paths.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let files = self.files();
        let mut out = Vec::new();
        for (name, bytes) in files {
            let p = dir.join(name);
            crate::output::write_atomic(&p, &bytes)?;
            out.push(p);
        }
        Ok(out)
    }
}

/// `summary_text` (a `summary.json`) with its `rescue` section set to `section`; the other
/// keys keep their order and values (the file is a JSON object written by
/// `serde_json::to_string_pretty`, so reading and writing it back gives the same bytes).
pub fn with_summary_section(summary_text: &str, section: Value) -> serde_json::Result<String> {
    let mut v: Value = serde_json::from_str(summary_text)?;
    if let Some(o) = v.as_object_mut() {
        o.insert("rescue".into(), section);
    }
    Ok(serde_json::to_string_pretty(&v)? + "\n")
}

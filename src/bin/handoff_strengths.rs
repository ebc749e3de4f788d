//! The connection strengths of a model side by side: BCB's Formula Assistant against the
//! FE-derived capacities at the gravity axial load (docs/handoff.md).
//!
//! `cargo run --release --bin handoff_strengths [-- MODEL.toml]` (default
//! `data/frame3/model.toml`). Prints, per kind of connection (the two bodies' types), the
//! median of each force (compression, tension, shear h/w, bending h/w) for both models
//! and their ratio FE / BCB, and the gravity force each kind carries (the weight above
//! it, for the columns).
use anyhow::{Context, Result};
use fem2rbd::fe::build::BuildOptions;
use fem2rbd::fe::capacity::{gravity_capacities, PushSettings};
use fem2rbd::mapping::foundation::bodies_of;
use fem2rbd::mapping::{self, MapOptions};
use fem2rbd::model::Model;
use fem2rbd::pipeline::{geoms, strengths::body_strengths};
use fem2rbd::ruin::connection::{build_connections, build_connections_with, RuinSettings};
use fem2rbd::ruin::groups::group_strengths;
use fem2rbd::ruin::search::find_contacts;
use std::collections::BTreeMap;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

fn main() -> Result<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/frame3/model.toml".into());
    let model = Model::load(&path).with_context(|| path.clone())?;
    let map = mapping::map_to_boxes(&mapping::from_model(&model)?, &MapOptions::default())?;
    let bodies = bodies_of(&model, &map);
    let g = geoms(&bodies);
    let groups = group_strengths(&model)?;
    let settings = RuinSettings::default();
    let contacts = find_contacts(&g, &settings.search)?;
    let poses: Vec<_> = g.iter().map(|b| b.pose()).collect();
    let bcb = build_connections(&g, &groups, &contacts, &poses, &settings)?;
    let t0 = std::time::Instant::now();
    let (_, caps) = gravity_capacities(&model, &BuildOptions::default(), &PushSettings::default())?;
    let wall = t0.elapsed().as_secs_f64();
    let mut rot: Vec<(f64, f64, bool)> = caps
        .values()
        .flat_map(|m| {
            m.ends
                .iter()
                .map(|e| (e.rotation_left, e.section.curvature_yield[0], e.lost))
        })
        .collect();
    rot.sort_by(|a, b| a.0.total_cmp(&b.0));
    println!(
        "rotation left (rad): min {:.4}, median {:.4}, max {:.4}; κy min {:.3} 1/m",
        rot[0].0,
        rot[rot.len() / 2].0,
        rot[rot.len() - 1].0,
        rot.iter().map(|r| r.1).fold(f64::INFINITY, f64::min)
    );
    let strengths = body_strengths(&model, &bodies, &caps, true);
    let fe = build_connections_with(&g, &groups, &contacts, &poses, &settings, &strengths)?;
    println!(
        "{path}: {} connections, {} members' capacities in {wall:.2} s",
        bcb.len(),
        caps.len()
    );
    let mut kinds: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, c) in bcb.iter().enumerate() {
        let (ta, tb) = (bodies[c.a].id.type_name(), bodies[c.b].id.type_name());
        let mut k = [ta, tb];
        k.sort();
        kinds
            .entry(format!("{}–{}", k[0], k[1]))
            .or_default()
            .push(i);
    }
    println!("| connection | n | value | BCB formula | FE-derived | FE / BCB |");
    println!("|---|---|---|---|---|---|");
    for (k, idx) in &kinds {
        let names = [
            "C (kN)",
            "T (kN)",
            "S_h (kN)",
            "S_w (kN)",
            "B_h (kN·m)",
            "B_w (kN·m)",
        ];
        let get = |c: &fem2rbd::ruin::connection::ConnectionSpec, j: usize| {
            let f = &c.forces;
            [
                f.compression_n,
                f.tension_n,
                f.shear_h_n,
                f.shear_w_n,
                f.bend_h_nm,
                f.bend_w_nm,
            ][j] / 1e3
        };
        for (j, name) in names.iter().enumerate() {
            let a = median(idx.iter().map(|&i| get(&bcb[i], j)).collect());
            let b = median(idx.iter().map(|&i| get(&fe[i], j)).collect());
            println!(
                "| {k} | {} | {name} | {a:.3} | {b:.3} | {:.3} |",
                idx.len(),
                b / a
            );
        }
    }
    Ok(())
}

//! The rescue figures (docs/rescue.md §7):
//!
//! * `voids_plan`, `voids_section_xz`, `voids_section_yz` — a run's voids from its
//!   `voids.csv` over the ruin (every active body's final projection in light grey): each
//!   void's bounding box in its pattern's colour ([`pattern_colour`]), filled when the void
//!   is survivable and outlined only when it is not; the survivable ones labelled `void N` with
//!   their number in `voids.csv`. Access: the rescuer's route to a survivable void it
//!   reaches is drawn as a black line (`voids.json` `rescuer.path_m`: from where the route
//!   leaves open air to the void's reached cell, simplified to within a cell,
//!   [`crate::rescue::route`]) with a filled black triangle where it leaves open air; the
//!   camera's route to a survivable void only the camera reaches as a grey line; a
//!   survivable void neither reaches has a black × at the first debris cell to breach
//!   (`breach_x/y/z`). A run folder whose `voids.json` has no routes (or no `voids.json`)
//!   gets the triangle at the middle of the side of the void's box the route enters from
//!   (`x-`: the box's −x side, …; `top`: its centre) and no lines. The void is drawn as its
//!   bounding box.
//! * `rescue_map` — an ensemble's `rescue_map.csv`: each plan cell with a survivable void
//!   beneath in some member, shaded by that share (white → dark blue); each cell the
//!   rescuer's route to a survivable void passes over in some member
//!   (`p_route_rescuer`) as a square of half the cell's edge at its centre, shaded by that
//!   share (light → dark orange, [`route_colour`]), and each cell where such a route leaves
//!   open air in some member (`p_entry_rescuer`) as a black triangle; the places of
//!   `rescue.json` that recur (two or more members) outlined with their share. A
//!   `rescue_map.csv` without the route columns (of an older analysis) is refused naming
//!   the file.
//!
//! Equal aspect; lengths at the model's scale.
use super::geometry::{Bounds, View};
use super::ruin::RuinFigure;
use super::style::{self, Swatch};
use super::{font::FAMILY, Figure, PlotError, Result, RunFolder};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// The colour of a collapse pattern ([`crate::output::palette::pattern_srgb`]: Okabe–Ito
/// colours, distinguishable with common colour vision deficiencies); black for a name not
/// listed.
pub fn pattern_colour(pattern: &str) -> RGBColor {
    let [r, g, b] = crate::output::palette::pattern_srgb(pattern);
    RGBColor(r, g, b)
}

/// The patterns in legend order.
pub const PATTERNS: [&str; 7] = [
    "pancake",
    "supported-lean-to",
    "unsupported-lean-to",
    "v",
    "a-frame",
    "cantilever",
    "debris",
];

/// Fill opacity of a survivable void's box.
pub const VOID_OPACITY: f64 = 0.45;

/// Light grey of the ruin's bodies behind the voids.
pub const BODY_GREY: RGBColor = RGBColor(215, 215, 215);

/// One void as the figures draw it.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotVoid {
    /// Its number in `voids.csv`.
    pub number: u32,
    /// Survivable.
    pub survivable: bool,
    /// Pattern name.
    pub pattern: String,
    /// Bounding box (min, max), m.
    pub bounds: [[f64; 3]; 2],
    /// The rescuer's entry side when reached (`x-`, `x+`, `y-`, `y+`, `top`).
    pub rescuer_entry: Option<String>,
    /// The first debris cell to breach, m, when not reached.
    pub breach: Option<[f64; 3]>,
    /// The rescuer's route as a line, m, when reached and `voids.json` holds it.
    pub rescuer_route: Option<Vec<[f64; 3]>>,
    /// The camera's route as a line, m, when the camera reaches it and `voids.json` holds it.
    pub camera_route: Option<Vec<[f64; 3]>>,
}

/// Grey of a camera's route.
pub const CAMERA_GREY: RGBColor = RGBColor(110, 110, 110);

/// The routes of `voids.json` in `dir` by void number: (rescuer, camera) lines, each
/// `None` when not reached or not recorded; empty without the file.
fn read_routes(dir: &Path) -> Result<RouteMap> {
    let file = dir.join("voids.json");
    if !file.is_file() {
        return Ok(RouteMap::new());
    }
    let f = file.display();
    let text = std::fs::read_to_string(&file).map_err(|e| input(format!("{f}: {e}")))?;
    let js: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| input(format!("{f}: {e}")))?;
    let line = |v: &serde_json::Value| -> Result<Option<Vec<[f64; 3]>>> {
        let Some(a) = v.get("path_m").and_then(|p| p.as_array()) else {
            return Ok(None);
        };
        a.iter()
            .map(|p| {
                let c = |k: usize| p.get(k).and_then(|x| x.as_f64());
                match (c(0), c(1), c(2)) {
                    (Some(x), Some(y), Some(z)) => Ok([x, y, z]),
                    _ => Err(input(format!("{f}: a route point {p} is not [x, y, z]"))),
                }
            })
            .collect::<Result<Vec<_>>>()
            .map(Some)
    };
    let mut out = RouteMap::new();
    for v in js["voids"].as_array().into_iter().flatten() {
        let Some(n) = v["void"].as_u64() else {
            return Err(input(format!("{f}: a void without its number")));
        };
        out.insert(n as u32, (line(&v["rescuer"])?, line(&v["camera"])?));
    }
    Ok(out)
}

type RouteMap = std::collections::BTreeMap<u32, (Option<Vec<[f64; 3]>>, Option<Vec<[f64; 3]>>)>;

fn input(e: impl std::fmt::Display) -> PlotError {
    PlotError::Input(e.to_string())
}

/// The voids of `dir/voids.csv`, by column name, with their routes from `voids.json`
/// when it holds them; `None` without `voids.csv`.
pub fn read_voids(dir: &Path) -> Result<Option<Vec<PlotVoid>>> {
    let file = dir.join("voids.csv");
    let f = file.display();
    let text = crate::model::limits::read_optional_regular_file(&file)
        .map_err(|e| input(format!("{f}: {e}")))?;
    let Some(text) = text else {
        return Ok(None);
    };
    let mut routes = read_routes(dir)?;
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h = r
        .headers()
        .map_err(|e| input(format!("{f}:1: {e}")))?
        .clone();
    let col = |name: &str| {
        h.iter()
            .position(|x| x == name)
            .ok_or_else(|| input(format!("{f}:1: no column `{name}`")))
    };
    let mut out = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| input(format!("{f}: {e}")))?;
        let line = rec.position().map_or(0, |p| p.line());
        let text = |name: &str| -> Result<&str> { Ok(rec.get(col(name)?).unwrap_or("")) };
        let num = |name: &str| -> Result<f64> {
            let t = text(name)?;
            t.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| input(format!("{f}:{line}: `{name}` = {t:?}: not a number")))
        };
        let reached = text("rescuer_access")? == "1";
        let breach = if !reached && !text("breach_x")?.is_empty() {
            Some([num("breach_x")?, num("breach_y")?, num("breach_z")?])
        } else {
            None
        };
        let number: u32 = text("void")?
            .parse()
            .map_err(|_| input(format!("{f}:{line}: `void`: not a number")))?;
        let (rescuer_route, camera_route) = routes.remove(&number).unwrap_or((None, None));
        out.push(PlotVoid {
            number,
            survivable: text("survivable")? == "1",
            pattern: text("pattern")?.to_string(),
            bounds: [
                [num("min_x")?, num("min_y")?, num("min_z")?],
                [num("max_x")?, num("max_y")?, num("max_z")?],
            ],
            rescuer_entry: reached.then(|| text("rescuer_entry").unwrap_or("").to_string()),
            breach,
            rescuer_route: rescuer_route.filter(|_| reached),
            camera_route: camera_route.filter(|_| text("camera_access").unwrap_or("") == "1"),
        });
    }
    Ok(Some(out))
}

/// A run's voids in one view (module docs).
pub struct VoidsFigure<'a> {
    run: Option<&'a RunFolder>,
    view: View,
    voids: Vec<PlotVoid>,
}

impl<'a> VoidsFigure<'a> {
    /// The figure of `voids` in `view`, over `run`'s ruin when given.
    pub fn new(run: Option<&'a RunFolder>, view: View, voids: Vec<PlotVoid>) -> Self {
        VoidsFigure { run, view, voids }
    }

    /// A box's rectangle in the view: (horizontal, vertical) ranges.
    pub fn rect(&self, b: &[[f64; 3]; 2]) -> [[f64; 2]; 2] {
        let (h, v) = self.view.axes();
        [[b[0][h], b[0][v]], [b[1][h], b[1][v]]]
    }

    /// A point in the view.
    fn point(&self, p: [f64; 3]) -> (f64, f64) {
        let (h, v) = self.view.axes();
        (p[h], p[v])
    }

    /// Where the rescuer's entry marker of `v` lies in the view: the start of its route,
    /// or without a route the middle of the box's side it enters through.
    pub fn entry_point(&self, v: &PlotVoid) -> Option<(f64, f64)> {
        let e = v.rescuer_entry.as_deref()?;
        if let Some(p) = v.rescuer_route.as_ref().and_then(|r| r.first()) {
            return Some(self.point(*p));
        }
        Some(self.point(entry_side_point(v.bounds, e)))
    }

    /// A route line in the view.
    pub fn line(&self, route: &[[f64; 3]]) -> Vec<(f64, f64)> {
        route.iter().map(|p| self.point(*p)).collect()
    }
}

impl Figure for VoidsFigure<'_> {
    fn name(&self) -> &'static str {
        match self.view {
            View::Plan => "voids_plan",
            View::ElevationXz => "voids_section_xz",
            View::ElevationYz => "voids_section_yz",
        }
    }

    fn size(&self) -> (u32, u32) {
        (1200, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let what = match self.view {
            View::Plan => "plan",
            View::ElevationXz => "section x-z",
            View::ElevationYz => "section y-z",
        };
        let surv = self.voids.iter().filter(|v| v.survivable).count();
        let title = format!(
            "Voids in {what} - {} voids, {surv} survivable",
            self.voids.len()
        );
        let root = root.titled(&title, (FAMILY, style::TITLE_PX))?;
        let (w, _) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(250));
        let ruin = self.run.map(|r| RuinFigure::new(r, self.view));
        let mut data = ruin.as_ref().map(RuinFigure::extent);
        for v in &self.voids {
            let r = self.rect(&v.bounds);
            let b = Bounds {
                x: [r[0][0], r[1][0]],
                y: [r[0][1], r[1][1]],
            };
            data = Some(data.map_or(b, |d| d.union(&b)));
        }
        let data = data.unwrap_or(Bounds {
            x: [0.0, 1.0],
            y: [0.0, 1.0],
        });
        let (pw, ph) = main.dim_in_pixel();
        let b = data.padded(0.03, 0.05).equal_aspect(
            pw.saturating_sub(94),
            ph.saturating_sub(72),
            self.view != View::Plan,
        );
        let mut chart = super::ruin::view_chart(&main, self.view, &b)?;
        if let Some(ruin) = &ruin {
            chart.draw_series(ruin.active_order().into_iter().map(|i| {
                let pts: Vec<(f64, f64)> =
                    ruin.projection(i).iter().map(|p| (p[0], p[1])).collect();
                Polygon::new(pts, BODY_GREY.filled())
            }))?;
        }
        // Not survivable first (outlines), then survivable (filled), largest first.
        let rect = |v: &PlotVoid| {
            let r = self.rect(&v.bounds);
            [(r[0][0], r[0][1]), (r[1][0], r[1][1])]
        };
        chart.draw_series(
            self.voids
                .iter()
                .filter(|v| !v.survivable)
                .map(|v| Rectangle::new(rect(v), pattern_colour(&v.pattern).stroke_width(1))),
        )?;
        for v in self.voids.iter().filter(|v| v.survivable) {
            let c = pattern_colour(&v.pattern);
            chart.draw_series([
                Rectangle::new(rect(v), c.mix(VOID_OPACITY).filled()),
                Rectangle::new(rect(v), c.stroke_width(2)),
            ])?;
            let r = rect(v);
            chart.draw_series(std::iter::once(Text::new(
                format!("void {}", v.number),
                (r[0].0, r[1].1),
                (FAMILY, style::LABEL_PX).into_font().color(&BLACK),
            )))?;
        }
        // Routes: the camera's where only the camera reaches, then the rescuer's.
        chart.draw_series(
            self.voids
                .iter()
                .filter(|v| v.survivable && v.rescuer_route.is_none())
                .filter_map(|v| v.camera_route.as_ref())
                .map(|r| PathElement::new(self.line(r), CAMERA_GREY.stroke_width(2))),
        )?;
        chart.draw_series(
            self.voids
                .iter()
                .filter(|v| v.survivable)
                .filter_map(|v| v.rescuer_route.as_ref())
                .map(|r| PathElement::new(self.line(r), BLACK.stroke_width(2))),
        )?;
        chart.draw_series(
            self.voids
                .iter()
                .filter(|v| v.survivable)
                .filter_map(|v| self.entry_point(v))
                .map(|p| TriangleMarker::new(p, 7, BLACK.filled())),
        )?;
        chart.draw_series(
            self.voids
                .iter()
                .filter(|v| v.survivable)
                .filter_map(|v| v.breach.map(|p| self.point(p)))
                .map(|p| Cross::new(p, 6, BLACK.stroke_width(2))),
        )?;
        let mut entries = vec![(Swatch::Heading, "Survivable void".to_string())];
        let used: Vec<&str> = PATTERNS
            .into_iter()
            .filter(|p| self.voids.iter().any(|v| v.pattern == *p))
            .collect();
        for p in &used {
            entries.push((Swatch::Fill(pattern_colour(p)), (*p).to_string()));
        }
        entries.push((Swatch::Heading, "Not survivable".to_string()));
        for p in &used {
            entries.push((Swatch::Outline(pattern_colour(p)), (*p).to_string()));
        }
        entries.push((Swatch::Heading, "Rescuer".to_string()));
        entries.push((Swatch::Line(BLACK), "route, ▲ entry".to_string()));
        entries.push((Swatch::Line(CAMERA_GREY), "camera's route".to_string()));
        entries.push((Swatch::Line(BLACK), "× cut here".to_string()));
        entries.push((Swatch::Fill(BODY_GREY), "ruin bodies".to_string()));
        style::draw_legend(&legend, &entries)?;
        Ok(())
    }
}

/// One recurring place of an ensemble.
#[derive(Debug, Clone, PartialEq)]
pub struct MapPlace {
    /// Plan box ([min x, min y], [max x, max y]) of its first void, m.
    pub plan: [[f64; 2]; 2],
    /// Share of the analysed members.
    pub probability: f64,
}

/// An ensemble's rescue map (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RescueMapFigure {
    /// Cell edge, m.
    pub cell_m: f64,
    /// (centre x, centre y, p_survivable) of every cell with p_survivable > 0.
    pub cells: Vec<(f64, f64, f64)>,
    /// (centre x, centre y, p_route_rescuer) of every cell with p_route_rescuer > 0.
    pub routes: Vec<(f64, f64, f64)>,
    /// (centre x, centre y, p_entry_rescuer) of every cell with p_entry_rescuer > 0.
    pub entries: Vec<(f64, f64, f64)>,
    /// All cells' centres' bounds, m.
    pub extent: Bounds,
    /// The recurring places.
    pub places: Vec<MapPlace>,
    /// Members analysed.
    pub members: u64,
}

/// White → dark blue for shares 0 → 1.
pub fn share_colour(s: f64) -> RGBColor {
    let s = s.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64| (a + (b - a) * s).round() as u8;
    RGBColor(lerp(235.0, 8.0), lerp(242.0, 48.0), lerp(255.0, 107.0))
}

/// Light → dark orange for the shares 0 → 1 of the rescuer's routes (ColorBrewer's
/// Oranges, #fdd0a2 → #a63603): apart from [`share_colour`]'s blues at every share.
pub fn route_colour(s: f64) -> RGBColor {
    let s = s.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64| (a + (b - a) * s).round() as u8;
    RGBColor(lerp(253.0, 166.0), lerp(208.0, 54.0), lerp(162.0, 3.0))
}

impl RescueMapFigure {
    /// Reads `dir/rescue_map.csv` and `dir/rescue.json`; `None` without them.
    pub fn load(dir: &Path) -> Result<Option<Self>> {
        let (mf, jf) = (dir.join("rescue_map.csv"), dir.join("rescue.json"));
        if !mf.exists() || !jf.exists() {
            return Ok(None);
        }
        let read = |p: &Path| {
            crate::model::limits::read_regular_file(p)
                .map_err(|e| input(format!("{}: {e}", p.display())))
        };
        Self::from_texts(dir, &read(&mf)?, &read(&jf)?).map(Some)
    }

    /// The figure of the texts of `rescue_map.csv` and `rescue.json` of the ensemble folder
    /// `dir` (as they are, or are about to be, there; the messages name the files).
    pub fn from_texts(dir: &Path, map_csv: &str, rescue_json: &str) -> Result<Self> {
        let (mf, jf) = (dir.join("rescue_map.csv"), dir.join("rescue.json"));
        let js: serde_json::Value = serde_json::from_str(rescue_json)
            .map_err(|e| input(format!("{}: {e}", jf.display())))?;
        let f = mf.display();
        let mut r = csv::Reader::from_reader(map_csv.as_bytes());
        let header = r.headers().map_err(|e| input(format!("{f}: {e}")))?.clone();
        let col = |name: &str| {
            header.iter().position(|h| h == name).ok_or_else(|| {
                input(format!(
                    "{f}: no column `{name}` (the file is of an older analysis: `fem2rbd voids {}` \
                     writes it again)",
                    dir.display()
                ))
            })
        };
        let (cr, ce) = (col("p_route_rescuer")?, col("p_entry_rescuer")?);
        let mut cells = Vec::new();
        let mut routes = Vec::new();
        let mut entries = Vec::new();
        let mut pts = Vec::new();
        for rec in r.records() {
            let rec = rec.map_err(|e| input(format!("{f}: {e}")))?;
            let line = rec.position().map_or(0, |p| p.line());
            let n = |k: usize| {
                rec.get(k)
                    .and_then(|t| t.parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| input(format!("{f}:{line}: column {}: not a number", k + 1)))
            };
            let (x, y, p) = (n(2)?, n(3)?, n(5)?);
            pts.push([x, y]);
            if p > 0.0 {
                cells.push((x, y, p));
            }
            let (route, entry) = (n(cr)?, n(ce)?);
            if route > 0.0 {
                routes.push((x, y, route));
            }
            if entry > 0.0 {
                entries.push((x, y, entry));
            }
        }
        let cell_m = js["map"]["cell_m"].as_f64().unwrap_or(0.0);
        let extent = Bounds::of(pts).unwrap_or(Bounds {
            x: [0.0, 1.0],
            y: [0.0, 1.0],
        });
        let extent = Bounds {
            x: [extent.x[0] - cell_m / 2.0, extent.x[1] + cell_m / 2.0],
            y: [extent.y[0] - cell_m / 2.0, extent.y[1] + cell_m / 2.0],
        };
        let places = js["places"]
            .as_array()
            .map(|a| {
                a.iter()
                    .filter(|p| p["recurs"] == true)
                    .map(|p| {
                        let b =
                            |i: usize, k: usize| p["first_bounds_m"][i][k].as_f64().unwrap_or(0.0);
                        MapPlace {
                            plan: [[b(0, 0), b(0, 1)], [b(1, 0), b(1, 1)]],
                            probability: p["probability"].as_f64().unwrap_or(0.0),
                        }
                    })
                    .collect()
            })
            .unwrap_or_default();
        Ok(RescueMapFigure {
            cell_m,
            cells,
            routes,
            entries,
            extent,
            places,
            members: js["members_analysed"].as_u64().unwrap_or(0),
        })
    }
}

impl Figure for RescueMapFigure {
    fn name(&self) -> &'static str {
        "rescue_map"
    }

    fn size(&self) -> (u32, u32) {
        (1100, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let title = format!(
            "Survivable voids beneath and the rescuer's routes over the plan - {} members",
            self.members
        );
        let root = root.titled(&title, (FAMILY, style::TITLE_PX))?;
        let (w, _) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(230));
        let (pw, ph) = main.dim_in_pixel();
        let b = self.extent.padded(0.02, 0.02).equal_aspect(
            pw.saturating_sub(94),
            ph.saturating_sub(72),
            false,
        );
        let mut chart = ChartBuilder::on(&main)
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d(b.x[0]..b.x[1], b.y[0]..b.y[1])?;
        let fx = style::tick_format(b.x[1] - b.x[0]);
        let fy = style::tick_format(b.y[1] - b.y[0]);
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style((FAMILY, style::TICK_PX))
            .axis_desc_style((FAMILY, style::LABEL_PX))
            .light_line_style(style::GRID_LIGHT)
            .bold_line_style(style::GRID_BOLD)
            .draw()?;
        let h = self.cell_m / 2.0;
        chart.draw_series(self.cells.iter().map(|&(x, y, p)| {
            Rectangle::new([(x - h, y - h), (x + h, y + h)], share_colour(p).filled())
        }))?;
        let q = h / 2.0;
        chart.draw_series(self.routes.iter().map(|&(x, y, p)| {
            Rectangle::new([(x - q, y - q), (x + q, y + q)], route_colour(p).filled())
        }))?;
        for p in &self.places {
            chart.draw_series([Rectangle::new(
                [(p.plan[0][0], p.plan[0][1]), (p.plan[1][0], p.plan[1][1])],
                BLACK.stroke_width(2),
            )])?;
            chart.draw_series(std::iter::once(Text::new(
                format!("{:.0} %", 100.0 * p.probability),
                (p.plan[0][0], p.plan[1][1]),
                (FAMILY, style::LABEL_PX).into_font().color(&BLACK),
            )))?;
        }
        chart.draw_series(
            self.entries
                .iter()
                .map(|&(x, y, _)| TriangleMarker::new((x, y), 6, BLACK.filled())),
        )?;
        let mut entries = vec![(Swatch::Heading, "Survivable void beneath".to_string())];
        for s in [0.25, 0.5, 0.75, 1.0] {
            entries.push((Swatch::Fill(share_colour(s)), format!("{:.0} %", 100.0 * s)));
        }
        entries.push((Swatch::Heading, "Rescuer's route over".to_string()));
        for s in [0.25, 0.5, 0.75, 1.0] {
            entries.push((Swatch::Fill(route_colour(s)), format!("{:.0} %", 100.0 * s)));
        }
        entries.push((Swatch::Triangle(BLACK), "route leaves open air".to_string()));
        entries.push((Swatch::Outline(BLACK), "recurring void".to_string()));
        entries.push((Swatch::Heading, format!("cell {:.3} m", self.cell_m)));
        style::draw_legend(&legend, &entries)?;
        Ok(())
    }
}

/// The middle of the side of a void's bounding box `b` (min, max corners, m) that the
/// rescuer's route enters through: `x-` the −x side, `x+`, `y-`, `y+`, `top` the top; the
/// box's centre for any other side. The rescuer's marker in the plots and the report.
pub fn entry_side_point(b: [[f64; 3]; 2], entry: &str) -> [f64; 3] {
    let mut p = [0, 1, 2].map(|k| 0.5 * (b[0][k] + b[1][k]));
    match entry {
        "x-" => p[0] = b[0][0],
        "x+" => p[0] = b[1][0],
        "y-" => p[1] = b[0][1],
        "y+" => p[1] = b[1][1],
        "top" => p[2] = b[1][2],
        _ => {}
    }
    p
}

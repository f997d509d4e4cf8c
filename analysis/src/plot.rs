//! Plots (PNG and SVG) with `plotters`. The only module of the suite that draws.
//!
//! Text is rendered by plotters' pure-Rust `ab_glyph` backend with DejaVu Sans, embedded from
//! `analysis/assets/` (no system fontconfig needed). Files are written atomically: rendered
//! to a temporary file in the target directory, then renamed.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Font shipped with the suite (DejaVu Sans, see `assets/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();
const FAMILY: &str = "sans-serif";
const SIZE: (u32, u32) = (1000, 700);

fn register_font() {
    REGISTER.call_once(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, FONT)
            .unwrap_or_else(|_| panic!("the shipped font is a valid TrueType file"));
    });
}

/// A failure to draw or write a plot.
#[derive(Debug)]
pub struct PlotError(pub String);

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PlotError {}

fn perr(e: impl std::fmt::Display) -> PlotError {
    PlotError(e.to_string())
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    Line,
    Points,
    LinePoints,
    Dashed,
}

/// One labelled series of `(x, y)` points.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub mark: Mark,
    /// Half-lengths of vertical error bars, one per point (none: no bars; a non-finite or
    /// non-positive value: no bar at that point).
    pub errors: Option<Vec<f64>>,
}

/// An x-y plot of one or more series. On a log axis, points with a non-positive coordinate
/// are left out (they cannot be placed); non-finite points are always left out.
#[derive(Clone, Debug, PartialEq)]
pub struct LinePlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub log_x: bool,
    pub log_y: bool,
    /// Corner of the legend (upper right unless set with [`LinePlot::legend`]).
    pub legend: LegendCorner,
    /// Values the y axis must show besides the data (see [`LinePlot::include_y`]).
    pub y_include: Vec<f64>,
    /// Label only whole numbers on the y axis (counts), see [`LinePlot::integer_y`].
    pub integer_y: bool,
}

/// Where the legend of a [`LinePlot`] sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendCorner {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

/// Distinct, colour-blind-friendly colours (Okabe-Ito, then Tableau).
const PALETTE: [RGBColor; 10] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Range of the values with a margin of 4% on each side (a log range starts on a power of
/// ten); degenerate ranges are widened.
fn padded(values: impl Iterator<Item = f64>, log: bool) -> Option<Range<f64>> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    if log {
        // The lower end on a whole decade, so that the lowest decade has its tick label
        // (plotters labels the powers of ten inside the range).
        let (a, b) = (lo.log10(), hi.log10());
        let pad = if b > a { 0.04 * (b - a) } else { 0.5 };
        // Just below the decade: `powf` may land an ulp above the power of ten, whose tick
        // would then fall outside the range.
        return Some(0.98 * 10f64.powf((a - pad).floor())..10f64.powf(b + pad));
    }
    let pad = if hi > lo {
        0.04 * (hi - lo)
    } else if lo != 0.0 {
        0.1 * lo.abs()
    } else {
        1.0
    };
    Some(lo - pad..hi + pad)
}

/// Short tick labels: plain for moderate magnitudes, scientific otherwise.
/// [`tick`] on an axis spanning `span`: on a linear axis a tick within `1e-9 span` of zero is
/// zero (the mesh's accumulated round-off drew `-1.11e-16` where 0 was meant); a log axis
/// has no zero, and its small ticks keep their value (1e-6 was drawn as 0).
fn tick_on(v: f64, span: f64, log: bool) -> String {
    tick(if !log && v.abs() <= 1e-9 * span.abs() { 0.0 } else { v })
}

fn tick(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&a) {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let s = format!("{v:.2e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exponent}", mantissa.trim_end_matches('0').trim_end_matches('.'))
    }
}

/// Tick labels of a count axis: whole numbers only, the ticks between them unlabelled.
fn count_tick(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 {
        format!("{}", v.round())
    } else {
        String::new()
    }
}

impl LinePlot {
    /// A plot with a title and axis labels and no series.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            log_x: false,
            log_y: false,
            legend: LegendCorner::UpperRight,
            y_include: Vec::new(),
            integer_y: false,
        }
    }

    /// Labels only whole numbers on the y axis (for counts).
    pub fn integer_y(mut self) -> Self {
        self.integer_y = true;
        self
    }

    /// Extends the y axis to show `y` (for example 0, so that nearly equal values are not
    /// drawn as if they differed a lot).
    pub fn include_y(mut self, y: f64) -> Self {
        self.y_include.push(y);
        self
    }

    /// Adds a series.
    pub fn series(mut self, label: &str, points: Vec<(f64, f64)>, mark: Mark) -> Self {
        self.series.push(Series {
            label: label.into(),
            points,
            mark,
            errors: None,
        });
        self
    }

    /// Adds a series with vertical error bars `y +- errors[i]` (for example standard errors
    /// over seeds); the axis range takes the bars in.
    pub fn series_with_errors(mut self, label: &str, points: Vec<(f64, f64)>, errors: Vec<f64>, mark: Mark) -> Self {
        assert_eq!(points.len(), errors.len(), "one error per point");
        self.series.push(Series {
            label: label.into(),
            points,
            mark,
            errors: Some(errors),
        });
        self
    }

    /// The error bars of series `k` that can be drawn: `(x, y - e, y + e)`.
    fn bars(&self, k: usize) -> Vec<(f64, f64, f64)> {
        let s = &self.series[k];
        let Some(errors) = &s.errors else {
            return Vec::new();
        };
        s.points
            .iter()
            .zip(errors)
            .filter(|&(&(x, y), &e)| e.is_finite() && e > 0.0 && x.is_finite() && y.is_finite())
            .map(|(&(x, y), &e)| (x, y - e, y + e))
            .filter(|&(x, lo, _)| (!self.log_x || x > 0.0) && (!self.log_y || lo > 0.0))
            .collect()
    }

    /// Logarithmic x axis.
    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    /// Puts the legend in another corner (where it hides no data).
    pub fn legend(mut self, corner: LegendCorner) -> Self {
        self.legend = corner;
        self
    }

    /// Logarithmic y axis.
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }

    /// The points of series `k` that can be drawn on these axes.
    fn drawable(&self, k: usize) -> Vec<(f64, f64)> {
        self.line_runs(k).concat()
    }

    /// Series `k`'s drawable points in runs: a point with a non-finite y ends a run (a line
    /// does not bridge it); empty runs are dropped.
    fn line_runs(&self, k: usize) -> Vec<Vec<(f64, f64)>> {
        let mut runs = vec![Vec::new()];
        for &(x, y) in &self.series[k].points {
            if !y.is_finite() {
                runs.push(Vec::new());
            } else if x.is_finite() && (!self.log_x || x > 0.0) && (!self.log_y || y > 0.0) {
                runs.last_mut().unwrap().push((x, y));
            }
        }
        runs.retain(|r| !r.is_empty());
        runs
    }

    /// Writes `<stem>.png` and `<stem>.svg`; returns the paths written.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        register_font();
        let (x, y) = self.ranges();
        let png = with_extension(stem, "png");
        let svg = with_extension(stem, "svg");
        write_png(&png, SIZE, |root| self.render_axes(root, x.clone(), y.clone()))?;
        write_svg(&svg, SIZE, |root| self.render_axes(root, x.clone(), y.clone()))?;
        Ok(vec![png, svg])
    }

    /// The axes' ranges: every drawable point and error bar, the values `include_y` asks
    /// for, padded, and room for the legend.
    fn ranges(&self) -> (Range<f64>, Range<f64>) {
        let mut all: Vec<(f64, f64)> = (0..self.series.len()).flat_map(|k| self.drawable(k)).collect();
        all.extend(
            (0..self.series.len())
                .flat_map(|k| self.bars(k))
                .flat_map(|(x, lo, hi)| [(x, lo), (x, hi)]),
        );
        let x = padded(all.iter().map(|p| p.0), self.log_x).unwrap_or(if self.log_x { 0.1..10.0 } else { 0.0..1.0 });
        let extra = self
            .y_include
            .iter()
            .copied()
            .filter(|&y| y.is_finite() && (!self.log_y || y > 0.0));
        let y = padded(all.iter().map(|p| p.1).chain(extra), self.log_y).unwrap_or(if self.log_y { 0.1..10.0 } else { 0.0..1.0 });
        (x, self.legend_room(y))
    }

    /// The y range widened so that the legend's corner holds no data: the legend takes
    /// about `LEGEND_LINE` pixels per series plus `LEGEND_PAD` of the plot area (the image
    /// height less the caption, margins and x labels), and the data are kept to the rest,
    /// below an upper legend or above a lower one (in log10 for a log axis).
    fn legend_room(&self, y: Range<f64>) -> Range<f64> {
        if self.series.len() < 2 {
            return y;
        }
        const LEGEND_LINE: f64 = 22.0;
        const LEGEND_PAD: f64 = 24.0;
        let area = SIZE.1 as f64 - 2.0 * 20.0 - 40.0 - 55.0;
        let f = ((self.series.len() as f64 * LEGEND_LINE + LEGEND_PAD) / area).min(0.6);
        let (lo, hi) = if self.log_y {
            (y.start.log10(), y.end.log10())
        } else {
            (y.start, y.end)
        };
        let span = (hi - lo) / (1.0 - f);
        let (lo, hi) = match self.legend {
            LegendCorner::UpperRight | LegendCorner::UpperLeft => (lo, lo + span),
            LegendCorner::LowerRight | LegendCorner::LowerLeft => (hi - span, hi),
        };
        if self.log_y {
            10f64.powf(lo)..10f64.powf(hi)
        } else {
            lo..hi
        }
    }

    fn render_axes<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
        x: Range<f64>,
        y: Range<f64>,
    ) -> Result<(), PlotError>
    where
        DB::ErrorType: 'static,
    {
        match (self.log_x, self.log_y) {
            (false, false) => self.render(root, x, y),
            (true, false) => self.render(root, x.log_scale(), y),
            (false, true) => self.render(root, x, y.log_scale()),
            (true, true) => self.render(root, x.log_scale(), y.log_scale()),
        }
    }

    fn render<DB, X, Y>(&self, root: DrawingArea<DB, plotters::coord::Shift>, x: X, y: Y) -> Result<(), PlotError>
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        root.fill(&WHITE).map_err(perr)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, (FAMILY, 26))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(95)
            .build_cartesian_2d(x, y)
            .map_err(perr)?;
        let (xr, yr) = (chart.x_range(), chart.y_range());
        let (x_span, y_span) = (xr.end - xr.start, yr.end - yr.start);
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_labels(8)
            .y_labels(10)
            .label_style((FAMILY, 16))
            .axis_desc_style((FAMILY, 19))
            .x_label_formatter(&|v| tick_on(*v, x_span, self.log_x))
            .y_label_formatter(&|v| {
                if self.integer_y {
                    count_tick(*v)
                } else {
                    tick_on(*v, y_span, self.log_y)
                }
            })
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(perr)?;
        for (k, s) in self.series.iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            let pts = self.drawable(k);
            let style = color.stroke_width(2);
            let legend = |c: RGBColor| move |(x, y): (i32, i32)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3));
            let anno = match s.mark {
                Mark::Line | Mark::LinePoints => {
                    // Two pixels wide as three lines of one, the second and third one pixel
                    // to the right and one down: the bitmap backend fills a wider line as a
                    // polygon, and a thin, steep one spikes far past its ends (a long run's
                    // stripe count drew spikes over the x labels). A point with a non-finite
                    // y breaks the line (a stretch without data is not bridged).
                    let thin = color.stroke_width(1);
                    let runs = self.line_runs(k);
                    let (last, rest) = runs.split_last().map_or((&[][..], &[][..]), |(l, r)| (&l[..], r));
                    for (n, run) in rest.iter().map(Vec::as_slice).chain([last]).enumerate() {
                        let px: Vec<(i32, i32)> = run.iter().map(|p| chart.backend_coord(p)).collect();
                        for (dx, dy) in [(1, 0), (0, 1)] {
                            let shifted: Vec<(i32, i32)> = px.iter().map(|&(x, y)| (x + dx, y + dy)).collect();
                            root.draw(&PathElement::new(shifted, thin)).map_err(perr)?;
                        }
                        if n < rest.len() {
                            chart.draw_series(LineSeries::new(run.to_vec(), thin)).map_err(perr)?;
                        }
                    }
                    chart.draw_series(LineSeries::new(last.to_vec(), thin)).map_err(perr)?
                }
                Mark::Dashed => chart.draw_series(DashedLineSeries::new(pts.clone(), 10, 6, style)).map_err(perr)?,
                Mark::Points => chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                    .map_err(perr)?,
            };
            anno.label(&s.label).legend(legend(color));
            if s.mark == Mark::LinePoints {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(perr)?;
            }
            chart
                .draw_series(
                    self.bars(k)
                        .into_iter()
                        .map(|(x, lo, hi)| PathElement::new(vec![(x, lo), (x, hi)], color.stroke_width(2))),
                )
                .map_err(perr)?;
        }
        if self.series.len() > 1 {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font((FAMILY, 16))
                .position(match self.legend {
                    LegendCorner::UpperRight => SeriesLabelPosition::UpperRight,
                    LegendCorner::UpperLeft => SeriesLabelPosition::UpperLeft,
                    LegendCorner::LowerRight => SeriesLabelPosition::LowerRight,
                    LegendCorner::LowerLeft => SeriesLabelPosition::LowerLeft,
                })
                .draw()
                .map_err(perr)?;
        }
        root.present().map_err(perr)
    }
}

/// A colour map over a grid: `values[row][col]`, rows along y (first row at `y_range.0`),
/// columns along x. Non-finite cells are drawn grey. A colour bar shows the scale.
#[derive(Clone, Debug, PartialEq)]
pub struct Heatmap {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub values: Vec<Vec<f64>>,
    pub colorbar_label: String,
    /// Values at the two ends of the colour scale [None: the values' own range]; give two
    /// maps the same range to compare them.
    pub scale: Option<(f64, f64)>,
    /// Names of the columns and of the rows, for axes whose cells are not evenly spaced
    /// values (a sweep over a list): `x_range` and `y_range` are then the cell indices
    /// `(-0.5, n - 0.5)`, and each cell's centre is labelled with its name.
    pub cell_names: Option<(Vec<String>, Vec<String>)>,
}

/// Tick label at `v` on an axis of named cells: the name of the cell centred there.
fn cell_tick(v: f64, names: &[String]) -> String {
    let k = v.round();
    if (v - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < names.len() {
        names[k as usize].clone()
    } else {
        String::new()
    }
}

/// Viridis colour map sampled at 9 points (matplotlib's values), linearly interpolated.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// Viridis colour of `t` in [0, 1] (clamped).
pub fn viridis(t: f64) -> RGBColor {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let s = t * (VIRIDIS.len() - 1) as f64;
    let k = (s.floor() as usize).min(VIRIDIS.len() - 2);
    let f = s - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl Heatmap {
    /// Writes `<stem>.png` and `<stem>.svg`; returns the paths written.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        register_font();
        if self.values.is_empty() || self.values[0].is_empty() {
            return Err(PlotError(format!("{}: heat map has no cells", self.title)));
        }
        let png = with_extension(stem, "png");
        let svg = with_extension(stem, "svg");
        write_png(&png, SIZE, |root| self.render(root, None))?;
        write_svg(&svg, SIZE, |root| self.render(root, None))?;
        Ok(vec![png, svg])
    }

    /// Like [`Heatmap::save`], with a class per cell (`classes[row][col]`, an index into
    /// `names`): a black line is drawn wherever neighbouring cells differ in class, and each
    /// cell is labelled with its class name (a phase diagram over a continuous metric).
    pub fn save_with_classes(&self, stem: &Path, classes: &[Vec<usize>], names: &[&str]) -> Result<Vec<PathBuf>, PlotError> {
        register_font();
        let shape_ok = classes.len() == self.values.len() && classes.iter().zip(&self.values).all(|(c, v)| c.len() == v.len());
        if !shape_ok || self.values.is_empty() || self.values[0].is_empty() {
            return Err(PlotError(format!("{}: classes must have the shape of the values", self.title)));
        }
        let overlay = Overlay { classes, names };
        let png = with_extension(stem, "png");
        let svg = with_extension(stem, "svg");
        write_png(&png, SIZE, |root| self.render(root, Some(&overlay)))?;
        write_svg(&svg, SIZE, |root| self.render(root, Some(&overlay)))?;
        Ok(vec![png, svg])
    }

    /// The values' own range (finite values only; (0, 1) without any).
    pub fn own_range(&self) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in self.values.iter().flatten().filter(|v| v.is_finite()) {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        if !lo.is_finite() {
            return (0.0, 1.0);
        }
        if hi <= lo {
            hi = lo + if lo == 0.0 { 1.0 } else { lo.abs() * 1e-3 };
        }
        (lo, hi)
    }

    fn render<DB: DrawingBackend>(&self, root: DrawingArea<DB, plotters::coord::Shift>, overlay: Option<&Overlay>) -> Result<(), PlotError>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(perr)?;
        let (w, _) = root.dim_in_pixel();
        let (main, bar) = root.split_horizontally(w.saturating_sub(150));
        let (lo, hi) = self.scale.unwrap_or_else(|| self.own_range());
        let (rows, cols) = (self.values.len(), self.values[0].len());
        let (x0, x1) = self.x_range;
        let (y0, y1) = self.y_range;
        let mut chart = ChartBuilder::on(&main)
            .caption(&self.title, (FAMILY, 26))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        let names = self.cell_names.as_ref();
        let x_fmt = |v: &f64| names.map_or_else(|| tick(*v), |(x, _)| cell_tick(*v, x));
        let y_fmt = |v: &f64| names.map_or_else(|| tick(*v), |(_, y)| cell_tick(*v, y));
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((FAMILY, 16))
            .axis_desc_style((FAMILY, 19))
            .x_labels(names.map_or(10, |(x, _)| 4 * x.len() + 1))
            .y_labels(names.map_or(10, |(_, y)| 4 * y.len() + 1))
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .draw()
            .map_err(perr)?;
        let (dx, dy) = ((x1 - x0) / cols as f64, (y1 - y0) / rows as f64);
        chart
            .draw_series(self.values.iter().enumerate().flat_map(|(r, row)| {
                row.iter().enumerate().map(move |(c, &v)| {
                    let color = if v.is_finite() {
                        viridis((v - lo) / (hi - lo))
                    } else {
                        RGBColor(160, 160, 160)
                    };
                    let (xa, ya) = (x0 + c as f64 * dx, y0 + r as f64 * dy);
                    Rectangle::new([(xa, ya), (xa + dx, ya + dy)], color.filled())
                })
            }))
            .map_err(perr)?;
        if let Some(o) = overlay {
            let cell = |r: usize, c: usize| (x0 + c as f64 * dx, y0 + r as f64 * dy);
            let mut lines = Vec::new();
            for r in 0..rows {
                for c in 0..cols {
                    let (xa, ya) = cell(r, c);
                    if c + 1 < cols && o.classes[r][c] != o.classes[r][c + 1] {
                        lines.push(vec![(xa + dx, ya), (xa + dx, ya + dy)]);
                    }
                    if r + 1 < rows && o.classes[r][c] != o.classes[r + 1][c] {
                        lines.push(vec![(xa, ya + dy), (xa + dx, ya + dy)]);
                    }
                }
            }
            chart
                .draw_series(lines.into_iter().map(|l| PathElement::new(l, BLACK.stroke_width(3))))
                .map_err(perr)?;
            // Labels in white on the dark end of the colour map, in black on the light end.
            chart
                .draw_series((0..rows).flat_map(|r| {
                    (0..cols).map(move |c| {
                        let (xa, ya) = cell(r, c);
                        let name = o.names.get(o.classes[r][c]).copied().unwrap_or("?");
                        let light = (self.values[r][c] - lo) / (hi - lo) > 0.6;
                        let font = (FAMILY, 18).into_font().color(if light { &BLACK } else { &WHITE });
                        Text::new(name.to_string(), (xa + 0.1 * dx, ya + 0.6 * dy), font)
                    })
                }))
                .map_err(perr)?;
        }
        // Colour bar.
        let mut cb: ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>> = ChartBuilder::on(&bar)
            .margin_top(60)
            .margin_bottom(75)
            .margin_right(10)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(perr)?;
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(&self.colorbar_label)
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 16))
            .y_label_formatter(&|v| tick(*v))
            .draw()
            .map_err(perr)?;
        let steps = 200;
        cb.draw_series((0..steps).map(|k| {
            let (a, b) = (
                lo + (hi - lo) * k as f64 / steps as f64,
                lo + (hi - lo) * (k + 1) as f64 / steps as f64,
            );
            Rectangle::new([(0.0, a), (1.0, b)], viridis((k as f64 + 0.5) / steps as f64).filled())
        }))
        .map_err(perr)?;
        root.present().map_err(perr)
    }
}

/// One panel of a [`FieldPlot`]: arrows from box centres and disks at them.
#[derive(Clone, Debug, Default)]
pub struct FieldPanel {
    pub title: String,
    /// `(x, z, v_x, v_z)`: an arrow from `(x, z)` along `(v_x, v_z)`.
    pub arrows: Vec<(f64, f64, f64, f64)>,
    /// `(x, z, weight)`: a disk at `(x, z)` whose radius is proportional to the weight.
    pub disks: Vec<(f64, f64, f64)>,
}

/// A vector field over a region, in panels side by side (e.g. one per phase of a drive): the
/// ratchet paper's momentum and mass fields (seed 004, Figs 13-14). Every panel shares one
/// scale for arrows and one for disks, so that panels compare: an arrow at the 90th
/// percentile of all lengths is `reach` long and a disk at the 90th percentile of all
/// weights `reach / 2` in radius (in the axes' units); longer arrows and heavier disks are
/// drawn at most 1.5 times that, so that a few boxes do not shrink the rest to dots. A
/// polyline `outline` (e.g. the base's profile) is drawn in every panel.
#[derive(Clone, Debug)]
pub struct FieldPlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x: Range<f64>,
    pub y: Range<f64>,
    pub reach: f64,
    pub outline: Vec<(f64, f64)>,
    pub panels: Vec<FieldPanel>,
    /// Panels per row.
    pub columns: usize,
}

impl FieldPlot {
    /// Writes `<stem>.png` and `<stem>.svg`; returns the paths written.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        register_font();
        if self.panels.is_empty() || self.columns == 0 {
            return Err(PlotError(format!("{}: no panels", self.title)));
        }
        let png = with_extension(stem, "png");
        let svg = with_extension(stem, "svg");
        write_png(&png, SIZE, |root| self.render(root))?;
        write_svg(&svg, SIZE, |root| self.render(root))?;
        Ok(vec![png, svg])
    }

    fn render<DB: DrawingBackend>(&self, root: DrawingArea<DB, plotters::coord::Shift>) -> Result<(), PlotError>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(perr)?;
        let root = root.titled(&self.title, (FAMILY, 24)).map_err(perr)?;
        let rows = self.panels.len().div_ceil(self.columns);
        let areas = root.split_evenly((rows, self.columns));
        let longest = percentile_90(self.panels.iter().flat_map(|p| p.arrows.iter().map(|a| a.2.hypot(a.3))));
        let heaviest = percentile_90(self.panels.iter().flat_map(|p| p.disks.iter().map(|d| d.2)));
        for (panel, area) in self.panels.iter().zip(areas) {
            let mut chart = ChartBuilder::on(&area)
                .caption(&panel.title, (FAMILY, 17))
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(52)
                .build_cartesian_2d(self.x.clone(), self.y.clone())
                .map_err(perr)?;
            let (x_span, y_span) = (self.x.end - self.x.start, self.y.end - self.y.start);
            chart
                .configure_mesh()
                .x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .x_labels(4)
                .y_labels(5)
                .label_style((FAMILY, 12))
                .axis_desc_style((FAMILY, 13))
                .x_label_formatter(&|v| tick_on(*v, x_span, false))
                .y_label_formatter(&|v| tick_on(*v, y_span, false))
                .light_line_style(RGBColor(240, 240, 240))
                .draw()
                .map_err(perr)?;
            let pixels_per_unit = chart.plotting_area().dim_in_pixel().0 as f64 / x_span;
            if heaviest > 0.0 {
                chart
                    .draw_series(panel.disks.iter().filter(|d| d.2 > 0.0).map(|&(x, z, w)| {
                        let radius = (0.5 * self.reach * (w / heaviest).min(1.5) * pixels_per_unit).max(1.0);
                        Circle::new((x, z), radius.round() as i32, RGBColor(170, 190, 220).filled())
                    }))
                    .map_err(perr)?;
            }
            if self.outline.len() > 1 {
                chart
                    .draw_series(LineSeries::new(self.outline.clone(), BLACK.stroke_width(2)))
                    .map_err(perr)?;
            }
            if longest > 0.0 {
                let scale = self.reach / longest;
                for &(x, z, vx, vz) in &panel.arrows {
                    let clamp = (1.5 * self.reach / (vx.hypot(vz) * scale)).min(1.0);
                    let (dx, dz) = (vx * scale * clamp, vz * scale * clamp);
                    if !(dx.is_finite() && dz.is_finite()) || dx.hypot(dz) < 1e-3 * self.reach {
                        continue;
                    }
                    let tip = (x + dx, z + dz);
                    // A head of two strokes, a quarter of the arrow long, 25 degrees off it.
                    let (len, angle) = (0.25 * dx.hypot(dz), dz.atan2(dx));
                    let head = |turn: f64| {
                        let a = angle + std::f64::consts::PI + turn;
                        (tip.0 + len * a.cos(), tip.1 + len * a.sin())
                    };
                    let style = RGBColor(180, 30, 30).stroke_width(2);
                    chart
                        .draw_series([
                            PathElement::new(vec![(x, z), tip], style),
                            PathElement::new(vec![head(0.44), tip, head(-0.44)], style),
                        ])
                        .map_err(perr)?;
                }
            }
        }
        root.present().map_err(perr)
    }
}

/// Top views (x-y) of a tray at chosen times: every grain a disk of its radius, to show
/// whether bands span the tray's width. A long tray is cut into rows at most `5 width` or a
/// quarter of its length long (the longer), drawn one under the other, so that grains stay
/// visible; the picture grows with the rows.
#[derive(Clone, Debug)]
pub struct TopView {
    pub title: String,
    /// The tray's length (x, periodic) and width (y) (m).
    pub length: f64,
    pub width: f64,
    /// One panel per time.
    pub panels: Vec<TopPanel>,
}

/// One time of a [`TopView`]: its label and the grains as `(x, y, radius)`.
pub type TopPanel = (String, Vec<(f64, f64, f64)>);

impl TopView {
    /// Pixels across the picture.
    const WIDTH: u32 = 1200;

    fn rows(&self) -> (usize, f64) {
        let segment = (5.0 * self.width).max(0.25 * self.length).min(self.length);
        let rows = (self.length / segment - 1e-9).ceil().max(1.0) as usize;
        (rows, self.length / rows as f64)
    }

    /// Writes `<stem>.png` and `<stem>.svg`; returns the paths written.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        register_font();
        if self.panels.is_empty() || !(self.length > 0.0 && self.width > 0.0) {
            return Err(PlotError(format!("{}: no panels or an empty tray", self.title)));
        }
        let (rows, segment) = self.rows();
        // Each row keeps the tray's aspect, plus room for its caption and x labels.
        let row_px = (f64::from(Self::WIDTH - 70) * self.width / segment).round() as u32 + 60;
        let size = (Self::WIDTH, 50 + row_px * (rows * self.panels.len()) as u32);
        let png = with_extension(stem, "png");
        let svg = with_extension(stem, "svg");
        write_png(&png, size, |root| self.render(root))?;
        write_svg(&svg, size, |root| self.render(root))?;
        Ok(vec![png, svg])
    }

    fn render<DB: DrawingBackend>(&self, root: DrawingArea<DB, plotters::coord::Shift>) -> Result<(), PlotError>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(perr)?;
        let root = root.titled(&self.title, (FAMILY, 22)).map_err(perr)?;
        let (rows, segment) = self.rows();
        let areas = root.split_evenly((rows * self.panels.len(), 1));
        let mut areas = areas.into_iter();
        for (label, grains) in &self.panels {
            for row in 0..rows {
                let area = areas.next().expect("one area per row");
                let (lo, hi) = (row as f64 * segment, (row + 1) as f64 * segment);
                let caption = if rows == 1 {
                    label.clone()
                } else {
                    format!("{label}, x from {} to {} m", tick(lo), tick(hi))
                };
                let mut chart = ChartBuilder::on(&area)
                    .caption(caption, (FAMILY, 14))
                    .margin_left(10)
                    .margin_right(10)
                    .x_label_area_size(22)
                    .y_label_area_size(50)
                    .build_cartesian_2d(lo..hi, 0.0..self.width)
                    .map_err(perr)?;
                chart
                    .configure_mesh()
                    .disable_mesh()
                    .x_labels(8)
                    .y_labels(2)
                    .label_style((FAMILY, 11))
                    .x_label_formatter(&|v| tick_on(*v, segment, false))
                    .y_label_formatter(&|v| tick_on(*v, self.width, false))
                    .draw()
                    .map_err(perr)?;
                let px_per_m = f64::from(chart.plotting_area().dim_in_pixel().0) / segment;
                // Dark grains on white, as the thesis' pictures with inverted colours.
                let style = RGBColor(30, 30, 30).filled();
                chart
                    .draw_series(
                        grains
                            .iter()
                            .filter(|g| g.0 >= lo - g.2 && g.0 < hi + g.2)
                            .map(|&(x, y, r)| Circle::new((x, y), ((r * px_per_m).round() as i32).max(1), style)),
                    )
                    .map_err(perr)?;
            }
        }
        root.present().map_err(perr)
    }
}

/// The 90th percentile of the finite positive values (0 when there are none).
fn percentile_90(values: impl Iterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite() && *x > 0.0).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[(0.9 * (v.len() - 1) as f64).round() as usize]
}

/// Class labels drawn over a heat map (see [`Heatmap::save_with_classes`]).
struct Overlay<'a> {
    classes: &'a [Vec<usize>],
    names: &'a [&'a str],
}

fn with_extension(stem: &Path, ext: &str) -> PathBuf {
    let mut name = stem.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".");
    name.push(ext);
    stem.with_file_name(name)
}

fn temp_for(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

fn write_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(DrawingArea<BitMapBackend, plotters::coord::Shift>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    // The bitmap encoder infers the format from the extension, so the temporary keeps `.png`.
    let tmp = temp_for(path).with_extension("tmp.png");
    let result = (|| {
        draw(BitMapBackend::new(&tmp, size).into_drawing_area())?;
        std::fs::rename(&tmp, path).map_err(|e| PlotError(format!("cannot write {}: {e}", path.display())))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

fn write_svg(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(DrawingArea<SVGBackend, plotters::coord::Shift>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    let mut text = String::new();
    draw(SVGBackend::with_string(&mut text, size).into_drawing_area())?;
    crate::io::write_atomic(path, text.as_bytes()).map_err(|e| PlotError(format!("cannot write {}: {e}", path.display())))
}

#[cfg(test)]
mod tests {

    #[test]
    fn a_non_finite_y_breaks_a_line_into_runs() {
        let pts = vec![(1.0, 1.0), (2.0, 2.0), (3.0, f64::NAN), (4.0, 1.0), (-1.0, 3.0), (5.0, f64::NAN)];
        let plot = LinePlot::new("gaps", "t", "S").series("S", pts.clone(), Mark::Line);
        assert_eq!(plot.line_runs(0), vec![vec![(1.0, 1.0), (2.0, 2.0)], vec![(4.0, 1.0), (-1.0, 3.0)]]);
        // On a log x axis the point at x = -1 is not drawable; it does not break the run.
        let plot = LinePlot::new("gaps", "t", "S").log_x().series("S", pts, Mark::Line);
        assert_eq!(plot.line_runs(0), vec![vec![(1.0, 1.0), (2.0, 2.0)], vec![(4.0, 1.0)]]);
    }

    #[test]
    fn a_dense_series_draws_nothing_outside_the_plot_area() {
        // 5000 points between counts 0 and 3 on a log time axis (a long run's stripe count):
        // the bitmap's thick lines once drew spikes below the x axis, over the labels, for
        // the nearly vertical segments. No pixel of the series' colour may lie below the
        // plot area.
        register_font();
        for n in [100, 5000] {
            let pts: Vec<(f64, f64)> = (0..n)
                .map(|k| (400.0 + 0.34 * k as f64, ((k * 7919 + k / 13) % 4) as f64))
                .collect();
            let plot = LinePlot::new("dense", "t (s)", "S")
                .integer_y()
                .include_y(0.0)
                .log_x()
                .series("S", pts, Mark::LinePoints);
            let (x, y) = plot.ranges();
            let (w, h) = SIZE;
            let mut buf = vec![255u8; (w * h * 3) as usize];
            {
                let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
                plot.render_axes(root, x, y).unwrap();
            }
            let blue = PALETTE[0];
            let is_blue = |row: u32, col: u32| {
                let i = ((row * w + col) * 3) as usize;
                (buf[i], buf[i + 1], buf[i + 2]) == (blue.0, blue.1, blue.2)
            };
            // The plot area ends above the x label area (55 px) and the margin (20 px).
            let bottom = h - 20 - 55 + 3;
            let stray = (bottom..h)
                .flat_map(|row| (0..w).map(move |col| (row, col)))
                .filter(|&(r, c)| is_blue(r, c))
                .count();
            assert_eq!(stray, 0, "{n} points: {stray} pixels of the series below the plot area");
            let drawn = (0..bottom)
                .flat_map(|row| (0..w).map(move |col| (row, col)))
                .filter(|&(r, c)| is_blue(r, c))
                .count();
            assert!(drawn > 1000, "{n} points: the series drew {drawn} pixels");
        }
    }

    /// Error bars: drawn where the error is a positive number, left out where a bar would
    /// reach below zero on a log axis, and taken into the axis range.
    #[test]
    fn error_bars_are_drawn_where_they_can_be() {
        let p = LinePlot::new("t", "x", "y").series_with_errors(
            "a",
            vec![(1.0, 1.0), (2.0, 2.0), (3.0, f64::NAN), (4.0, 3.0)],
            vec![0.5, f64::NAN, 1.0, 0.0],
            Mark::LinePoints,
        );
        assert_eq!(p.bars(0), vec![(1.0, 0.5, 1.5)]);
        assert_eq!(p.clone().log_y().bars(0), vec![(1.0, 0.5, 1.5)]);
        let below_zero = LinePlot::new("t", "x", "y")
            .log_y()
            .series_with_errors("a", vec![(1.0, 1.0)], vec![2.0], Mark::Points);
        assert!(below_zero.bars(0).is_empty());
        let dir = std::env::temp_dir().join(format!("stripes-plot-errors-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let files = p.save(&dir.join("e")).unwrap();
        assert!(files.iter().all(|f| std::fs::metadata(f).map(|m| m.len() > 0).unwrap_or(false)));
        let _ = std::fs::remove_dir_all(dir);
    }

    /// The MSD plot's lowest decade had no label: a log range now starts just below a power
    /// of ten, so that the lowest decade's tick lies inside it.
    #[test]
    fn a_log_range_starts_just_below_a_decade() {
        let r = padded([3.2e-9, 4.0e-6].into_iter(), true).unwrap();
        assert!(r.start < 1e-9 && r.start > 0.9e-9, "{r:?}");
        assert!(r.end > 4.0e-6);
        let r = padded([1e-8, 1e-4].into_iter(), true).unwrap();
        assert!(r.start < 1e-8 && r.start > 0.9e-9 * 0.9, "{r:?}");
    }

    /// Legends covered data in `thermo.png` and `stripe_count.png`: with two or more series
    /// the y range grows so that the legend's corner holds no data, above the data for an
    /// upper legend, below for a lower one; a single series needs no legend room.
    #[test]
    fn the_legend_gets_a_corner_without_data() {
        let two = LinePlot::new("t", "x", "y")
            .series("a", vec![(0.0, 0.0), (1.0, 1.0)], Mark::Line)
            .series("b", vec![(0.0, 0.5)], Mark::Line);
        let up = two.legend_room(0.0..1.0);
        assert!(up.start == 0.0 && up.end > 1.1, "{up:?}");
        let low = two.clone().legend(LegendCorner::LowerRight).legend_room(0.0..1.0);
        assert!(low.end == 1.0 && low.start < -0.1, "{low:?}");
        let one = LinePlot::new("t", "x", "y").series("a", vec![(0.0, 0.0)], Mark::Line);
        assert_eq!(one.legend_room(0.0..1.0), 0.0..1.0);
    }

    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("stripes-plot-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn line_plot_writes_png_and_svg_even_with_unplottable_points() {
        let d = temp_dir("line");
        let plot = LinePlot::new("Test", "x", "y")
            .series("a", vec![(0.0, 1.0), (1.0, 2.0), (2.0, 0.0), (3.0, f64::NAN)], Mark::Line)
            .series("b", vec![(1.0, 1.0)], Mark::Points)
            .log_y();
        let files = plot.save(&d.join("p")).unwrap();
        assert_eq!(files.len(), 2);
        for f in &files {
            assert!(std::fs::metadata(f).unwrap().len() > 1000, "{}", f.display());
        }
        assert!(std::fs::read_to_string(&files[1]).unwrap().contains("<svg"));
        let leftovers = std::fs::read_dir(&d)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with('.'))
            .count();
        assert_eq!(leftovers, 0, "temporary files left behind");
        std::fs::remove_dir_all(d).unwrap();
    }

    /// A long tray is cut into rows that keep grains visible, and the picture grows with
    /// them: 0.4 m x 0.02 m gives four rows of 0.1 m per time; a 0.1 m tray one.
    #[test]
    fn a_top_view_cuts_a_long_tray_into_rows() {
        let grains: Vec<(f64, f64, f64)> = (0..400).map(|k| (k as f64 * 1e-3, 0.01, 4e-4)).collect();
        let view = |length: f64| TopView {
            title: "top".into(),
            length,
            width: 0.02,
            panels: vec![("t = 0 s".into(), grains.clone()), ("t = 1 s".into(), grains.clone())],
        };
        let (rows, segment) = view(0.4).rows();
        assert_eq!(rows, 4);
        assert!((segment - 0.1).abs() < 1e-12);
        assert_eq!(view(0.1).rows().0, 1);
        assert_eq!(view(0.05).rows(), (1, 0.05));
        let d = temp_dir("top");
        let files = view(0.4).save(&d.join("top")).unwrap();
        let png = image_height(&files[0]);
        // 2 times x 4 rows of (1130 px x 0.2 + 60 px) + 50 px of title.
        assert_eq!(png, 50 + 8 * 286);
        assert!(TopView {
            panels: vec![],
            ..view(0.4)
        }
        .save(&d.join("none"))
        .is_err());
        std::fs::remove_dir_all(d).unwrap();
    }

    /// The height of a PNG, from its header.
    fn image_height(path: &Path) -> u32 {
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        u32::from_be_bytes(bytes[20..24].try_into().unwrap())
    }

    /// Issue 19, point 14: stripe counts get whole-number ticks.
    #[test]
    fn count_axes_label_whole_numbers_only() {
        assert_eq!((count_tick(2.0), count_tick(0.5)), ("2".to_string(), String::new()));
        assert!(LinePlot::new("t", "x", "y").integer_y().integer_y);
    }

    #[test]
    fn heatmap_writes_and_handles_constant_and_nan_cells() {
        let d = temp_dir("heat");
        let h = Heatmap {
            title: "Density".into(),
            x_label: "x (m)".into(),
            y_label: "t (s)".into(),
            x_range: (0.0, 0.4),
            y_range: (0.0, 20.0),
            values: vec![vec![0.2, 0.2, f64::NAN], vec![0.2, 0.2, 0.2]],
            colorbar_label: "phi".into(),
            scale: None,
            cell_names: None,
        };
        let files = h.save(&d.join("h")).unwrap();
        assert!(files.iter().all(|f| std::fs::metadata(f).unwrap().len() > 1000));
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn tick_labels_are_compact() {
        assert_eq!(tick(5e-4), "5e-4");
        assert_eq!(tick(2.5e-5), "2.5e-5");
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(1e5), "1e5");
        assert_eq!(tick_on(-1.11e-16, 0.9, false), "0", "round-off at zero");
        assert_eq!(tick_on(-1e-7, 1e-6, false), "-1e-7", "small values on a small axis stay");
        assert_eq!(tick_on(1e-6, 800.0, true), "1e-6", "a log axis spanning 1e-6..800 has no zero");
    }

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), RGBColor(68, 1, 84));
    }
}

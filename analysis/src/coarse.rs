//! What the coarse model (the automaton) needs from a DEM run, measured on its frames
//! (issue 40, step 1): never fitted to patterns.
//!
//! A grain's move over a half period of the drive is the change of its position **in the
//! tray's frame** between two consecutive turning points of the tray (`+A` then `-A`, or the
//! reverse): the automaton's unit of time. For every such pair of frames and every grain:
//! - the excursion along the shaking direction `|dx|` and the sideways step `|dy|`;
//! - the grain's local state at the first frame: its local packing (the projected area of the
//!   grains whose centres lie within [`LOCAL_RADIUS_DIAMETERS`] mean diameters, over that
//!   disk's area) and its contact number (grains nearer than `(r_i + r_j)(1 +`
//!   [`CONTACT_GAP`]`)`).
//!
//! On a periodic tray a move is taken as its nearest periodic image: the tray must be longer
//! than twice the largest excursion (a free sphere rolling without slip swings `(5/7) 2A`).
//!
//! Excursions are tabled by packing class ([`PACKING_EDGES`]) and by contact number, with
//! mean, spread and quantiles, over the half periods before the bands form (before the
//! camera's stripe onset, or every half period where none forms).
//!
//! Bands are the camera's ([`crate::stripes::detect`] on the tray-frame profile of each
//! turning-point frame). A grain is in a band when its tray-frame x lies in one. Measured, from
//! each turning point to the same one a period later (between the two turning points a band's
//! grains swing against the tray by about a band's width: on the stripe scene 0.87-1.0 of them
//! are outside the bands half a period later, 0.09-0.35 a period later): how long grains stay
//! in bands (runs of consecutive periods, those cut by the start or end of the record left
//! out), the rate at which grains leave a band per period, over all its grains and over those
//! within one mean diameter of its edges, and the area fraction of the band cores (the central
//! half of each band).

use serde::Serialize;

use crate::density::{add_area_fraction_cells, mean_area_fraction};
use crate::drive::TrayDrive;
use crate::snapshot::{Frame, Header};
use crate::stripes::{detect, Stripe, StripeParams};

/// Radius of the disk over which a grain's local packing is taken, in mean diameters.
pub const LOCAL_RADIUS_DIAMETERS: f64 = 2.5;

/// Two grains touch when their centres are nearer than `(r_i + r_j)(1 + CONTACT_GAP)`.
pub const CONTACT_GAP: f64 = 0.05;

/// Upper edges of the packing classes (the last class is everything above the last edge).
pub const PACKING_EDGES: [f64; 8] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8];

/// Contact numbers tabled one by one up to this; more are pooled into the last row.
pub const MAX_CONTACTS: usize = 6;

/// Frames farther than this from a turning point (fraction of a period) are not used.
pub const MAX_OFFSET: f64 = 0.125;

/// Why the measures cannot be taken; each names the quantity.
#[derive(Debug, Clone, PartialEq)]
pub enum CoarseError {
    /// No drive that moves the tray: there are no half periods.
    NoDrive,
    /// Fewer than two turning-point frames one half period apart.
    TooShort { quantity: &'static str, half_periods: usize },
}

impl std::fmt::Display for CoarseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CoarseError::NoDrive => write!(f, "the run's drive does not move the tray: no half periods to measure"),
            CoarseError::TooShort { quantity, half_periods } => write!(
                f,
                "{quantity}: the run holds {half_periods} pairs of turning-point frames half a period apart, at least 1 is needed \
                 (write at least 2 snapshots per period, at the turning points, e.g. run.snapshots_per_period = 4)"
            ),
        }
    }
}

impl std::error::Error for CoarseError {}

/// A frame at a turning point of the tray.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TurningFrame {
    /// Index among the run's frames.
    pub frame: usize,
    pub time: f64,
    /// The tray's displacement then (m).
    pub tray_x: f64,
    /// `+1` at `+A`, `-1` at `-A`.
    pub side: i8,
    /// Stage of the drive and half period within it (consecutive half periods differ by 1).
    pub stage: usize,
    pub half: i64,
}

/// The frames nearest each turning point (`+A` and `-A`) of a moving drive, within
/// [`MAX_OFFSET`] of a period, in time order.
pub fn turning_frames(times: &[f64], drive: &TrayDrive) -> Vec<TurningFrame> {
    let mut out: Vec<(TurningFrame, f64)> = Vec::new();
    for (frame, &time) in times.iter().enumerate() {
        let Some(tp) = drive.turning_point(time) else {
            continue;
        };
        // Half periods since the stage's first +A turning point: even at +A, odd at -A.
        let q = 2.0 * tp.offset;
        let step = q.round();
        let residual = (q - step).abs() / 2.0;
        if residual > MAX_OFFSET + 1e-12 {
            continue;
        }
        let half = 2 * tp.index + step as i64;
        let here = TurningFrame {
            frame,
            time,
            tray_x: drive.displacement(time),
            side: if half.rem_euclid(2) == 0 { 1 } else { -1 },
            stage: tp.stage,
            half,
        };
        match out.last_mut() {
            Some((prev, r)) if prev.stage == here.stage && prev.half == here.half => {
                if residual < *r {
                    *prev = here;
                    *r = residual;
                }
            }
            _ => out.push((here, residual)),
        }
    }
    out.into_iter().map(|(f, _)| f).collect()
}

/// Mean, spread and quantiles of a set of lengths (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Default)]
pub struct Spread {
    pub samples: usize,
    pub mean: f64,
    /// Standard deviation.
    pub sd: f64,
    pub q10: f64,
    pub q25: f64,
    pub median: f64,
    pub q75: f64,
    pub q90: f64,
}

impl Spread {
    /// The statistics of `values` (consumed: sorted in place); all zero when empty.
    pub fn of(mut values: Vec<f64>) -> Self {
        let n = values.len();
        if n == 0 {
            return Spread::default();
        }
        values.sort_by(f64::total_cmp);
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n.max(2) - 1) as f64;
        let q = |p: f64| {
            let pos = p * (n - 1) as f64;
            let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
            values[lo] + (values[hi] - values[lo]) * (pos - lo as f64)
        };
        Spread {
            samples: n,
            mean,
            sd: if n > 1 { var.sqrt() } else { 0.0 },
            q10: q(0.1),
            q25: q(0.25),
            median: q(0.5),
            q75: q(0.75),
            q90: q(0.9),
        }
    }
}

/// Excursions of one class of local state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClassMoves {
    /// The class: packing range `[low, high)`, or contact number `low` (= `high`; the last
    /// row holds every number from it on).
    pub low: f64,
    pub high: f64,
    /// `|dx|` per half period (m).
    pub excursion: Spread,
    /// `|dy|` per half period (m).
    pub sideways: Spread,
}

/// The swing at one class of window packing ([`SwingField`]), over every half period of the
/// run (the swing field of the automaton's `swing` rule).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SwingClass {
    /// Packing range `[low, high)` (the last class: from `low` on) and the mean packing of
    /// the grains in it.
    pub low: f64,
    pub high: f64,
    pub packing: f64,
    /// `|dx|` per half period (m).
    pub swing: Spread,
    /// The signed move less the mean move of the other grains within
    /// [`LOCAL_RADIUS_DIAMETERS`] mean diameters (m): its `sd` is how far a grain moves apart
    /// from its neighbourhood.
    pub relative: Spread,
}

/// The swing against the packing of a window around the grain, over the whole run: dense
/// packings occur only once bands have formed, so this table is taken over every half
/// period, not only before the onset as the excursion tables are.
///
/// The window reaches [`LOCAL_RADIUS_DIAMETERS`] mean diameters along x and `across_m`
/// across: as far as grains move together across the tray (the correlation of two grains'
/// moves, each less the half period's mean move, for pairs within the same reach along x,
/// falls below 1/e at `across_m`, at least one mean diameter; the tray's width where it
/// never does).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SwingField {
    /// The window's end (s): half periods starting before it; None: the whole run.
    pub until_s: Option<f64>,
    pub half_periods: usize,
    /// The window's half-length along x and half-height across (m).
    pub reach_m: f64,
    pub across_m: f64,
    /// The correlation of moves across the tray, per bin of one mean diameter of `|dy|`
    /// (None: no pair).
    pub correlation_across: Vec<Option<f64>>,
    pub classes: Vec<SwingClass>,
}

/// The band measures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bands {
    /// Turning-point frames holding at least one band.
    pub frames_with_bands: usize,
    /// Mean area fraction of the band cores (the central half of each band), None without
    /// bands.
    pub core_packing: Option<f64>,
    /// Stays still running at the end of the record, or begun before its start.
    pub residence_censored: usize,
    /// Per drive period (from a turning point to the same one a period later), the fraction
    /// of a band's grains that are in no band then: over all band grains, and over those
    /// within one mean diameter of an edge.
    pub escape_per_period: Option<f64>,
    pub edge_escape_per_period: Option<f64>,
    /// Grain-periods behind the two rates.
    pub band_samples: usize,
    pub edge_samples: usize,
    /// Completed stays in a band, in periods (seen at one turning point; stays cut by the
    /// record's start or end left out).
    pub residence_periods: Spread,
}

/// Everything measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Coarse {
    pub turning_frames: usize,
    /// Half periods measured for the excursions (before `before_s`).
    pub half_periods: usize,
    /// End of the window of the excursions (s): the stripe onset given, or the run's end.
    pub before_s: Option<f64>,
    pub mean_diameter_m: f64,
    pub mean_packing: f64,
    /// Every excursion of the window.
    pub all: ClassMoves,
    /// Over two consecutive half periods with moves `dx1`, `dx2` (signed): the swing
    /// `|dx1 - dx2| / 2` (the back-and-forth; `(5/7) 2A` for a sphere rolling without slip,
    /// whatever it carries along) and the drift over the period `|dx1 + dx2|` (m).
    pub swing: Spread,
    pub drift: Spread,
    /// The signed drift over the period `dx1 + dx2` along the tray's x (m; `+` towards +x),
    /// and the fraction of the periods in which it is positive (0.5 when the tray's two
    /// strokes move grains alike).
    pub drift_signed: Spread,
    pub drift_positive_fraction: f64,
    pub by_packing: Vec<ClassMoves>,
    pub by_contacts: Vec<ClassMoves>,
    pub swing_field: SwingField,
    pub bands: Bands,
    /// Bands counted at each turning-point frame.
    pub frames: Vec<FrameBands>,
}

/// The bands of one turning-point frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrameBands {
    pub time: f64,
    /// `+1` at `+A`, `-1` at `-A`.
    pub side: i8,
    pub bands: usize,
    /// Fraction of the grains in bands.
    pub in_bands: f64,
}

/// A half period's tray-frame positions `x`, `y` at its start and moves along x.
type HalfPeriod = (Vec<f64>, Vec<f64>, Vec<f64>);

/// One grain's move over a half period, with its local state at the start.
struct Move {
    packing: f64,
    contacts: usize,
    dx: f64,
    dy: f64,
}

/// Calls `visit(k, m, dx, dy)` for every grain `k` and every grain `m` (`k` itself included)
/// whose centre lies within `reach` of `k`'s (`dx`, `dy` from `k` to `m`, the nearest image
/// across x when `periodic`), on a tray of `length` x `width`.
fn for_neighbours(
    x: &[f64],
    y: &[f64],
    length: f64,
    width: f64,
    periodic: bool,
    reach: f64,
    mut visit: impl FnMut(usize, usize, f64, f64),
) {
    let n = x.len();
    let (cx, cy) = (
        ((length / reach).floor() as usize).max(1),
        ((width / reach).floor() as usize).max(1),
    );
    let (hx, hy) = (length / cx as f64, width / cy as f64);
    let key = |xi: f64, yi: f64| {
        let i = ((xi.rem_euclid(length) / hx) as usize).min(cx - 1);
        let j = ((yi / hy).floor().clamp(0.0, (cy - 1) as f64)) as usize;
        (i, j)
    };
    let mut cells: Vec<Vec<usize>> = vec![Vec::new(); cx * cy];
    for k in 0..n {
        let (i, j) = key(x[k], y[k]);
        cells[j * cx + i].push(k);
    }
    for k in 0..n {
        let (i, j) = key(x[k], y[k]);
        for dj in -1i64..=1 {
            let jj = j as i64 + dj;
            if jj < 0 || jj >= cy as i64 {
                continue;
            }
            let mut columns: Vec<usize> = Vec::with_capacity(3);
            for di in -1i64..=1 {
                let ii = i as i64 + di;
                if !periodic && (ii < 0 || ii >= cx as i64) {
                    continue;
                }
                // A tray of fewer than three columns must not visit one twice.
                let ii = ii.rem_euclid(cx as i64) as usize;
                if !columns.contains(&ii) {
                    columns.push(ii);
                }
            }
            for &ii in &columns {
                for &m in &cells[jj as usize * cx + ii] {
                    let mut dx = x[m] - x[k];
                    if periodic {
                        dx -= length * (dx / length).round();
                    }
                    let dy = y[m] - y[k];
                    if dx * dx + dy * dy <= reach * reach {
                        visit(k, m, dx, dy);
                    }
                }
            }
        }
    }
}

/// Local packing and contact number of every grain of a frame (positions `x`, `y`, tray of
/// `length` periodic in x when `periodic`, and `width`).
pub fn local_state(x: &[f64], y: &[f64], radii: &[f64], length: f64, width: f64, periodic: bool, mean_d: f64) -> (Vec<f64>, Vec<usize>) {
    let n = x.len();
    let reach = LOCAL_RADIUS_DIAMETERS * mean_d;
    let rmax = radii.iter().copied().fold(0.0, f64::max);
    let search = reach.max(2.0 * rmax * (1.0 + CONTACT_GAP));
    let disk = std::f64::consts::PI * reach * reach;
    let mut area = vec![0.0; n];
    let mut contacts = vec![0; n];
    for_neighbours(x, y, length, width, periodic, search, |k, m, dx, dy| {
        let d2 = dx * dx + dy * dy;
        if d2 <= reach * reach {
            area[k] += std::f64::consts::PI * radii[m] * radii[m];
        }
        let touch = (radii[k] + radii[m]) * (1.0 + CONTACT_GAP);
        if m != k && d2 < touch * touch {
            contacts[k] += 1;
        }
    });
    (area.into_iter().map(|a| a / disk).collect(), contacts)
}

/// Each grain's signed move `moves[k]` less the mean move of the other grains within
/// [`LOCAL_RADIUS_DIAMETERS`] mean diameters of it at the positions `x`, `y` (None for a
/// grain with no such neighbour): how far a grain moves apart from its neighbourhood.
pub fn relative_moves(x: &[f64], y: &[f64], moves: &[f64], length: f64, width: f64, periodic: bool, mean_d: f64) -> Vec<Option<f64>> {
    let n = x.len();
    let mut sum = vec![(0.0, 0usize); n];
    for_neighbours(x, y, length, width, periodic, LOCAL_RADIUS_DIAMETERS * mean_d, |k, m, _, _| {
        if m != k {
            sum[k].0 += moves[m];
            sum[k].1 += 1;
        }
    });
    sum.iter()
        .zip(moves)
        .map(|(&(s, c), &d)| (c > 0).then(|| d - s / c as f64))
        .collect()
}

/// Where the measures are taken (s; None: the whole run): the excursion tables over the half
/// periods that start before `before` (the stripe onset), the swing field over those that
/// start before `swing_until`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Windows {
    pub before: Option<f64>,
    pub swing_until: Option<f64>,
}

/// The measures of a run: `frames` in time order of a tray of `header`, periodic in x when
/// `periodic`, shaken by `drive`, in the `windows`; bands counted with `params` on `cells`
/// cells.
pub fn measure(
    header: &Header,
    frames: &[Frame],
    drive: &TrayDrive,
    periodic: bool,
    windows: Windows,
    params: &StripeParams,
    cells: usize,
) -> Result<Coarse, CoarseError> {
    let before = windows.before;
    if drive.shortest_period().is_none() {
        return Err(CoarseError::NoDrive);
    }
    let (l, w) = (header.length, header.width);
    let radii = &header.radii;
    let n = radii.len();
    let mean_d = 2.0 * radii.iter().sum::<f64>() / n.max(1) as f64;
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    let turning = turning_frames(&times, drive);
    let pairs: Vec<(TurningFrame, TurningFrame)> = turning
        .windows(2)
        .filter(|p| p[0].stage == p[1].stage && p[1].half == p[0].half + 1)
        .map(|p| (p[0], p[1]))
        .collect();
    let window: Vec<&(TurningFrame, TurningFrame)> = pairs.iter().filter(|(a, _)| before.is_none_or(|t| a.time < t)).collect();
    if window.is_empty() {
        return Err(CoarseError::TooShort {
            quantity: "excursion per half period",
            half_periods: window.len(),
        });
    }
    let tray = |f: &TurningFrame| -> (Vec<f64>, Vec<f64>) {
        let p = &frames[f.frame].pos;
        (p.iter().map(|q| q[0] - f.tray_x).collect(), p.iter().map(|q| q[1]).collect())
    };
    // Excursions with the local state at the pair's first frame; the signed moves of each
    // pair, to split two consecutive half periods into a swing and a drift.
    let mut moves: Vec<Move> = Vec::new();
    let mut signed: Vec<Vec<f64>> = Vec::new();
    for (a, b) in &window {
        let (xa, ya) = tray(a);
        let (xb, yb) = tray(b);
        let (packing, contacts) = local_state(&xa, &ya, radii, l, w, periodic, mean_d);
        let mut pair = Vec::with_capacity(n);
        for k in 0..n {
            let mut dx = xb[k] - xa[k];
            if periodic {
                dx -= l * (dx / l).round();
            }
            pair.push(dx);
            moves.push(Move {
                packing: packing[k],
                contacts: contacts[k],
                dx: dx.abs(),
                dy: (yb[k] - ya[k]).abs(),
            });
        }
        signed.push(pair);
    }
    // Two consecutive half periods (the second starts where the first ends): the swing
    // `|dx1 - dx2| / 2` and the drift over the period `|dx1 + dx2|`.
    let (mut swing, mut drift, mut drift_signed) = (Vec::new(), Vec::new(), Vec::new());
    for k in 1..window.len() {
        if window[k].0.frame != window[k - 1].1.frame {
            continue;
        }
        for (d1, d2) in signed[k - 1].iter().zip(&signed[k]) {
            swing.push(0.5 * (d1 - d2).abs());
            drift.push((d1 + d2).abs());
            drift_signed.push(d1 + d2);
        }
    }
    let drift_positive_fraction = if drift_signed.is_empty() {
        0.5
    } else {
        drift_signed.iter().filter(|&&d| d > 0.0).count() as f64 / drift_signed.len() as f64
    };
    let class = |low: f64, high: f64, pick: &dyn Fn(&Move) -> bool| ClassMoves {
        low,
        high,
        excursion: Spread::of(moves.iter().filter(|m| pick(m)).map(|m| m.dx).collect()),
        sideways: Spread::of(moves.iter().filter(|m| pick(m)).map(|m| m.dy).collect()),
    };
    let mut by_packing = Vec::new();
    let mut low = 0.0;
    for (c, &high) in PACKING_EDGES.iter().chain(std::iter::once(&f64::INFINITY)).enumerate() {
        let last = c == PACKING_EDGES.len();
        let row = class(low, high, &|m| m.packing >= low && (last || m.packing < high));
        if row.excursion.samples > 0 {
            by_packing.push(row);
        }
        low = high;
    }
    let by_contacts: Vec<ClassMoves> = (0..=MAX_CONTACTS)
        .map(|z| {
            class(z as f64, z as f64, &|m| {
                if z == MAX_CONTACTS {
                    m.contacts >= z
                } else {
                    m.contacts == z
                }
            })
        })
        .filter(|r| r.excursion.samples > 0)
        .collect();
    let all = class(0.0, f64::INFINITY, &|_| true);
    let (swing, drift, drift_signed) = (Spread::of(swing), Spread::of(drift), Spread::of(drift_signed));
    let half_periods: Vec<HalfPeriod> = pairs
        .iter()
        .filter(|(a, _)| windows.swing_until.is_none_or(|t| a.time < t))
        .map(|(a, b)| {
            let ((xa, ya), (xb, _)) = (tray(a), tray(b));
            let dx = xa
                .iter()
                .zip(&xb)
                .map(|(p, q)| if periodic { (q - p) - l * ((q - p) / l).round() } else { q - p })
                .collect();
            (xa, ya, dx)
        })
        .collect();
    if half_periods.is_empty() {
        return Err(CoarseError::TooShort {
            quantity: "swing field (half periods before the swing field's window end)",
            half_periods: 0,
        });
    }
    let swing_field = SwingField {
        until_s: windows.swing_until,
        ..swing_field(&half_periods, radii, l, w, periodic, mean_d)
    };
    let (bands, per_frame) = band_measures(header, frames, &turning, params, cells, mean_d);
    Ok(Coarse {
        turning_frames: turning.len(),
        half_periods: window.len(),
        before_s: before,
        mean_diameter_m: mean_d,
        mean_packing: mean_area_fraction(radii, l, w),
        all,
        swing,
        drift,
        drift_signed,
        drift_positive_fraction,
        by_packing,
        by_contacts,
        swing_field,
        bands,
        frames: per_frame,
    })
}

/// Calls `visit(k, m, dy)` for every pair of grains `k != m` whose centres are at most
/// `reach` apart along x (the nearest image when `periodic`), each pair once, with their
/// separation across `dy = |y_m - y_k|`.
fn strip_pairs(x: &[f64], y: &[f64], length: f64, periodic: bool, reach: f64, mut visit: impl FnMut(usize, usize, f64)) {
    let n = x.len();
    let mut order: Vec<usize> = (0..n).collect();
    let xs: Vec<f64> = x.iter().map(|v| if periodic { v.rem_euclid(length) } else { *v }).collect();
    order.sort_by(|&a, &b| xs[a].total_cmp(&xs[b]));
    for (p, &k) in order.iter().enumerate() {
        // Partners ahead in x order, round the seam when periodic; each pair once.
        for q in 1..n {
            let idx = p + q;
            if idx >= n && !periodic {
                break;
            }
            let m = order[idx % n];
            let ahead = if idx < n { xs[m] - xs[k] } else { xs[m] + length - xs[k] };
            if ahead > reach || (periodic && 2.0 * ahead > length) {
                break;
            }
            visit(k, m, (y[m] - y[k]).abs());
        }
    }
}

/// The correlation of two grains' moves (each less the half period's mean move) against
/// their separation across the tray, in bins of `bin` (m), for pairs within `reach` along x,
/// over half periods of moves `dx` at positions `(x, y)`: running sums per bin.
struct AcrossCorrelation {
    bin: f64,
    products: Vec<f64>,
    pairs: Vec<usize>,
    squares: f64,
    grains: usize,
}

impl AcrossCorrelation {
    fn new(width: f64, bin: f64) -> Self {
        let bins = (width / bin).ceil().max(1.0) as usize;
        Self {
            bin,
            products: vec![0.0; bins],
            pairs: vec![0; bins],
            squares: 0.0,
            grains: 0,
        }
    }

    fn add(&mut self, x: &[f64], y: &[f64], dx: &[f64], length: f64, periodic: bool, reach: f64) {
        let mean = dx.iter().sum::<f64>() / dx.len().max(1) as f64;
        let dev: Vec<f64> = dx.iter().map(|d| d - mean).collect();
        self.squares += dev.iter().map(|d| d * d).sum::<f64>();
        self.grains += dev.len();
        let last = self.pairs.len() - 1;
        strip_pairs(x, y, length, periodic, reach, |k, m, dy| {
            let b = ((dy / self.bin) as usize).min(last);
            self.products[b] += dev[k] * dev[m];
            self.pairs[b] += 1;
        });
    }

    /// The correlation per bin (None where no pair fell).
    fn values(&self) -> Vec<Option<f64>> {
        let var = self.squares / self.grains.max(1) as f64;
        self.products
            .iter()
            .zip(&self.pairs)
            .map(|(&s, &c)| (c > 0 && var > 0.0).then(|| s / c as f64 / var))
            .collect()
    }
}

/// A window around a grain: `|dx| <= reach` along x and `|dy| <= across` across (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    pub reach: f64,
    pub across: f64,
}

/// Each grain's packing in its [`Window`] (clamped to the tray's `width`): the projected
/// area of the grains centred in it over the window's area inside the tray.
pub fn window_packing(x: &[f64], y: &[f64], radii: &[f64], length: f64, width: f64, periodic: bool, window: Window) -> Vec<f64> {
    let Window { reach, across } = window;
    let mut area: Vec<f64> = radii.iter().map(|r| std::f64::consts::PI * r * r).collect();
    let own = area.clone();
    strip_pairs(x, y, length, periodic, reach, |k, m, dy| {
        if dy <= across {
            area[k] += own[m];
            area[m] += own[k];
        }
    });
    y.iter()
        .zip(area)
        .map(|(&yk, a)| {
            let tall = (yk + across).min(width) - (yk - across).max(0.0);
            a / (2.0 * reach * tall.max(f64::MIN_POSITIVE))
        })
        .collect()
}

/// The swing field over the moves of every half period (`(x, y, dx)` in the tray's frame at
/// the half period's start, and the move along x). First the correlation of moves across the
/// tray, which sets the window's height (`across_m`: where the correlation first falls
/// below 1/e, or the tray's width); then the swing by the packing of that window.
fn swing_field(moves: &[HalfPeriod], radii: &[f64], l: f64, w: f64, periodic: bool, mean_d: f64) -> SwingField {
    let reach = LOCAL_RADIUS_DIAMETERS * mean_d;
    let mut corr = AcrossCorrelation::new(w, mean_d);
    for (x, y, dx) in moves {
        corr.add(x, y, dx, l, periodic, reach);
    }
    let correlation_across = corr.values();
    let across_m = correlation_across
        .iter()
        .position(|c| c.is_some_and(|c| c < (-1.0f64).exp()))
        .map_or(w, |b| b.max(1) as f64 * mean_d);
    let classes = PACKING_EDGES.len() + 1;
    let mut packing = vec![Vec::new(); classes];
    let mut swing = vec![Vec::new(); classes];
    let mut relative = vec![Vec::new(); classes];
    for (x, y, dx) in moves {
        let phi = window_packing(x, y, radii, l, w, periodic, Window { reach, across: across_m });
        let rel = relative_moves(x, y, dx, l, w, periodic, mean_d);
        for k in 0..x.len() {
            let c = PACKING_EDGES.iter().take_while(|&&e| phi[k] >= e).count();
            packing[c].push(phi[k]);
            swing[c].push(dx[k].abs());
            if let Some(r) = rel[k] {
                relative[c].push(r);
            }
        }
    }
    let mut low = 0.0;
    let mut out = Vec::new();
    for (c, ((p, s), r)) in packing.into_iter().zip(swing).zip(relative).enumerate() {
        let high = PACKING_EDGES.get(c).copied().unwrap_or(f64::INFINITY);
        if !p.is_empty() {
            out.push(SwingClass {
                low,
                high,
                packing: p.iter().sum::<f64>() / p.len() as f64,
                swing: Spread::of(s),
                relative: Spread::of(r),
            });
        }
        low = high;
    }
    SwingField {
        until_s: None,
        half_periods: moves.len(),
        reach_m: reach,
        across_m,
        correlation_across,
        classes: out,
    }
}

/// Which band (index) holds tray-frame position `x`, if any.
fn band_of(x: f64, stripes: &[Stripe], length: f64) -> Option<usize> {
    stripes.iter().position(|s| s.contains(x, length))
}

/// Distance (m) from `x` to the nearer edge of stripe `s` (periodic).
fn edge_distance(x: f64, s: &Stripe, length: f64) -> f64 {
    let from_start = (x - s.start).rem_euclid(length);
    from_start.min(s.width - from_start).max(0.0)
}

fn band_measures(
    header: &Header,
    frames: &[Frame],
    turning: &[TurningFrame],
    params: &StripeParams,
    cells: usize,
    mean_d: f64,
) -> (Bands, Vec<FrameBands>) {
    let (l, w) = (header.length, header.width);
    let n = header.radii.len();
    let h = l / cells as f64;
    let mut phi = vec![0.0; cells];
    let mut core = (0.0, 0usize);
    let (mut left, mut band_samples, mut edge_left, mut edge_samples) = (0usize, 0usize, 0usize, 0usize);
    // One pass over the turning frames. Membership is compared between frames one period
    // apart (the same turning point, as the camera sees it): between the two turning points
    // a band's grains swing by about a band's width against the tray, so frames half a period
    // apart would count the swing as escape. Per side of the stroke: the last frame's (stage,
    // half), each grain's (in a band, within a mean diameter of its edge), and its current
    // stay (length in periods, begun before the record).
    struct Side {
        at: Option<(usize, i64)>,
        was: Vec<(bool, bool)>,
        stay: Vec<Option<(usize, bool)>>,
    }
    let mut sides: [Side; 2] = std::array::from_fn(|_| Side {
        at: None,
        was: vec![(false, false); n],
        stay: vec![None; n],
    });
    let (mut stays, mut censored) = (Vec::new(), 0);
    let mut per_frame = Vec::with_capacity(turning.len());
    let mut frames_with_bands = 0;
    for f in turning {
        let x: Vec<f64> = frames[f.frame].pos.iter().map(|q| (q[0] - f.tray_x).rem_euclid(l)).collect();
        add_area_fraction_cells(&x, &header.radii, l, w, &mut phi);
        let stripes = detect(&phi, l, params);
        frames_with_bands += usize::from(!stripes.is_empty());
        for b in &stripes {
            // The central half of the band, cell by cell.
            let (from, to) = (b.start + 0.25 * b.width, b.start + 0.75 * b.width);
            let (c0, c1) = ((from / h).ceil() as i64, (to / h).floor() as i64);
            for c in c0..c1 {
                core.0 += phi[c.rem_euclid(cells as i64) as usize];
                core.1 += 1;
            }
        }
        let side = &mut sides[usize::from(f.side < 0)];
        // One period after this side's previous frame, in the same stage.
        let consecutive = side.at == Some((f.stage, f.half - 2));
        side.at = Some((f.stage, f.half));
        let mut members = 0;
        for (k, &xk) in x.iter().enumerate() {
            let now = match band_of(xk, &stripes, l) {
                Some(s) => (true, edge_distance(xk, &stripes[s], l) <= mean_d),
                None => (false, false),
            };
            members += usize::from(now.0);
            if consecutive && side.was[k].0 {
                let gone = usize::from(!now.0);
                band_samples += 1;
                left += gone;
                if side.was[k].1 {
                    edge_samples += 1;
                    edge_left += gone;
                }
            }
            if !consecutive && side.stay[k].take().is_some() {
                censored += 1;
            }
            match (now.0, side.stay[k].as_mut()) {
                (true, Some((len, _))) => *len += 1,
                (true, None) => side.stay[k] = Some((1, !consecutive)),
                (false, Some(&mut (len, cut))) => {
                    if cut {
                        censored += 1;
                    } else {
                        stays.push(len as f64);
                    }
                    side.stay[k] = None;
                }
                (false, None) => {}
            }
            side.was[k] = now;
        }
        per_frame.push(FrameBands {
            time: f.time,
            side: f.side,
            bands: stripes.len(),
            in_bands: members as f64 / n.max(1) as f64,
        });
    }
    censored += sides.iter().flat_map(|s| &s.stay).filter(|s| s.is_some()).count();
    let bands = Bands {
        frames_with_bands,
        core_packing: (core.1 > 0).then(|| core.0 / core.1 as f64),
        residence_periods: Spread::of(stays),
        residence_censored: censored,
        escape_per_period: (band_samples > 0).then(|| left as f64 / band_samples as f64),
        edge_escape_per_period: (edge_samples > 0).then(|| edge_left as f64 / edge_samples as f64),
        band_samples,
        edge_samples,
    };
    (bands, per_frame)
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: f64 = 0.01;
    const NU: f64 = 3.0;

    /// `per` frames per period from t = 0 for `periods` periods; grain k at tray-frame
    /// position `place(k, half)` where `half` counts the half periods since t = T/4 (the
    /// first +A); frames between turning points copy the previous turning frame's position.
    fn frames(n: usize, periods: usize, per: usize, place: impl Fn(usize, i64) -> [f64; 2]) -> (TrayDrive, Vec<Frame>) {
        let drive = TrayDrive::harmonic(A, NU).unwrap();
        let mut out = Vec::new();
        for i in 0..periods * per {
            let t = i as f64 / (per as f64 * NU);
            let half = ((t * NU - 0.25) * 2.0 + 1e-9).floor() as i64;
            let tray = drive.displacement(t);
            out.push(Frame {
                time: t,
                pos: (0..n)
                    .map(|k| {
                        let p = place(k, half);
                        [p[0] + tray, p[1], 0.001]
                    })
                    .collect(),
                vel: vec![[0.0; 3]; n],
            });
        }
        (drive, out)
    }

    fn header(n: usize, l: f64, w: f64, r: f64) -> Header {
        Header {
            length: l,
            width: w,
            radii: vec![r; n],
        }
    }

    #[test]
    fn turning_frames_alternate_sides_one_per_half_period() {
        let drive = TrayDrive::harmonic(A, NU).unwrap();
        let times: Vec<f64> = (0..24).map(|i| i as f64 / (8.0 * NU)).collect();
        let t = turning_frames(&times, &drive);
        // 8 frames per period: +A at T/4 (frame 2), -A at 3T/4 (frame 6), ...
        assert_eq!(t.iter().map(|f| f.frame).collect::<Vec<_>>(), vec![2, 6, 10, 14, 18, 22]);
        assert!(t.windows(2).all(|p| p[1].half == p[0].half + 1 && p[1].side == -p[0].side));
        assert_eq!(t[0].side, 1);
        assert!((t[0].tray_x - A).abs() < 1e-12 && (t[1].tray_x + A).abs() < 1e-12);
    }

    #[test]
    fn known_excursions_are_measured_exactly_with_their_spread() {
        // 40 lone grains far apart; grain k moves k * 0.1 mm along x and 0.05 mm sideways
        // each half period, alternately forward and back: |dx| is k * 0.1 mm exactly.
        let n = 40;
        let (l, w, r) = (0.4, 0.1, 5e-4);
        let (drive, f) = frames(n, 6, 8, |k, half| {
            let base = [0.005 + 0.01 * k as f64, 0.05];
            let on = half.rem_euclid(2) as f64;
            [base[0] + on * 1e-4 * k as f64, base[1] + on * 5e-5]
        });
        let p = StripeParams::default_for(0.01, 2.0 * r);
        let c = measure(&header(n, l, w, r), &f, &drive, true, Windows::default(), &p, 400).unwrap();
        assert_eq!(c.half_periods, 11);
        let expected: Vec<f64> = (0..n).map(|k| 1e-4 * k as f64).collect();
        let mean = expected.iter().sum::<f64>() / n as f64;
        assert!((c.all.excursion.mean - mean).abs() < 1e-12, "{:?}", c.all.excursion);
        let sd = (expected.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        // Every half period repeats the same n values: the pooled sd is slightly smaller.
        let pooled = sd * ((n - 1) as f64 * 11.0 / (n as f64 * 11.0 - 1.0)).sqrt();
        assert!((c.all.excursion.sd - pooled).abs() < 1e-12, "{} vs {pooled}", c.all.excursion.sd);
        assert!((c.all.sideways.mean - 5e-5).abs() < 1e-12);
        // Back and forth by the same amount: the swing is the excursion, the drift zero.
        assert!(
            (c.swing.mean - mean).abs() < 1e-12 && c.drift.q90 < 1e-12,
            "{:?} {:?}",
            c.swing,
            c.drift
        );
        assert_eq!(c.swing.samples, n * 10);
        assert!(
            c.drift_signed.q10.abs() < 1e-12 && c.drift_signed.q90.abs() < 1e-12,
            "{:?}",
            c.drift_signed
        );
        assert_eq!(c.drift_positive_fraction, 0.0, "no period drifts");
        assert!((c.all.excursion.median - 1e-4 * 19.5).abs() < 1e-12);
        // Lone grains: no contacts, packing of one grain in the local disk.
        assert_eq!(c.by_contacts.len(), 1);
        assert_eq!(c.by_contacts[0].low, 0.0);
        let own = (r / (LOCAL_RADIUS_DIAMETERS * 2.0 * r)).powi(2);
        assert_eq!(c.by_packing.len(), 1);
        assert!(c.by_packing[0].low <= own && own < c.by_packing[0].high);
        assert_eq!(c.bands.frames_with_bands, 0);
        assert_eq!(c.bands.escape_per_period, None);
    }

    #[test]
    fn the_window_ends_at_the_onset_given() {
        let (drive, f) = frames(3, 6, 4, |k, _| [0.01 * (k + 1) as f64, 0.05]);
        let p = StripeParams::default_for(0.01, 1e-3);
        let h = header(3, 0.1, 0.1, 5e-4);
        let all = measure(&h, &f, &drive, true, Windows::default(), &p, 100).unwrap();
        let early = measure(
            &h,
            &f,
            &drive,
            true,
            Windows {
                before: Some(1.0 / NU),
                swing_until: None,
            },
            &p,
            100,
        )
        .unwrap();
        assert_eq!(all.half_periods, 11);
        // Turning points at T/4 and 3T/4 lie before T: two pairs start there.
        assert_eq!(early.half_periods, 2);
        assert!(all.all.excursion.mean < 1e-15, "{}", all.all.excursion.mean);
        let e = measure(
            &h,
            &f,
            &drive,
            true,
            Windows {
                before: Some(0.0),
                swing_until: None,
            },
            &p,
            100,
        )
        .unwrap_err();
        assert!(e.to_string().contains("excursion per half period"), "{e}");
        // The swing field's own window end.
        assert_eq!((all.swing_field.half_periods, all.swing_field.until_s), (11, None));
        let w = Windows {
            before: None,
            swing_until: Some(1.0 / NU),
        };
        let early = measure(&h, &f, &drive, true, w, &p, 100).unwrap();
        assert_eq!((early.swing_field.half_periods, early.swing_field.until_s), (2, Some(1.0 / NU)));
        assert_eq!(early.half_periods, 11, "the excursions keep their own window");
        let w = Windows {
            before: None,
            swing_until: Some(0.0),
        };
        let e = measure(&h, &f, &drive, true, w, &p, 100).unwrap_err();
        assert!(e.to_string().contains("swing field"), "{e}");
    }

    #[test]
    fn contacts_and_packing_of_a_touching_chain() {
        // Five grains in a row along x, touching: the ends have one contact, the others two.
        let r = 5e-4;
        let x: Vec<f64> = (0..5).map(|k| 0.05 + 2.0 * r * k as f64).collect();
        let y = vec![0.05; 5];
        let (packing, contacts) = local_state(&x, &y, &[r; 5], 0.1, 0.1, true, 2.0 * r);
        assert_eq!(contacts, vec![1, 2, 2, 2, 1]);
        // The middle grain sees all five within 2.5 diameters (the farthest at 2).
        let disk = std::f64::consts::PI * (LOCAL_RADIUS_DIAMETERS * 2.0 * r).powi(2);
        assert!((packing[2] - 5.0 * std::f64::consts::PI * r * r / disk).abs() < 1e-12);
        // Across the periodic seam the same.
        let xs: Vec<f64> = x.iter().map(|v| (v + 0.048_f64).rem_euclid(0.1)).collect();
        let (_, seam) = local_state(&xs, &y, &[r; 5], 0.1, 0.1, true, 2.0 * r);
        assert_eq!(seam, contacts);
    }

    #[test]
    fn relative_moves_are_taken_against_the_other_neighbours() {
        // Three grains within 2.5 diameters of each other, a fourth far off.
        let r = 5e-4;
        let x = [0.050, 0.051, 0.052, 0.090];
        let y = [0.05; 4];
        let rel = relative_moves(&x, &y, &[1.0, 2.0, 3.0, 7.0], 0.1, 0.1, true, 2.0 * r);
        assert_eq!(rel, vec![Some(-1.5), Some(0.0), Some(1.5), None]);
        // Across the periodic seam the first grain's neighbours are the same.
        let xs: Vec<f64> = x.iter().map(|v| (v + 0.0495_f64).rem_euclid(0.1)).collect();
        assert_eq!(relative_moves(&xs, &y, &[1.0, 2.0, 3.0, 7.0], 0.1, 0.1, true, 2.0 * r), rel);
    }

    #[test]
    fn a_sheet_that_swings_as_one_has_no_relative_move() {
        // A square patch of touching grains swinging 8 mm out and back, and lone grains
        // swinging 14 mm: two packing classes with those swings, no move apart within the patch.
        let (l, w, r) = (0.4, 0.1, 5e-4);
        let patch = 100;
        let lone = 20;
        let (drive, f) = frames(patch + lone, 6, 8, |k, half| {
            let on = half.rem_euclid(2) as f64;
            if k < patch {
                [0.1 + 2.0 * r * (k % 10) as f64 + on * 8e-3, 0.03 + 2.0 * r * (k / 10) as f64]
            } else {
                [0.2 + 0.01 * (k - patch) as f64 + on * 14e-3, 0.08]
            }
        });
        let p = StripeParams::default_for(0.01, 2.0 * r);
        let c = measure(&header(patch + lone, l, w, r), &f, &drive, true, Windows::default(), &p, 400).unwrap();
        let field = &c.swing_field;
        assert_eq!(field.half_periods, 11);
        let sparse = &field.classes[0];
        assert!(sparse.high <= 0.1 && (sparse.swing.mean - 14e-3).abs() < 1e-12, "{sparse:?}");
        let dense = field.classes.last().unwrap();
        assert!(dense.low >= 0.3, "the patch's centre is dense: {dense:?}");
        assert!((dense.swing.mean - 8e-3).abs() < 1e-12 && dense.relative.sd < 1e-12, "{dense:?}");
        let grains: usize = field.classes.iter().map(|k| k.swing.samples).sum();
        assert_eq!(grains, (patch + lone) * 11);
    }

    #[test]
    fn moves_alike_across_the_tray_open_the_window_to_its_width() {
        // A layer of 30 x 10 grains on a 0.1 m tray: in the first run every grain's move is a
        // function of its x only (a long wave), in the second a scramble of the same values.
        let (l, w, r) = (0.1, 0.01, 4e-4);
        let (nx, ny) = (60usize, 10usize);
        let n = nx * ny;
        let wave = |k: usize| 1e-3 * (std::f64::consts::TAU * (k % nx) as f64 / nx as f64).sin();
        // A pseudo-random index (SplitMix-like): nothing in common with the grain's column.
        let scramble = |k: usize| wave(((k as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) as usize % n);
        for (moves, coherent) in [(&wave as &dyn Fn(usize) -> f64, true), (&scramble, false)] {
            let (drive, f) = frames(n, 4, 8, |k, half| {
                let on = half.rem_euclid(2) as f64;
                [
                    (k % nx) as f64 * l / nx as f64 + on * (5e-3 + moves(k)),
                    5e-4 + (k / nx) as f64 * 1e-3,
                ]
            });
            let p = StripeParams::default_for(0.1, 2.0 * r);
            let c = measure(&header(n, l, w, r), &f, &drive, true, Windows::default(), &p, 100).unwrap();
            let field = &c.swing_field;
            let corr: Vec<f64> = field.correlation_across.iter().flatten().copied().collect();
            if coherent {
                assert!(corr.iter().all(|&c| c > 0.9), "{corr:?}");
                assert_eq!(field.across_m, w);
            } else {
                // (In the first bin, grains of one row, half the frames place them by their
                // own moves, so nearness along x selects pairs that moved apart: negative.)
                assert!(corr[0] < 0.37 && corr[1..].iter().all(|&c| c.abs() < 0.2), "{corr:?}");
                assert!(
                    (field.across_m - 2.0 * r).abs() < 1e-15,
                    "at least one mean diameter: {}",
                    field.across_m
                );
            }
        }
    }

    #[test]
    fn window_packing_of_a_full_strip_is_its_area_fraction() {
        // Rows of touching grains filling a 0.02 m wide tray: every grain's window over the
        // whole width holds the layer's area fraction (pi / 4 on a square lattice).
        let (l, w, r) = (0.05, 0.02, 5e-4);
        let (x, y): (Vec<f64>, Vec<f64>) = (0..50 * 20)
            .map(|k| (r + 2.0 * r * (k % 50) as f64, r + 2.0 * r * (k / 50) as f64))
            .unzip();
        let reach = 2.5 * 2.0 * r;
        let phi = window_packing(&x, &y, &vec![r; x.len()], l, w, true, Window { reach, across: w });
        // The window holds 5 columns of 1 mm each (|dx| <= 2.5 mm) over 5 mm: exact.
        for p in phi {
            assert!((p - std::f64::consts::PI / 4.0).abs() < 1e-9, "{p}");
        }
    }

    #[test]
    fn a_band_that_holds_its_grains_and_one_that_loses_its_edge() {
        // A dense band of grains at rest in the tray frame, on a periodic tray of 0.1 m: no
        // grain leaves it, and every stay spans the record (censored).
        let (l, w, r) = (0.1, 0.01, 4.5e-4);
        let mut place = Vec::new();
        for i in 0..10 {
            for j in 0..10 {
                place.push([0.04 + 1e-3 * i as f64, 5e-4 + 1e-3 * j as f64]);
            }
        }
        let n = place.len();
        let p = StripeParams::default_for(mean_area_fraction(&vec![r; n], l, w), 2.0 * r);
        let (drive, f) = frames(n, 5, 4, |k, _| place[k]);
        let c = measure(&header(n, l, w, r), &f, &drive, true, Windows::default(), &p, 400).unwrap();
        assert_eq!(c.bands.frames_with_bands, c.turning_frames);
        assert_eq!(c.bands.escape_per_period, Some(0.0));
        assert_eq!(c.bands.residence_periods.samples, 0);
        assert_eq!(c.bands.residence_censored, 2 * n, "one stay per grain on each side");
        let core = c.bands.core_packing.unwrap();
        assert!(core > 0.5 && core < 0.7, "{core}");
        // The left column leaves the band for good after the third turning frame: 10 of the
        // band's edge grains escape once, in one of the half periods.
        let (drive, f) = frames(n, 5, 4, |k, half| {
            let mut q = place[k];
            if k < 10 && half >= 2 {
                q[0] -= 0.02;
            }
            q
        });
        let c = measure(&header(n, l, w, r), &f, &drive, true, Windows::default(), &p, 400).unwrap();
        // Turning frames at halves 0..9: the column is in the band at halves 0 and 1 and
        // leaves at 2 (+A side) and 3 (-A side). Samples are band grains one period before a
        // frame: on each side, the first comparison has all n, the later ones n - 10.
        let per_side = c.turning_frames / 2 - 1;
        let band = (2 * (n + (n - 10) * (per_side - 1))) as f64;
        assert_eq!(c.bands.band_samples as f64, band);
        assert!((c.bands.escape_per_period.unwrap() - 20.0 / band).abs() < 1e-12);
        assert!(c.bands.edge_escape_per_period.unwrap() > c.bands.escape_per_period.unwrap());
    }
}

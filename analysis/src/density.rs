//! Binning-free one-dimensional density of a layer of disks (thesis Appendix A), periodic in x
//! over `[0, L)`.
//!
//! - Count density: each grain adds +1 at `x_i - r_i` and -1 at `x_i + r_i`; the running sum
//!   is the exact, piecewise-constant number of grains covering `x` ([`CountProfile`]).
//! - Projected area fraction: `phi(x) = sum_i 2 sqrt(r_i^2 - (x - x_i)^2) / W`, the fraction
//!   of the tray's width covered at `x`. [`area_fraction_cells`] gives its exact average over
//!   each cell of a grid, from the antiderivative of `2 sqrt(r^2 - u^2)`,
//!   `u sqrt(r^2 - u^2) + r^2 asin(u / r)`, so no binning error enters.
//!
//! Both are O(N log N) (the profile) or O(N + cells) (the cell averages).

/// Wraps `x` into `[0, l)`.
pub(crate) fn wrap(x: f64, l: f64) -> f64 {
    if (0.0..l).contains(&x) {
        return x; // the common case, without a floating-point remainder
    }
    let w = x.rem_euclid(l);
    if w >= l {
        0.0
    } else {
        w
    }
}

/// The exact count density: `values[k]` grains cover `[breaks[k], breaks[k+1])`, the last
/// interval wrapping to `breaks[0] + L`. Periodic: `breaks` are sorted in `[0, L)`.
#[derive(Clone, Debug, PartialEq)]
pub struct CountProfile {
    pub length: f64,
    pub breaks: Vec<f64>,
    pub values: Vec<i64>,
}

impl CountProfile {
    /// Builds the profile of grains at `x` with radii `r` (m, each `< length / 2`) on a
    /// periodic axis of length `length`.
    pub fn new(x: &[f64], r: &[f64], length: f64) -> Self {
        assert_eq!(x.len(), r.len(), "one radius per grain");
        let mut events: Vec<(f64, i64)> = Vec::with_capacity(2 * x.len());
        // Grains straddling the seam (their wrapped start lies after their wrapped end)
        // cover x = 0 and set the starting level.
        let mut level0 = 0i64;
        for (&xi, &ri) in x.iter().zip(r) {
            assert!(2.0 * ri < length, "a grain wider than the box");
            let (wa, wb) = (wrap(xi - ri, length), wrap(xi + ri, length));
            events.push((wa, 1));
            events.push((wb, -1));
            level0 += (wa > wb) as i64;
        }
        events.sort_by(|p, q| p.0.total_cmp(&q.0));
        let mut breaks = Vec::with_capacity(events.len());
        let mut values = Vec::with_capacity(events.len());
        let mut level = level0;
        let mut k = 0;
        while k < events.len() {
            let at = events[k].0;
            while k < events.len() && events[k].0 == at {
                level += events[k].1;
                k += 1;
            }
            breaks.push(at);
            values.push(level);
        }
        if breaks.first() != Some(&0.0) {
            breaks.insert(0, 0.0);
            values.insert(0, level0);
        }
        Self { length, breaks, values }
    }

    /// Number of grains covering `x`.
    pub fn value_at(&self, x: f64) -> i64 {
        let x = wrap(x, self.length);
        let k = self.breaks.partition_point(|&b| b <= x);
        self.values[k.saturating_sub(1)]
    }

    /// `integral_0^L n(x) dx` (m); equals `sum_i 2 r_i`.
    pub fn integral(&self) -> f64 {
        let mut sum = 0.0;
        for k in 0..self.breaks.len() {
            let end = self.breaks.get(k + 1).copied().unwrap_or(self.length);
            sum += self.values[k] as f64 * (end - self.breaks[k]);
        }
        sum
    }
}

/// Antiderivative of the chord length `2 sqrt(r^2 - u^2)` of a disk of radius `r` at
/// offset `u` from its centre: `u sqrt(r^2 - u^2) + r^2 asin(u / r)`, constant outside
/// `[-r, r]` (m^2).
pub fn chord_primitive(u: f64, r: f64) -> f64 {
    // Outside the disk the primitive is +-pi r^2 / 2; the first and last cell boundary of
    // every grain lie there, so this saves most of the `asin` calls.
    if u <= -r {
        -std::f64::consts::FRAC_PI_2 * r * r
    } else if u >= r {
        std::f64::consts::FRAC_PI_2 * r * r
    } else {
        u * (r * r - u * u).max(0.0).sqrt() + r * r * (u / r).clamp(-1.0, 1.0).asin()
    }
}

/// Exact cell averages of the projected area fraction `phi(x)` on `cells` equal cells of
/// `[0, length)`; `width` is the tray width W (m). Cell `c` covers `[c h, (c + 1) h)`,
/// `h = length / cells`, and holds `(1 / (h W)) integral_cell sum_i 2 sqrt(r_i^2 - (x - x_i)^2) dx`,
/// so `sum_c phi_c h W = sum_i pi r_i^2` exactly (up to round-off). O(N + cells).
pub fn area_fraction_cells(x: &[f64], r: &[f64], length: f64, width: f64, cells: usize) -> Vec<f64> {
    let mut out = vec![0.0; cells];
    add_area_fraction_cells(x, r, length, width, &mut out);
    out
}

/// [`area_fraction_cells`] into a caller's buffer (its length is the number of cells).
pub fn add_area_fraction_cells(x: &[f64], r: &[f64], length: f64, width: f64, out: &mut [f64]) {
    assert_eq!(x.len(), r.len(), "one radius per grain");
    let cells = out.len();
    out.iter_mut().for_each(|v| *v = 0.0);
    let h = length / cells as f64;
    for (&xi, &ri) in x.iter().zip(r) {
        if ri <= 0.0 {
            continue;
        }
        let xi = wrap(xi, length);
        let (a, b) = (xi - ri, xi + ri);
        let (first, last) = ((a / h).floor() as i64, ((b / h).ceil() as i64) - 1);
        // The primitive at each cell boundary is evaluated once and shared by the two
        // cells that meet there.
        let mut below = chord_primitive(first as f64 * h - xi, ri);
        for c in first..=last {
            let above = chord_primitive((c + 1) as f64 * h - xi, ri);
            let part = above - below;
            below = above;
            if part > 0.0 {
                out[c.rem_euclid(cells as i64) as usize] += part;
            }
        }
    }
    let scale = 1.0 / (h * width);
    for v in out.iter_mut() {
        *v *= scale;
    }
}

/// Mean projected area fraction of the layer, `sum_i pi r_i^2 / (L W)`.
pub fn mean_area_fraction(r: &[f64], length: f64, width: f64) -> f64 {
    r.iter().map(|r| std::f64::consts::PI * r * r).sum::<f64>() / (length * width)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn one_disk_and_the_seam() {
        let p = CountProfile::new(&[0.5], &[0.1], 1.0);
        assert_eq!(p.value_at(0.45), 1);
        assert_eq!(p.value_at(0.3), 0);
        assert!((p.integral() - 0.2).abs() < 1e-15);
        let p = CountProfile::new(&[0.02], &[0.05], 1.0);
        assert_eq!(p.value_at(0.99), 1);
        assert_eq!(p.value_at(0.06), 1);
        assert_eq!(p.value_at(0.5), 0);
        assert!((p.integral() - 0.1).abs() < 1e-15);
        let p = CountProfile::new(&[0.5, 0.55], &[0.1, 0.1], 1.0);
        assert_eq!(p.value_at(0.5), 2);
        assert_eq!(p.value_at(0.42), 1);
    }

    #[test]
    fn area_fraction_of_one_disk_is_its_area() {
        let cells = area_fraction_cells(&[0.999], &[0.01], 1.0, 0.5, 100);
        let total: f64 = cells.iter().sum::<f64>() * 0.01 * 0.5;
        assert!((total - std::f64::consts::PI * 1e-4).abs() < 1e-15, "{total}");
        assert!(cells[0] > 0.0 && cells[99] > 0.0, "wraps across the seam");
    }

    proptest! {
        #[test]
        fn profiles_integrate_to_the_grains_and_ignore_order_and_shift(
            grains in prop::collection::vec((0.0f64..1.0, 0.001f64..0.05), 1..60),
            shift in 0.0f64..1.0,
        ) {
            let (l, w, n) = (1.0, 0.2, 64);
            let x: Vec<f64> = grains.iter().map(|g| g.0).collect();
            let r: Vec<f64> = grains.iter().map(|g| g.1).collect();
            let p = CountProfile::new(&x, &r, l);
            let two_r: f64 = r.iter().map(|r| 2.0 * r).sum();
            prop_assert!((p.integral() - two_r).abs() < 1e-12);
            let cells = area_fraction_cells(&x, &r, l, w, n);
            let area: f64 = r.iter().map(|r| std::f64::consts::PI * r * r).sum();
            prop_assert!((cells.iter().sum::<f64>() * (l / n as f64) * w - area).abs() < 1e-12 * area.max(1e-9) + 1e-15);
            // Permutation changes nothing.
            let (mut xr, mut rr) = (x.clone(), r.clone());
            xr.reverse();
            rr.reverse();
            prop_assert_eq!(CountProfile::new(&xr, &rr, l), p.clone());
            // The area fraction ignores order too (up to round-off of the sums).
            let cells_r = area_fraction_cells(&xr, &rr, l, w, n);
            for (a, b) in cells.iter().zip(&cells_r) {
                prop_assert!((a - b).abs() < 1e-12);
            }
            // A shift by a whole number of cells rotates the cells and changes nothing else.
            let k = (shift * n as f64).floor() as usize;
            let xk: Vec<f64> = x.iter().map(|x| x + k as f64 * l / n as f64).collect();
            let cells_k = area_fraction_cells(&xk, &r, l, w, n);
            for c in 0..n {
                prop_assert!((cells_k[(c + k) % n] - cells[c]).abs() < 1e-9, "cell {c}");
            }
            // A periodic shift shifts the profile.
            let xs: Vec<f64> = x.iter().map(|x| (x + shift).rem_euclid(l)).collect();
            let q = CountProfile::new(&xs, &r, l);
            for k in 0..50 {
                let at = (k as f64 + 0.37) / 50.0;
                let near_break = p.breaks.iter().any(|b| ((b - at).rem_euclid(l)).min((at - b).rem_euclid(l)) < 1e-9);
                if !near_break {
                    prop_assert_eq!(q.value_at(at + shift), p.value_at(at));
                }
            }
        }
    }
}

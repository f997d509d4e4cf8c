//! Periodic boundaries (minimum image) of an axis-aligned box with its lower corner at the origin.

use crate::Vec3;

/// Per axis: `Some(L)` for a periodic axis of length `L` (m), `None` for an open or walled axis.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Boundary {
    pub periodic: [Option<f64>; 3],
}

impl Boundary {
    /// No periodic axis (free space).
    pub fn open() -> Self {
        Self::default()
    }

    /// Minimum-image version of a separation vector. Separations of wrapped positions lie
    /// within one box length, so a compare-and-shift suffices (`round` is a software call on
    /// baseline x86-64 and dominated the step).
    #[inline(always)]
    pub fn min_image(&self, mut d: Vec3) -> Vec3 {
        for (k, p) in self.periodic.iter().enumerate() {
            if let Some(l) = *p {
                let half = 0.5 * l;
                if d[k] > half {
                    d[k] -= l;
                } else if d[k] < -half {
                    d[k] += l;
                }
                if d[k].abs() > half {
                    d[k] -= l * (d[k] / l).round(); // far outside: the general formula
                }
            }
        }
        d
    }

    /// Maps a position back into `[0, L)` on periodic axes (one shift for a grain that just
    /// crossed the seam; the general `rem_euclid` only when it is farther out).
    #[inline(always)]
    pub fn wrap(&self, mut x: Vec3) -> Vec3 {
        for (k, p) in self.periodic.iter().enumerate() {
            if let Some(l) = *p {
                x[k] = Self::wrap_coordinate(x[k], l);
            }
        }
        x
    }

    /// [`Self::wrap`] on one periodic axis of length `l`.
    #[inline(always)]
    pub fn wrap_coordinate(mut c: f64, l: f64) -> f64 {
        if c < 0.0 {
            c += l;
        } else if c >= l {
            c -= l;
        }
        if !(0.0..l).contains(&c) {
            c = c.rem_euclid(l);
            if c >= l {
                c = 0.0; // rem_euclid can return l for tiny negative inputs
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_image_and_wrap() {
        let b = Boundary {
            periodic: [Some(1.0), None, None],
        };
        let d = b.min_image(Vec3::new(0.9, 0.9, 0.0));
        assert!((d.x + 0.1).abs() < 1e-15 && d.y == 0.9);
        let x = b.wrap(Vec3::new(-1e-20, 2.0, 0.0));
        assert!(x.x >= 0.0 && x.x < 1.0 && x.y == 2.0);
        for v in [-3.7, -1.0, -0.3, 0.0, 0.5, 1.0, 1.2, 5.5] {
            let w = b.wrap(Vec3::new(v, 0.0, 0.0)).x;
            assert!((0.0..1.0).contains(&w) && (w - v.rem_euclid(1.0)).abs() < 1e-15, "{v} -> {w}");
            let d = b.min_image(Vec3::new(v, 0.0, 0.0)).x;
            assert!(d.abs() <= 0.5 && ((d - v) - (d - v).round()).abs() < 1e-12, "{v} -> {d}");
        }
    }
}

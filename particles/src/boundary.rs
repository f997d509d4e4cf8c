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

    /// Minimum-image version of a separation vector.
    #[inline]
    pub fn min_image(&self, mut d: Vec3) -> Vec3 {
        for (k, p) in self.periodic.iter().enumerate() {
            if let Some(l) = *p {
                d[k] -= l * (d[k] / l).round();
            }
        }
        d
    }

    /// Maps a position back into `[0, L)` on periodic axes.
    #[inline]
    pub fn wrap(&self, mut x: Vec3) -> Vec3 {
        for (k, p) in self.periodic.iter().enumerate() {
            if let Some(l) = *p {
                x[k] = x[k].rem_euclid(l);
                if x[k] >= l {
                    x[k] = 0.0; // rem_euclid can return l for tiny negative inputs
                }
            }
        }
        x
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
    }
}

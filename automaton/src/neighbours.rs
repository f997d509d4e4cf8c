//! The neighbouring cells of a cell across rows (y), shared by both update paths
//! ([`crate::step`] on bits and [`crate::scalar`] on bytes): rows end at the side walls or
//! wrap round when y is periodic.

/// The 8 neighbouring cells `(row offset, column offset)` of a grain in the flight frame,
/// in the order of their frustration draws (`rng::neighbour_key`).
pub(crate) const NEIGHBOURS: [(i32, isize); 8] = [(0, 1), (0, -1), (-1, 0), (-1, 1), (-1, -1), (1, 0), (1, 1), (1, -1)];

/// Row `j + dj` for `dj` in -1, 0, 1, or `None` beyond a wall.
#[inline]
pub(crate) fn offset_row(j: usize, dj: i32, ny: usize, periodic: bool) -> Option<usize> {
    if dj == 0 {
        Some(j)
    } else {
        neighbour_row(j, dj > 0, ny, periodic)
    }
}

/// Row `j + 1` (`up`) or `j - 1` of `ny` rows, wrapping round when `periodic`, or `None`
/// beyond a wall.
#[inline]
pub(crate) fn neighbour_row(j: usize, up: bool, ny: usize, periodic: bool) -> Option<usize> {
    if up {
        if j + 1 < ny {
            Some(j + 1)
        } else if periodic {
            Some(0)
        } else {
            None
        }
    } else if j > 0 {
        Some(j - 1)
    } else if periodic {
        Some(ny - 1)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_end_at_walls_and_wrap_when_periodic() {
        assert_eq!(neighbour_row(0, false, 4, false), None);
        assert_eq!(neighbour_row(3, true, 4, false), None);
        assert_eq!(neighbour_row(0, false, 4, true), Some(3));
        assert_eq!(neighbour_row(3, true, 4, true), Some(0));
        assert_eq!(neighbour_row(1, true, 4, false), Some(2));
        assert_eq!(offset_row(2, 0, 4, false), Some(2));
        assert_eq!(offset_row(2, -1, 4, false), Some(1));
        // One periodic row is its own neighbour.
        assert_eq!(neighbour_row(0, true, 1, true), Some(0));
    }
}

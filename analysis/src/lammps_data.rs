//! LAMMPS data files of a state (`atom_style sphere`, `units si`), so that LAMMPS can run
//! exactly the grains, positions, velocities and spins of a `stripes` run
//! (`bench/lammps/in.tray`, `stripes run --lammps-data`).

use std::fmt::Write;

/// The grains of a state as plain arrays (m, m/s, rad/s, m), one entry per grain.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Grains {
    pub pos: Vec<[f64; 3]>,
    pub vel: Vec<[f64; 3]>,
    pub omega: Vec<[f64; 3]>,
    pub radius: Vec<f64>,
}

impl Grains {
    /// Appends one grain.
    pub fn push(&mut self, pos: [f64; 3], vel: [f64; 3], omega: [f64; 3], radius: f64) {
        self.pos.push(pos);
        self.vel.push(vel);
        self.omega.push(omega);
        self.radius.push(radius);
    }
}

/// The data file of `state` in the box `[0, length] x [0, width]` (m) with the floor at
/// `z = 0`: one atom type, each grain `id type diameter density x y z`, and its
/// `vx vy vz wx wy wz`. Every number is written in Rust's shortest round-trip form, so LAMMPS
/// reads back the same doubles. The z range leaves 1 mm below the floor (grains sink by their
/// overlap) and reaches 0.1 m, or 1 cm above the highest grain.
pub fn data_file(state: &Grains, density: f64, length: f64, width: f64, title: &str) -> String {
    let n = state.pos.len();
    let top = state.pos.iter().map(|x| x[2]).fold(0.0, f64::max);
    let zhi = (top + 0.01).max(0.1);
    let mut s = String::with_capacity(200 * n + 300);
    let _ = writeln!(s, "{title}\n\n{n} atoms\n1 atom types\n");
    let _ = writeln!(
        s,
        "0 {length:?} xlo xhi\n0 {width:?} ylo yhi\n-0.001 {zhi:?} zlo zhi\n\nAtoms # sphere\n"
    );
    for i in 0..n {
        let x = &state.pos[i];
        let _ = writeln!(
            s,
            "{} 1 {:?} {density:?} {:?} {:?} {:?}",
            i + 1,
            2.0 * state.radius[i],
            x[0],
            x[1],
            x[2]
        );
    }
    let _ = writeln!(s, "\nVelocities\n");
    for i in 0..n {
        let (v, w) = (&state.vel[i], &state.omega[i]);
        let _ = writeln!(s, "{} {:?} {:?} {:?} {:?} {:?} {:?}", i + 1, v[0], v[1], v[2], w[0], w[1], w[2]);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_file_round_trips_every_number() {
        let mut state = Grains::default();
        state.push([0.1, 0.01, 3.1e-4], [0.3, -1e-7, 0.0], [1.0, 2.0, -3.5], 3.1e-4);
        state.push([0.35, 0.019, 0.004], [-2.5, 0.0, 0.1], [0.0; 3], 4.9e-4);
        let text = data_file(&state, 2500.0, 0.4, 0.02, "test");
        assert!(text.contains("2 atoms\n1 atom types\n"));
        assert!(text.contains("0 0.4 xlo xhi\n0 0.02 ylo yhi\n-0.001 0.1 zlo zhi\n"));
        let atoms: Vec<Vec<f64>> = text
            .split("Atoms # sphere\n\n")
            .nth(1)
            .unwrap()
            .lines()
            .take(2)
            .map(|l| l.split(' ').map(|w| w.parse().unwrap()).collect())
            .collect();
        assert_eq!(atoms[1], vec![2.0, 1.0, 2.0 * 4.9e-4, 2500.0, 0.35, 0.019, 0.004]);
        let vel: Vec<f64> = text
            .split("Velocities\n\n")
            .nth(1)
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .split(' ')
            .map(|w| w.parse().unwrap())
            .collect();
        assert_eq!(vel, vec![1.0, 0.3, -1e-7, 0.0, 1.0, 2.0, -3.5]);
    }
}

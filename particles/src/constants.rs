//! Physical constants shared by the tray, the sample preparation and the experiments.

/// Gravitational acceleration of the tray scenes (m/s^2).
pub const GRAVITY: f64 = 10.0;

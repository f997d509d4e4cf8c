//! Single impacts of the event-driven rule from a chosen state: one grain on a wall, or two
//! grains, and the closed forms of Walton's rule that they follow (the rough-sphere checks of
//! the rule: the angle of rebound against the angle of impact, for several `mu` and `beta0`).
//!
//! Grain 1 comes down onto a floor (the unit normal `n = +z`) or onto grain 2 below it (`n`
//! from 2 to 1). Its contact point's velocity relative to the partner's is `g = (g_t, g_n)`
//! with `g_n < 0`; the impact angle `psi` is the contact velocity's angle from the normal,
//! `tan psi = g_t / |g_n|`, and the rebound angle `psi'` that of the velocity after,
//! `tan psi' = g_t' / g_n'`. Walton's rule (`collision`) gives `g_n' = -e g_n`,
//! `g_t' = -beta g_t`, so `tan psi' = -(beta / e) tan psi` with
//! - the smooth branch (`mu = 0`): `beta = -1`, `tan psi' = tan psi / e`;
//! - the sticking branch: `beta = beta0`, `tan psi' = -(beta0 / e) tan psi`, for
//!   `tan psi <= tan psi*`;
//! - the Coulomb (sliding) branch: `beta = -1 + mu (1 + e) (1 + 1/q) / tan psi`, so
//!   `tan psi' = tan psi / e - mu (1 + e) (1 + 1/q) / e`, where `|J_t| = mu |J_n|`;
//! - the switch between them at `tan psi* = mu (1 + e) (1 + 1/q) / (1 + beta0)` (no switch
//!   for `beta0 = -1`, which is smooth for any `mu`).
//!
//! The inertia factor `q = I / (m R^2)` may be anything in `(0, 1]`: a solid sphere 2/5, a
//! disk 1/2, a hollow sphere 2/3, a ring 1, a grain whose mass sits at its centre near 0.

use crate::collision::{collide, Body, Outcome, Restitution, Rule};
use crate::error::{invalid, EventsError};
use crate::Vec2;

/// What grain 1 hits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// A floor at rest below grain 1, of infinite mass, that does not turn.
    Wall,
    /// Grain 2, below grain 1 with its centre at the origin.
    Pair,
}

/// The rule's branch an impact took.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Branch {
    /// No friction: no tangential impulse.
    Smooth,
    /// The contact sticks: `beta = beta0`.
    Sticking,
    /// The contact slides: Coulomb's `|J_t| = mu |J_n|` caps the tangential impulse.
    Coulomb,
}

impl Branch {
    pub fn name(self) -> &'static str {
        match self {
            Branch::Smooth => "smooth",
            Branch::Sticking => "sticking",
            Branch::Coulomb => "coulomb",
        }
    }
}

/// Walton's rule with a constant `e`, and the inertia factor, of one impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walton {
    pub e: f64,
    pub mu: f64,
    pub beta0: f64,
    pub q: f64,
}

impl Walton {
    /// Checks the coefficients; errors name the key.
    pub fn validate(&self) -> Result<(), EventsError> {
        if !(self.q > 0.0 && self.q <= 1.0) {
            return Err(invalid(
                "q",
                format!("the inertia factor I/(m R^2) must lie in (0, 1], got {}", self.q),
            ));
        }
        self.rule().validate("rule")
    }

    pub fn rule(&self) -> Rule {
        Rule::Walton {
            e: Restitution::Constant(self.e),
            mu: self.mu,
            beta0: self.beta0,
        }
    }

    /// `tan psi*`, the impact angle's tangent beyond which the contact slides (infinite when
    /// it never does: `beta0 = -1`, or `mu` infinite).
    pub fn switch_tangent(&self) -> f64 {
        if self.beta0 <= -1.0 {
            return f64::INFINITY;
        }
        self.mu * (1.0 + self.e) * (1.0 + 1.0 / self.q) / (1.0 + self.beta0)
    }

    /// The closed form of `tan psi'` at the impact angle's tangent `tan_in`, and its branch
    /// (odd in `tan_in`: the formulas above hold for `tan_in >= 0`).
    pub fn rebound_tangent(&self, tan_in: f64) -> (f64, Branch) {
        let (sign, a) = (tan_in.signum(), tan_in.abs());
        if self.mu == 0.0 || self.beta0 == -1.0 {
            return (tan_in / self.e, Branch::Smooth);
        }
        if a <= self.switch_tangent() {
            (-self.beta0 / self.e * tan_in, Branch::Sticking)
        } else {
            (
                sign * (a / self.e - self.mu * (1.0 + self.e) * (1.0 + 1.0 / self.q) / self.e),
                Branch::Coulomb,
            )
        }
    }
}

/// One grain and its state just before the impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grain {
    /// Centre (m); for a wall impact, its height above the floor at `z = 0`.
    pub r: Vec2,
    pub v: Vec2,
    /// Spin (rad/s, counter-clockwise in the x-z plane).
    pub w: f64,
    pub radius: f64,
    pub mass: f64,
}

/// One impact from a given state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    pub target: Target,
    pub rule: Walton,
    pub grain: Grain,
    /// Grain 2 (ignored for a wall).
    pub partner: Grain,
}

/// What an impact did, with its angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rebound {
    pub outcome: Outcome,
    /// `tan psi` of the impact and `tan psi'` of the rebound (the contact point's velocity).
    pub tan_in: f64,
    pub tan_out: f64,
    pub branch: Branch,
    /// The unit normal used (from 2, or the wall, to grain 1).
    pub n: Vec2,
}

/// How far from contact (relative to the contact distance) a state may be.
pub const CONTACT_TOLERANCE: f64 = 1e-9;

impl Impact {
    /// A grain 1 of `radius` and `mass` coming in at `speed` and `angle` (rad, from the
    /// normal; positive along the contact's tangent `t = perp(n)`, which is -x for the +z
    /// normal, so that `tan psi = tan(angle)` without spin) with spin `w`, touching a floor
    /// or an equal grain 2 at rest below it.
    pub fn at_angle(target: Target, rule: Walton, speed: f64, angle: f64, w: f64, radius: f64, mass: f64) -> Self {
        let grain = Grain {
            r: Vec2::new(
                0.0,
                match target {
                    Target::Wall => radius,
                    Target::Pair => 2.0 * radius,
                },
            ),
            v: speed * Vec2::new(-angle.sin(), -angle.cos()),
            w,
            radius,
            mass,
        };
        let partner = Grain {
            r: Vec2::zeros(),
            v: Vec2::zeros(),
            w: 0.0,
            radius,
            mass,
        };
        Impact {
            target,
            rule,
            grain,
            partner,
        }
    }

    /// Checks the state: the coefficients, positive radii and masses, the grains touching
    /// (within [`CONTACT_TOLERANCE`]) and approaching. Errors name the key.
    pub fn validate(&self) -> Result<(), EventsError> {
        self.rule.validate()?;
        let grains: &[(&str, Grain)] = match self.target {
            Target::Wall => &[("grain", self.grain)],
            Target::Pair => &[("grain", self.grain), ("partner", self.partner)],
        };
        for (name, g) in grains {
            for (key, x) in [("radius", g.radius), ("mass", g.mass)] {
                if !(x.is_finite() && x > 0.0) {
                    return Err(invalid(&format!("{name}.{key}"), format!("must be a positive number, got {x}")));
                }
            }
            if !(g.r.iter().chain(g.v.iter()).all(|x| x.is_finite()) && g.w.is_finite()) {
                return Err(invalid(name, "position, velocity and spin must be finite"));
            }
        }
        let (n, distance, contact) = self.geometry();
        let gap = (distance - contact) / contact;
        if gap.abs() > CONTACT_TOLERANCE {
            let how = if gap > 0.0 { "apart" } else { "overlapping" };
            return Err(invalid(
                "grain.position",
                format!(
                    "an impact needs the grains in contact: they are {how} by {:e} m (centre distance {distance:e} m, contact at {contact:e} m)",
                    (distance - contact).abs()
                ),
            ));
        }
        let (b1, b2) = self.bodies();
        let t = Vec2::new(-n.y, n.x);
        let spin2 = if b2.m.is_infinite() { 0.0 } else { b2.r * b2.w };
        let g = b1.v - b2.v - (b1.r * b1.w + spin2) * t;
        if g.dot(&n) >= 0.0 {
            return Err(invalid(
                "grain.velocity",
                format!(
                    "the grains must approach: the normal relative speed is {:e} m/s (needs < 0)",
                    g.dot(&n)
                ),
            ));
        }
        Ok(())
    }

    /// The unit normal, the centres' distance and the contact distance.
    fn geometry(&self) -> (Vec2, f64, f64) {
        match self.target {
            Target::Wall => (Vec2::new(0.0, 1.0), self.grain.r.y, self.grain.radius),
            Target::Pair => {
                let d = self.grain.r - self.partner.r;
                let norm = d.norm();
                (d / norm, norm, self.grain.radius + self.partner.radius)
            }
        }
    }

    fn bodies(&self) -> (Body, Body) {
        let body = |g: &Grain| Body {
            v: g.v,
            w: g.w,
            r: g.radius,
            m: g.mass,
            q: self.rule.q,
        };
        let b2 = match self.target {
            Target::Wall => Body {
                v: Vec2::zeros(),
                w: 0.0,
                r: 0.0,
                m: f64::INFINITY,
                q: self.rule.q,
            },
            Target::Pair => body(&self.partner),
        };
        (body(&self.grain), b2)
    }

    /// Carries the impact out with the engine's collision rule.
    pub fn run(&self) -> Result<Rebound, EventsError> {
        self.validate()?;
        let (n, ..) = self.geometry();
        let (b1, b2) = self.bodies();
        let o = collide(b1, b2, n, &self.rule.rule(), None);
        let t = Vec2::new(-n.y, n.x);
        let spin2 = |w2: f64| if b2.m.is_infinite() { 0.0 } else { b2.r * w2 };
        let after = o.v1 - o.v2 - (b1.r * o.w1 + spin2(o.w2)) * t;
        let branch = if self.rule.mu == 0.0 || self.rule.beta0 == -1.0 {
            Branch::Smooth
        } else if o.beta < self.rule.beta0 {
            Branch::Coulomb
        } else {
            Branch::Sticking
        };
        Ok(Rebound {
            outcome: o,
            tan_in: o.gt / o.gn.abs(),
            tan_out: after.dot(&t) / after.dot(&n),
            branch,
            n,
        })
    }
}

/// One row of a sweep over the impact angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepRow {
    /// The impact angle of grain 1's velocity from the normal (rad).
    pub angle: f64,
    pub rebound: Rebound,
    /// The closed form's `tan psi'` and branch at the same `tan psi`.
    pub closed_tan_out: f64,
    pub closed_branch: Branch,
}

/// Impacts of a non-spinning grain 1 at `count` angles evenly spaced in `[0, max_angle]`.
pub fn sweep(
    target: Target,
    rule: Walton,
    speed: f64,
    max_angle: f64,
    count: usize,
    radius: f64,
    mass: f64,
) -> Result<Vec<SweepRow>, EventsError> {
    if !(speed.is_finite() && speed > 0.0) {
        return Err(invalid("speed", format!("must be a positive speed, got {speed}")));
    }
    (0..count)
        .map(|k| {
            let angle = if count > 1 {
                max_angle * k as f64 / (count - 1) as f64
            } else {
                0.0
            };
            let rebound = Impact::at_angle(target, rule, speed, angle, 0.0, radius, mass).run()?;
            let (closed_tan_out, closed_branch) = rule.rebound_tangent(rebound.tan_in);
            Ok(SweepRow {
                angle,
                rebound,
                closed_tan_out,
                closed_branch,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn walton(e: f64, mu: f64, beta0: f64, q: f64) -> Walton {
        Walton { e, mu, beta0, q }
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    /// Impulses on grain 1 along n and t.
    fn impulses(imp: &Impact, r: &Rebound) -> (f64, f64) {
        let j = imp.grain.mass * (r.outcome.v1 - imp.grain.v);
        let t = Vec2::new(-r.n.y, r.n.x);
        (j.dot(&r.n), j.dot(&t))
    }

    #[test]
    fn the_three_branches_follow_their_closed_forms_to_machine_precision() {
        for target in [Target::Wall, Target::Pair] {
            for q in [0.05, 0.4, 0.5, 2.0 / 3.0, 1.0] {
                let rule = walton(0.8, 0.3, 0.4, q);
                let switch = rule.switch_tangent().atan();
                for angle in [0.1 * switch, 0.5 * switch, 0.99 * switch, 1.01 * switch, 0.5 * (switch + 1.5), 1.5] {
                    let imp = Impact::at_angle(target, rule, 1.3, angle, 0.0, 1e-3, 2e-6);
                    let r = imp.run().unwrap();
                    assert!(close(r.tan_in, angle.tan(), 1e-14), "{} {}", r.tan_in, angle.tan());
                    let (closed, branch) = rule.rebound_tangent(r.tan_in);
                    assert_eq!(r.branch, branch, "q {q} angle {angle}");
                    assert!(close(r.tan_out, closed, 1e-13), "{:?} q {q}: {} vs {closed}", branch, r.tan_out);
                    let (jn, jt) = impulses(&imp, &r);
                    match branch {
                        Branch::Sticking => {
                            assert_eq!(r.outcome.beta, 0.4);
                            assert!(jt.abs() <= 0.3 * jn.abs() * (1.0 + 1e-12));
                        }
                        Branch::Coulomb => {
                            assert!(r.outcome.beta < 0.4);
                            assert!(close(jt.abs(), 0.3 * jn.abs(), 1e-13), "{jt} {jn}");
                        }
                        Branch::Smooth => unreachable!(),
                    }
                }
                // Smooth: no tangential impulse, the spin kept, the rebound angle tan psi / e.
                let smooth = walton(0.8, 0.0, 0.4, q);
                let imp = Impact::at_angle(target, smooth, 1.3, 0.7, 5.0, 1e-3, 2e-6);
                let r = imp.run().unwrap();
                assert_eq!(r.branch, Branch::Smooth);
                assert_eq!(r.outcome.w1, 5.0);
                assert!(impulses(&imp, &r).1.abs() <= 1e-16);
                assert!(close(r.tan_out, r.tan_in / 0.8, 1e-13));
            }
        }
    }

    #[test]
    fn the_branch_switches_at_the_angle_the_rule_gives_and_beta_is_continuous_there() {
        let rule = walton(0.9, 0.2, 0.5, 0.4);
        let s = rule.switch_tangent();
        assert!(close(s, 0.2 * 1.9 * 3.5 / 1.5, 1e-15));
        let at = |tan: f64| {
            Impact::at_angle(Target::Wall, rule, 1.0, tan.atan(), 0.0, 1e-3, 1e-6)
                .run()
                .unwrap()
        };
        let below = at(s * (1.0 - 1e-9));
        let above = at(s * (1.0 + 1e-9));
        assert_eq!(below.branch, Branch::Sticking);
        assert_eq!(above.branch, Branch::Coulomb);
        assert!((above.outcome.beta - 0.5).abs() < 1e-8, "{}", above.outcome.beta);
        assert!((above.tan_out - below.tan_out).abs() < 1e-8);
        // Without a switch: beta0 = -1 is smooth at every angle, an infinite mu always sticks.
        assert_eq!(walton(0.9, 0.2, -1.0, 0.4).switch_tangent(), f64::INFINITY);
        let sticky = walton(0.9, f64::INFINITY, 0.5, 0.4);
        let r = Impact::at_angle(Target::Pair, sticky, 1.0, 1.5, 0.0, 1e-3, 1e-6).run().unwrap();
        assert_eq!(r.branch, Branch::Sticking);
    }

    #[test]
    fn a_sweep_matches_its_closed_form_on_every_row() {
        let rule = walton(0.7, 0.1, 0.0, 1.0);
        let rows = sweep(Target::Pair, rule, 0.5, 1.5, 61, 1e-3, 1e-6).unwrap();
        assert_eq!(rows.len(), 61);
        assert!(rows.iter().any(|r| r.closed_branch == Branch::Sticking));
        assert!(rows.iter().any(|r| r.closed_branch == Branch::Coulomb));
        for r in &rows {
            assert_eq!(r.rebound.branch, r.closed_branch);
            assert!(close(r.rebound.tan_out, r.closed_tan_out, 1e-13));
        }
    }

    proptest! {
        #[test]
        fn any_impact_keeps_momentum_and_angular_momentum_and_loses_the_closed_form_energy(
            e in 0.0f64..=1.0, mu in 0.0f64..3.0, beta0 in -1.0f64..=1.0, q in 0.01f64..=1.0,
            speed in 0.01f64..10.0, angle in -1.55f64..1.55, w1 in -100.0f64..100.0, w2 in -100.0f64..100.0,
            m2 in 0.2f64..5.0, r2 in 0.5f64..2.0, dir in 0.0f64..std::f64::consts::TAU,
        ) {
            let rule = walton(e, mu, beta0, q);
            let n = Vec2::new(dir.cos(), dir.sin());
            let (ra, rb) = (1e-3, r2 * 1e-3);
            let grain = Grain { r: (ra + rb) * n, v: speed * Vec2::new(n.x * -angle.cos() - n.y * angle.sin(), n.y * -angle.cos() + n.x * angle.sin()), w: w1, radius: ra, mass: 1e-6 };
            let partner = Grain { r: Vec2::zeros(), v: Vec2::zeros(), w: w2, radius: rb, mass: m2 * 1e-6 };
            let imp = Impact { target: Target::Pair, rule, grain, partner };
            prop_assume!(imp.validate().is_ok());
            let r = imp.run().unwrap();
            let o = r.outcome;
            let p0 = grain.mass * grain.v + partner.mass * partner.v;
            let p1 = grain.mass * o.v1 + partner.mass * o.v2;
            prop_assert!((p1 - p0).norm() <= 1e-12 * grain.mass * speed);
            // Angular momentum about the contact point c (origin + rb n).
            let cross = |a: Vec2, b: Vec2| a.x * b.y - a.y * b.x;
            let l = |v1: Vec2, w1: f64, v2: Vec2, w2: f64| {
                q * grain.mass * ra * ra * w1 + grain.mass * cross(ra * n, v1)
                    + q * partner.mass * rb * rb * w2 + partner.mass * cross(-rb * n, v2)
            };
            let scale = grain.mass * ra * (speed + ra * w1.abs()) + partner.mass * rb * rb * w2.abs() + 1e-30;
            prop_assert!((l(o.v1, o.w1, o.v2, o.w2) - l(grain.v, w1, partner.v, w2)).abs() <= 1e-12 * scale);
            let ke = |m: f64, rad: f64, v: Vec2, w: f64| 0.5 * m * v.norm_squared() + 0.5 * q * m * rad * rad * w * w;
            let e0 = ke(grain.mass, ra, grain.v, w1) + ke(partner.mass, rb, partner.v, w2);
            let e1 = ke(grain.mass, ra, o.v1, o.w1) + ke(partner.mass, rb, o.v2, o.w2);
            let m12 = grain.mass * partner.mass / (grain.mass + partner.mass);
            let closed = 0.5 * m12 * ((1.0 - o.e * o.e) * o.gn * o.gn + q / (1.0 + q) * (1.0 - o.beta * o.beta) * o.gt * o.gt);
            prop_assert!(((e0 - e1) - closed).abs() <= 1e-10 * e0);
            prop_assert!(closed >= 0.0);
            let (closed_tan, branch) = rule.rebound_tangent(r.tan_in);
            prop_assert_eq!(branch, r.branch);
            prop_assert!(close(r.tan_out, closed_tan, 1e-9), "{} {}", r.tan_out, closed_tan);
        }
    }

    #[test]
    fn bad_impacts_are_refused_naming_the_key() {
        let rule = walton(0.9, 0.2, 0.5, 0.4);
        let key = |imp: Impact| match imp.run().unwrap_err() {
            EventsError::Invalid { field, .. } => field,
            other => panic!("{other}"),
        };
        for q in [0.0, -0.1, 1.01, f64::NAN] {
            assert_eq!(
                key(Impact::at_angle(Target::Wall, walton(0.9, 0.2, 0.5, q), 1.0, 0.3, 0.0, 1e-3, 1e-6)),
                "q"
            );
        }
        let mut apart = Impact::at_angle(Target::Pair, rule, 1.0, 0.3, 0.0, 1e-3, 1e-6);
        apart.grain.r.y *= 1.001;
        assert_eq!(key(apart), "grain.position");
        let mut overlapping = Impact::at_angle(Target::Wall, rule, 1.0, 0.3, 0.0, 1e-3, 1e-6);
        overlapping.grain.r.y *= 0.999;
        let err = overlapping.run().unwrap_err().to_string();
        assert!(err.contains("grain.position") && err.contains("overlapping"), "{err}");
        let mut leaving = Impact::at_angle(Target::Wall, rule, 1.0, 0.3, 0.0, 1e-3, 1e-6);
        leaving.grain.v.y = 0.5;
        assert_eq!(key(leaving), "grain.velocity");
        for speed in [0.0, -1.0] {
            match sweep(Target::Wall, rule, speed, 1.0, 3, 1e-3, 1e-6).unwrap_err() {
                EventsError::Invalid { field, .. } => assert_eq!(field, "speed"),
                other => panic!("{other}"),
            }
        }
        assert_eq!(
            key(Impact::at_angle(
                Target::Wall,
                walton(1.2, 0.2, 0.5, 0.4),
                1.0,
                0.3,
                0.0,
                1e-3,
                1e-6
            )),
            "rule.e"
        );
    }
}

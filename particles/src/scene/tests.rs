//! Unit tests of scene parsing, overrides and laws.

use super::*;

const MINIMAL: &str = r#"
    [box]
    length = 0.4
    width = 0.02
    [drive]
    frequency = 20.0
    amplitude = 0.025
    [particles]
    count = 4000
    radius_min = 0.25e-3
    radius_max = 0.5e-3
    [run]
    duration = 20.0
    dt = 8e-6
    seed = 1
"#;

#[test]
fn defaults_are_the_thesis_values() {
    let s = Scene::parse(MINIMAL, &[], "test").unwrap();
    s.validate().unwrap();
    assert_eq!(s.material, Material::default());
    assert!((s.packing() - 0.229).abs() < 0.002, "packing {}", s.packing());
    let (pp, pw) = s.laws().unwrap();
    assert_eq!(pp, pw);
    assert_eq!(pp.tangential, TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 });
}

#[test]
fn overrides_set_any_key_and_toggles_change_only_values() {
    let s = Scene::parse(
        MINIMAL,
        &[
            "toggles.friction=false".into(),
            "run.dt=auto".into(),
            "contact.rolling=none".into(),
            "run.threads=2".into(),
        ],
        "test",
    )
    .unwrap();
    let (pp, pw) = s.laws().unwrap();
    // Friction off empties the pair's tangential slot (one slot edit, no zero as a switch).
    assert_eq!(pp.tangential, TangentialLaw::None);
    assert_eq!(pw.tangential.mu(), 0.7, "the floor still drives");
    assert_eq!(pp.rolling, RollingLaw::None);
    assert_eq!(s.run.dt, TimeStep::Auto(AutoDt::Auto));
    assert_eq!(s.run.threads, 2);
}

#[test]
fn the_default_restitution_tolerance_leaves_the_serialised_scene_unchanged() {
    // Sample keys hash the serialised scene: a new key at its default must not move them.
    let s = Scene::parse(MINIMAL, &[], "test").unwrap();
    assert!(!toml::to_string(&s).unwrap().contains("restitution_tolerance"));
    let t = Scene::parse(MINIMAL, &["run.restitution_tolerance=1e-3".into()], "test").unwrap();
    let again = Scene::parse(&toml::to_string(&t).unwrap(), &[], "test").unwrap();
    assert_eq!(again.run.restitution_tolerance, 1e-3);
}

#[test]
fn unknown_keys_and_bad_values_name_the_key() {
    let e = Scene::parse(MINIMAL, &["toggles.jumpin=false".into()], "test").unwrap_err();
    assert!(e.message.contains("jumpin"), "{e}");
    let e = Scene::parse(MINIMAL, &["particles.radius_max=1e-4".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "particles.radius_max");
    let e = Scene::parse(MINIMAL, &["run.dt=-1".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "run.dt");
    let e = Scene::parse(MINIMAL, &["contact.normal=linear".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "contact.kn");
    let e = Scene::parse(MINIMAL, &["contact.wall_friction=-0.1".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "contact.wall_friction");
}

#[test]
fn friction_accepts_inf_as_the_uncapped_law() {
    let s = Scene::parse(MINIMAL, &["contact.wall_friction=inf".into()], "test").unwrap();
    s.validate().unwrap();
    let (pair, wall) = s.laws().unwrap();
    assert_eq!(
        wall.tangential,
        TangentialLaw::HaffWerner {
            gamma_t: 0.007,
            mu: f64::INFINITY
        }
    );
    assert_eq!(pair.tangential.mu(), 0.7);
    let e = Scene::parse(MINIMAL, &["contact.friction=nan".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "contact.friction");
}

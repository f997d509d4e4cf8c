//! Unit tests of scene text: parsing, overrides, and the laws of a parsed scene.

use particles::contact::{RollingLaw, TangentialLaw};
use particles::material::Material;
use particles::scene::{AutoDt, TimeStep};

use super::overrides::{parse, plain_words};
use super::parse_scene;

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
    let s = parse_scene(MINIMAL, &[], "test").unwrap();
    s.validate().unwrap();
    assert_eq!(s.material, Material::default());
    assert!((s.packing() - 0.229).abs() < 0.002, "packing {}", s.packing());
    let (pp, pw) = s.laws().unwrap();
    assert_eq!(pp, pw);
    assert_eq!(pp.tangential, TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 });
}

#[test]
fn overrides_set_any_key_and_toggles_change_only_values() {
    let s = parse_scene(
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
    let s = parse_scene(MINIMAL, &[], "test").unwrap();
    assert!(!toml::to_string(&s).unwrap().contains("restitution_tolerance"));
    let t = parse_scene(MINIMAL, &["run.restitution_tolerance=1e-3".into()], "test").unwrap();
    let again = parse_scene(&toml::to_string(&t).unwrap(), &[], "test").unwrap();
    assert_eq!(again.run.restitution_tolerance, 1e-3);
}

#[test]
fn unknown_keys_and_bad_values_name_the_key() {
    let e = parse_scene(MINIMAL, &["toggles.jumpin=false".into()], "test").unwrap_err();
    assert!(e.message.contains("jumpin"), "{e}");
    let e = parse_scene(MINIMAL, &["particles.radius_max=1e-4".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "particles.radius_max");
    let e = parse_scene(MINIMAL, &["run.dt=-1".into()], "test").unwrap().validate().unwrap_err();
    assert_eq!(e.key, "run.dt");
    let e = parse_scene(MINIMAL, &["contact.normal=linear".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "contact.kn");
    let e = parse_scene(MINIMAL, &["contact.wall_friction=-0.1".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "contact.wall_friction");
}

#[test]
fn bad_sds_rolling_values_name_their_key() {
    let invalid = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        parse_scene(MINIMAL, &sets, "test").unwrap().validate().unwrap_err()
    };
    let sds = "contact.rolling=sds";
    let e = invalid(&[sds]);
    assert!(e.key == "contact.rolling_resistance" && e.message.contains("needed"), "{e}");
    let e = invalid(&[sds, "contact.rolling_resistance=-0.1"]);
    assert_eq!(e.key, "contact.rolling_resistance", "{e}");
    let e = invalid(&[sds, "contact.rolling_resistance=0.1", "contact.rolling_resistance_spread=0.2"]);
    assert!(e.key == "contact.rolling_resistance_spread" && e.message.contains("at most"), "{e}");
    let e = invalid(&[sds, "contact.rolling_resistance=0.1", "contact.rolling_stiffness=0"]);
    assert_eq!(e.key, "contact.rolling_stiffness", "{e}");
    let e = invalid(&[sds, "contact.rolling_resistance=0.1", "contact.rolling_damping=-1"]);
    assert_eq!(e.key, "contact.rolling_damping", "{e}");
    // A valid one: the law whole, and the per-grain values within the spread.
    let s = parse_scene(
        MINIMAL,
        &[
            sds.into(),
            "contact.rolling_resistance=0.1".into(),
            "contact.rolling_resistance_spread=0.05".into(),
        ],
        "test",
    )
    .unwrap();
    s.validate().unwrap();
    assert_eq!(
        s.laws().unwrap().0.rolling,
        RollingLaw::SpringDashpotSlider {
            mu_r: 0.1,
            k_roll: None,
            gamma_roll: 0.0
        }
    );
    let mu = s.rolling_mu();
    assert_eq!(mu.len(), s.particles.count);
    assert!(mu.iter().all(|&m| (0.05..=0.15).contains(&m)));
    assert!(mu.iter().any(|&m| m < 0.09) && mu.iter().any(|&m| m > 0.11), "spread out");
}

#[test]
fn friction_accepts_inf_as_the_uncapped_law() {
    let s = parse_scene(MINIMAL, &["contact.wall_friction=inf".into()], "test").unwrap();
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
    let e = parse_scene(MINIMAL, &["contact.friction=nan".into()], "test")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_eq!(e.key, "contact.friction");
}

// The `--set` parser on plain TOML tables, whatever reads them.
fn read(doc: toml::Table) -> Result<toml::Table, String> {
    match doc.keys().find(|k| k.as_str() != "a") {
        Some(k) => Err(format!("unknown field `{k}`")),
        None => Ok(doc),
    }
}

#[test]
fn an_index_reaches_into_an_array_of_tables() {
    let text = "[[a]]\ncount = 1\n[[a]]\ncount = 2\n";
    let doc = parse(text, &["a.1.count=7".into()], "s.toml", read).unwrap();
    assert_eq!(doc["a"][1]["count"].as_integer(), Some(7));
    assert_eq!(doc["a"][0]["count"].as_integer(), Some(1));
    let e = parse(text, &["a.2.count=7".into()], "s.toml", read).unwrap_err();
    assert!(e.message.contains("list of 2"), "{e:?}");
}

#[test]
fn values_nest_and_errors_name_the_override_not_the_file() {
    let doc = parse("a = { b = 1 }", &["a.c=inf".into(), "a.d=none".into()], "s.toml", read).unwrap();
    assert_eq!(doc["a"]["c"].as_float(), Some(f64::INFINITY));
    assert_eq!(doc["a"]["d"].as_str(), Some("none"));
    let e = parse("a = 1", &["a=2".into(), "durration=5".into()], "s.toml", read).unwrap_err();
    assert_eq!(e.key, "--set durration=5");
    assert!(e.to_string().contains("unknown field `durration`"), "{e}");
    let e = parse("b = 1", &["a=2".into()], "s.toml", read).unwrap_err();
    assert_eq!(e.key, "s.toml", "the file's own error names the file");
    let e = parse("a = 1", &["a.b=2".into()], "s.toml", read).unwrap_err();
    assert_eq!(e.key, "--set a.b=2");
    // A table set to a value is named as a table, with its keys.
    let e = parse("a = { b = 1 }", &["a=5".into()], "s.toml", read).unwrap_err();
    assert!(e.to_string().contains("`a` is a table of keys (b)"), "{e}");
    assert_eq!(
        plain_words("invalid type: integer `5`, expected struct TrayBox"),
        "invalid type: integer `5`, expected a table of keys"
    );
    let e = parse("a = 1", &["novalue".into()], "s.toml", read).unwrap_err();
    assert_eq!(e.key, "--set novalue");
}

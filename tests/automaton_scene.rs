//! The `[automaton]` scene table: optional, validated by key, and invisible to the DEM's
//! sample cache (regression guard: adding the table must not re-key existing samples).

use particles::prepare::sample_key;
use particles::scene::{AutomatonLateral, AutomatonRule, Scene};

const SCENE: &str = r#"
[box]
length = 0.1
width = 0.02
[drive]
frequency = 20.0
amplitude = 0.025
[particles]
count = 1000
radius_min = 0.25e-3
radius_max = 0.5e-3
[run]
duration = 3.0
dt = 8e-6
seed = 1
"#;

#[test]
fn default_table_is_omitted_and_automaton_keys_never_change_the_sample() {
    let plain = Scene::parse(SCENE, &[], "test").unwrap();
    assert_eq!(plain.automaton.rule, AutomatonRule::Physical);
    assert_eq!(plain.automaton.lateral, AutomatonLateral::Clusters);
    assert!(!toml::to_string(&plain).unwrap().contains("[automaton]"));
    let tuned = Scene::parse(
        SCENE,
        &[
            "automaton.activation=0.3".into(),
            "automaton.rule=strict".into(),
            "automaton.lateral=none".into(),
        ],
        "test",
    )
    .unwrap();
    assert!(toml::to_string(&tuned).unwrap().contains("[automaton]"));
    assert_eq!(sample_key(&plain), sample_key(&tuned));
}

#[test]
fn bad_automaton_values_name_their_key() {
    for (set, key) in [
        ("automaton.activation=1.5", "automaton.activation"),
        ("automaton.sideways_probability=-0.1", "automaton.sideways_probability"),
        ("automaton.knock_speed=0", "automaton.knock_speed"),
        ("automaton.cell=-1e-3", "automaton.cell"),
    ] {
        let s = Scene::parse(SCENE, &[set.into()], "test").unwrap();
        assert_eq!(s.automaton.validate().unwrap_err().key, key);
    }
    let e = Scene::parse(SCENE, &["automaton.flight=true".into()], "test").unwrap_err();
    assert!(e.message.contains("flight"), "{e}");
}

//! Scene text: the TOML of a scene file and the `--set dotted.key=value` overrides, read into
//! the typed scenes of the physics crates. The physics crates know no file format: their
//! scene types only derive serde, and this module is where text becomes a scene.

pub mod overrides;

use particles::scene::{Scene, SceneError};
use serde::Deserialize;

/// Parses a DEM scene from TOML text with `--set`-style overrides applied first. `origin`
/// names the source in messages; an error an override causes names the override. The
/// scene is not validated: call [`Scene::validate`].
pub fn parse_scene(text: &str, overrides: &[String], origin: &str) -> Result<Scene, SceneError> {
    overrides::parse(text, overrides, origin, |doc| {
        Scene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())
    })
}

#[cfg(test)]
mod tests;

//! The scenes built into the tools, by the names their `--scene` takes: `courtyard` and
//! `city:N`, with where the tools put procedural lights in each.

use super::city::{self, city};
use super::courtyard::{self, courtyard};
use crate::scene::{Aabb, Scene};

/// A scene built into the tools, with where they put procedural lights in it.
#[derive(Debug, Clone)]
pub struct BuiltinScene {
    /// The scene itself.
    pub scene: Scene,
    /// Where procedural lights go, and their radii.
    pub light_region: Aabb,
    /// `(min, max)` range in metres that procedural lights draw theirs from.
    pub light_radii: (f32, f32),
    /// Whether it is the courtyard, which has its own calibrated look
    /// (`renderer::frame::courtyard_look`).
    pub courtyard: bool,
}

/// The built-in scene a tool's `--scene` names, if it names one: `courtyard` (the demo scene)
/// or `city:N` (a generated city of `N` instances, [`city`], its lights along the streets
/// around its camera). `Ok(None)`: not a built-in name (a file path); `Err`: a `city:` name
/// with a bad count.
pub fn builtin(name: &str) -> Result<Option<BuiltinScene>, String> {
    if name == "courtyard" {
        return Ok(Some(BuiltinScene {
            scene: courtyard(),
            light_region: courtyard::LIGHT_REGION,
            light_radii: courtyard::LIGHT_RADII,
            courtyard: true,
        }));
    }
    let Some(count) = name.strip_prefix("city:") else {
        return Ok(None);
    };
    match count.replace('_', "").parse::<usize>() {
        Ok(n) if (1..=city::MAX_INSTANCES).contains(&n) => Ok(Some(BuiltinScene {
            scene: city(n),
            light_region: city::LIGHT_REGION,
            light_radii: city::LIGHT_RADII,
            courtyard: false,
        })),
        _ => Err(format!(
            "`{name}`: give the city's instance count, from 1 to {}, as in `city:20000`",
            city::MAX_INSTANCES
        )),
    }
}

//! The JSON sidecar: decals (and PNG materials) for a scene, in a file beside it.
//!
//! ```json
//! {
//!   "materials": [
//!     { "name": "logo", "base_color": "logo.png", "normal": "logo_normal.png" }
//!   ],
//!   "decals": [
//!     { "material": "scorch", "position": [0, 0.01, 2], "normal": [0, 1, 0],
//!       "size": [1.5, 1.5, 0.4], "roll": 30, "sort_key": 1 },
//!     { "material": "logo", "position": [3, 1, -4], "normal": [0, 0, 1], "size": [2, 1, 0.2],
//!       "blend": 0.8, "angle_fade": [50, 75], "distance_fade": [20, 30] }
//!   ]
//! }
//! ```
//!
//! Materials are the built-ins ([`super::procedural`]: `scorch`, `stain`, `sign`) and those the
//! file names; image paths are relative to the file. `normal` is the direction the decal faces
//! (out of the surface), `roll` turns it about that direction (degrees), `size` is width, height
//! and depth of its box; `angle_fade` is in degrees. Unknown fields are errors, so a typo is
//! never silently ignored.

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;

use super::decal::box_on_surface;
use super::{Decal, DecalError, DecalImage, DecalMaterial, DecalSet, procedural};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    materials: Vec<MaterialEntry>,
    #[serde(default)]
    decals: Vec<DecalEntry>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialEntry {
    name: String,
    base_color: PathBuf,
    normal: Option<PathBuf>,
    orm: Option<PathBuf>,
    emissive: Option<PathBuf>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DecalEntry {
    material: String,
    position: [f32; 3],
    normal: [f32; 3],
    size: [f32; 3],
    #[serde(default)]
    roll: f32,
    #[serde(default = "one")]
    blend: f32,
    angle_fade: Option<[f32; 2]>,
    distance_fade: Option<[f32; 2]>,
    #[serde(default)]
    sort_key: i32,
}

fn one() -> f32 {
    1.0
}

/// Reads a sidecar: the built-in materials, then the file's, and its decals (validated).
pub fn load(path: &Path) -> Result<DecalSet, DecalError> {
    let fail = |reason: String| DecalError::Sidecar {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
    let file: File = serde_json::from_str(&text).map_err(|e| fail(e.to_string()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut materials = procedural::materials();
    for m in &file.materials {
        if materials.iter().any(|known| known.name == m.name) {
            return Err(fail(format!("material {:?} is defined twice", m.name)));
        }
        let image =
            |p: &PathBuf| DecalImage::load_png(&dir.join(p)).map_err(|e| fail(e.to_string()));
        let optional = |p: &Option<PathBuf>| p.as_ref().map(image).transpose();
        materials.push(DecalMaterial {
            name: m.name.clone(),
            base_color: image(&m.base_color)?,
            normal: optional(&m.normal)?,
            orm: optional(&m.orm)?,
            emissive: optional(&m.emissive)?,
        });
    }
    let decals = file
        .decals
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let material = materials
                .iter()
                .position(|m| m.name == d.material)
                .ok_or_else(|| {
                    let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
                    fail(format!(
                        "decal {i}: no material {:?} (known: {})",
                        d.material,
                        names.join(", ")
                    ))
                })?;
            let normal = Vec3::from_array(d.normal);
            if !normal.is_finite() || normal.length_squared() < 1e-12 {
                return Err(fail(format!(
                    "decal {i}: normal {:?} has no direction",
                    d.normal
                )));
            }
            let mut decal = Decal::new(
                box_on_surface(
                    Vec3::from_array(d.position),
                    normal,
                    d.roll.to_radians(),
                    Vec3::from_array(d.size),
                ),
                material,
            );
            decal.blend = d.blend;
            if let Some([a, b]) = d.angle_fade {
                decal.angle_fade = [a.to_radians(), b.to_radians()];
            }
            if let Some(f) = d.distance_fade {
                decal.distance_fade = f;
            }
            decal.sort_key = d.sort_key;
            Ok(decal)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let set = DecalSet { materials, decals };
    set.validate().map_err(|e| fail(e.to_string()))?;
    Ok(set)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("decal-sidecar-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn a_sidecar_with_built_in_and_png_materials_loads() {
        let png = write("red.png", "");
        image::RgbaImage::from_pixel(8, 4, image::Rgba([255, 0, 0, 200]))
            .save(&png)
            .unwrap();
        let path = write(
            "ok.json",
            r#"{ "materials": [ { "name": "red", "base_color": "red.png" } ],
                 "decals": [
                   { "material": "scorch", "position": [0, 0, 0], "normal": [0, 1, 0],
                     "size": [2, 2, 0.5], "sort_key": 3 },
                   { "material": "red", "position": [1, 2, 3], "normal": [0, 0, 1],
                     "size": [1, 1, 1], "roll": 90, "angle_fade": [10, 20], "blend": 0.5 } ] }"#,
        );
        let set = load(&path).unwrap();
        assert_eq!(set.materials.len(), 4);
        assert_eq!(set.materials[3].base_color.width, 8);
        assert_eq!(set.decals[0].sort_key, 3);
        assert_eq!(set.decals[1].material, 3);
        assert!((set.decals[1].angle_fade[1] - 20f32.to_radians()).abs() < 1e-6);
        let b = set.decals[0].bounds().unwrap();
        assert!((b.axes[2] - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn mistakes_name_the_file_and_what_is_wrong() {
        let cases = [
            ("typo.json", r#"{ "decal": [] }"#, "unknown field `decal`"),
            ("syntax.json", r#"{ "decals": [ }"#, "line 1"),
            (
                "material.json",
                r#"{ "decals": [ { "material": "graffiti", "position": [0,0,0],
                   "normal": [0,1,0], "size": [1,1,1] } ] }"#,
                "no material \"graffiti\" (known: scorch, stain, sign)",
            ),
            (
                "normal.json",
                r#"{ "decals": [ { "material": "stain", "position": [0,0,0],
                   "normal": [0,0,0], "size": [1,1,1] } ] }"#,
                "no direction",
            ),
            (
                "size.json",
                r#"{ "decals": [ { "material": "stain", "position": [0,0,0],
                   "normal": [0,1,0], "size": [1,0,1] } ] }"#,
                "decal 0: its box",
            ),
            (
                "png.json",
                r#"{ "materials": [ { "name": "x", "base_color": "missing.png" } ] }"#,
                "missing.png",
            ),
        ];
        for (name, text, words) in cases {
            let e = load(&write(name, text)).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains(words), "{name}: {e}");
        }
    }
}

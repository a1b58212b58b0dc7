//! The benchmark matrix: the axes chosen on the command line, expanded into renderer set-ups
//! (one `Renderer` each) that are measured at every light count.

use anyhow::{Result, bail};
use renderer::frame::{RenderPath, VisibilityRaster};

/// A path of the matrix, with its command-line name: a render path, and on the visibility
/// path what rasterises it (`visibility-compute`: the compute rasteriser).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PathChoice(pub RenderPath, pub VisibilityRaster);

/// The name of the visibility path with the compute rasteriser.
const VISIBILITY_COMPUTE: &str = "visibility-compute";

impl PathChoice {
    pub fn parse(s: &str) -> Result<Self> {
        if s == VISIBILITY_COMPUTE {
            return Ok(Self(RenderPath::Visibility, VisibilityRaster::Compute));
        }
        let path = s.parse().map_err(|e: String| {
            anyhow::anyhow!("{e} (or {VISIBILITY_COMPUTE}: the visibility path, compute raster)")
        })?;
        Ok(Self(path, VisibilityRaster::Hardware))
    }

    pub fn name(self) -> &'static str {
        match self.1 {
            VisibilityRaster::Compute if self.0 == RenderPath::Visibility => VISIBILITY_COMPUTE,
            _ => self.0.name(),
        }
    }

    fn has_tiles(self) -> bool {
        self.0.is_culled()
    }

    /// Whether the scalarize axis changes anything: the culled forward shader and the TBDR
    /// kernel have subgroup variants; the naive loop and the light volumes have none.
    fn has_scalarize(self) -> bool {
        !matches!(
            self.0,
            RenderPath::Naive | RenderPath::NaivePrez | RenderPath::Deferred
        )
    }
}

/// The axes of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Axes {
    pub scenes: Vec<String>,
    pub sizes: Vec<(u32, u32)>,
    pub msaa: Vec<u32>,
    pub paths: Vec<PathChoice>,
    pub tiles: Vec<u32>,
    pub scalarize: Vec<bool>,
    /// Culling without the super-tile level (brute force): `false`, `true` or both.
    pub brute_force: Vec<bool>,
    pub lights: Vec<u32>,
}

/// One renderer set-up of the matrix; it is measured at every light count of the run.
#[derive(Debug, Clone, PartialEq)]
pub struct Setup {
    /// Index into `Axes::scenes`.
    pub scene: usize,
    pub width: u32,
    pub height: u32,
    pub msaa: u32,
    pub path: PathChoice,
    /// 0 for paths without tiles.
    pub tile: u32,
    pub scalarize: bool,
    /// Every tile tests every light (no super-tile level).
    pub brute_force: bool,
}

/// What the adapter can run; cells outside it are left out (and said so).
#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    pub msaa: Vec<u32>,
    pub subgroup: bool,
    /// 64-bit atomic min/max (the compute rasteriser).
    pub int64_atomics: bool,
}

/// Expands the axes into set-ups the adapter supports, in a stable order, and lists what was
/// left out.
pub fn expand(axes: &Axes, support: &Support) -> (Vec<Setup>, Vec<String>) {
    let mut setups = Vec::new();
    let mut left_out = Vec::new();
    for &m in &axes.msaa {
        if !support.msaa.contains(&m) {
            left_out.push(format!(
                "MSAA {m}: not supported by this adapter ({:?})",
                support.msaa
            ));
        }
    }
    if axes.tiles.contains(&32) && axes.paths.iter().any(|p| p.0.is_deferred()) {
        left_out.push("tile 32 on the TBDR paths: their tiles are 8 or 16".into());
    }
    let compute_raster = |p: &PathChoice| p.1 == VisibilityRaster::Compute;
    if axes.paths.iter().any(compute_raster) && !support.int64_atomics {
        left_out.push(format!(
            "{VISIBILITY_COMPUTE}: the adapter has no 64-bit atomic min/max"
        ));
    }
    if axes.scalarize.contains(&true) && !support.subgroup {
        left_out.push("scalarize on: the adapter has no SUBGROUP feature".into());
    }
    for scene in 0..axes.scenes.len() {
        for &(width, height) in &axes.sizes {
            for &msaa in axes.msaa.iter().filter(|m| support.msaa.contains(m)) {
                for &path in axes
                    .paths
                    .iter()
                    .filter(|p| support.int64_atomics || !compute_raster(p))
                {
                    // TBDR tiles are 8 or 16 (one invocation per pixel); the light volumes
                    // have none (their base pass runs at 16).
                    let tbdr_tiles: Vec<u32> =
                        axes.tiles.iter().copied().filter(|t| *t <= 16).collect();
                    let tiles: &[u32] = if path.0 == RenderPath::Deferred {
                        &[16]
                    } else if path.0.is_deferred() && path.0 != RenderPath::Visibility {
                        &tbdr_tiles
                    } else if path.has_tiles() {
                        &axes.tiles
                    } else {
                        &[0]
                    };
                    let scalar: Vec<bool> = if path.has_scalarize() {
                        axes.scalarize
                            .iter()
                            .copied()
                            .filter(|&s| !s || support.subgroup)
                            .collect()
                    } else {
                        vec![false]
                    };
                    let brute: &[bool] = if path.has_tiles() && !path.0.is_deferred() {
                        &axes.brute_force
                    } else {
                        &[false]
                    };
                    for &tile in tiles {
                        for &scalarize in &scalar {
                            for &brute_force in brute {
                                setups.push(Setup {
                                    scene,
                                    width,
                                    height,
                                    msaa,
                                    path,
                                    tile,
                                    scalarize,
                                    brute_force,
                                });
                            }
                        }
                    }
                }
            }
        }
    }
    (setups, left_out)
}

/// What a group of set-ups shares: scene, size and MSAA (`--isolate` runs a group per process).
pub type GroupKey = (usize, u32, u32, u32);

pub fn group_key(s: &Setup) -> GroupKey {
    (s.scene, s.width, s.height, s.msaa)
}

/// The distinct groups of `setups`, in order of first appearance.
pub fn groups(setups: &[Setup]) -> Vec<GroupKey> {
    let mut keys: Vec<GroupKey> = Vec::new();
    for s in setups {
        let k = group_key(s);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    s.split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| (1..=8192).contains(&w) && (1..=8192).contains(&h))
        .ok_or_else(|| {
            anyhow::anyhow!("size {s:?}: use WxH with each side 1..=8192, e.g. 1920x1080")
        })
}

/// Parses a culling level choice: `hierarchical` or `brute-force` (whether brute force).
pub fn parse_cull(s: &str) -> Result<bool> {
    match s {
        "hierarchical" => Ok(false),
        "brute-force" => Ok(true),
        other => bail!("cull {other:?}: use hierarchical, brute-force or both"),
    }
}

/// Parses `on` / `off`.
pub fn parse_on_off(s: &str) -> Result<bool> {
    match s {
        "on" => Ok(true),
        "off" => Ok(false),
        other => bail!("scalarize {other:?}: use off, on or off,on"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> Axes {
        Axes {
            scenes: vec!["demo".into()],
            sizes: vec![(1920, 1080), (3840, 2160)],
            msaa: vec![1, 2, 4, 8],
            paths: ["naive", "naive-prez", "tiled", "2.5d", "clustered"]
                .iter()
                .map(|p| PathChoice::parse(p).unwrap())
                .collect(),
            tiles: vec![8, 16, 32],
            scalarize: vec![false, true],
            brute_force: vec![false],
            lights: vec![1024, 4096],
        }
    }

    #[test]
    fn the_default_matrix_on_a_full_gpu() {
        let support = Support {
            msaa: vec![1, 2, 4, 8],
            subgroup: true,
            int64_atomics: true,
        };
        let (setups, left_out) = expand(&axes(), &support);
        // Per size and MSAA: naive, naive-prez, tiled 3×2, 2.5D 3×2, clustered 3×2.
        assert_eq!(setups.len(), 2 * 4 * 20);
        assert!(left_out.is_empty());
        assert!(setups.iter().all(|s| s.tile == 0 || s.path.has_tiles()));
    }

    #[test]
    fn the_compute_raster_is_a_path_left_out_without_64_bit_atomics() {
        let compute = PathChoice::parse("visibility-compute").unwrap();
        assert_eq!(
            (compute.0, compute.1, compute.name()),
            (
                RenderPath::Visibility,
                VisibilityRaster::Compute,
                "visibility-compute"
            )
        );
        let mut axes = axes();
        axes.msaa = vec![4];
        axes.tiles = vec![16];
        let hardware = PathChoice::parse("visibility").unwrap();
        axes.paths = vec![hardware, compute];
        let support = |int64_atomics| Support {
            msaa: vec![4],
            subgroup: true,
            int64_atomics,
        };
        let (setups, left_out) = expand(&axes, &support(true));
        assert!(left_out.is_empty());
        let count = |path| setups.iter().filter(|s| s.path == path).count();
        assert!(count(compute) > 0 && count(compute) == count(hardware));
        let (setups, left_out) = expand(&axes, &support(false));
        assert!(setups.iter().all(|s| s.path != compute) && !setups.is_empty());
        assert!(left_out.iter().any(|l| l.contains("visibility-compute")));
    }

    #[test]
    fn unsupported_cells_are_left_out_and_named() {
        let support = Support {
            msaa: vec![1, 4],
            subgroup: false,
            int64_atomics: false,
        };
        let (setups, left_out) = expand(&axes(), &support);
        assert_eq!(setups.len(), 2 * 2 * 11);
        assert!(
            setups
                .iter()
                .all(|s| !s.scalarize && [1, 4].contains(&s.msaa))
        );
        assert_eq!(left_out.len(), 3, "{left_out:?}");
        assert_eq!(groups(&setups).len(), 2 * 2, "one group per size and MSAA");
    }

    #[test]
    fn bad_axis_values_say_what_to_use() {
        assert!(
            PathChoice::parse("forward-plus")
                .unwrap_err()
                .to_string()
                .contains("2.5d")
        );
        assert!(parse_size("1920").is_err());
        assert!(parse_on_off("maybe").is_err());
        assert!(
            parse_cull("fast")
                .unwrap_err()
                .to_string()
                .contains("brute-force")
        );
        assert_eq!(parse_size("64x32").unwrap(), (64, 32));
    }
}

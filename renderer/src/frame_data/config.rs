//! The renderer's configuration: size, MSAA, light-culling path, view.

use glam::Vec3;

/// How the forward pass finds its lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderPath {
    /// Every light at every pixel, without a depth pre-pass (overdraw shades every layer).
    Naive,
    /// Every light at every pixel after a depth pre-pass (the reference image of the culled
    /// paths).
    NaivePrez,
    /// Tiled culling (Forward+).
    Tiled,
    /// Tiled culling with the 2.5D depth mask.
    Depth25,
    /// Clustered culling: froxels of one tile × one of 32 exponential depth slices.
    Clustered,
    /// Tile-based deferred shading in compute (reference 000): a G-buffer, then one dispatch
    /// per frame that bounds each tile's depth, culls the lights in workgroup memory and
    /// shades, per sample where a pixel's samples differ (each pixel shades its own samples).
    Tbdr,
    /// [`RenderPath::Tbdr`] with deferred per-sample shading: the edge pixels' samples go to a
    /// tile list that every invocation of the tile drains.
    TbdrPerSample,
    /// Traditional deferred shading (reference 000's "deferred" method): the G-buffer, a
    /// full-screen base pass (ambient, emissive, directional lights, edge pixels marked), then
    /// every punctual light drawn as a light volume (its bounding cube's back faces) blended
    /// additively into the resolved image, per sample at edge pixels. No light culling: each
    /// light costs the pixels its volume covers.
    Deferred,
    /// The visibility buffer: one raster pass writes depth and, per sample, the ID of the
    /// triangle it sees (4 bytes); a compute pass finds each pixel's triangles again,
    /// evaluates their materials and lights them through clustered lists, each distinct
    /// triangle of a pixel once. It replaces pre-Z and the G-buffer.
    Visibility,
}

impl RenderPath {
    /// Every path, in the order tools list them.
    pub const ALL: [RenderPath; 9] = [
        Self::Naive,
        Self::NaivePrez,
        Self::Tiled,
        Self::Depth25,
        Self::Clustered,
        Self::Tbdr,
        Self::TbdrPerSample,
        Self::Deferred,
        Self::Visibility,
    ];

    /// The command-line name: `naive`, `naive-prez`, `tiled`, `2.5d`, `clustered`, `tbdr`,
    /// `tbdr-per-sample`, `deferred`, `visibility`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Naive => "naive",
            Self::NaivePrez => "naive-prez",
            Self::Tiled => "tiled",
            Self::Depth25 => "2.5d",
            Self::Clustered => "clustered",
            Self::Tbdr => "tbdr",
            Self::TbdrPerSample => "tbdr-per-sample",
            Self::Deferred => "deferred",
            Self::Visibility => "visibility",
        }
    }

    /// Whether the path culls lights into per-cell lists. The deferred paths do when a pass
    /// other than their own shading needs lists (blended surfaces, decals in the G-buffer,
    /// particles, the heatmap views), with tiled culling; they shade opaque surfaces without.
    pub fn is_culled(self) -> bool {
        !matches!(self, Self::Naive | Self::NaivePrez)
    }

    /// Whether opaque surfaces are shaded after the geometry is drawn, from a G-buffer (the
    /// deferred paths) or a visibility buffer, and blended surfaces drawn over the result.
    pub fn is_deferred(self) -> bool {
        matches!(
            self,
            Self::Tbdr | Self::TbdrPerSample | Self::Deferred | Self::Visibility
        )
    }

    /// Whether a pass before shading writes the scene's depth: pre-Z, or the visibility
    /// path's raster pass.
    pub fn has_prepass(self) -> bool {
        self != Self::Naive
    }

    /// Whether the frame runs the depth pre-pass proper (and, with occlusion culling, its
    /// late half; the visibility path splits its raster pass instead).
    pub fn has_prez(self) -> bool {
        !matches!(self, Self::Naive | Self::Visibility)
    }
}

/// What a frame shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrameView {
    /// The shaded image.
    #[default]
    Lit,
    /// The light-count heatmap of the culled path's lists, with a legend.
    Heatmap,
    /// The shadow atlas: depth as grey, each region outlined in its light's colour.
    ShadowAtlas,
    /// The decal-count heatmap: the same ramp and legend as [`FrameView::Heatmap`], over the
    /// cells' decal lists.
    DecalHeatmap,
    /// The particle lighting atlas of the frame, exposed like the image.
    ParticleAtlas,
    /// The TBDR paths' shading frequency: the image, with the pixels shaded per sample in red
    /// (reference 000's view).
    ShadingFrequency,
}

/// What rasterises the visibility path's opaque triangles
/// ([`RenderPath::Visibility`]; the other paths ignore it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VisibilityRaster {
    /// [`VisibilityRaster::Compute`] where the device has 64-bit atomic min/max and the storage
    /// buffers its shading kernels bind (a material program's 21,
    /// [`crate::gpu::requirements::WANTED_STORAGE_BUFFERS_PER_STAGE`]), else
    /// [`VisibilityRaster::Hardware`]: chosen when the renderer is created or reconfigured
    /// ([`VisibilityRaster::for_device`]; [`crate::frame::Renderer::config`] holds the choice).
    /// On the H200 the compute rasteriser's frame was the faster one at every sample count on
    /// every scene measured (BENCHMARKS.md); browsers have no 64-bit atomics.
    #[default]
    Auto,
    /// The hardware rasteriser, every draw.
    Hardware,
    /// Compute kernels with 64-bit atomics (`passes::visibility::compute_raster`) write one
    /// `u64` a sample into a buffer; the alpha-masked draws, on the hardware rasteriser, add
    /// theirs with the same atomics. Every pass of the frame reads that buffer
    /// ([`crate::frame_data::VisibilitySamples::Buffer`]): the shading kernels, the light and
    /// occlusion culling, and the blended surfaces and particles, which test the samples in
    /// their fragment stage. No multisampled depth target is written; a full-screen pass
    /// resolves the buffer's depths into one only for a pass that reads it (a tool's depth
    /// probe).
    /// Needs `SHADER_INT64_ATOMIC_MIN_MAX`
    /// ([`crate::gpu::Capabilities::int64_atomic_min_max`]).
    Compute,
}

impl VisibilityRaster {
    /// The command-line name: `auto`, `hardware` or `compute`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Hardware => "hardware",
            Self::Compute => "compute",
        }
    }

    /// The raster a device with `caps` and `limits` runs for this choice:
    /// [`VisibilityRaster::Auto`] made concrete, the others as they are (an explicit `Compute`
    /// on a device without 64-bit atomics stays, and the visibility path then refuses it by
    /// name).
    pub fn for_device(self, caps: &crate::gpu::Capabilities, limits: &wgpu::Limits) -> Self {
        let storage = limits.max_storage_buffers_per_shader_stage;
        match self {
            Self::Auto
                if caps.int64_atomic_min_max
                    && storage >= crate::gpu::requirements::WANTED_STORAGE_BUFFERS_PER_STAGE =>
            {
                Self::Compute
            }
            Self::Auto => Self::Hardware,
            chosen => chosen,
        }
    }
}

impl std::str::FromStr for VisibilityRaster {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        [Self::Auto, Self::Hardware, Self::Compute]
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| format!("visibility raster {s:?}: use auto, hardware or compute"))
    }
}

/// How particles are lit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ParticleLighting {
    /// Once per frame into the lighting atlas, at a few texels per particle; the draw samples
    /// it bicubically (DOOM 2016).
    #[default]
    Atlas,
    /// In the particle fragment shader, per pixel of every overlapping particle: the reference
    /// the atlas is measured against.
    PerPixel,
}

impl ParticleLighting {
    /// The command-line name: `atlas` or `per-pixel`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Atlas => "atlas",
            Self::PerPixel => "per-pixel",
        }
    }
}

impl std::str::FromStr for ParticleLighting {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        [Self::Atlas, Self::PerPixel]
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("particle lighting {s:?}: use atlas or per-pixel"))
    }
}

/// When the TBDR paths shade a pixel per sample: when any of its samples differs from sample 0
/// by one of these (or one is sky and the other not). Within one triangle every sample of a
/// pixel has the same G-buffer values, so only depth varies there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeThresholds {
    /// Largest distance of a sample from the plane of sample 0 (its point and geometric
    /// normal), relative to sample 0's view depth (default 0.01): a slope never counts.
    pub depth: f32,
    /// Smallest cosine between the shading normals (default 0.999, about 2.6°).
    pub normal_cos: f32,
    /// Largest difference of albedo, metalness or roughness, and of base radiance relative to
    /// `1 +` its size (default 0.01).
    pub material: f32,
}

impl Default for EdgeThresholds {
    fn default() -> Self {
        Self {
            depth: 0.01,
            normal_cos: 0.999,
            material: 0.01,
        }
    }
}

impl EdgeThresholds {
    /// Thresholds no pair of samples passes: every pixel is shaded once, at sample 0 (for
    /// comparisons; edges then lose their antialiasing).
    pub const NEVER: Self = Self {
        depth: f32::MAX,
        normal_cos: -2.0,
        material: f32::MAX,
    };
}

/// Hemisphere ambient light, linear RGB radiance: `sky` reaches a surface facing straight up
/// (world +Y), `ground` one facing straight down, and a surface in between gets
/// `ground + (sky − ground) · (n.y / 2 + 1/2)` at its shading normal `n`, times its base colour
/// and occlusion (particles: times their colour). A scene without lights of its own shows by it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ambient {
    /// Radiance reaching a surface that faces straight up.
    pub sky: Vec3,
    /// Radiance reaching a surface that faces straight down.
    pub ground: Vec3,
}

impl Ambient {
    /// No ambient light: only lights and emission show.
    pub const OFF: Self = Self::uniform(Vec3::ZERO);

    /// The default: a grey sky of 0.3 over a grey ground of 0.1, so a file scene without lights
    /// of its own is plainly visible, and, flat and brighter from above, still reads as unlit.
    pub const DEFAULT: Self = Self {
        sky: Vec3::splat(0.3),
        ground: Vec3::splat(0.1),
    };

    /// The same `radiance` from every direction.
    pub const fn uniform(radiance: Vec3) -> Self {
        Self {
            sky: radiance,
            ground: radiance,
        }
    }
}

impl Default for Ambient {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// [`RendererConfig::light_cutoff`]'s default.
pub const DEFAULT_LIGHT_CUTOFF: f32 = 1.0e-3;

/// Renderer settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RendererConfig {
    /// Frame width in pixels: the target's, and every internal target's.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// 1, 2, 4 or 8, as the adapter supports for Depth32Float and Rgba16Float.
    pub msaa: u32,
    /// How lights are culled and surfaces shaded.
    pub path: RenderPath,
    /// What rasterises the visibility path's opaque triangles.
    pub visibility_raster: VisibilityRaster,
    /// Tile size of the tiled and clustered paths (8, 16 or 32) and of the TBDR paths (8 or
    /// 16: one invocation per pixel, and a tile's per-sample colours in workgroup memory).
    pub tile: u32,
    /// Use subgroup variants of the forward shader where the device has SUBGROUP.
    pub scalarize: bool,
    /// Cull without the super-tile level (every tile tests every light), for comparison.
    pub cull_brute_force: bool,
    /// Time each culling dispatch separately (frame timings then list `cull: tile depth`,
    /// `cull: super-tiles` and `cull: tiles`); costs a few tens of µs per frame.
    pub time_cull_dispatches: bool,
    /// Format of the caller's target (an sRGB format gets sRGB output).
    pub output_format: wgpu::TextureFormat,
    /// Ambient light: sky above, ground below ([`Ambient`]).
    pub ambient: Ambient,
    /// Background where no surface is drawn, linear HDR RGB (before exposure).
    pub sky: Vec3,
    /// Scale of the HDR colour before tonemapping (`2^EV`).
    pub exposure: f32,
    /// Shaded image or light-count heatmap.
    pub view: FrameView,
    /// Light count at which the heatmap saturates (red).
    pub heatmap_max: u32,
    /// Decal count shown as full red in the decal heatmap.
    pub decal_heatmap_max: u32,
    /// How particles are lit (when the renderer has particles).
    pub particle_lighting: ParticleLighting,
    /// Side of the particle lighting atlas, texels (a power of two); 0 picks 2048, or more
    /// when the particle capacity needs it.
    pub particle_atlas_side: u32,
    /// View-depth distance over which particles fade out in front of a surface (soft
    /// particles); 0 turns the fade off.
    pub soft_particle_distance: f32,
    /// The shadow atlas: size, resolutions, caching.
    pub shadows: crate::shadow::ShadowConfig,
    /// Which pixels the TBDR paths shade per sample.
    pub edges: EdgeThresholds,
    /// Illuminance, after exposure, below which a point or spot light without a range (glTF
    /// allows none: infinite) is cut off. Such a light gets the effective range
    /// `crate::frame_data::effective_range`, where its illuminance falls to this; the range
    /// window then changes no surface's illuminance by more than this anywhere. The default,
    /// 0.001, is under half an 8-bit step on a white surface through the ACES tonemap. 0 keeps
    /// such lights infinite (every tile and froxel lists them; a light volume covers the
    /// screen).
    pub light_cutoff: f32,
    /// Cull the scene's draws against the view frustum on the GPU before the geometry passes
    /// draw them (`passes::scene_cull`), and the shadow casters against each shadow region
    /// drawn (`shadow_cull`). Off, every draw is drawn, in the same batches and order, and
    /// every caster into every region drawn: the frame is the same either way.
    pub cull_draws: bool,
    /// With `cull_draws`, on the paths with a depth pre-pass or the visibility raster:
    /// two-phase occlusion culling (`passes::scene_cull::occlusion`). Pre-Z (or the visibility
    /// raster) draws what was visible last frame, a depth pyramid is built from it, every draw
    /// in the frustum is tested against the pyramid, and the newly visible ones are drawn into
    /// the depth (and the IDs) too; the passes after it draw both. The frame is the same
    /// either way.
    pub occlusion_cull: bool,
    /// Occlusion culling runs on scenes of at least this many opaque and masked draws: its
    /// fixed cost (a depth pyramid of the frame, about 0.1 ms at 1080p on an H200) outweighs
    /// what it saves on small scenes (the courtyard's 154 draws). 0 always runs it.
    pub occlusion_min_draws: u32,
    /// Tonemap with a compute kernel where the target allows it (an `Rgba8Unorm` output with
    /// `STORAGE_BINDING`, written directly; an `Rgba8Unorm` or `Rgba8UnormSrgb` one with
    /// `COPY_DST`, written by a copy), else with a full-screen fragment pass; `false`: always the
    /// fragment pass. The two agree within one 8-bit step; on GPUs whose fragment
    /// rate is far below their compute rate the kernel costs a tenth of the pass.
    pub compute_tonemap: bool,
    /// On the compute rasteriser's frame, how many blended fragments are listed and lit in
    /// compute (16 bytes each); a fragment past them is shaded by the forward pass's fragment
    /// stage, the same colour at the fragment rate. 0 picks one for every two pixels (16.6 MB
    /// at 1080p).
    pub blended_fragment_records: u32,
}

impl std::str::FromStr for RenderPath {
    type Err = String;

    /// Parses a [`RenderPath::name`].
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|p| p.name()).collect();
                format!("path {s:?}: use one of {}", names.join(", "))
            })
    }
}

impl RendererConfig {
    /// Whether the frame's passes read the compute rasteriser's buffer of samples rather than
    /// raster targets: the visibility path under [`VisibilityRaster::Compute`] (the shading
    /// kernels', light culling's and depth pyramid's `vis64` variants). Ask a configuration the
    /// renderer made concrete ([`crate::frame::Renderer::config`]): before, `Auto` answers
    /// `false`, whatever the device will choose.
    pub fn reads_compute_samples(&self) -> bool {
        self.path == RenderPath::Visibility && self.visibility_raster == VisibilityRaster::Compute
    }

    /// The shadow settings this configuration draws with: `shadows` fitted to the output
    /// ([`crate::shadow::ShadowConfig::fitted`]).
    pub fn fitted_shadows(&self) -> crate::shadow::ShadowConfig {
        self.shadows.fitted(self.width, self.height)
    }
}

impl Default for RendererConfig {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            msaa: 4,
            path: RenderPath::Tiled,
            visibility_raster: VisibilityRaster::Auto,
            tile: 16,
            scalarize: false,
            cull_brute_force: false,
            time_cull_dispatches: false,
            output_format: wgpu::TextureFormat::Rgba8UnormSrgb,
            ambient: Ambient::DEFAULT,
            sky: Vec3::ZERO,
            exposure: 1.0,
            view: FrameView::Lit,
            heatmap_max: 256,
            decal_heatmap_max: 16,
            particle_lighting: ParticleLighting::Atlas,
            particle_atlas_side: 0,
            soft_particle_distance: 0.3,
            shadows: crate::shadow::ShadowConfig::default(),
            edges: EdgeThresholds::default(),
            light_cutoff: DEFAULT_LIGHT_CUTOFF,
            cull_draws: true,
            occlusion_cull: true,
            occlusion_min_draws: 512,
            compute_tonemap: true,
            blended_fragment_records: 0,
        }
    }
}

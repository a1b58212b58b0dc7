//! What the page shows, built the same way in the browser and natively: the built-in courtyard
//! with seeded procedural lights (the nearest casting shadows), decals and particles, its look,
//! and an orbit camera around it. The browser test renders a [`Showcase`] natively on lavapipe
//! and compares the page's frame with it.

use glam::Vec3;
use renderer::decals::{DecalSet, procedural};
use renderer::demo::{courtyard_look, pick_shadowed, procedural_lights, scatter_decals};
use renderer::frame::{FrameCamera, RenderError, Renderer, RendererConfig, VisibilityRaster};
use renderer::particles::{ParticleSystem, WARMUP_STEPS, builtin_system};
use renderer::scene::{Scene, SceneError, SceneLight};
use renderer::{GpuContext, frame::RenderPath};

/// What the page renders and how: the path, MSAA, size and the scene's contents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// The lighting path (`RenderPath::name` on the page's path switch).
    pub path: RenderPath,
    /// Samples per pixel: 1 or 4 (WebGPU guarantees no other count).
    pub msaa: u32,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Procedural point lights.
    pub lights: usize,
    /// Of them, those that cast shadows: the ones covering most of the opening view.
    pub shadowed: usize,
    /// Procedural decals on the courtyard's surfaces.
    pub decals: usize,
    /// About this many live particles (smoke, sparks, dust); 0 for none.
    pub particles: u32,
    /// Seed of the lights, decals and particles.
    pub seed: u64,
}

impl Default for Settings {
    /// Forward+ at MSAA 4, 960×540, 256 lights (4 with shadows), 24 decals, 2,000 particles.
    fn default() -> Self {
        Self {
            path: RenderPath::Tiled,
            msaa: 4,
            width: 960,
            height: 540,
            lights: 256,
            shadowed: 4,
            decals: 24,
            particles: 2000,
            seed: 1,
        }
    }
}

impl Settings {
    /// Settings from a page address's query (`path=clustered&msaa=1&lights=512`): the
    /// defaults, with each `key=value` pair replacing one. Keys: `path` (a
    /// [`RenderPath::name`]), `msaa`, `width`, `height`, `lights`, `shadowed`, `decals`,
    /// `particles`, `seed`. An unknown key or a bad value is an error naming it.
    pub fn from_query(query: &str) -> Result<Self, String> {
        let mut settings = Self::default();
        for pair in query.trim_start_matches('?').split('&') {
            if pair.is_empty() {
                continue;
            }
            let (key, value) = pair
                .split_once('=')
                .ok_or_else(|| format!("`{pair}`: give a value, as in `{pair}=…`"))?;
            settings.set(key, value)?;
        }
        if !(1..=4096).contains(&settings.width) || !(1..=4096).contains(&settings.height) {
            return Err(format!(
                "a {}×{} frame: width and height go from 1 to 4096",
                settings.width, settings.height
            ));
        }
        Ok(settings)
    }

    /// Sets one setting from its query key and text.
    fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        fn number<T: std::str::FromStr>(key: &str, value: &str) -> Result<T, String> {
            value
                .parse()
                .map_err(|_| format!("`{key}={value}`: not a whole number"))
        }
        match key {
            "path" => self.path = value.parse()?,
            "msaa" => self.msaa = number(key, value)?,
            "width" => self.width = number(key, value)?,
            "height" => self.height = number(key, value)?,
            "lights" => self.lights = number(key, value)?,
            "shadowed" => self.shadowed = number(key, value)?,
            "decals" => self.decals = number(key, value)?,
            "particles" => self.particles = number(key, value)?,
            "seed" => self.seed = number(key, value)?,
            _ => {
                return Err(format!(
                    "`{key}`: not a setting (path, msaa, width, height, lights, shadowed, \
                     decals, particles, seed)"
                ));
            }
        }
        Ok(())
    }
}

/// The courtyard and what is placed in it for one [`Settings`].
#[derive(Debug, Clone)]
pub struct Showcase {
    /// The scene (the built-in courtyard, or a glTF scene the page was given).
    pub scene: Scene,
    /// Its own lights, then the procedural ones.
    pub lights: Vec<SceneLight>,
    /// Procedural decals with the built-in materials.
    pub decals: DecalSet,
    /// The built-in emitters, or `None` for `particles == 0`.
    pub particles: Option<ParticleSystem>,
    /// Whether the scene is the courtyard, which has a look of its own.
    pub courtyard: bool,
    /// The camera the page opens on.
    pub orbit: Orbit,
}

impl Showcase {
    /// The built-in courtyard, placed as `settings` say.
    pub fn courtyard(settings: &Settings) -> Self {
        let scene = renderer::scene::procedural::courtyard();
        Self::around(scene, true, settings)
    }

    /// A glTF scene (a `.glb`, or a `.gltf` with its buffers embedded) placed as `settings`
    /// say, with lights spread through its bounds.
    pub fn from_gltf(bytes: &[u8], settings: &Settings) -> Result<Self, SceneError> {
        let scene = Scene::from_slice(bytes)?;
        Ok(Self::around(scene, false, settings))
    }

    fn around(scene: Scene, courtyard: bool, settings: &Settings) -> Self {
        let (region, (min_radius, max_radius)) = renderer::demo::light_space(&scene, courtyard);
        let mut lights = scene.lights.clone();
        let first = lights.len();
        lights.extend(procedural_lights(
            region,
            settings.lights,
            settings.seed,
            min_radius,
            max_radius,
        ));
        // Half the framing camera's distance: the scene fills the page rather than a third of it.
        let mut orbit = Orbit::framing(&scene);
        orbit.zoom(0.5);
        let aspect = settings.width as f32 / settings.height.max(1) as f32;
        pick_shadowed(
            &mut lights[first..],
            &orbit.camera(aspect),
            settings.height as f32,
            settings.shadowed,
        );
        let materials = procedural::materials();
        let decals = DecalSet {
            decals: scatter_decals(&scene, settings.decals, materials.len(), settings.seed),
            materials,
        };
        let particles = (settings.particles > 0)
            .then(|| builtin_system(scene.bounds, settings.particles, settings.seed as u32));
        Self {
            scene,
            lights,
            decals,
            particles,
            courtyard,
            orbit,
        }
    }

    /// The renderer configuration of `settings` with the scene's look. The visibility path
    /// rasterises with the hardware, the only raster a browser has (WebGPU has no 64-bit
    /// atomics), so a native renderer of the same showcase draws the same frame.
    pub fn config(&self, settings: &Settings) -> RendererConfig {
        let config = RendererConfig {
            width: settings.width,
            height: settings.height,
            msaa: settings.msaa,
            path: settings.path,
            visibility_raster: VisibilityRaster::Hardware,
            ..RendererConfig::default()
        };
        if self.courtyard {
            courtyard_look(config)
        } else {
            config
        }
    }

    /// A renderer of `settings` on `gpu` holding the scene, lights, decals and particles.
    /// Settings the device cannot run (a path whose kernels exceed its limits, an MSAA count
    /// it lacks) are refused with the reason.
    pub fn renderer(&self, gpu: &GpuContext, settings: &Settings) -> Result<Renderer, RenderError> {
        let mut renderer = Renderer::new(gpu, self.config(settings))?;
        renderer.prepare_scene(&self.scene)?;
        renderer.set_lights(&self.lights)?;
        renderer.set_decals(&self.decals)?;
        if let Some(particles) = &self.particles {
            renderer.set_particles(particles, WARMUP_STEPS)?;
        }
        Ok(renderer)
    }
}

/// A camera circling a point: yaw and pitch in radians, distance in scene units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The point it looks at.
    pub target: Vec3,
    /// Angle around the vertical axis; 0 looks down −Z.
    pub yaw: f32,
    /// Angle above the horizon, kept within ±85°.
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Scene size, which sets the near and far planes.
    pub radius: f32,
}

impl Orbit {
    /// Highest pitch either way: the camera never flips over the pole.
    const MAX_PITCH: f32 = 85.0 * std::f32::consts::PI / 180.0;

    /// Where [`renderer::frame::framing_camera`] stands: in front of the scene's centre and a
    /// little above, at 2.4 scene radii.
    pub fn framing(scene: &Scene) -> Self {
        let radius = ((scene.bounds.max - scene.bounds.min).length() * 0.5).max(1e-3);
        Self {
            target: scene.bounds.center(),
            yaw: 0.0,
            pitch: 0.35f32.atan2(1.0),
            distance: radius * 2.4,
            radius,
        }
    }

    /// Turns by a pointer drag of `dx`, `dy` pixels (a full turn per 720 pixels).
    pub fn drag(&mut self, dx: f32, dy: f32) {
        let per_pixel = std::f32::consts::TAU / 720.0;
        self.yaw -= dx * per_pixel;
        self.pitch = (self.pitch + dy * per_pixel).clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
    }

    /// Moves closer (`factor` < 1) or further, between a tenth and four times the scene radius
    /// from the target.
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(self.radius * 0.1, self.radius * 4.0);
        }
    }

    /// The camera at `aspect` (width ÷ height).
    pub fn camera(&self, aspect: f32) -> FrameCamera {
        let (sin_yaw, cos_yaw) = self.yaw.sin_cos();
        let (sin_pitch, cos_pitch) = self.pitch.sin_cos();
        let back = Vec3::new(sin_yaw * cos_pitch, sin_pitch, cos_yaw * cos_pitch);
        FrameCamera::look_at(
            self.target + back * self.distance,
            self.target,
            Vec3::Y,
            renderer::frame::FRAMING_YFOV_DEGREES.to_radians(),
            aspect,
            (self.radius * 0.05, self.radius * 8.0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_come_from_a_query_and_bad_ones_are_named() {
        let s =
            Settings::from_query("?path=clustered&msaa=1&lights=512&width=320&height=180").unwrap();
        assert_eq!(s.path, RenderPath::Clustered);
        assert_eq!((s.msaa, s.lights, s.width, s.height), (1, 512, 320, 180));
        assert_eq!(s.decals, Settings::default().decals);
        assert_eq!(Settings::from_query("").unwrap(), Settings::default());
        for (query, named) in [
            ("path=fast", "\"fast\""),
            ("msaa=four", "msaa=four"),
            ("zoom=2", "`zoom`"),
            ("lights", "`lights`"),
            ("width=0", "0×540"),
        ] {
            let err = Settings::from_query(query).unwrap_err();
            assert!(err.contains(named), "{query}: {err}");
        }
    }

    #[test]
    fn the_opening_orbit_is_the_framing_camera() {
        let scene = renderer::scene::procedural::courtyard();
        let orbit = Orbit::framing(&scene).camera(16.0 / 9.0);
        let framing = renderer::frame::framing_camera(scene.bounds, 16.0 / 9.0);
        assert!(
            (orbit.eye - framing.eye).length() < 1e-4,
            "{orbit:?} {framing:?}"
        );
        assert!(orbit.view.abs_diff_eq(framing.view, 1e-5));
        assert!(orbit.projection.abs_diff_eq(framing.projection, 1e-5));
    }

    #[test]
    fn the_orbit_stays_off_the_poles_and_within_its_distances() {
        let scene = renderer::scene::procedural::courtyard();
        let mut orbit = Orbit::framing(&scene);
        orbit.drag(0.0, 1e6);
        assert!((orbit.pitch - Orbit::MAX_PITCH).abs() < 1e-6);
        orbit.zoom(1e-6);
        assert!((orbit.distance - orbit.radius * 0.1).abs() < 1e-4);
        orbit.zoom(f32::NAN);
        assert!((orbit.distance - orbit.radius * 0.1).abs() < 1e-4);
        orbit.zoom(1e6);
        assert!((orbit.distance - orbit.radius * 4.0).abs() < 1e-3);
    }

    #[test]
    fn the_courtyard_has_what_the_page_shows() {
        let settings = Settings::default();
        let shown = Showcase::courtyard(&settings);
        let shadowed = shown.lights.iter().filter(|l| l.casts_shadow).count();
        assert_eq!(shadowed, settings.shadowed);
        assert_eq!(shown.decals.decals.len(), settings.decals);
        assert!(shown.particles.is_some());
        assert_eq!(shown.config(&settings).msaa, 4);
    }
}

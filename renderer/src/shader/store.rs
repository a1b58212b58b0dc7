//! Compiled programs and pipelines kept per device, so that a second renderer, a reconfigured
//! one or a second view compiles nothing it already has.
//!
//! Compiling a variant (WGSL parsed and validated, then translated and built by the driver) is
//! most of what creating a renderer costs: on lavapipe about 0.5–1.3 s a renderer against
//! 10–40 ms a frame. [`GpuContext::program`](crate::GpuContext::program) keeps each variant's
//! module and layouts once per context, keyed by the variant and the exact WGSL it was
//! compiled from (a hot-reloaded replacement is a new key), and every copy of a program shares
//! one memo of the pipelines built from it ([`ShaderProgram::compute_pipeline`],
//! [`ShaderProgram::render_pipeline`]).
//!
//! Pipelines are kept by `pipeline_memo`. wgpu pipelines are immutable, so sharing one between
//! renderers changes nothing they draw.

use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use codegen::rt::Variant;

use super::{ShaderProgram, VariantError};
use crate::gpu::adapter::Capabilities;

/// A program's key: the variant's address and the exact WGSL compiled.
type ProgramKey = (usize, Cow<'static, str>);

/// The programs compiled on one device, by variant and source.
#[derive(Default)]
pub(crate) struct ProgramStore {
    programs: Mutex<HashMap<ProgramKey, ShaderProgram>>,
    /// Compilations so far.
    compiled: std::sync::atomic::AtomicUsize,
    /// Pipelines built from programs since released ([`ProgramStore::release`]).
    released_pipelines: std::sync::atomic::AtomicUsize,
}

impl std::fmt::Debug for ProgramStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let programs = self.programs.lock().unwrap_or_else(PoisonError::into_inner);
        f.debug_struct("ProgramStore")
            .field("programs", &programs.len())
            .finish()
    }
}

impl ProgramStore {
    /// `variant` compiled on `device` (checked against `caps` every time), from the store when
    /// the same source was compiled before. The copy returned has its own binding log.
    pub(crate) fn program(
        &self,
        device: &wgpu::Device,
        caps: &Capabilities,
        variant: &'static Variant,
    ) -> Result<ShaderProgram, VariantError> {
        super::check_supported(variant, caps)?;
        let key = (
            std::ptr::from_ref(variant) as usize,
            super::source_for(variant, caps),
        );
        let mut programs = self.programs.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(kept) = programs.get(&key) {
            return Ok(kept.fresh_copy());
        }
        let program = ShaderProgram::compile(device, caps, variant, key.1.clone());
        self.compiled
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        programs.insert(key, program.fresh_copy());
        Ok(program)
    }

    /// Programs compiled so far, and pipelines built so far.
    pub(crate) fn counts(&self) -> (usize, usize) {
        let programs = self.programs.lock().unwrap_or_else(PoisonError::into_inner);
        let kept: usize = programs.values().map(|p| p.pipelines.built()).sum();
        let released = self
            .released_pipelines
            .load(std::sync::atomic::Ordering::Relaxed);
        let compiled = self.compiled.load(std::sync::atomic::Ordering::Relaxed);
        (compiled, kept + released)
    }

    /// Forgets every kept program and its pipelines: they are destroyed once no renderer holds
    /// them, and compiled again when asked for.
    pub(crate) fn release(&self) {
        let mut programs = self.programs.lock().unwrap_or_else(PoisonError::into_inner);
        let built: usize = programs.values().map(|p| p.pipelines.built()).sum();
        self.released_pipelines
            .fetch_add(built, std::sync::atomic::Ordering::Relaxed);
        programs.clear();
    }
}

/// A store shared by every clone of a context.
pub(crate) type SharedProgramStore = Arc<ProgramStore>;

//! What editing a scene by handle costs the CPU between frames: adding an instance (appended
//! with new draws, or into the slot of a removed one), moving it and removing it, each timed
//! alone, and the CPU of the frames that follow the edits (the passes catch up there: the
//! culling layout and boxes, the shadow casters).
//!
//! Every instance added is removed again, so the scene ends as it began (the appended draws
//! stay, dead: they hold no batch slot and draw nothing). Then a mesh is streamed in and out:
//! added, instanced, drawn and removed, its addition and removal timed alone.

use std::time::Instant;

use anyhow::Result;
use glam::{Mat4, Vec3};
use renderer::frame::{FrameCamera, Renderer};
use renderer::scene::Scene;

use super::measure::Samples;
use super::record::CellRecord;

/// Instances added per round; a frame is rendered after every `FRAME_EVERY` edits.
const ADDED: usize = 100;
const FRAME_EVERY: usize = 10;

/// Times the edits on `renderer` (whose scene is `scene`) and writes their medians into
/// `record`.
pub fn measure(
    renderer: &mut Renderer,
    scene: &Scene,
    target: &wgpu::Texture,
    camera: &FrameCamera,
    record: &mut CellRecord,
) -> Result<()> {
    if scene.instances.is_empty() {
        return Ok(());
    }
    let (mut add, mut moves, mut remove, mut frames) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut edits = 0;
    let mut frame = |renderer: &mut Renderer, edits: &mut usize| -> Result<()> {
        *edits += 1;
        if edits.is_multiple_of(FRAME_EVERY) {
            let report = renderer.render(camera, target)?;
            renderer.wait_for_frames_in_flight(0)?;
            frames.push(report.cpu_upload_ms + report.cpu_graph_ms + report.cpu_submit_ms);
        }
        Ok(())
    };
    let step = (scene.instances.len() / ADDED).max(1);
    // Twice: the first round appends draws, the second takes the slots the first left.
    for _ in 0..2 {
        let mut added = Vec::with_capacity(ADDED);
        for k in 0..ADDED {
            let source = &scene.instances[(k * step) % scene.instances.len()];
            let lifted = Mat4::from_translation(Vec3::Y * 0.5) * source.world_from_mesh;
            let started = Instant::now();
            let handle = renderer.add_instance(source.mesh, lifted)?;
            add.push(started.elapsed().as_secs_f64() * 1e6);
            added.push((handle, lifted));
            frame(renderer, &mut edits)?;
        }
        for &(handle, lifted) in &added {
            let moved = Mat4::from_translation(Vec3::X * 0.25) * lifted;
            let started = Instant::now();
            renderer.set_instance_transform(handle, moved)?;
            moves.push(started.elapsed().as_secs_f64() * 1e6);
            frame(renderer, &mut edits)?;
        }
        for &(handle, _) in &added {
            let started = Instant::now();
            renderer.remove_instance(handle)?;
            remove.push(started.elapsed().as_secs_f64() * 1e6);
            frame(renderer, &mut edits)?;
        }
    }
    let add = Samples::from(add);
    record.edit_add_median_us = add.median();
    record.edit_add_max_us = add.max();
    record.edit_move_median_us = Samples::from(moves).median();
    record.edit_remove_median_us = Samples::from(remove).median();
    record.edit_frame_cpu_median_ms = Samples::from(frames).median();
    let (mesh_add, mesh_remove) = stream_meshes(renderer, scene, (camera, target))?;
    record.edit_mesh_add_median_us = Samples::from(mesh_add).median();
    record.edit_mesh_remove_median_us = Samples::from(mesh_remove).median();
    Ok(())
}

/// Rounds of streaming a mesh in and out: a copy of the first instance's mesh added (timed),
/// an instance of it added, a frame, the instance and the mesh removed (timed), a frame. The
/// µs each addition and removal of the mesh took.
fn stream_meshes(
    renderer: &mut Renderer,
    scene: &Scene,
    (camera, target): (&FrameCamera, &wgpu::Texture),
) -> Result<(Vec<f64>, Vec<f64>)> {
    const ROUNDS: usize = 20;
    let source = &scene.instances[0];
    let mesh = &scene.meshes[source.mesh];
    let (mut added, mut removed) = (Vec::new(), Vec::new());
    let frame = |renderer: &mut Renderer| -> Result<()> {
        renderer.render(camera, target)?;
        renderer.wait_for_frames_in_flight(0)?;
        Ok(())
    };
    for _ in 0..ROUNDS {
        let started = Instant::now();
        let index = renderer.add_mesh(mesh)?;
        added.push(started.elapsed().as_secs_f64() * 1e6);
        let handle = renderer.add_instance(index, source.world_from_mesh)?;
        frame(renderer)?;
        renderer.remove_instance(handle)?;
        let started = Instant::now();
        renderer.remove_mesh(index)?;
        removed.push(started.elapsed().as_secs_f64() * 1e6);
        frame(renderer)?;
    }
    Ok((added, removed))
}

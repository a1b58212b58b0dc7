//! The particle simulation: one fixed time step per dispatch set. `update` ages and moves every
//! live particle and frees the dead (pushing their slots on the dead list), `spawn` takes slots
//! from the dead list for this step's births, `compact` lists the live slots. Births depend
//! only on (seed, emitter, spawn index): which slot a particle lands in does not matter.

/// Fixed-step GPU particle simulation: update, spawn from the dead list, compact.
///
/// Counters (`COUNTERS`, `i32`): 0 the dead list's length, 1 the live list's length (cleared by
/// the host before `compact`), 2 births refused because no slot was free (the pool is full;
/// reported, never silent).
#[shader_dsl::shader(uses(crate::particles::common::particle_common))]
pub mod particle_sim {
    pub const WORKGROUP: u32 = 64;

    /// One step's parameters.
    pub struct SimParams {
        /// Particle slots.
        pub capacity: u32,
        /// Births this step (threads of `spawn`).
        pub spawn_total: u32,
        /// Entries of `BATCHES`.
        pub batch_count: u32,
        pub seed: u32,
        /// Step length in seconds.
        pub dt: f32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
    }

    /// This step's births of one emitter: spawn indices `first_index..first_index + count`,
    /// taken by `spawn` threads `base..base + count`. Batches have `count > 0` and rising bases.
    pub struct SpawnBatch {
        pub emitter: u32,
        pub first_index: u32,
        pub count: u32,
        pub base: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: SimParams;
    #[storage(group = 0, binding = 1)]
    static EMITTERS: [GpuEmitter];
    #[storage(group = 0, binding = 2)]
    static BATCHES: [SpawnBatch];
    #[storage(group = 0, binding = 3, read_write)]
    static PARTICLES: [GpuParticle];
    #[storage(group = 0, binding = 4, read_write)]
    static DEAD: [u32];
    #[storage(group = 0, binding = 5, read_write)]
    static COUNTERS: [Atomic<i32>];
    #[storage(group = 0, binding = 6, read_write)]
    static ALIVE: [u32];

    /// A unit vector around `axis` (unit), at most the cone's angle from it.
    fn in_cone(axis: Vec3, cos_max: f32, r0: f32, r1: f32) -> Vec3 {
        let helper = select(axis.y.abs() < 0.99, Vec3::Y, Vec3::X);
        let tangent = helper.cross(axis).normalize();
        let bitangent = axis.cross(tangent);
        let cos_t = 1.0 + (cos_max - 1.0) * r0;
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = r1 * 6.2831855;
        tangent * (sin_t * phi.cos()) + bitangent * (sin_t * phi.sin()) + axis * cos_t
    }

    /// Particle `index` of emitter `emitter`, just born.
    fn born(e: GpuEmitter, emitter: u32, index: u32) -> GpuParticle {
        let seed = PARAMS.seed;
        let lifetime =
            e.lifetime.x + (e.lifetime.y - e.lifetime.x) * random(seed, emitter, index, 0u32);
        let cos_polar = random(seed, emitter, index, 1u32) * 2.0 - 1.0;
        let sin_polar = (1.0 - cos_polar * cos_polar).max(0.0).sqrt();
        let phi = random(seed, emitter, index, 2u32) * 6.2831855;
        let radius = e.spawn_radius * random(seed, emitter, index, 3u32).powf(1.0 / 3.0);
        let offset = Vec3::new(sin_polar * phi.cos(), cos_polar, sin_polar * phi.sin()) * radius;
        let speed = e.velocity.length();
        let axis = select(speed > 0.0, e.velocity / speed.max(1e-30), Vec3::Y);
        let r4 = random(seed, emitter, index, 4u32);
        let r5 = random(seed, emitter, index, 5u32);
        let jitter = 1.0 + e.speed_jitter * (random(seed, emitter, index, 6u32) * 2.0 - 1.0);
        GpuParticle {
            position: e.position + offset,
            age: 0.0,
            velocity: in_cone(axis, e.spread_cos, r4, r5) * (speed * jitter),
            lifetime,
            emitter,
            index,
            alive: 1u32,
            pad: 0u32,
        }
    }

    /// Ages and moves one slot's particle; frees it when its life is over.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn update(#[builtin(global_invocation_id)] gid: UVec3) {
        let slot = gid.x;
        if slot < PARAMS.capacity {
            let mut p = PARTICLES[slot];
            if p.alive != 0u32 {
                let e = EMITTERS[p.emitter];
                let dt = PARAMS.dt;
                let v = (p.velocity + e.gravity * dt) * (1.0 - e.drag * dt).max(0.0);
                p.velocity = v;
                p.position = p.position + v * dt;
                p.age = p.age + dt;
                if p.age >= p.lifetime {
                    p.alive = 0u32;
                    let d = COUNTERS[0].fetch_add(1);
                    DEAD[d as u32] = slot;
                }
                PARTICLES[slot] = p;
            }
        }
    }

    /// Births one particle of this step into a slot from the dead list.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn spawn(#[builtin(global_invocation_id)] gid: UVec3) {
        let i = gid.x;
        if i < PARAMS.spawn_total {
            let mut b = 0u32;
            for k in 0u32..PARAMS.batch_count {
                if BATCHES[k].base <= i {
                    b = k;
                }
            }
            let batch = BATCHES[b];
            let n = COUNTERS[0].fetch_sub(1);
            if n <= 0 {
                COUNTERS[0].fetch_add(1);
                COUNTERS[2].fetch_add(1);
            } else {
                let slot = DEAD[(n - 1) as u32];
                let index = batch.first_index + (i - batch.base);
                PARTICLES[slot] = born(EMITTERS[batch.emitter], batch.emitter, index);
            }
        }
    }

    /// Appends every live slot to `ALIVE` (in no particular order).
    #[compute(workgroup_size(64, 1, 1))]
    pub fn compact(#[builtin(global_invocation_id)] gid: UVec3) {
        let slot = gid.x;
        if slot < PARAMS.capacity {
            if PARTICLES[slot].alive != 0u32 {
                let at = COUNTERS[1].fetch_add(1);
                ALIVE[at as u32] = slot;
            }
        }
    }
}

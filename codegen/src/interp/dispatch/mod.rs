//! Running a compute entry point over a whole dispatch on the host: workgroups one after
//! another, the invocations of a workgroup under a deterministic scheduler, workgroup memory,
//! barriers, atomics and subgroups of a size the caller chooses.
//!
//! Each invocation is a [`Machine`] in a coroutine on the caller's thread (the IR's spans are
//! not `Send`), and only one runs at a time: the scheduler resumes the invocations in the order of its [`Schedule`], each running until its
//! next barrier or subgroup operation (or its end), then resolves what every invocation waits
//! for. So a missing barrier is a wrong result in a fixed order, the same every run: a kernel
//! must give the same answer under [`Schedule::InOrder`] and [`Schedule::Reversed`].
//!
//! Invocations that do not all reach the same barrier are [`EvalError::Uniformity`], as WGSL
//! requires uniform control flow there. A subgroup operation runs over its active lanes: those
//! of the subgroup waiting at it, the others having left the loop or branch it is in (as on
//! hardware, where a loop's last, partial round runs with fewer lanes); lanes of a subgroup at
//! two different subgroup operations at once are a uniformity error. Subgroup `k` holds the
//! invocations `k·size ..` by `local_invocation_index`.
//!
//! Running one workgroup (its invocations' coroutines and the scheduler between them) is in
//! `workgroup`.

mod workgroup;

use std::rc::Rc;

use corosensei::Coroutine;
use corosensei::stack::DefaultStack;

use super::memory::Memory;
use super::sync::{Finished, Globals, Resume, Suspended};
use super::{DEFAULT_STEP_LIMIT, EvalError, HostSampler, HostTexture, Value};
use crate::ir::{Module, Stage};
use crate::variants::{Env, Value as ConstValue, eval};

/// The order in which the scheduler runs a workgroup's invocations to their next barrier or
/// subgroup operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Schedule {
    /// `local_invocation_index` 0, 1, 2, ...
    InOrder,
    /// The last invocation first.
    Reversed,
    /// A permutation from this seed, a new one after every barrier.
    Shuffled(u64),
}

impl Schedule {
    fn order(self, n: usize, phase: u64) -> Vec<usize> {
        let mut order: Vec<usize> = (0..n).collect();
        match self {
            Schedule::InOrder => {}
            Schedule::Reversed => order.reverse(),
            Schedule::Shuffled(seed) => {
                let mut state = seed ^ phase.wrapping_mul(0x9e37_79b9_7f4a_7c15);
                for i in (1..n).rev() {
                    state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
                    let mut z = state;
                    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
                    order.swap(i, ((z ^ (z >> 31)) % (i as u64 + 1)) as usize);
                }
            }
        }
        order
    }
}

/// One invocation: a coroutine running the entry point.
type Invocation = Coroutine<Resume, Suspended, Finished, DefaultStack>;

/// Stack of one invocation's coroutine (the interpreter recurses through expressions and calls).
const STACK_BYTES: usize = 2 << 20;

/// Subgroup sizes hardware has: a power of two from 4 to 128.
pub const SUBGROUP_SIZES: [u32; 6] = [4, 8, 16, 32, 64, 128];

/// One compute entry point of one variant, its statics, and how to run it.
///
/// ```
/// # use codegen::interp::{Dispatch, Schedule};
/// let c = codegen::compile_source(
///     "#[shader] mod m {
///         #[storage(group = 0, binding = 0, read_write)]
///         static OUT: [u32];
///         #[compute(workgroup_size(8, 1, 1))]
///         fn main(#[builtin(global_invocation_id)] id: UVec3) { OUT[id.x] = id.x * 2u32; }
///     }",
/// )
/// .unwrap();
/// let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main").unwrap();
/// d.set_buffer("OUT", &[0u8; 64]).unwrap();
/// d.run([2, 1, 1]).unwrap();
/// let out: Vec<u32> = d.buffer("OUT").unwrap().chunks(4).map(|b| u32::from_le_bytes(b.try_into().unwrap())).collect();
/// assert_eq!(out, (0..16).map(|i| i * 2).collect::<Vec<u32>>());
/// ```
pub struct Dispatch<'a> {
    module: &'a Module,
    env: &'a Env,
    entry: usize,
    workgroup_size: [u32; 3],
    subgroup_size: u32,
    schedule: Schedule,
    step_limit: u64,
    races: bool,
    unwritten_reads: bool,
    globals: Globals,
    /// Stacks of finished invocations, for the next workgroup: a new stack maps fresh memory,
    /// which costs more than most workgroups' work.
    stacks: Vec<DefaultStack>,
}

impl std::fmt::Debug for Dispatch<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Dispatch")
            .field("module", &self.module.name)
            .field("entry", &self.module.functions[self.entry].name)
            .field("workgroup_size", &self.workgroup_size)
            .field("subgroup_size", &self.subgroup_size)
            .field("schedule", &self.schedule)
            .finish_non_exhaustive()
    }
}

impl<'a> Dispatch<'a> {
    /// The compute entry point `entry` of `module` in the variant `env`, with subgroups of 32,
    /// [`Schedule::InOrder`] and no static given a value yet.
    pub fn new(module: &'a Module, env: &'a Env, entry: &str) -> Result<Self, EvalError> {
        let index = module
            .functions
            .iter()
            .position(|f| f.name == entry)
            .ok_or_else(|| EvalError::Type(format!("the module has no function `{entry}`")))?;
        let Some(Stage::Compute(size)) = &module.functions[index].stage else {
            return Err(EvalError::Unsupported(format!(
                "running `{entry}`: only compute entry points run as a dispatch"
            )));
        };
        if !crate::variants::entry_present(&module.functions[index], module, env) {
            return Err(EvalError::Type(format!(
                "`{entry}` is not an entry point of this variant (its `#[when(..)]` is false here)"
            )));
        }
        let mut workgroup_size = [1u32; 3];
        for (slot, e) in workgroup_size.iter_mut().zip(size.iter()) {
            *slot = match eval(e, module, env) {
                Some(ConstValue::Int(n)) if n > 0 => u32::try_from(n).unwrap_or(u32::MAX),
                other => {
                    return Err(EvalError::Type(format!(
                        "workgroup size of `{entry}` evaluates to {other:?}"
                    )));
                }
            };
        }
        Ok(Dispatch {
            module,
            env,
            entry: index,
            workgroup_size,
            subgroup_size: 32,
            schedule: Schedule::InOrder,
            step_limit: DEFAULT_STEP_LIMIT,
            races: true,
            unwritten_reads: false,
            globals: vec![None; module.globals.len()],
            stacks: vec![],
        })
    }

    /// Runs with subgroups of `size` invocations (one of [`SUBGROUP_SIZES`]).
    pub fn with_subgroup_size(mut self, size: u32) -> Result<Self, EvalError> {
        if !SUBGROUP_SIZES.contains(&size) {
            return Err(EvalError::Unsupported(format!(
                "a subgroup size of {size}: use one of {SUBGROUP_SIZES:?}"
            )));
        }
        self.subgroup_size = size;
        Ok(self)
    }

    /// Runs the invocations of each workgroup in this order.
    pub fn with_schedule(mut self, schedule: Schedule) -> Self {
        self.schedule = schedule;
        self
    }

    /// Whether data races on workgroup memory are errors ([`EvalError::Race`]; on by default).
    pub fn with_race_detection(mut self, on: bool) -> Self {
        self.races = on;
        self
    }

    /// Whether reading workgroup memory that no invocation of the workgroup wrote is an error
    /// ([`EvalError::Unwritten`]; off by default). WGSL zero-fills workgroup memory, so such a
    /// read is legal, but a kernel that means to read a zero seldom gets it that way: the
    /// usual cause is an append that skipped a slot, or a loop that filled fewer elements than
    /// another reads. Atomics are neither checked nor count as writes.
    pub fn with_unwritten_read_check(mut self, on: bool) -> Self {
        self.unwritten_reads = on;
        self
    }

    /// Each invocation stops with [`EvalError::StepLimit`] after this many statements.
    pub fn with_step_limit(mut self, steps: u64) -> Self {
        self.step_limit = steps;
        self
    }

    /// The entry point's workgroup size in this variant.
    pub fn workgroup_size(&self) -> [u32; 3] {
        self.workgroup_size
    }

    fn memory(&self) -> Memory<'a> {
        Memory {
            module: self.module,
            env: self.env,
        }
    }

    fn global_index(&self, name: &str) -> Result<usize, EvalError> {
        self.module
            .globals
            .iter()
            .position(|g| g.name == name)
            .ok_or_else(|| EvalError::Type(format!("the module has no static `{name}`")))
    }

    /// Gives the buffer static `name` the contents `bytes`, laid out as on the GPU (the
    /// generated host structs' bytes); a runtime-sized array takes every whole element.
    pub fn set_buffer(&mut self, name: &str, bytes: &[u8]) -> Result<(), EvalError> {
        let g = self.global_index(name)?;
        let value = self.memory().decode(&self.module.globals[g].ty, bytes, 0)?;
        self.globals[g] = Some(value);
        Ok(())
    }

    /// The buffer static `name` as bytes laid out as on the GPU.
    pub fn buffer(&self, name: &str) -> Result<Vec<u8>, EvalError> {
        let g = self.global_index(name)?;
        let value = self.globals[g].as_ref().ok_or_else(|| {
            EvalError::Type(format!("the static `{name}` was never given a value"))
        })?;
        let mut bytes = vec![];
        self.memory()
            .encode(&self.module.globals[g].ty, value, &mut bytes, 0)?;
        Ok(bytes)
    }

    /// Gives the texture static `name` its texels.
    pub fn set_texture(&mut self, name: &str, texture: HostTexture) -> Result<(), EvalError> {
        let g = self.global_index(name)?;
        self.globals[g] = Some(texture.into_value()?);
        Ok(())
    }

    /// Gives the sampler static `name` its filtering, addressing and comparison.
    pub fn set_sampler(&mut self, name: &str, sampler: HostSampler) -> Result<(), EvalError> {
        let g = self.global_index(name)?;
        self.globals[g] = Some(sampler.into_value());
        Ok(())
    }

    /// The texture static `name` as it is now (a storage texture the dispatch wrote).
    pub fn texture(&self, name: &str) -> Result<HostTexture, EvalError> {
        let g = self.global_index(name)?;
        let value = self.globals[g].as_ref().ok_or_else(|| {
            EvalError::Type(format!("the static `{name}` was never given a value"))
        })?;
        HostTexture::from_value(value)
    }

    /// Gives the static `name` a value directly.
    pub fn set_value(&mut self, name: &str, value: Value) -> Result<(), EvalError> {
        let g = self.global_index(name)?;
        self.globals[g] = Some(value);
        Ok(())
    }

    /// The current value of the static `name`, if it has one.
    pub fn value(&self, name: &str) -> Option<&Value> {
        let g = self.global_index(name).ok()?;
        self.globals[g].as_ref()
    }

    /// Runs `workgroups` workgroups (x fastest), one after another. Workgroup memory starts
    /// zeroed in each, as WGSL gives it.
    pub fn run(&mut self, workgroups: [u32; 3]) -> Result<(), EvalError> {
        // The invocations' coroutines own what they run.
        let shared = (Rc::new(self.module.clone()), Rc::new(self.env.clone()));
        for z in 0..workgroups[2] {
            for y in 0..workgroups[1] {
                for x in 0..workgroups[0] {
                    self.run_workgroup([x, y, z], workgroups, &shared)?;
                }
            }
        }
        Ok(())
    }
}

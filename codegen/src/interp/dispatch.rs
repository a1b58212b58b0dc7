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

use std::cell::RefCell;
use std::rc::Rc;

use corosensei::stack::DefaultStack;
use corosensei::{Coroutine, CoroutineResult};

use super::memory::Memory;
use super::race::Tracker;
use super::sync::{Arrival, Finished, Globals, Resume, Suspended, SyncOp, Yielder, collective};
use super::{DEFAULT_STEP_LIMIT, EvalError, HostSampler, HostTexture, Machine, Value};
use crate::ir::{Io, Module, Space, Stage};
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

    /// The entry point's arguments for invocation `local` of workgroup `wg`: its builtins.
    fn arguments(
        &self,
        wg: [u32; 3],
        count: [u32; 3],
        local: u32,
    ) -> Result<Vec<Value>, EvalError> {
        let [sx, sy, _] = self.workgroup_size;
        let lid = [local % sx, (local / sx) % sy, local / (sx * sy)];
        let uvec3 = |v: [u32; 3]| Value::Vector(v.iter().map(|c| Value::U32(*c)).collect());
        let func = &self.module.functions[self.entry];
        func.params
            .iter()
            .map(|p| {
                let name = p.io.as_ref().and_then(Io::builtin).ok_or_else(|| {
                    EvalError::Unsupported(format!(
                        "the parameter `{}` of `{}`: a compute entry point's parameters are builtins",
                        func.locals[p.local].name, func.name
                    ))
                })?;
                Ok(match name {
                    "local_invocation_index" => Value::U32(local),
                    "local_invocation_id" => uvec3(lid),
                    "workgroup_id" => uvec3(wg),
                    "num_workgroups" => uvec3(count),
                    "global_invocation_id" => uvec3([
                        wg[0] * self.workgroup_size[0] + lid[0],
                        wg[1] * self.workgroup_size[1] + lid[1],
                        wg[2] * self.workgroup_size[2] + lid[2],
                    ]),
                    "subgroup_size" => Value::U32(self.subgroup_size),
                    "subgroup_invocation_id" => Value::U32(local % self.subgroup_size),
                    other => {
                        return Err(EvalError::Unsupported(format!(
                            "the builtin `{other}` in a dispatch"
                        )));
                    }
                })
            })
            .collect()
    }

    fn run_workgroup(
        &mut self,
        wg: [u32; 3],
        count: [u32; 3],
        shared: &(Rc<Module>, Rc<Env>),
    ) -> Result<(), EvalError> {
        for (g, global) in self.module.globals.iter().enumerate() {
            if global.space == Space::Workgroup {
                self.globals[g] = Some(self.memory().zero(&global.ty)?);
            }
        }
        let n = self.workgroup_size.iter().product::<u32>();
        let (entry, limit) = (self.entry, self.step_limit);
        let tracker = (self.races || self.unwritten_reads)
            .then(|| Rc::new(RefCell::new(Tracker::new(self.races, self.unwritten_reads))));
        let mut invocations = Vec::with_capacity(n as usize);
        for local in 0..n {
            let args = self.arguments(wg, count, local)?;
            let (module, env) = (Rc::clone(&shared.0), Rc::clone(&shared.1));
            let race = tracker.as_ref().map(|t| (Rc::clone(t), local));
            let stack = match self.stacks.pop() {
                Some(stack) => stack,
                None => DefaultStack::new(STACK_BYTES).map_err(|e| {
                    EvalError::Unsupported(format!("a stack for invocation {local}: {e}"))
                })?,
            };
            invocations.push(Invocation::with_stack(
                stack,
                move |yielder: &Yielder, first: Resume| {
                    let mut machine = Machine::new(&module, &env).with_step_limit(limit);
                    machine.globals = first.globals;
                    machine.yielder = Some(yielder);
                    machine.race = race;
                    let result = machine.call(entry, args).map(|_| ());
                    (result, std::mem::take(&mut machine.globals))
                },
            ));
        }
        // On failure the invocations still suspended are dropped, which unwinds their stacks.
        self.schedule_workgroup(&mut invocations, tracker.as_deref())
            .map_err(|(local, error)| EvalError::Invocation {
                workgroup: wg,
                local,
                error: Box::new(error),
            })?;
        self.stacks.extend(
            invocations
                .into_iter()
                .filter(Invocation::done)
                .map(Invocation::into_stack),
        );
        Ok(())
    }

    /// Runs one workgroup's invocations to completion; on failure, the invocation and error.
    fn schedule_workgroup(
        &mut self,
        invocations: &mut [Invocation],
        tracker: Option<&RefCell<Tracker>>,
    ) -> Result<(), (u32, EvalError)> {
        let n = invocations.len();
        let mut state: Vec<State> = (0..n).map(|_| State::Runnable(None)).collect();
        for phase in 0u64.. {
            for i in self.schedule.order(n, phase) {
                // Only runnable invocations run; one waiting keeps waiting.
                let result = match std::mem::replace(&mut state[i], State::Done) {
                    State::Runnable(result) => result,
                    other => {
                        state[i] = other;
                        continue;
                    }
                };
                let globals = std::mem::take(&mut self.globals);
                match invocations[i].resume(Resume { globals, result }) {
                    CoroutineResult::Yield((at, globals)) => {
                        self.globals = globals;
                        state[i] = State::Waiting(at);
                    }
                    CoroutineResult::Return((result, globals)) => {
                        self.globals = globals;
                        result.map_err(|e| (i as u32, e))?;
                    }
                }
            }
            if state.iter().all(|s| matches!(s, State::Done)) {
                return Ok(());
            }
            self.resolve(&mut state, tracker)
                .map_err(|e| (first_waiting(&state), e))?;
        }
        Ok(())
    }

    /// Releases what the waiting invocations wait for. In each subgroup, the lanes waiting at a
    /// subgroup operation are its active lanes (the others have left the branch or loop it is
    /// in: they wait at a barrier or have returned), as on hardware; they get their results.
    /// Lanes of one subgroup at two different subgroup operations are a uniformity error. Once
    /// no subgroup operation is pending, every invocation must be at the same barrier.
    fn resolve(
        &self,
        state: &mut [State],
        tracker: Option<&RefCell<Tracker>>,
    ) -> Result<(), EvalError> {
        let size = self.subgroup_size as usize;
        let mut released = false;
        for start in (0..state.len()).step_by(size) {
            let lanes = start..(start + size).min(state.len());
            let active: Vec<usize> = lanes
                .clone()
                .filter(|&i| {
                    matches!(
                        &state[i],
                        State::Waiting(Arrival {
                            op: SyncOp::Subgroup { .. },
                            ..
                        })
                    )
                })
                .collect();
            let Some(&leader) = active.first() else {
                continue;
            };
            let State::Waiting(first) = &state[leader] else {
                continue;
            };
            let first = first.clone();
            if !active
                .iter()
                .all(|&i| matches!(&state[i], State::Waiting(a) if a.same_site(&first)))
            {
                return Err(uniformity(&state[lanes.clone()], start, "subgroup"));
            }
            let args: Vec<(usize, &[Value])> = active
                .iter()
                .map(|&i| match &state[i] {
                    State::Waiting(Arrival {
                        op: SyncOp::Subgroup { args, .. },
                        ..
                    }) => (i - start, args.as_slice()),
                    _ => (i - start, &[][..]),
                })
                .collect();
            let results = collective(first.op.name(), &args)?;
            for (&i, r) in active.iter().zip(results) {
                state[i] = State::Runnable(Some(r));
            }
            released = true;
        }
        if released {
            return Ok(());
        }
        let first = match state.iter().find(|s| !matches!(s, State::Done)) {
            Some(State::Waiting(a)) => a.clone(),
            _ => return Ok(()),
        };
        if state
            .iter()
            .all(|s| matches!(s, State::Waiting(a) if a.same_site(&first)))
        {
            state.fill_with(|| State::Runnable(None));
            if let Some(t) = tracker {
                t.borrow_mut().barrier();
            }
            return Ok(());
        }
        Err(uniformity(state, 0, "workgroup"))
    }
}

/// Where one invocation is between two scheduling steps.
enum State {
    /// Ready to run, with the result of the subgroup operation it waited at.
    Runnable(Option<Value>),
    /// At a barrier or subgroup operation.
    Waiting(Arrival),
    /// Returned.
    Done,
}

fn first_waiting(state: &[State]) -> u32 {
    state
        .iter()
        .position(|s| matches!(s, State::Waiting(_)))
        .unwrap_or(0) as u32
}

/// Where each invocation of `state` (the first being `first`) stands, runs of equal states
/// merged: `invocations 0–31 at workgroupBarrier at 40:9; invocation 32 returned`.
fn uniformity(state: &[State], first: usize, scope: &str) -> EvalError {
    let describe = |s: &State| match s {
        State::Waiting(a) => a.describe(),
        State::Done => "returned".to_owned(),
        State::Runnable(_) => "running".to_owned(),
    };
    let mut runs: Vec<(usize, usize, String)> = vec![];
    for (i, s) in state.iter().enumerate() {
        let d = describe(s);
        match runs.last_mut() {
            Some((_, end, last)) if *last == d => *end = first + i,
            _ => runs.push((first + i, first + i, d)),
        }
    }
    let parts: Vec<String> = runs
        .iter()
        .map(|(a, b, d)| {
            if a == b {
                format!("invocation {a} {d}")
            } else {
                format!("invocations {a}–{b} {d}")
            }
        })
        .collect();
    EvalError::Uniformity(format!(
        "the {scope} did not arrive together: {}",
        parts.join("; ")
    ))
}

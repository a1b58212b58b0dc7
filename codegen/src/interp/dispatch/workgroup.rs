//! One workgroup of a [`Dispatch`]: its invocations as coroutines, each given its builtins,
//! and the scheduler that runs them to their next barrier or subgroup operation and resolves
//! what they wait for, or reports where every invocation stands when they do not agree.

use std::cell::RefCell;
use std::rc::Rc;

use corosensei::CoroutineResult;
use corosensei::stack::DefaultStack;

use super::{Dispatch, Invocation, STACK_BYTES};
use crate::interp::race::Tracker;
use crate::interp::sync::{Arrival, Resume, SyncOp, Yielder, collective};
use crate::interp::{EvalError, Machine, Value};
use crate::ir::{Io, Module, Space};
use crate::variants::Env;

impl Dispatch<'_> {
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

    pub(super) fn run_workgroup(
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

//! Our own WGSL printer. Output is readable, deterministic and stable (it is what the golden
//! snapshots show), and every printed construct is recorded in a [`SourceMap`].
//!
//! The printer specialises while printing: axes are printed as literals, constant `if`s are
//! pruned, unreachable functions are left out. It must not use naga's WGSL backend (which
//! normalises the output and mishandles `override`), and never emits `override`.

mod expr;
mod options;
mod printed;
mod source_map;
mod stmt;
mod writer;

pub use options::Options;
pub use printed::Printed;
pub use source_map::SourceMap;

use crate::ir::Module;
use crate::variants::Env;

/// Prints one variant of `module` as WGSL, with its source map.
pub fn write_string(module: &Module, env: &Env, options: Options) -> Printed {
    let mut w = writer::Writer::new(module, env, options);
    w.module();
    w.finish()
}

//! A Graphviz DOT dump of a compiled graph: passes (culled ones dashed), resources with their
//! pool slots, and the versions each pass reads and writes.

use std::fmt::Write as _;

use super::compile::{CompiledGraph, Plan};
use super::nodes::{PassNode, ResourceNode};

impl CompiledGraph {
    /// The graph in Graphviz DOT, deterministic for the same graph.
    pub fn to_dot(&self) -> String {
        to_dot(&self.passes, &self.resources, &self.plan)
    }
}

/// The DOT of a graph of `passes` and `resources` compiled into `plan`.
pub(crate) fn to_dot(passes: &[PassNode], resources: &[ResourceNode], plan: &Plan) -> String {
    let mut out =
        String::from("digraph frame {\n  rankdir=LR;\n  node [fontname=\"monospace\"];\n");
    for (p, pass) in passes.iter().enumerate() {
        let (position, style) = match plan.order.iter().position(|&q| q == p) {
            Some(i) => (format!("#{i} "), "solid"),
            None => ("culled ".to_owned(), "dashed"),
        };
        let _ = writeln!(
            out,
            "  p{p} [shape=box, style={style}, label=\"{position}{}\"];",
            escape(&pass.name)
        );
    }
    for (r, res) in resources.iter().enumerate() {
        let origin = match (res.import, plan.slot_of[r]) {
            (Some(access), _) => format!("imported {access:?}"),
            (None, Some(slot)) => format!("slot {slot}"),
            (None, None) => "unused".to_owned(),
        };
        let _ = writeln!(
            out,
            "  r{r} [shape=ellipse, label=\"{}\\n{origin}\"];",
            escape(&res.name)
        );
    }
    for (p, pass) in passes.iter().enumerate() {
        for u in &pass.reads {
            let _ = writeln!(out, "  r{} -> p{p} [label=\"v{}\"];", u.resource, u.version);
        }
        for u in &pass.writes {
            let _ = writeln!(out, "  p{p} -> r{} [label=\"v{}\"];", u.resource, u.version);
        }
    }
    out.push_str("}\n");
    out
}

fn escape(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

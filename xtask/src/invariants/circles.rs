//! Circles in the file graph: its strongly connected components of more than one file
//! (Tarjan's algorithm), each described by a shortest cycle and one example edge per file.

use std::collections::VecDeque;

use super::graph::FileGraph;
use super::modules::FileId;
use super::resolve::Edge;

/// Files that import each other, directly or around a ring.
#[derive(Debug, PartialEq, Eq)]
pub struct Circle {
    /// Sorted paths.
    pub files: Vec<String>,
    /// `a.rs -> b.rs (line 6: super::b::X) -> a.rs (line 3: super::a::Y)`, through the first
    /// file.
    pub cycle: String,
    /// Per file, one edge to another file of the circle: `a.rs:6 super::b::X -> b.rs`.
    pub examples: Vec<String>,
}

/// Every circle of `graph`, ordered by its first file.
pub fn circles(graph: &FileGraph) -> Vec<Circle> {
    let n = graph.tree.files.len();
    let mut next = vec![Vec::new(); n];
    for e in &graph.edges {
        next[e.from].push(e.to);
    }
    let mut found: Vec<Circle> = strongly_connected(&next)
        .into_iter()
        .filter(|c| c.len() > 1)
        .map(|mut members| {
            members.sort_by_key(|&f| graph.file(f));
            describe(graph, &members)
        })
        .collect();
    found.sort_by(|a, b| a.files.cmp(&b.files));
    found
}

fn describe(graph: &FileGraph, members: &[FileId]) -> Circle {
    // The first (lowest-line) edge from each member to each other member.
    let inside = |e: &&Edge| members.contains(&e.to) && members.contains(&e.from);
    let first_edge = |from: FileId, to: Option<FileId>| {
        graph
            .edges
            .iter()
            .filter(inside)
            .find(|e| e.from == from && to.is_none_or(|t| e.to == t))
    };
    let ring = shortest_cycle(graph, members);
    let mut cycle = graph.file(ring[0]).to_owned();
    for pair in ring.windows(2) {
        let e = first_edge(pair[0], Some(pair[1])).expect("the cycle follows edges");
        cycle += &format!(" -> {} (line {}: {})", graph.file(e.to), e.line, e.path);
    }
    let examples = members
        .iter()
        .filter_map(|&f| first_edge(f, None))
        .map(|e| {
            format!(
                "{}:{} {} -> {}",
                graph.file(e.from),
                e.line,
                e.path,
                graph.file(e.to)
            )
        })
        .collect();
    Circle {
        files: members.iter().map(|&f| graph.file(f).to_owned()).collect(),
        cycle,
        examples,
    }
}

/// A shortest cycle through `members[0]` inside the component, as files, first = last.
fn shortest_cycle(graph: &FileGraph, members: &[FileId]) -> Vec<FileId> {
    let start = members[0];
    let mut came_from: Vec<Option<FileId>> = vec![None; graph.tree.files.len()];
    let mut queue = VecDeque::from([start]);
    while let Some(f) = queue.pop_front() {
        for e in graph
            .edges
            .iter()
            .filter(|e| e.from == f && members.contains(&e.to))
        {
            if e.to == start {
                let mut ring = vec![start, f];
                while let Some(prev) = came_from[*ring.last().expect("non-empty")] {
                    ring.push(prev);
                }
                ring.reverse();
                return ring;
            }
            if came_from[e.to].is_none() {
                came_from[e.to] = Some(f);
                queue.push_back(e.to);
            }
        }
    }
    unreachable!("a strongly connected component has a cycle through each member")
}

/// Tarjan's strongly connected components of the graph `next[v]` = successors of `v`.
fn strongly_connected(next: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct State<'a> {
        next: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        counter: usize,
        components: Vec<Vec<usize>>,
    }
    fn visit(s: &mut State<'_>, v: usize) {
        s.index[v] = Some(s.counter);
        s.low[v] = s.counter;
        s.counter += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for &w in &s.next[v] {
            match s.index[w] {
                None => {
                    visit(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            s.components.push(component);
        }
    }
    let n = next.len();
    let mut s = State {
        next,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        counter: 0,
        components: Vec::new(),
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(&mut s, v);
        }
    }
    s.components
}

//! Structure-aware mutation of glTF files for the `gltf_load` target: the JSON (of a `.gltf`,
//! or of a GLB's JSON chunk, its BIN chunk kept) is parsed, one number or array in it is edited,
//! and the file is written back. Edits aim at what loaders get wrong: counts, byte offsets and
//! lengths, indices into other arrays, component types, node children (cycles, shared
//! children), missing keys.

use std::borrow::Cow;

use serde_json::Value;

/// Values a number is replaced with: boundaries of the types glTF uses, and component types.
const INTERESTING: &[i64] = &[
    0,
    1,
    2,
    3,
    4,
    -1,
    255,
    256,
    65_535,
    65_536,
    i32::MAX as i64,
    u32::MAX as i64,
    1 << 32,
    5120,
    5121,
    5122,
    5123,
    5125,
    5126,
];

/// A small deterministic generator for the mutation's choices.
struct Choices(u64);

impl Choices {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n.max(1) as u64) as usize
    }
}

/// One structure-aware edit of `file`, or `None` when it is not a glTF whose JSON parses.
pub fn mutate(file: &[u8], seed: u32) -> Option<Vec<u8>> {
    let mut choices = Choices(u64::from(seed).wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    // gltf 1.4.1 subtracts the 12-byte header from the declared length unchecked: skip a GLB
    // whose length field is below it, as the loader rejects it (`check_glb_header`).
    let declared_length = file
        .get(8..12)
        .and_then(|b| <[u8; 4]>::try_from(b).ok())
        .map(u32::from_le_bytes);
    let glb = (file.starts_with(b"glTF") && declared_length.is_some_and(|n| n >= 12))
        .then(|| gltf::binary::Glb::from_slice(file).ok())
        .flatten();
    let json_bytes: &[u8] = match &glb {
        Some(glb) => &glb.json,
        None => file,
    };
    let mut json: Value = serde_json::from_slice(json_bytes).ok()?;
    edit(&mut json, &mut choices);
    let text = serde_json::to_vec(&json).ok()?;
    match glb {
        Some(mut glb) => {
            glb.json = Cow::Owned(text);
            glb.to_vec().ok()
        }
        None => Some(text),
    }
}

/// Every place in `v`: numbers, arrays and object keys, by path.
fn places(v: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        Value::Number(_) => out.push(path.clone()),
        Value::Array(items) => {
            out.push(path.clone());
            for (i, item) in items.iter().enumerate() {
                path.push(Step::Index(i));
                places(item, path, out);
                path.pop();
            }
        }
        Value::Object(map) => {
            for (k, item) in map {
                path.push(Step::Key(k.clone()));
                out.push(path.clone());
                places(item, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn at<'v>(v: &'v mut Value, path: &[Step]) -> Option<&'v mut Value> {
    path.iter().try_fold(v, |v, step| match step {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

fn edit(json: &mut Value, c: &mut Choices) {
    // Node children get their own edits: cycles and shared children are what a tree walk misses.
    if c.below(4) == 0
        && let Some(nodes) = json.get_mut("nodes").and_then(Value::as_array_mut)
        && !nodes.is_empty()
    {
        let (from, to) = (c.below(nodes.len()), c.below(nodes.len()));
        if let Some(node) = nodes.get_mut(from).and_then(Value::as_object_mut) {
            let children = node
                .entry("children")
                .or_insert_with(|| Value::Array(Vec::new()));
            if let Some(children) = children.as_array_mut() {
                children.push(Value::from(to));
            }
        }
        return;
    }
    let mut all = Vec::new();
    places(json, &mut Vec::new(), &mut all);
    if all.is_empty() {
        return;
    }
    let path = all.swap_remove(c.below(all.len()));
    let Some(target) = at(json, &path) else {
        return;
    };
    match target {
        Value::Number(n) => {
            let old = n.as_i64().unwrap_or(0);
            *target = match c.below(4) {
                0 => Value::from(old.wrapping_add(1)),
                1 => Value::from(old.wrapping_sub(1)),
                2 => Value::from(old.wrapping_mul(2)),
                _ => Value::from(INTERESTING[c.below(INTERESTING.len())]),
            };
        }
        Value::Array(items) => match c.below(3) {
            0 if !items.is_empty() => {
                let i = c.below(items.len());
                items.push(items[i].clone());
            }
            1 if !items.is_empty() => {
                items.remove(c.below(items.len()));
            }
            _ => items.clear(),
        },
        _ => {
            // An object key: remove it from its parent.
            if let (Some(Step::Key(key)), parent) = (path.last(), &path[..path.len() - 1])
                && let Some(Value::Object(map)) = at(json, parent)
            {
                map.remove(key.as_str());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mutations_keep_the_file_parseable_and_change_it() {
        for (name, seed) in crate::gltf_seeds::seeds() {
            let mut changed = 0;
            for s in 0..64 {
                if let Some(m) = mutate(&seed, s) {
                    changed += usize::from(m != seed);
                }
            }
            if gltf::Gltf::from_slice(&seed).is_ok() {
                assert!(
                    changed > 32,
                    "{name}: only {changed} of 64 mutations changed it"
                );
            }
        }
    }
}

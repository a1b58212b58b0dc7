//! Scripted input for unattended runs (`--script`): keys pressed at given frames, parsed from
//! `FRAME:KEY[xN],...` (for example `2:w x10,12:h`: hold W for ten frames from frame 2, then
//! press H at frame 12). Key names are the viewer's own: `w a s d q e` move, `1`-`5` choose
//! the path, `m` MSAA, `t` tile size, `h` heatmap, `v` shadow atlas, `+`/`-` lights.

use anyhow::{Result, bail};

/// One scripted key press.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Press {
    /// First frame (0-based) the key is down.
    pub frame: u32,
    /// Frames it stays down.
    pub frames: u32,
    pub key: char,
}

/// A parsed `--script`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Script(pub Vec<Press>);

/// Parses a `--script` value.
pub fn parse_script(s: &str) -> Result<Script> {
    parse(s).map(Script)
}

/// Keys the viewer understands.
pub const KEYS: &str = "wasdqe12345mthv+-";

/// Parses a script.
pub fn parse(s: &str) -> Result<Vec<Press>> {
    let mut out = vec![];
    for item in s.split(',').map(str::trim).filter(|i| !i.is_empty()) {
        let Some((frame, rest)) = item.split_once(':') else {
            bail!("--script {item:?}: write FRAME:KEY or FRAME:KEY xN, e.g. 2:w x10");
        };
        let frame: u32 = frame
            .trim()
            .parse()
            .map_err(|_| anyhow::anyhow!("--script {item:?}: {frame:?} is not a frame number"))?;
        let (key, frames) = match rest.split_once('x') {
            Some((k, n)) => (
                k.trim(),
                n.trim()
                    .parse()
                    .map_err(|_| anyhow::anyhow!("--script {item:?}: {n:?} is not a count"))?,
            ),
            None => (rest.trim(), 1),
        };
        let mut chars = key.chars();
        let (Some(key), None) = (chars.next(), chars.next()) else {
            bail!("--script {item:?}: one key per item, one of {KEYS}");
        };
        if !KEYS.contains(key) {
            bail!("--script {item:?}: unknown key {key:?}; keys are {KEYS}");
        }
        out.push(Press { frame, frames, key });
    }
    Ok(out)
}

/// Keys down at `frame`, and keys newly pressed at it.
pub fn at(script: &[Press], frame: u32) -> (Vec<char>, Vec<char>) {
    let down = script
        .iter()
        .filter(|p| (p.frame..p.frame + p.frames).contains(&frame))
        .map(|p| p.key)
        .collect();
    let pressed = script
        .iter()
        .filter(|p| p.frame == frame)
        .map(|p| p.key)
        .collect();
    (down, pressed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scripts_parse_and_bad_ones_say_why() {
        let s = parse("2:w x3, 4:h").expect("parses");
        assert_eq!(at(&s, 3), (vec!['w'], vec![]));
        assert_eq!(at(&s, 4), (vec!['w', 'h'], vec!['h']));
        assert_eq!(at(&s, 5), (vec![], vec![]));
        for bad in ["w", "x:w", "2:wq", "2:z", "2:w xq"] {
            assert!(parse(bad).is_err(), "{bad:?}");
        }
    }
}

//! Textures and samplers given as host data: [`HostTexture`] texels, read by `textureLoad`
//! (`.load(..)`), written by `textureStore` (storage textures), sized by `textureDimensions`,
//! `textureNumLayers` and `textureNumSamples`, and sampled through a [`HostSampler`] by
//! `textureSample`, `textureSampleLevel`, `textureSampleGrad`, `textureSampleCompare` and
//! `textureSampleCompareLevel`.
//!
//! A host texture has one mip level, so sampling reads level 0 whatever the level of detail, as
//! a GPU does with a one-level texture. Filtering follows the Vulkan rules: texel centres at
//! half-integers, bilinear weights between the four nearest texels, clamp-to-edge or repeat
//! addressing per tap; a comparison sampler compares each tap with the reference and filters
//! the 0/1 results (percentage-closer filtering).

use super::{EvalError, Machine, Value};
use crate::ir::{Expr, ExprKind};

/// A texture's texels on the host: mip level 0 of every layer, `samples` per texel (1 unless
/// multisampled). `texels[((layer · height + y) · width + x) · samples + sample]` is an `f32`
/// for a depth texture and a 4-vector for a colour one.
#[derive(Debug, Clone, PartialEq)]
pub struct HostTexture {
    pub width: u32,
    pub height: u32,
    pub layers: u32,
    pub samples: u32,
    pub texels: Vec<Value>,
}

impl HostTexture {
    /// A depth texture of `width`×`height` with `samples` samples per texel, from its values in
    /// texel-then-sample order.
    pub fn depth(width: u32, height: u32, samples: u32, depth: &[f32]) -> HostTexture {
        HostTexture {
            width,
            height,
            layers: 1,
            samples,
            texels: depth.iter().map(|d| Value::F32(*d)).collect(),
        }
    }

    /// The texture as the value a static holds.
    pub(crate) fn into_value(self) -> Result<Value, EvalError> {
        let expected = [self.width, self.height, self.layers, self.samples]
            .iter()
            .map(|&n| n as usize)
            .product::<usize>();
        if self.texels.len() != expected {
            return Err(EvalError::Type(format!(
                "a {}×{}×{} texture with {} samples needs {expected} texels, given {}",
                self.width,
                self.height,
                self.layers,
                self.samples,
                self.texels.len()
            )));
        }
        let size = [self.width, self.height, self.layers, self.samples].map(Value::U32);
        let mut fields = size.to_vec();
        fields.push(Value::Array(self.texels));
        Ok(Value::Struct(fields))
    }
}

/// How a [`HostSampler`] compares a depth tap with the reference (`reference OP texel`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compare {
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    Equal,
    NotEqual,
    Always,
    Never,
}

/// Address mode of a [`HostSampler`], on both axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Address {
    ClampToEdge,
    Repeat,
}

/// A sampler on the host.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HostSampler {
    /// Bilinear filtering (else nearest).
    pub linear: bool,
    pub address: Address,
    /// For a comparison sampler.
    pub compare: Option<Compare>,
}

const COMPARES: [Compare; 8] = [
    Compare::Less,
    Compare::LessEqual,
    Compare::Greater,
    Compare::GreaterEqual,
    Compare::Equal,
    Compare::NotEqual,
    Compare::Always,
    Compare::Never,
];

impl HostSampler {
    /// The sampler as the value a static holds.
    pub(crate) fn into_value(self) -> Value {
        let compare = self
            .compare
            .and_then(|c| COMPARES.iter().position(|k| *k == c))
            .map_or(0, |i| i as u32 + 1);
        Value::Struct(vec![
            Value::U32(u32::from(self.linear)),
            Value::U32(u32::from(self.address == Address::Repeat)),
            Value::U32(compare),
        ])
    }

    fn from_value(v: &Value) -> Result<HostSampler, EvalError> {
        if let Value::Struct(f) = v
            && let [Value::U32(linear), Value::U32(repeat), Value::U32(compare)] = f.as_slice()
        {
            return Ok(HostSampler {
                linear: *linear != 0,
                address: if *repeat != 0 {
                    Address::Repeat
                } else {
                    Address::ClampToEdge
                },
                compare: (*compare as usize)
                    .checked_sub(1)
                    .and_then(|i| COMPARES.get(i).copied()),
            });
        }
        Err(EvalError::Type(format!("a sampler expected, found {v}")))
    }
}

fn compares(c: Compare, reference: f32, texel: f32) -> bool {
    match c {
        Compare::Less => reference < texel,
        Compare::LessEqual => reference <= texel,
        Compare::Greater => reference > texel,
        Compare::GreaterEqual => reference >= texel,
        Compare::Equal => reference == texel,
        Compare::NotEqual => reference != texel,
        Compare::Always => true,
        Compare::Never => false,
    }
}

fn float(v: &Value) -> Result<f32, EvalError> {
    match v {
        Value::F32(x) => Ok(*x),
        Value::I32(i) => Ok(*i as f32),
        Value::U32(u) => Ok(*u as f32),
        v => Err(EvalError::Type(format!("a float expected, found {v}"))),
    }
}

/// `a · (1 − t) + b · t`, component-wise.
fn lerp(a: &Value, b: &Value, t: f32) -> Result<Value, EvalError> {
    Ok(match (a, b) {
        (Value::Vector(x), Value::Vector(y)) => Value::Vector(
            x.iter()
                .zip(y)
                .map(|(p, q)| lerp(p, q, t))
                .collect::<Result<_, _>>()?,
        ),
        (p, q) => Value::F32(float(p)? * (1.0 - t) + float(q)? * t),
    })
}

/// The texel index along one axis of `size` texels for integer coordinate `i`.
fn address(i: i64, size: u32, mode: Address) -> usize {
    let n = i64::from(size.max(1));
    (match mode {
        Address::ClampToEdge => i.clamp(0, n - 1),
        Address::Repeat => i.rem_euclid(n),
    }) as usize
}

/// Width, height, layers and samples of a texture static's value, and its texels.
fn parts(v: &Value) -> Result<([u32; 4], &[Value]), EvalError> {
    if let Value::Struct(f) = v
        && let [
            Value::U32(w),
            Value::U32(h),
            Value::U32(l),
            Value::U32(s),
            Value::Array(t),
        ] = f.as_slice()
    {
        return Ok(([*w, *h, *l, *s], t));
    }
    Err(EvalError::Type(format!("a texture expected, found {v}")))
}

fn uint(v: &Value) -> Result<i64, EvalError> {
    match v {
        Value::U32(u) => Ok(i64::from(*u)),
        Value::I32(i) => Ok(i64::from(*i)),
        v => Err(EvalError::Type(format!("a texture coordinate {v}"))),
    }
}

impl Machine<'_> {
    fn texture_static<'v>(&'v self, e: &Expr) -> Result<&'v Value, EvalError> {
        match e.kind {
            ExprKind::Global(g) => self.global(g),
            _ => Err(EvalError::Unsupported(
                "a texture that is not a static".into(),
            )),
        }
    }

    /// `textureLoad`, `textureDimensions` and `textureNumSamples`; `None` for other builtins.
    pub(crate) fn texture_builtin(
        &mut self,
        locals: &[Value],
        wgsl: &str,
        args: &[Expr],
    ) -> Option<Result<Value, EvalError>> {
        let [texture, rest @ ..] = args else {
            return None;
        };
        let run = |m: &mut Self| -> Result<Value, EvalError> {
            let rest = rest
                .iter()
                .map(|a| m.eval(locals, a, None))
                .collect::<Result<Vec<_>, _>>()?;
            let ([w, h, layers, samples], texels) = parts(m.texture_static(texture)?)?;
            match wgsl {
                "textureDimensions" => Ok(Value::Vector(vec![Value::U32(w), Value::U32(h)])),
                "textureNumSamples" => Ok(Value::U32(samples)),
                "textureNumLayers" => Ok(Value::U32(layers)),
                _ => {
                    let zero = Value::U32(0);
                    let (coords, layer, last) = match rest.as_slice() {
                        // A storage texture: coordinates only.
                        [c] => (c, 0, &zero),
                        [c, last] => (c, 0, last),
                        [c, layer, last] => (c, uint(layer)?, last),
                        _ => return Err(EvalError::Type("textureLoad arguments".into())),
                    };
                    let Value::Vector(xy) = coords else {
                        return Err(EvalError::Type(format!("texture coordinates {coords}")));
                    };
                    let (x, y) = match xy.as_slice() {
                        [x, y] => (uint(x)?, uint(y)?),
                        _ => return Err(EvalError::Type("texture coordinates".into())),
                    };
                    let last = uint(last)?;
                    let sample = if samples > 1 { last } else { 0 };
                    if samples == 1 && last != 0 {
                        return Err(EvalError::Unsupported(format!(
                            "mip level {last} (host textures have level 0 only)"
                        )));
                    }
                    for (index, len) in [(x, w), (y, h), (layer, layers), (sample, samples)] {
                        if !(0..i64::from(len)).contains(&index) {
                            return Err(EvalError::OutOfBounds {
                                index,
                                len: len as usize,
                            });
                        }
                    }
                    let at = ((layer * i64::from(h) + y) * i64::from(w) + x) * i64::from(samples)
                        + sample;
                    texels
                        .get(at as usize)
                        .cloned()
                        .ok_or(EvalError::OutOfBounds {
                            index: at,
                            len: texels.len(),
                        })
                }
            }
        };
        match wgsl {
            "textureLoad" | "textureDimensions" | "textureNumSamples" | "textureNumLayers" => {
                Some(run(self))
            }
            "textureStore" => Some(self.texture_store(locals, texture, rest)),
            w if w.starts_with("textureSample") => {
                Some(self.texture_sample(locals, w, texture, rest))
            }
            _ => None,
        }
    }
}

impl Machine<'_> {
    /// `textureStore(texture, coords, value)` on a host storage texture.
    fn texture_store(
        &mut self,
        locals: &[Value],
        texture: &Expr,
        rest: &[Expr],
    ) -> Result<Value, EvalError> {
        let [coords, value] = rest else {
            return Err(EvalError::Type("textureStore arguments".into()));
        };
        let coords = self.eval(locals, coords, None)?;
        let value = self.eval(locals, value, None)?;
        let (x, y) = match &coords {
            Value::Vector(c) if c.len() == 2 => (uint(&c[0])?, uint(&c[1])?),
            c => return Err(EvalError::Type(format!("texture coordinates {c}"))),
        };
        let ExprKind::Global(g) = texture.kind else {
            return Err(EvalError::Unsupported(
                "a texture that is not a static".into(),
            ));
        };
        let slot = self.global_mut(g)?;
        let Value::Struct(fields) = slot else {
            return Err(EvalError::Type("a texture expected".into()));
        };
        let (w, h) = match fields.as_slice() {
            [Value::U32(w), Value::U32(h), ..] => (*w, *h),
            _ => return Err(EvalError::Type("a texture expected".into())),
        };
        for (index, len) in [(x, w), (y, h)] {
            if !(0..i64::from(len)).contains(&index) {
                return Err(EvalError::OutOfBounds {
                    index,
                    len: len as usize,
                });
            }
        }
        let at = (y * i64::from(w) + x) as usize;
        match fields.get_mut(4) {
            Some(Value::Array(texels)) if at < texels.len() => texels[at] = value,
            _ => return Err(EvalError::Type("a texture's texels".into())),
        }
        Ok(Value::Struct(vec![]))
    }

    /// `textureSample*` through a host sampler: `[sampler, uv, (layer), extra..]` in `rest`.
    fn texture_sample(
        &mut self,
        locals: &[Value],
        wgsl: &str,
        texture: &Expr,
        rest: &[Expr],
    ) -> Result<Value, EvalError> {
        let [sampler, uv, extra @ ..] = rest else {
            return Err(EvalError::Type(format!("{wgsl} arguments")));
        };
        let sampler = match sampler.kind {
            ExprKind::Global(g) => HostSampler::from_value(self.global(g)?)?,
            _ => {
                return Err(EvalError::Unsupported(
                    "a sampler that is not a static".into(),
                ));
            }
        };
        let uv = self.eval(locals, uv, None)?;
        let extra = extra
            .iter()
            .map(|e| self.eval(locals, e, None))
            .collect::<Result<Vec<_>, _>>()?;
        let ([w, h, layers, _], texels) = parts(self.texture_static(texture)?)?;
        let arrayed = matches!(&texture.ty, crate::ir::Ty::Texture(t) if t.arrayed);
        let (layer, extra) = if arrayed {
            match extra.split_first() {
                Some((l, rest)) => (uint(l)?, rest.to_vec()),
                None => return Err(EvalError::Type(format!("{wgsl} without its layer"))),
            }
        } else {
            (0, extra)
        };
        if !(0..i64::from(layers)).contains(&layer) {
            return Err(EvalError::OutOfBounds {
                index: layer,
                len: layers as usize,
            });
        }
        let reference = if wgsl.starts_with("textureSampleCompare") {
            let r = extra
                .first()
                .ok_or_else(|| EvalError::Type(format!("{wgsl} without its reference")))?;
            let c = sampler.compare.ok_or_else(|| {
                EvalError::Type(format!("{wgsl} with a sampler that does not compare"))
            })?;
            Some((c, float(r)?))
        } else {
            None
        };
        let (u, v) = match &uv {
            Value::Vector(c) if c.len() == 2 => (float(&c[0])?, float(&c[1])?),
            c => return Err(EvalError::Type(format!("texture coordinates {c}"))),
        };
        let tap = |x: i64, y: i64| -> Result<Value, EvalError> {
            let (x, y) = (
                address(x, w, sampler.address),
                address(y, h, sampler.address),
            );
            let at = (layer as usize * h as usize + y) * w as usize + x;
            let texel = texels.get(at).cloned().ok_or(EvalError::OutOfBounds {
                index: at as i64,
                len: texels.len(),
            })?;
            Ok(match reference {
                Some((c, r)) => Value::F32(if compares(c, r, float(&texel)?) {
                    1.0
                } else {
                    0.0
                }),
                None => texel,
            })
        };
        let (x, y) = (u * w as f32, v * h as f32);
        if !sampler.linear {
            return tap(x.floor() as i64, y.floor() as i64);
        }
        let (x, y) = (x - 0.5, y - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (tx, ty) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = lerp(&tap(x0, y0)?, &tap(x0 + 1, y0)?, tx)?;
        let bottom = lerp(&tap(x0, y0 + 1)?, &tap(x0 + 1, y0 + 1)?, tx)?;
        lerp(&top, &bottom, ty)
    }
}

impl HostTexture {
    /// A texture from the value a static holds (what a dispatch wrote into a storage texture).
    pub(crate) fn from_value(v: &Value) -> Result<HostTexture, EvalError> {
        let ([width, height, layers, samples], texels) = parts(v)?;
        Ok(HostTexture {
            width,
            height,
            layers,
            samples,
            texels: texels.to_vec(),
        })
    }
}

//! Textures given as host data: [`HostTexture`] texels, read by `textureLoad` (`.load(..)`) and
//! sized by `textureDimensions` and `textureNumSamples`. Sampling (filtering, samplers) is not
//! interpreted yet.

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
                _ => {
                    let (coords, layer, last) = match rest.as_slice() {
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
            "textureLoad" | "textureDimensions" | "textureNumSamples" => Some(run(self)),
            _ => None,
        }
    }
}

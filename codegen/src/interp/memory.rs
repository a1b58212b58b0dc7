//! Host bytes ↔ interpreter values, by the WGSL memory layout of the DSL type (`crate::layout`,
//! the offsets the generated host structs copy): what lets a [`super::Dispatch`] take the same
//! `bytemuck` bytes a GPU buffer would, and give them back. Memory is read and written in
//! little-endian 32-bit words; a `u64` is two of them, the low word first.

use super::{EvalError, Value};
use crate::ir::{Module, Scalar, Ty};
use crate::layout::{array_len, layout_of, round_up, struct_layout};
use crate::variants::Env;

/// Types and the variant that sizes their arrays.
#[derive(Clone, Copy)]
pub(crate) struct Memory<'a> {
    pub module: &'a Module,
    pub env: &'a Env,
}

impl Memory<'_> {
    /// Bytes from one element to the next in an array of `elem`.
    fn stride(&self, elem: &Ty) -> usize {
        let l = layout_of(elem, self.module, self.env);
        round_up(l.size, l.align) as usize
    }

    /// The value of type `ty` stored at `bytes[offset..]`; a runtime array takes every whole
    /// element that fits.
    pub fn decode(&self, ty: &Ty, bytes: &[u8], offset: usize) -> Result<Value, EvalError> {
        let word = |at: usize| -> Result<u32, EvalError> {
            bytes
                .get(at..at + 4)
                .and_then(|b| <[u8; 4]>::try_from(b).ok())
                .map(u32::from_le_bytes)
                .ok_or_else(|| too_short(ty, bytes.len(), at + 4))
        };
        Ok(match ty {
            Ty::Scalar(s @ Scalar::U64) | Ty::Atomic(s @ Scalar::U64) => {
                Value::from_words(*s, &[word(offset)?, word(offset + 4)?])
            }
            Ty::Scalar(s) | Ty::Atomic(s) => Value::from_bits(*s, word(offset)?),
            Ty::Vector(n, s) => Value::Vector(
                (0..usize::from(*n))
                    .map(|i| word(offset + 4 * i).map(|w| Value::from_bits(*s, w)))
                    .collect::<Result<_, _>>()?,
            ),
            Ty::Matrix(c, r) => {
                let column = Ty::Vector(*r, Scalar::F32);
                let stride = self.stride(&column);
                Value::Array(
                    (0..usize::from(*c))
                        .map(|i| self.decode(&column, bytes, offset + i * stride))
                        .collect::<Result<_, _>>()?,
                )
            }
            Ty::Array(elem, len) => {
                let n = array_len(len, self.module, self.env).ok_or_else(|| {
                    EvalError::Type("an array length that does not evaluate".into())
                })?;
                let stride = self.stride(elem);
                Value::Array(
                    (0..n as usize)
                        .map(|i| self.decode(elem, bytes, offset + i * stride))
                        .collect::<Result<_, _>>()?,
                )
            }
            Ty::RuntimeArray(elem) => {
                let stride = self.stride(elem).max(1);
                let n = bytes.len().saturating_sub(offset) / stride;
                Value::Array(
                    (0..n)
                        .map(|i| self.decode(elem, bytes, offset + i * stride))
                        .collect::<Result<_, _>>()?,
                )
            }
            Ty::Struct(id) => {
                let layout = struct_layout(*id, self.module, self.env);
                let fields = &self.module.structs[*id].fields;
                Value::Struct(
                    fields
                        .iter()
                        .zip(&layout.members)
                        .map(|(f, m)| self.decode(&f.ty, bytes, offset + m.offset as usize))
                        .collect::<Result<_, _>>()?,
                )
            }
            t => {
                return Err(EvalError::Unsupported(format!(
                    "host data for a static of type {t:?}"
                )));
            }
        })
    }

    /// Writes `v`, of type `ty`, into `bytes[offset..]`, growing `bytes` as needed (padding
    /// stays zero).
    pub fn encode(
        &self,
        ty: &Ty,
        v: &Value,
        bytes: &mut Vec<u8>,
        offset: usize,
    ) -> Result<(), EvalError> {
        let mut put = |at: usize, bits: u32| {
            if bytes.len() < at + 4 {
                bytes.resize(at + 4, 0);
            }
            bytes[at..at + 4].copy_from_slice(&bits.to_le_bytes());
        };
        match (ty, v) {
            (Ty::Scalar(_) | Ty::Atomic(_), v) => {
                let words = v
                    .words()
                    .ok_or_else(|| EvalError::Type(format!("{v} stored as a scalar")))?;
                for (i, w) in words.into_iter().enumerate() {
                    put(offset + 4 * i, w);
                }
            }
            (Ty::Vector(..), Value::Vector(c)) => {
                for (i, x) in c.iter().enumerate() {
                    let bits = x
                        .bits()
                        .ok_or_else(|| EvalError::Type(format!("{x} in a vector")))?;
                    put(offset + 4 * i, bits);
                }
            }
            (Ty::Matrix(_, r), Value::Array(columns)) => {
                let column = Ty::Vector(*r, Scalar::F32);
                let stride = self.stride(&column);
                for (i, c) in columns.iter().enumerate() {
                    self.encode(&column, c, bytes, offset + i * stride)?;
                }
            }
            (Ty::Array(elem, _) | Ty::RuntimeArray(elem), Value::Array(items)) => {
                let stride = self.stride(elem);
                for (i, x) in items.iter().enumerate() {
                    self.encode(elem, x, bytes, offset + i * stride)?;
                }
            }
            (Ty::Struct(id), Value::Struct(values)) => {
                let layout = struct_layout(*id, self.module, self.env);
                let fields = &self.module.structs[*id].fields;
                for ((f, m), x) in fields.iter().zip(&layout.members).zip(values) {
                    self.encode(&f.ty, x, bytes, offset + m.offset as usize)?;
                }
                let end = offset + layout.layout.size as usize;
                if bytes.len() < end {
                    bytes.resize(end, 0);
                }
            }
            (t, v) => return Err(EvalError::Type(format!("{v} stored as {t:?}"))),
        }
        Ok(())
    }

    /// The zero value of `ty` (what WGSL gives workgroup memory), where the type has one.
    pub fn zero(&self, ty: &Ty) -> Result<Value, EvalError> {
        let size = layout_of(ty, self.module, self.env).size as usize;
        self.decode(ty, &vec![0; size], 0)
    }
}

fn too_short(ty: &Ty, len: usize, needed: usize) -> EvalError {
    EvalError::Type(format!(
        "host data of {len} bytes is too short for {ty:?}: it needs at least {needed}"
    ))
}

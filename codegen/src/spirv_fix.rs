//! Rewrites naga 30's scalar `SampleMask` built-in into the array Vulkan requires.
//!
//! naga 30 declares a `#[builtin(sample_mask)]` input or output as a variable of type
//! `u32`; the SPIR-V environment for Vulkan requires `BuiltIn SampleMask` to decorate an array
//! of 32-bit integers (`VUID-SampleMask-SampleMask-04359`), and `spirv-val` rejects the module.
//! This step, run on every variant's words after naga's backend, retypes each such variable as
//! `array<u32, 1>` and turns every use of it inside functions into a use of its element 0
//! through an `OpAccessChain`. Nothing else in the module changes, and a module without a
//! scalar `SampleMask` comes back word for word.
//!
//! Works on rspirv's data representation, so instruction encoding stays rspirv's business.

use rspirv::binary::Assemble as _;
use rspirv::dr::{Instruction, Module, Operand};
use rspirv::spirv::{BuiltIn, Decoration, Op, Word};

/// The module with every scalar `SampleMask` variable made a one-element array; `words` as is
/// when it has none.
pub fn fix_sample_mask(words: &[u32]) -> Result<Vec<u32>, String> {
    let mut module =
        rspirv::dr::load_words(words).map_err(|e| format!("reading naga's SPIR-V: {e}"))?;
    let variables = sample_mask_variables(&module);
    let mut changed = false;
    for variable in variables {
        changed |= retype_variable(&mut module, variable)?;
    }
    if !changed {
        return Ok(words.to_vec());
    }
    // rspirv's loader stamps its own generator id; the module is still naga's.
    if let (Some(header), Some(&generator)) = (module.header.as_mut(), words.get(2)) {
        header.generator = generator;
    }
    Ok(module.assemble())
}

/// The ids decorated `BuiltIn SampleMask`.
fn sample_mask_variables(module: &Module) -> Vec<Word> {
    module
        .annotations
        .iter()
        .filter(|i| i.class.opcode == Op::Decorate)
        .filter_map(|i| match i.operands.as_slice() {
            [
                Operand::IdRef(target),
                Operand::Decoration(Decoration::BuiltIn),
                Operand::BuiltIn(BuiltIn::SampleMask),
                ..,
            ] => Some(*target),
            _ => None,
        })
        .collect()
}

fn next_id(module: &mut Module) -> Result<Word, String> {
    let header = module
        .header
        .as_mut()
        .ok_or("naga's SPIR-V has no header")?;
    let id = header.bound;
    header.bound += 1;
    Ok(id)
}

fn defining(module: &Module, id: Word) -> Option<usize> {
    module
        .types_global_values
        .iter()
        .position(|i| i.result_id == Some(id))
}

/// Makes `variable` an `array<u32, 1>`; `false` if it already is an array.
fn retype_variable(module: &mut Module, variable: Word) -> Result<bool, String> {
    let at = defining(module, variable)
        .ok_or_else(|| format!("SampleMask target %{variable} is not a global variable"))?;
    let scalar_pointer = module.types_global_values[at]
        .result_type
        .ok_or_else(|| format!("SampleMask variable %{variable} has no type"))?;
    let pointer = defining(module, scalar_pointer)
        .map(|i| module.types_global_values[i].clone())
        .ok_or_else(|| format!("SampleMask variable %{variable}'s type is not declared"))?;
    let (storage, pointee) = match pointer.operands.as_slice() {
        [Operand::StorageClass(storage), Operand::IdRef(pointee)] => (*storage, *pointee),
        _ => return Err(format!("SampleMask variable %{variable} is not a pointer")),
    };
    let pointee_op = defining(module, pointee).map(|i| module.types_global_values[i].class.opcode);
    match pointee_op {
        Some(Op::TypeArray) => return Ok(false),
        Some(Op::TypeInt) => {}
        _ => {
            return Err(format!(
                "SampleMask variable %{variable} is neither u32 nor an array"
            ));
        }
    }
    let one = next_id(module)?;
    let zero = next_id(module)?;
    let array = next_id(module)?;
    let array_pointer = next_id(module)?;
    let declarations = [
        Instruction::new(
            Op::Constant,
            Some(pointee),
            Some(one),
            vec![Operand::LiteralBit32(1)],
        ),
        Instruction::new(
            Op::Constant,
            Some(pointee),
            Some(zero),
            vec![Operand::LiteralBit32(0)],
        ),
        Instruction::new(
            Op::TypeArray,
            None,
            Some(array),
            vec![Operand::IdRef(pointee), Operand::IdRef(one)],
        ),
        Instruction::new(
            Op::TypePointer,
            None,
            Some(array_pointer),
            vec![Operand::StorageClass(storage), Operand::IdRef(array)],
        ),
    ];
    module.types_global_values[at].result_type = Some(array_pointer);
    module.types_global_values.splice(at..at, declarations);
    let mut bound = next_id(module)?;
    for function in &mut module.functions {
        for block in &mut function.blocks {
            let mut rewritten = Vec::with_capacity(block.instructions.len());
            for mut instruction in std::mem::take(&mut block.instructions) {
                let uses = instruction.operands.contains(&Operand::IdRef(variable));
                if uses {
                    let element = bound;
                    bound += 1;
                    rewritten.push(Instruction::new(
                        Op::AccessChain,
                        Some(scalar_pointer),
                        Some(element),
                        vec![Operand::IdRef(variable), Operand::IdRef(zero)],
                    ));
                    for operand in &mut instruction.operands {
                        if *operand == Operand::IdRef(variable) {
                            *operand = Operand::IdRef(element);
                        }
                    }
                }
                rewritten.push(instruction);
            }
            block.instructions = rewritten;
        }
    }
    if let Some(header) = module.header.as_mut() {
        header.bound = bound;
    }
    Ok(true)
}

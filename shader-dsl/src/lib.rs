//! Proc-macro front door of the shader DSL.
//!
//! This crate is only an adapter: it parses the macro input with syn, hands it to `codegen`,
//! and turns the result (or the error, at the user's span) back into tokens. Anything that can be
//! tested without a proc-macro lives in `codegen`.

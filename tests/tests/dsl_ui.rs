//! Compile-fail tests of the shader DSL: each `tests/ui/*.rs` must fail with the committed
//! `.stderr` (the DSL's message, at the offending span). Re-approve with `TRYBUILD=overwrite`.

#[test]
fn dsl_compile_errors() {
    let t = trybuild::TestCases::new();
    t.compile_fail("ui/*.rs");
}

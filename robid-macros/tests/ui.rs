//! Compile-error tests of `robot_model!`: each bad input is one file in
//! `tests/ui/` with the expected compiler output next to it (`.stderr`).

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}

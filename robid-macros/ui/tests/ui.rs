//! Compile-error tests of `robot_model!`: each bad input is one file in
//! `tests/ui/` with the expected compiler output next to it (`.stderr`).

#[test]
fn ui() {
    // trybuild builds this crate's dependencies again in a project of its own, in the
    // default dev profile, whose full debug info none of these compile errors need:
    // without it the test takes 38 s instead of 52 s on two cores from a fresh clone.
    // SAFETY: the binary's only test, before trybuild starts any thread or process.
    unsafe { std::env::set_var("CARGO_PROFILE_DEV_DEBUG", "false") };
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}

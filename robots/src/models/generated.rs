//! The checked-in generated code of every reference robot (`generated/NAME.rs`)
//! must be what robid emits now. Run with `ROBID_BLESS=1` to rewrite the files.

use super::REFERENCES;
use robid_symbolic::Robot;
use std::path::Path;

#[test]
fn generated_code_is_up_to_date() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bless = std::env::var_os("ROBID_BLESS").is_some();
    let mut stale = Vec::new();
    for name in REFERENCES.iter().map(|r| r.name) {
        let robot = Robot::from_file(&root.join(format!("descriptions/{name}.toml"))).unwrap();
        let code = robid_symbolic::emit::emit_robot(&robot).unwrap();
        let path = root.join(format!("generated/{name}.rs"));
        let current = std::fs::read_to_string(&path).unwrap_or_default();
        if current != code {
            if bless {
                // atomically: an interrupted bless leaves the old file whole
                robid_runtime::output::write_bytes(&path, code.as_bytes()).unwrap();
            } else {
                stale.push(path.display().to_string());
            }
        }
    }
    assert!(
        stale.is_empty(),
        "stale generated code: {stale:?}; regenerate with `ROBID_BLESS=1 cargo test -p robots generated` and commit"
    );
}

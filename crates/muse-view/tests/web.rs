//! The front-end's own tests (`web/test`, node's test runner) under `cargo test`.
//!
//! Without `node` on the machine the test says so and passes, unless `CI` is set: CI must
//! run them.

use std::path::Path;
use std::process::Command;

#[test]
fn front_end_tests_pass_under_node() {
    let web = Path::new(env!("CARGO_MANIFEST_DIR")).join("web");
    let out = match Command::new("node")
        .arg("--test")
        .arg("test/")
        .current_dir(&web)
        .output()
    {
        Ok(out) => out,
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!(
                "SKIPPED: `node` not found ({e}); install Node.js to run the viewer's front-end tests"
            );
            return;
        }
        Err(e) => panic!("CI is set but `node` cannot run: {e}"),
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    let summary: Vec<&str> = stdout.lines().filter(|l| l.starts_with("# ")).collect();
    eprintln!("{}", summary.join("\n"));
    assert!(
        out.status.success(),
        "node --test failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        summary
            .iter()
            .any(|l| l.starts_with("# pass ") && l != &"# pass 0"),
        "no front-end test ran:\n{stdout}"
    );
}

//! Regressions from the hardening issue (12) at the level of the program: exit codes and
//! messages on inputs and environments that once gave exit 0 or a panic.

use std::fs::File;
use std::process::{Command, Stdio};

use crate::support::root;

/// Runs `bondgraph ARGS` with its standard output going to `/dev/full`, where every write
/// fails with "no space left on device".
fn run_into_full_disk(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_bondgraph"))
        .args(args)
        .current_dir(root())
        .stdout(Stdio::from(
            File::create("/dev/full").expect("/dev/full exists"),
        ))
        .stderr(Stdio::piped())
        .output()
        .expect("the program runs")
}

#[test]
fn a_failed_write_on_standard_output_is_an_error() {
    for args in [
        &["equations", "models/examples/mass_spring_damper.ron"][..],
        &["check", "models/examples/mass_spring_damper.ron"],
        &["check", "models/examples/nonlinear/pendulum.ron"],
    ] {
        let output = run_into_full_disk(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("could not write to standard output"),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

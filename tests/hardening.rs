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

/// Writes `bytes` to a fresh file in the temporary folder and returns its path.
fn temporary(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("bondgraph-hardening-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A byte that is not UTF-8 once said only "stream did not contain valid UTF-8".
#[test]
fn a_byte_that_is_not_utf8_is_located() {
    let text =
        std::fs::read_to_string(root().join("models/examples/mass_spring_damper.ron")).unwrap();
    // Break the first letter of line 3.
    let line_start: usize = text.split_inclusive('\n').take(2).map(str::len).sum();
    let mut bytes = text.into_bytes();
    bytes[line_start] = 0xff;
    let path = temporary("not_utf8.ron", &bytes);
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{}:3:1: byte 0xff is not valid UTF-8",
            path.display()
        )),
        "{stderr}"
    );
}

/// A file over the size limit is refused before it is parsed.
#[test]
fn a_file_over_the_size_limit_is_refused() {
    let size = usize::try_from(bondgraph_core::limits::MAX_FILE_BYTES).unwrap() + 1;
    let path = temporary("huge.ron", &vec![b' '; size]);
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("larger than the limit of 16777216 bytes"),
        "{stderr}"
    );
}

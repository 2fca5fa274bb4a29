//! Standard output that does not lose its errors: every write goes through [`print()`],
//! which remembers the first failure (a full disk, `> /dev/full`), and `main` asks
//! [`finish`] before it reports success. A closed pipe (`bondgraph ... | head`) is not a
//! failure: the reader has all it wanted.
//!
//! Why a remembered error rather than a `Result` from every print: commands print from many
//! places, and a write that fails half-way through a document leaves nothing to do but stop
//! with a non-zero exit, which `finish` does once.

use std::io::{ErrorKind, Write};
use std::sync::Mutex;

static FAILURE: Mutex<Option<String>> = Mutex::new(None);

fn remember(error: &std::io::Error) {
    if error.kind() == ErrorKind::BrokenPipe {
        return;
    }
    let mut failure = FAILURE.lock().unwrap_or_else(|e| e.into_inner());
    if failure.is_none() {
        *failure = Some(error.to_string());
    }
}

/// Writes `text` to standard output; a failure is kept for [`finish`].
pub fn print(text: &str) {
    if let Err(error) = std::io::stdout().lock().write_all(text.as_bytes()) {
        remember(&error);
    }
}

/// Flushes standard output; the first write error since the start, if any.
pub fn finish() -> Result<(), String> {
    if let Err(error) = std::io::stdout().lock().flush() {
        remember(&error);
    }
    match FAILURE.lock().unwrap_or_else(|e| e.into_inner()).take() {
        Some(message) => Err(format!("could not write to standard output: {message}")),
        None => Ok(()),
    }
}

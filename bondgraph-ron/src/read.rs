//! Reading an input file as text, within [`bondgraph_core::limits::MAX_FILE_BYTES`] and with invalid
//! UTF-8 located at its line and column (the standard library says only "stream did not
//! contain valid UTF-8").
//!
//! ```
//! use bondgraph_ron::read::decode;
//! let error = decode("m.ron", b"Model(\n  name: \"\xff\"\n)".to_vec()).unwrap_err();
//! assert_eq!(error, "m.ron:2:10: byte 0xff is not valid UTF-8 (files must be UTF-8 text)");
//! ```

use std::io::Read;
use std::path::Path;

use bondgraph_core::limits::MAX_FILE_BYTES;

/// The text of the file at `path`, or why not, in one sentence naming the file as `what`
/// (`"model file"`, or `""`) and, for invalid UTF-8, the line and column.
///
/// # Errors
/// The file cannot be opened or read, is larger than [`MAX_FILE_BYTES`], or is not UTF-8.
pub fn read_text(path: &Path, what: &str) -> Result<String, String> {
    let name = path.display().to_string();
    let what = if what.is_empty() {
        String::new()
    } else {
        format!("{what} ")
    };
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read {what}'{name}': {e}"))?;
    let mut bytes = Vec::new();
    // `take` rather than the file's length: a device or a pipe has no length.
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {what}'{name}': {e}"))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(format!(
            "cannot read {what}'{name}': it is larger than the limit of {MAX_FILE_BYTES} bytes"
        ));
    }
    decode(&name, bytes)
}

/// `bytes` as text, or the line and column (in characters) of the first byte that is not
/// UTF-8.
///
/// # Errors
/// The bytes are not UTF-8.
pub fn decode(name: &str, bytes: Vec<u8>) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|error| {
        let (line, column, byte) = invalid_utf8_at(&error);
        format!(
            "{name}:{line}:{column}: byte {byte:#04x} is not valid UTF-8 (files must be UTF-8 text)"
        )
    })
}

/// Where the first byte that is not UTF-8 is: its line and column (in characters, both
/// from 1) and the byte itself.
pub fn invalid_utf8_at(error: &std::string::FromUtf8Error) -> (usize, usize, u8) {
    let bytes = error.as_bytes();
    let at = error.utf8_error().valid_up_to();
    let before = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, column, bytes[at])
}

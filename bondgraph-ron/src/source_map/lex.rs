//! The scanner's tokens: identifiers, numbers, strings (raw ones included), characters and
//! punctuation, with comments and whitespace as RON has them skipped between.

use bondgraph_core::source::Span;

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TokenKind {
    /// An identifier, possibly raw (`r#C`).
    Ident,
    /// A string or byte string, possibly raw.
    Str,
    /// A number, possibly signed, or `inf`/`NaN` with a sign.
    Number,
    /// A character or byte literal.
    Char,
    /// An `#![...]` attribute, whole.
    Attribute,
    /// One of `( ) [ ] { } : ,`.
    Punct(u8),
}

/// A token and where it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Token {
    /// What it is.
    pub(crate) kind: TokenKind,
    /// The whole token.
    pub(crate) span: Span,
    /// For strings, the bytes between the quotes; otherwise the whole token.
    pub(crate) content: Span,
}

impl Token {
    pub(crate) fn is_punct(&self, c: u8) -> bool {
        self.kind == TokenKind::Punct(c)
    }
}

/// A position where the text is not RON: an unknown character, or an unterminated
/// string, character or comment starting there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct LexError {
    /// Byte offset of the problem.
    pub(crate) at: usize,
}

/// RON's whitespace characters.
fn is_whitespace(c: char) -> bool {
    matches!(
        c,
        ' ' | '\t'
            | '\n'
            | '\r'
            | '\x0B'
            | '\x0C'
            | '\u{85}'
            | '\u{200E}'
            | '\u{200F}'
            | '\u{2028}'
            | '\u{2029}'
    )
}

fn is_ident_start(c: char) -> bool {
    c == '_' || c.is_alphabetic()
}

fn is_ident_continue(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

/// The offset of the first byte at or after `pos` that is not whitespace or a comment.
pub(crate) fn skip_trivia(text: &str, mut pos: usize) -> Result<usize, LexError> {
    loop {
        let rest = text.get(pos..).unwrap_or("");
        let trimmed = rest.trim_start_matches(is_whitespace);
        pos += rest.len() - trimmed.len();
        if trimmed.starts_with("//") {
            pos += trimmed.find('\n').unwrap_or(trimmed.len());
        } else if trimmed.starts_with("/*") {
            let start = pos;
            let bytes = text.as_bytes();
            let mut level = 0_usize;
            loop {
                if pos + 1 >= bytes.len() {
                    return Err(LexError { at: start });
                }
                match (bytes[pos], bytes[pos + 1]) {
                    (b'/', b'*') => {
                        level += 1;
                        pos += 2;
                    }
                    (b'*', b'/') => {
                        level -= 1;
                        pos += 2;
                        if level == 0 {
                            break;
                        }
                    }
                    _ => pos += 1,
                }
            }
        } else {
            return Ok(pos);
        }
    }
}

/// The next token at or after `pos` (after whitespace and comments); `None` at the end.
pub(crate) fn lex(text: &str, pos: usize) -> Result<Option<Token>, LexError> {
    let start = skip_trivia(text, pos)?;
    let rest = text.get(start..).unwrap_or("");
    let mut chars = rest.chars();
    let Some(c) = chars.next() else {
        return Ok(None);
    };
    let second = chars.next();
    let token = |kind, len: usize| Token {
        kind,
        span: Span::new(start, start + len),
        content: Span::new(start, start + len),
    };
    let bytes = rest.as_bytes();
    match c {
        '(' | ')' | '[' | ']' | '{' | '}' | ':' | ',' => {
            Ok(Some(token(TokenKind::Punct(bytes[0]), 1)))
        }
        '"' => lex_string(text, start, start).map(Some),
        '\'' => lex_char(text, start, start).map(Some),
        'b' if second == Some('"') => lex_string(text, start, start + 1).map(Some),
        'b' if second == Some('\'') => lex_char(text, start, start + 1).map(Some),
        'b' if second == Some('r') && raw_string_hashes(&rest[2..]).is_some() => {
            lex_raw_string(text, start, start + 2).map(Some)
        }
        'r' if raw_string_hashes(&rest[1..]).is_some() => {
            lex_raw_string(text, start, start + 1).map(Some)
        }
        'r' if second == Some('#') && rest[2..].chars().next().is_some_and(is_ident_continue) => {
            let len = 2 + ident_len(&rest[2..]);
            Ok(Some(token(TokenKind::Ident, len)))
        }
        '#' => {
            if !rest.starts_with("#![") {
                return Err(LexError { at: start });
            }
            match rest.find(']') {
                Some(end) => Ok(Some(token(TokenKind::Attribute, end + 1))),
                None => Err(LexError { at: start }),
            }
        }
        '0'..='9' => Ok(Some(token(TokenKind::Number, number_len(rest)))),
        '+' | '-' | '.'
            if second.is_some_and(|d| d.is_ascii_digit() || d == '.' || is_ident_start(d)) =>
        {
            Ok(Some(token(TokenKind::Number, number_len(rest))))
        }
        c if is_ident_start(c) => Ok(Some(token(TokenKind::Ident, ident_len(rest)))),
        _ => Err(LexError { at: start }),
    }
}

fn ident_len(text: &str) -> usize {
    text.find(|c: char| !is_ident_continue(c))
        .unwrap_or(text.len())
}

/// Length of a number token at the start of `text` (which starts with a digit, a sign or
/// a dot): digits, letters (hex digits, exponents, `inf`), `_` and `.`, and a sign right
/// after a decimal exponent's `e`.
fn number_len(text: &str) -> usize {
    let bytes = text.as_bytes();
    let hex = text.trim_start_matches(['+', '-']).starts_with("0x");
    let mut i = 1;
    while i < bytes.len() {
        let b = bytes[i];
        let sign_after_exponent =
            matches!(b, b'+' | b'-') && matches!(bytes[i - 1], b'e' | b'E') && !hex;
        if b.is_ascii_alphanumeric() || b == b'_' || b == b'.' || sign_after_exponent {
            i += 1;
        } else {
            break;
        }
    }
    i
}

/// If `text` starts with `#`* followed by `"`, the number of `#`s.
fn raw_string_hashes(text: &str) -> Option<usize> {
    let hashes = text.len() - text.trim_start_matches('#').len();
    text[hashes..].starts_with('"').then_some(hashes)
}

/// A `"..."` string whose opening quote is at `quote` (the token starts at `start`,
/// before any `b` prefix).
fn lex_string(text: &str, start: usize, quote: usize) -> Result<Token, LexError> {
    let bytes = text.as_bytes();
    let mut i = quote + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' => {
                return Ok(Token {
                    kind: TokenKind::Str,
                    span: Span::new(start, i + 1),
                    content: Span::new(quote + 1, i),
                });
            }
            _ => i += 1,
        }
    }
    Err(LexError { at: start })
}

/// A raw string `r#"..."#` whose `r` is just before `r_end` (at `start` or after `b`).
fn lex_raw_string(text: &str, start: usize, r_end: usize) -> Result<Token, LexError> {
    let hashes = raw_string_hashes(&text[r_end..]).unwrap_or(0);
    let content_start = r_end + hashes + 1;
    let closing = format!("\"{}", "#".repeat(hashes));
    match text[content_start..].find(&closing) {
        Some(len) => Ok(Token {
            kind: TokenKind::Str,
            span: Span::new(start, content_start + len + closing.len()),
            content: Span::new(content_start, content_start + len),
        }),
        None => Err(LexError { at: start }),
    }
}

/// A `'c'` literal whose opening quote is at `quote`.
fn lex_char(text: &str, start: usize, quote: usize) -> Result<Token, LexError> {
    let bytes = text.as_bytes();
    let mut i = quote + 1;
    while i < bytes.len() && bytes[i] != b'\n' {
        match bytes[i] {
            b'\\' => i += 2,
            b'\'' => {
                return Ok(Token {
                    kind: TokenKind::Char,
                    span: Span::new(start, i + 1),
                    content: Span::new(quote + 1, i),
                });
            }
            _ => i += 1,
        }
    }
    Err(LexError { at: start })
}

/// The text of a string token, with escapes decoded for ordinary strings.
pub(crate) fn string_value(text: &str, token: &Token) -> String {
    let content = text
        .get(token.content.start..token.content.end)
        .unwrap_or("");
    let raw = text[token.span.start..token.content.start].contains('r');
    if raw {
        content.to_string()
    } else {
        unescape(content)
    }
}

/// Decodes RON string escapes; anything malformed is kept as written (ron reports it).
fn unescape(content: &str) -> String {
    let mut out = String::with_capacity(content.len());
    let mut chars = content.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some('0') => out.push('\0'),
            Some('\\') => out.push('\\'),
            Some('"') => out.push('"'),
            Some('\'') => out.push('\''),
            Some('\n') => {
                while chars
                    .peek()
                    .is_some_and(|c| matches!(c, ' ' | '\t' | '\n' | '\r'))
                {
                    chars.next();
                }
            }
            Some('x') => {
                let hex: String = chars.by_ref().take(2).collect();
                match u8::from_str_radix(&hex, 16) {
                    Ok(b) if b.is_ascii() => out.push(char::from(b)),
                    _ => {
                        out.push_str("\\x");
                        out.push_str(&hex);
                    }
                }
            }
            Some('u') if chars.peek() == Some(&'{') => {
                chars.next();
                let hex: String = chars.by_ref().take_while(|&c| c != '}').collect();
                match u32::from_str_radix(&hex, 16).ok().and_then(char::from_u32) {
                    Some(ch) => out.push(ch),
                    None => {
                        out.push_str("\\u{");
                        out.push_str(&hex);
                        out.push('}');
                    }
                }
            }
            Some(other) => {
                out.push('\\');
                out.push(other);
            }
            None => out.push('\\'),
        }
    }
    out
}

/// The brackets open at byte `offset` (outermost first), each with its offset, as far as
/// the text before `offset` can be tokenised.
pub(crate) fn open_brackets(text: &str, offset: usize) -> Vec<(u8, usize)> {
    let mut stack = Vec::new();
    let mut pos = 0;
    while let Ok(Some(token)) = lex(text, pos) {
        if token.span.start >= offset {
            break;
        }
        match token.kind {
            TokenKind::Punct(c @ (b'(' | b'[' | b'{')) => stack.push((c, token.span.start)),
            TokenKind::Punct(c @ (b')' | b']' | b'}'))
                if stack.last().is_some_and(|&(open, _)| closer(open) == c) =>
            {
                stack.pop();
            }
            _ => {}
        }
        pos = token.span.end;
    }
    stack
}

/// The closing bracket for opening bracket `open`.
pub(crate) fn closer(open: u8) -> u8 {
    match open {
        b'(' => b')',
        b'[' => b']',
        _ => b'}',
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens() {
        fn kinds(text: &str) -> Vec<(TokenKind, &str)> {
            let mut pos = 0;
            let mut out = Vec::new();
            while let Ok(Some(token)) = lex(text, pos) {
                out.push((token.kind, &text[token.span.start..token.span.end]));
                pos = token.span.end;
            }
            out
        }
        use TokenKind::*;
        assert_eq!(
            kinds("#![enable(implicit_some)] r#x -inf +1 0x1F 1e-3 'c' '\\'' b\"b\" br#\"r\"# :,"),
            [
                (Attribute, "#![enable(implicit_some)]"),
                (Ident, "r#x"),
                (Number, "-inf"),
                (Number, "+1"),
                (Number, "0x1F"),
                (Number, "1e-3"),
                (Char, "'c'"),
                (Char, "'\\''"),
                (Str, "b\"b\""),
                (Str, "br#\"r\"#"),
                (Punct(b':'), ":"),
                (Punct(b','), ","),
            ]
        );
        assert_eq!(lex("  $", 0), Err(LexError { at: 2 }));
        assert_eq!(lex(" /* a /* b */", 0), Err(LexError { at: 1 }));
        assert_eq!(lex("\"abc", 0), Err(LexError { at: 0 }));
        assert_eq!(unescape(r"a\n\u{e9}\x41\q\"), "a\n\u{e9}A\\q\\");
        assert_eq!(open_brackets("({[", 3), [(b'(', 0), (b'{', 1), (b'[', 2)]);
        assert_eq!(open_brackets("({})[", 5), [(b'[', 4)]);
    }
}

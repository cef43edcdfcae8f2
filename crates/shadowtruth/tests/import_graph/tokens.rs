//! Rust source as identifiers and punctuation: comments, strings, characters and numbers are
//! dropped, so a `use` written inside a string or a comment is never read as one.

/// One token: an identifier or keyword, `::`, or a single punctuation character.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Token {
    Ident(String),
    PathSep,
    Punct(char),
}

impl Token {
    pub fn is_ident(&self, word: &str) -> bool {
        matches!(self, Token::Ident(name) if name == word)
    }

    pub fn ident(&self) -> Option<&str> {
        match self {
            Token::Ident(name) => Some(name),
            _ => None,
        }
    }
}

pub fn tokenize(source: &str) -> Vec<Token> {
    let chars: Vec<char> = source.chars().collect();
    let mut tokens = Vec::new();
    let mut at = 0;
    while at < chars.len() {
        let c = chars[at];
        if c.is_whitespace() {
            at += 1;
        } else if starts_with(&chars, at, "//") {
            at = line_end(&chars, at);
        } else if starts_with(&chars, at, "/*") {
            at = block_comment_end(&chars, at);
        } else if let Some(end) = string_end(&chars, at) {
            at = end;
        } else if c == '\'' {
            at = quote_end(&chars, at);
        } else if c.is_ascii_digit() {
            at = number_end(&chars, at);
        } else if c == '_' || c.is_alphabetic() {
            let end = ident_end(&chars, at);
            let word: String = chars[at..end].iter().collect();
            tokens.push(Token::Ident(word.trim_start_matches("r#").to_string()));
            at = end;
        } else if starts_with(&chars, at, "::") {
            tokens.push(Token::PathSep);
            at += 2;
        } else {
            tokens.push(Token::Punct(c));
            at += 1;
        }
    }
    tokens
}

fn starts_with(chars: &[char], at: usize, text: &str) -> bool {
    text.chars().enumerate().all(|(i, t)| chars.get(at + i) == Some(&t))
}

fn line_end(chars: &[char], at: usize) -> usize {
    (at..chars.len()).find(|&i| chars[i] == '\n').unwrap_or(chars.len())
}

/// Block comments nest in Rust.
fn block_comment_end(chars: &[char], mut at: usize) -> usize {
    let mut depth = 0;
    while at < chars.len() {
        if starts_with(chars, at, "/*") {
            depth += 1;
            at += 2;
        } else if starts_with(chars, at, "*/") {
            depth -= 1;
            at += 2;
            if depth == 0 {
                return at;
            }
        } else {
            at += 1;
        }
    }
    at
}

/// The end of a string literal starting at `at` (`"…"`, `b"…"`, `r#"…"#`, `br"…"`, `c"…"`),
/// or `None` when none starts there.
fn string_end(chars: &[char], at: usize) -> Option<usize> {
    let mut i = at;
    if matches!(chars[i], 'b' | 'c') {
        i += 1;
    }
    let raw = chars.get(i) == Some(&'r');
    if raw {
        i += 1;
    }
    let hashes = (i..chars.len()).take_while(|&j| chars[j] == '#').count();
    i += hashes;
    if chars.get(i) != Some(&'"')
        || (!raw && hashes > 0)
        || (i > at && at > 0 && is_ident_char(chars[at - 1]))
    {
        return None;
    }
    i += 1;
    let closing: String = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
    while i < chars.len() {
        if !raw && chars[i] == '\\' {
            i += 2;
        } else if starts_with(chars, i, &closing) {
            return Some(i + closing.len());
        } else {
            i += 1;
        }
    }
    Some(i)
}

/// A character literal (`'a'`, `'\n'`, `'\u{1F600}'`) or a lifetime (`'a`).
fn quote_end(chars: &[char], at: usize) -> usize {
    if chars.get(at + 1) == Some(&'\\') {
        return (at + 2..chars.len()).find(|&i| chars[i] == '\'').map_or(chars.len(), |i| i + 1);
    }
    if chars.get(at + 2) == Some(&'\'') {
        return at + 3;
    }
    ident_end(chars, at + 1)
}

fn number_end(chars: &[char], mut at: usize) -> usize {
    while at < chars.len() {
        let fraction = chars[at] == '.' && chars.get(at + 1).is_some_and(|c| c.is_ascii_digit());
        if !(is_ident_char(chars[at]) || fraction) {
            break;
        }
        at += 1;
    }
    at
}

fn ident_end(chars: &[char], at: usize) -> usize {
    let start = if starts_with(chars, at, "r#") { at + 2 } else { at };
    (start..chars.len()).find(|&i| !is_ident_char(chars[i])).unwrap_or(chars.len())
}

fn is_ident_char(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

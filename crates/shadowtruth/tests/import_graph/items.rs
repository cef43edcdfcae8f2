//! What one source file says about names: the modules it declares, the names it defines at its
//! top level, its `use` trees flattened to paths, and the other paths it writes
//! (`crate::a::B`, `super::c::D`). Items under `#[cfg(test)]` are skipped: tests import their
//! parent module by design.

use crate::tokens::Token;

/// One path a `use` tree brings in: `use a::{b::C as D, e::*}` gives `a::b::C` bound to `D` and
/// the glob `a::e`.
#[derive(Clone, Debug)]
pub struct UsePath {
    pub segments: Vec<String>,
    /// The name it binds in the file; `None` for a glob or `as _`.
    pub binding: Option<String>,
    pub glob: bool,
    pub public: bool,
}

#[derive(Default, Debug)]
pub struct FileItems {
    /// `mod x;` declarations of file modules, without the `#[cfg(test)]` ones.
    pub modules: Vec<String>,
    pub defined: Vec<String>,
    pub uses: Vec<UsePath>,
    /// Paths written outside `use` items, each at least two segments long.
    pub paths: Vec<Vec<String>>,
    /// The name of `extern crate self as NAME;`.
    pub self_alias: Option<String>,
}

const DEFINING_KEYWORDS: [&str; 8] = ["fn", "struct", "enum", "trait", "type", "const", "static", "union"];

pub fn read_items(tokens: &[Token]) -> FileItems {
    let mut items = FileItems::default();
    let mut depth = 0usize;
    let mut at = 0;
    while at < tokens.len() {
        let token = &tokens[at];
        if *token == Token::Punct('#') {
            let (end, is_test) = attribute_end(tokens, at);
            at = if is_test { item_end(tokens, end) } else { end };
            continue;
        }
        match token {
            Token::Punct('{') => depth += 1,
            Token::Punct('}') => depth = depth.saturating_sub(1),
            Token::Ident(word) if word == "use" && !follows_path_sep(tokens, at) => {
                let public = is_public(tokens, at);
                let mut prefix = Vec::new();
                at = read_use_tree(tokens, at + 1, &mut prefix, public, &mut items.uses);
                continue;
            }
            Token::Ident(word) if word == "extern" => read_extern_crate(tokens, at, &mut items),
            Token::Ident(word) if word == "mod" && depth == 0 => read_module(tokens, at, &mut items),
            Token::Ident(word) if depth == 0 && is_defining(tokens, at, word) => {
                let name_at = if word == "macro_rules" { at + 2 } else { at + 1 };
                if let Some(name) = tokens.get(name_at).and_then(Token::ident) {
                    items.defined.push(name.to_string());
                }
            }
            Token::Ident(_) if !follows_path_sep(tokens, at) => {
                let (path, end) = read_path(tokens, at);
                if path.len() > 1 {
                    items.paths.push(path);
                }
                at = end;
                continue;
            }
            _ => {}
        }
        at += 1;
    }
    items
}

fn is_defining(tokens: &[Token], at: usize, word: &str) -> bool {
    let next_is_fn = tokens.get(at + 1).is_some_and(|t| t.is_ident("fn"));
    (DEFINING_KEYWORDS.contains(&word) && !(word == "const" && next_is_fn))
        || (word == "macro_rules" && tokens.get(at + 1) == Some(&Token::Punct('!')))
}

fn follows_path_sep(tokens: &[Token], at: usize) -> bool {
    at > 0 && tokens[at - 1] == Token::PathSep
}

/// `pub use`, `pub(crate) use`, `pub(super) use`.
fn is_public(tokens: &[Token], at: usize) -> bool {
    match at.checked_sub(1).map(|i| &tokens[i]) {
        Some(t) if t.is_ident("pub") => true,
        Some(Token::Punct(')')) => (0..at).rev().take(5).any(|i| tokens[i].is_ident("pub")),
        _ => false,
    }
}

/// Skips `#[…]` or `#![…]`; says whether it was exactly `#[cfg(test)]`.
fn attribute_end(tokens: &[Token], at: usize) -> (usize, bool) {
    let mut open = at + 1;
    if tokens.get(open) == Some(&Token::Punct('!')) {
        open += 1;
    }
    if tokens.get(open) != Some(&Token::Punct('[')) {
        return (at + 1, false);
    }
    let end = balanced_end(tokens, open);
    let inside = &tokens[open + 1..end - 1];
    let cfg_test =
        [Token::Ident("cfg".into()), Token::Punct('('), Token::Ident("test".into()), Token::Punct(')')];
    (end, inside == cfg_test)
}

/// The index after the item starting at `at`, attributes included: its `;` or its body's `}`.
fn item_end(tokens: &[Token], mut at: usize) -> usize {
    let mut nesting = 0usize;
    while at < tokens.len() {
        match tokens[at] {
            Token::Punct('#') if nesting == 0 => {
                at = attribute_end(tokens, at).0;
                continue;
            }
            Token::Punct('(' | '[') => nesting += 1,
            Token::Punct(')' | ']') => nesting = nesting.saturating_sub(1),
            Token::Punct(';') if nesting == 0 => return at + 1,
            Token::Punct('{') if nesting == 0 => return balanced_end(tokens, at),
            _ => {}
        }
        at += 1;
    }
    at
}

/// The index after the bracket that closes the one at `open`.
fn balanced_end(tokens: &[Token], open: usize) -> usize {
    let mut depth = 0usize;
    for (i, token) in tokens.iter().enumerate().skip(open) {
        match token {
            Token::Punct('(' | '[' | '{') => depth += 1,
            Token::Punct(')' | ']' | '}') => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            _ => {}
        }
    }
    tokens.len()
}

fn read_module(tokens: &[Token], at: usize, items: &mut FileItems) {
    let Some(name) = tokens.get(at + 1).and_then(Token::ident) else { return };
    match tokens.get(at + 2) {
        Some(Token::Punct(';')) => items.modules.push(name.to_string()),
        // Inline modules are not followed: the workspace writes none outside tests.
        _ => items.defined.push(name.to_string()),
    }
}

fn read_extern_crate(tokens: &[Token], at: usize, items: &mut FileItems) {
    let words: Vec<Option<&str>> = (at..at + 5).map(|i| tokens.get(i).and_then(Token::ident)).collect();
    if words[1..4] == [Some("crate"), Some("self"), Some("as")] {
        items.self_alias = words[4].map(str::to_string);
    }
}

/// `a::b::c` starting at `at`; stops before anything that is not `:: identifier`.
fn read_path(tokens: &[Token], mut at: usize) -> (Vec<String>, usize) {
    let mut path = vec![tokens[at].ident().unwrap_or_default().to_string()];
    at += 1;
    while tokens.get(at) == Some(&Token::PathSep) {
        match tokens.get(at + 1).and_then(Token::ident) {
            Some(name) => path.push(name.to_string()),
            None => break,
        }
        at += 2;
    }
    (path, at)
}

/// Reads one use tree after `prefix`, pushing its paths; returns the index after it (after the
/// `;` that ends the item, at the top level).
fn read_use_tree(
    tokens: &[Token],
    mut at: usize,
    prefix: &mut Vec<String>,
    public: bool,
    out: &mut Vec<UsePath>,
) -> usize {
    let depth_at_entry = prefix.len();
    if tokens.get(at) == Some(&Token::PathSep) {
        at += 1;
    }
    loop {
        match tokens.get(at) {
            Some(Token::Ident(word))
                if word == "self" && depth_at_entry > 0 && prefix.len() == depth_at_entry =>
            {
                let binding = prefix.last().cloned();
                at = read_rename(tokens, at + 1, binding, prefix.clone(), public, out);
                break;
            }
            Some(Token::Ident(word)) => {
                prefix.push(word.clone());
                if tokens.get(at + 1) == Some(&Token::PathSep) {
                    at += 2;
                    continue;
                }
                at = read_rename(tokens, at + 1, Some(word.clone()), prefix.clone(), public, out);
                break;
            }
            Some(Token::Punct('*')) => {
                out.push(UsePath { segments: prefix.clone(), binding: None, glob: true, public });
                at += 1;
                break;
            }
            Some(Token::Punct('{')) => {
                at += 1;
                while !matches!(tokens.get(at), Some(Token::Punct('}')) | None) {
                    let mut inner = prefix.clone();
                    at = read_use_tree(tokens, at, &mut inner, public, out);
                    if tokens.get(at) == Some(&Token::Punct(',')) {
                        at += 1;
                    }
                }
                at += 1;
                break;
            }
            _ => break,
        }
    }
    prefix.truncate(depth_at_entry);
    if tokens.get(at) == Some(&Token::Punct(';')) {
        at += 1;
    }
    at
}

/// The `as NAME` (or `as _`) after a use path, if any.
fn read_rename(
    tokens: &[Token],
    at: usize,
    binding: Option<String>,
    segments: Vec<String>,
    public: bool,
    out: &mut Vec<UsePath>,
) -> usize {
    let renamed = tokens.get(at).is_some_and(|t| t.is_ident("as"));
    let (binding, end) = match renamed {
        true => (tokens.get(at + 1).and_then(Token::ident).filter(|&n| n != "_").map(str::to_string), at + 2),
        false => (binding, at),
    };
    out.push(UsePath { segments, binding, glob: false, public });
    end
}

//! The one way names become file names. Scene, camera, light and technique names come from
//! untrusted files and may hold anything (`..`, `/`, `\`, an absolute path, nothing, 300
//! characters, NUL, control characters, non-ASCII): none of it may decide where a file goes or
//! fail its write. Every file the tool names after such names is named by [`stem`] (or
//! [`stem_with`]): a readable, filtered and length-capped part, then the digest of the exact
//! names, so that the stem is always one safe path component of bounded length and two
//! identities whose readable parts coincide still get distinct stems.

use sha2::{Digest, Sha256};

/// Hex digits of the identity's digest in every stem: 64 bits, so that two identities sharing a
/// stem is not a practical concern (32 bits collide by chance among some 77 000 names).
pub const DIGEST_HEX_DIGITS: usize = 16;

/// The most characters of a stem's readable part: with the digest and the longest suffix the
/// tool appends (`.error.zoom.png`), a file name stays far below the 255 bytes file systems
/// allow.
pub const MAX_READABLE_CHARS: usize = 160;

/// The stem of the identity `parts`: `<part>.<part>…` filtered by [`readable`] and capped at
/// [`MAX_READABLE_CHARS`], then `.` and [`digest`] of the exact parts.
pub fn stem(parts: &[&str]) -> String {
    let readable_parts: Vec<String> = parts.iter().map(|p| readable(p)).collect();
    stem_with(&readable_parts.join("."), parts)
}

/// As [`stem`] with a readable part of the caller's choosing (filtered and capped the same):
/// the digest alone tells identities apart, so `readable_text` only has to help a reader.
pub fn stem_with(readable_text: &str, parts: &[&str]) -> String {
    let mut text = readable(readable_text);
    // `readable` leaves ASCII only, so every byte index is a character boundary.
    text.truncate(MAX_READABLE_CHARS);
    format!("{text}.{}", digest(parts))
}

/// A file-name-safe rendering of `s`: ASCII letters, digits, `_`, `-` and `.` are kept, `=`
/// becomes `-`, `)` is dropped, anything else (`(`, `,`, `/`, `\`, spaces, NUL, control
/// characters, non-ASCII…) becomes `_`; a leading `.` or `-` becomes `_` (no hidden file, no
/// `..`, no option) and an empty result `_`. Not injective: a stem's digest is what is.
pub fn readable(s: &str) -> String {
    let mut out: String = s
        .chars()
        .filter(|&c| c != ')')
        .map(|c| match c {
            c if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') => c,
            '=' => '-',
            _ => '_',
        })
        .collect();
    if out.starts_with(['.', '-']) {
        out.replace_range(0..1, "_");
    }
    if out.is_empty() {
        out.push('_');
    }
    out
}

/// The first [`DIGEST_HEX_DIGITS`] hex digits of the SHA-256 of `parts`, each prefixed with its
/// length in bytes, so that part boundaries count (`a__b` + `c` differs from `a` + `b__c`).
pub fn digest(parts: &[&str]) -> String {
    let mut hasher = Sha256::new();
    hasher.update((parts.len() as u64).to_le_bytes());
    for part in parts {
        hasher.update((part.len() as u64).to_le_bytes());
        hasher.update(part.as_bytes());
    }
    crate::scene::hex(&hasher.finalize()[..DIGEST_HEX_DIGITS / 2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The most bytes of a stem: its readable part, a `.` and the digest.
    const MAX_STEM_BYTES: usize = MAX_READABLE_CHARS + 1 + DIGEST_HEX_DIGITS;

    /// One path component, not `.`/`..`, no hidden file, only safe bytes, bounded.
    fn assert_safe(s: &str) {
        assert!(s.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.')), "{s:?}");
        assert!(!s.starts_with(['.', '-']) && s.len() <= MAX_STEM_BYTES, "{s:?}");
    }

    #[test]
    fn readable_keeps_names_readable() {
        assert_eq!(readable("constant(bias_depth=0.001)"), "constant_bias_depth-0.001");
        assert_eq!(
            readable("slope_scaled(factor=1.5,units=2,cull=none)"),
            "slope_scaled_factor-1.5_units-2_cull-none"
        );
        assert_eq!(readable("../a b/c"), "_._a_b_c");
        assert_eq!(readable(""), "_");
        assert_eq!(readable("-x"), "_x");
        assert_eq!(readable("a\0b\nc\\d"), "a_b_c_d");
        assert_eq!(readable("Ébène"), "_b_ne");
    }

    #[test]
    fn hostile_names_give_safe_bounded_stems() {
        let long = "x".repeat(300);
        let names = ["..", "../../x", "/tmp-abs", "", ")", "a\0b", "a\nb", "C:\\x", "名前", &long];
        for name in names {
            let s = stem(&[name, name, name]);
            assert_safe(&s);
            assert_eq!(s.len() - s.rfind('.').unwrap() - 1, DIGEST_HEX_DIGITS);
        }
        assert_safe(&stem_with(&long, &[&long]));
    }

    #[test]
    fn part_boundaries_count() {
        assert_ne!(digest(&["a__b", "c"]), digest(&["a", "b__c"]));
        assert_ne!(digest(&["a/b", "c"]), digest(&["a", "b/c"]));
        assert_ne!(digest(&["ab", ""]), digest(&["a", "b"]));
        assert_ne!(digest(&["a"]), digest(&["a", ""]));
        // Same readable part, different identities.
        assert_ne!(stem(&["a b"]), stem(&["a_b"]));
        assert!(stem(&["plane_box", "main", "sun"]).starts_with("plane_box.main.sun."));
        assert_eq!(stem(&["s"]), stem(&["s"]), "stable");
    }
}

//! `data:` URIs of embedded glTF buffers (base64 only) and the percent-decoding of
//! relative file URIs.

/// The bytes of a `data:[<media type>];base64,<data>` URI.
pub(super) fn decode_data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let rest = uri.strip_prefix("data:").ok_or("not a data: URI")?;
    let (header, data) = rest.split_once(',').ok_or("a data: URI needs a comma before its data")?;
    if !header.ends_with(";base64") {
        return Err("only base64 data: URIs are supported".into());
    }
    decode_base64(data)
}

/// Standard base64 (alphabet `A–Z a–z 0–9 + /`), padding optional.
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let digits = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(digits.len() / 4 * 3 + 3);
    let (mut acc, mut bits) = (0u32, 0u32);
    for (i, &c) in digits.iter().enumerate() {
        let value = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return Err(format!("invalid base64 character at offset {i}")),
        };
        acc = (acc << 6) | value as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

/// A relative URI's path with `%XX` escapes decoded (glTF URIs are percent-encoded).
pub(super) fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = uri.get(i + 1..i + 3).and_then(|h| u8::from_str_radix(h, 16).ok());
            out.push(hex.ok_or_else(|| format!("bad percent escape at offset {i}"))?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "the decoded URI is not UTF-8".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_percent_escapes_decode() {
        assert_eq!(
            decode_data_uri("data:application/octet-stream;base64,AAECAw==").unwrap(),
            vec![0, 1, 2, 3]
        );
        assert_eq!(decode_data_uri("data:application/gltf-buffer;base64,/+8").unwrap(), vec![0xFF, 0xEF]);
        assert!(decode_data_uri("data:text/plain,hello").is_err());
        assert!(decode_data_uri("data:;base64,AA*A").is_err());
        assert_eq!(percent_decode("my%20mesh.bin").unwrap(), "my mesh.bin");
        assert!(percent_decode("a%2").is_err());
    }
}

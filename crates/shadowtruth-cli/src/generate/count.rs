//! Triangle counts on the command line: `250000`, `250K`, `10M` (K = 10³, M = 10⁶).

use super::request::MIN_TRIANGLES;
use shadowtruth::scene::IndexedMesh;

/// The most triangles a generated scene may number: what a scene may place with its instances
/// (src/scene/format.rs); without instancing it may hold no more than `MAX_SCENE_TRIANGLES`.
const MAX_TRIANGLES: u64 = shadowtruth::scene::MAX_INSTANCED_TRIANGLES;

/// Parses a triangle count with an optional K or M suffix (decimals allowed with a suffix).
pub(crate) fn parse_triangle_count(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let (number, scale) = match trimmed.char_indices().last() {
        Some((i, 'k' | 'K')) => (&trimmed[..i], 1e3),
        Some((i, 'm' | 'M')) => (&trimmed[..i], 1e6),
        _ => (trimmed, 1.0),
    };
    let value: f64 =
        number.parse().map_err(|_| format!("'{text}' is not a count such as 500000, 250K or 10M"))?;
    let count = (value * scale).round();
    if !count.is_finite() || count < MIN_TRIANGLES as f64 || count > MAX_TRIANGLES as f64 {
        return Err(format!("'{text}': the count must be between {MIN_TRIANGLES} and {MAX_TRIANGLES}"));
    }
    Ok(count as u64)
}

/// Appends `part` to `mesh`, its indices shifted past the vertices already there.
pub(super) fn append_mesh(mesh: &mut IndexedMesh, part: &IndexedMesh) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend_from_slice(&part.positions);
    mesh.triangles.extend(part.triangles.iter().map(|t| t.map(|i| base + i)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generate_counts_take_k_and_m_suffixes() {
        assert_eq!(parse_triangle_count("10M"), Ok(10_000_000));
        assert_eq!(parse_triangle_count("250k"), Ok(250_000));
        assert_eq!(parse_triangle_count("1.5M"), Ok(1_500_000));
        assert_eq!(parse_triangle_count("5000"), Ok(5000));
        assert!(parse_triangle_count("10G").is_err());
        assert_eq!(parse_triangle_count("100M"), Ok(100_000_000));
        assert!(parse_triangle_count("2148M").is_err());
        assert!(parse_triangle_count("10").is_err());
    }
}

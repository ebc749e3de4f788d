//! The one colour table of element types, shared by the figures (`plot`) and the glTF
//! animation (`output::gltf`), so a slab is the same blue in both; and the colours of the
//! voids' collapse patterns, shared by the void figures, the report and the glTF.
//!
//! Colours are sRGB, 8 bits per channel. Known types have fixed colours; any other type
//! name gets one of a fixed palette chosen by an FNV-1a hash of the name, so the same name
//! always gets the same colour.

/// The known element types, in legend order.
pub const KNOWN_TYPES: [&str; 6] = ["Column", "Beam", "Slab", "Wall", "Foundation", "Ground"];

/// sRGB colour of an element type (or of `Ground`, the glTF ground box).
pub(crate) fn type_srgb(type_name: &str) -> [u8; 3] {
    match type_name {
        "Column" => [192, 57, 43],
        "Beam" => [240, 160, 20],
        "Slab" => [90, 130, 190],
        "Wall" => [140, 110, 70],
        "Foundation" => [120, 120, 120],
        "Ground" => [149, 162, 139],
        other => {
            const PALETTE: [[u8; 3]; 5] = [
                [80, 160, 80],
                [150, 90, 170],
                [40, 160, 160],
                [200, 100, 140],
                [160, 160, 50],
            ];
            let h = other.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
            });
            PALETTE[(h % PALETTE.len() as u64) as usize]
        }
    }
}

/// sRGB colour of a void's collapse pattern (Okabe–Ito colours, distinguishable with
/// common colour vision deficiencies); black for a name not listed.
pub fn pattern_srgb(pattern: &str) -> [u8; 3] {
    match pattern {
        "pancake" => [0, 114, 178],
        "supported-lean-to" => [230, 159, 0],
        "unsupported-lean-to" => [213, 94, 0],
        "v" => [0, 158, 115],
        "a-frame" => [204, 121, 167],
        "cantilever" => [86, 180, 233],
        "debris" => [120, 120, 120],
        _ => [0, 0, 0],
    }
}

/// Linear-light RGB (0..1) of an sRGB colour, as glTF's `baseColorFactor` wants it
/// (IEC 61966-2-1: c ≤ 0.04045 → c/12.92, else ((c + 0.055)/1.055)^2.4).
pub(crate) fn srgb_to_linear(c: [u8; 3]) -> [f32; 3] {
    c.map(|v| {
        let c = f64::from(v) / 255.0;
        let l = if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        };
        l as f32
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_types_are_distinct_and_unknown_names_stable() {
        for (i, a) in KNOWN_TYPES.iter().enumerate() {
            for b in &KNOWN_TYPES[i + 1..] {
                assert_ne!(type_srgb(a), type_srgb(b), "{a} and {b}");
            }
        }
        assert_eq!(type_srgb("Zeta"), type_srgb("Zeta"));
    }

    #[test]
    fn srgb_to_linear_matches_the_standard_at_known_points() {
        // IEC 61966-2-1: 0 → 0, 255 → 1, sRGB 0.5 (≈ 128) → 0.2158605.
        assert_eq!(srgb_to_linear([0, 255, 0]), [0.0, 1.0, 0.0]);
        let mid = srgb_to_linear([128, 128, 128])[0];
        assert!((f64::from(mid) - 0.215_860_5).abs() < 1e-6, "{mid}");
    }
}

//! Base64 (RFC 4648 §4, standard alphabet, `=` padding) of the binary arrays the report
//! page decodes with the browser's `atob`: float32, and the 16-bit codes of the poses.

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// The base64 text of `bytes`.
pub fn encode(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The base64 text of `values` as little-endian IEEE 754 binary32 (JavaScript's
/// `Float32Array` on every platform a browser runs on).
pub fn encode_f32(values: &[f32]) -> String {
    let mut bytes = Vec::with_capacity(values.len() * 4);
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    encode(&bytes)
}

/// The base64 text of `values` as little-endian unsigned 16-bit integers (`Uint16Array`).
pub fn encode_u16(values: &[u16]) -> String {
    encode(
        &values
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<u8>>(),
    )
}

/// The base64 text of `values` as little-endian two's-complement 16-bit integers
/// (`Int16Array`).
pub fn encode_i16(values: &[i16]) -> String {
    encode(
        &values
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<u8>>(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rfc_4648_test_vectors() {
        // RFC 4648 §10.
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, coded) in cases {
            assert_eq!(encode(plain.as_bytes()), coded, "{plain:?}");
        }
    }

    #[test]
    fn floats_are_little_endian_binary32() {
        // 1.0f32 = 0x3F800000 → bytes 00 00 80 3F → "AACAPw=="; -2.5 = 0xC0200000.
        assert_eq!(encode_f32(&[1.0]), "AACAPw==");
        assert_eq!(encode_f32(&[-2.5]), encode(&[0x00, 0x00, 0x20, 0xC0]));
        // All 256 byte values survive (every alphabet character used).
        let all: Vec<u8> = (0..=255).collect();
        let text = encode(&all);
        assert_eq!(text.len(), 344);
        assert!(text.ends_with("+/w=="), "{text}");
    }

    #[test]
    fn integers_are_little_endian_16_bit() {
        // 0x1234 → bytes 34 12; -2 = 0xFFFE → bytes FE FF.
        assert_eq!(
            encode_u16(&[0x1234, 65_535]),
            encode(&[0x34, 0x12, 0xFF, 0xFF])
        );
        assert_eq!(encode_i16(&[-2, 1]), encode(&[0xFE, 0xFF, 0x01, 0x00]));
    }
}

//! Finds the line on which each element of a top-level JSON array starts, so that errors
//! about a body or constraint can name its line (serde's typed parse keeps no positions).

/// Where the elements of a top-level array start, and where the array ends.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ArrayLines {
    /// 1-based line on which each element starts.
    pub starts: Vec<usize>,
    /// 1-based line of the closing `]` (0 if not found).
    pub end: usize,
}

impl ArrayLines {
    /// The index of the element that contains `line`, if any.
    pub fn element_at(&self, line: usize) -> Option<usize> {
        let i = self.starts.iter().rposition(|&l| l <= line)?;
        let next = self.starts.get(i + 1).copied().unwrap_or(self.end);
        (line < next || (i + 1 == self.starts.len() && line <= self.end)).then_some(i)
    }
}

/// The lines of the elements of the array under the top-level key `key`.
/// Returns no elements if the key is not found or the text is not the expected shape.
pub(crate) fn array_element_lines(text: &str, key: &str) -> ArrayLines {
    let bytes = text.as_bytes();
    let mut line = 1usize;
    let mut depth = 0i32; // nesting of {} and []
    let mut i = 0usize;
    // State for the array we are collecting from.
    let mut collecting = false;
    let mut array_depth = 0i32;
    let mut expect_key_value = false; // the last string at depth 1 was our key
    let mut out = ArrayLines::default();
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'\n' => line += 1,
            b'"' => {
                // Read the string (handling escapes).
                let start = i + 1;
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    if bytes[i] == b'\\' {
                        i += 1;
                    } else if bytes[i] == b'\n' {
                        line += 1;
                    }
                    i += 1;
                }
                let s = &text[start..i.min(text.len())];
                if collecting && depth == array_depth {
                    out.starts.push(line);
                }
                expect_key_value = depth == 1 && !collecting && s == key;
            }
            b'{' | b'[' => {
                if collecting && depth == array_depth {
                    out.starts.push(line);
                }
                depth += 1;
                if c == b'[' && expect_key_value && depth == 2 {
                    collecting = true;
                    array_depth = depth;
                }
                expect_key_value = false;
            }
            b'}' | b']' => {
                if collecting && depth == array_depth {
                    out.end = line;
                    return out;
                }
                depth -= 1;
            }
            b':' | b' ' | b'\t' | b'\r' => {}
            _ => {
                if collecting && depth == array_depth && c != b',' {
                    // A scalar element: record its line once (at its first byte).
                    let prev = if i > 0 { bytes[i - 1] } else { b',' };
                    if matches!(prev, b',' | b'[' | b' ' | b'\n' | b'\t' | b'\r') {
                        out.starts.push(line);
                    }
                }
                if c == b',' {
                    expect_key_value = false;
                }
            }
        }
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_element_lines() {
        let text = "{\n \"x\": {\"bodies\": [1]},\n \"bodies\": [\n  {\"name\": \"a\",\n   \"v\": [1, 2]},\n  {\"name\": \"b\"}\n ]\n}\n";
        let b = array_element_lines(text, "bodies");
        assert_eq!(b.starts, vec![4, 6]);
        assert_eq!(b.end, 7);
        assert_eq!(b.element_at(5), Some(0));
        assert_eq!(b.element_at(6), Some(1));
        assert_eq!(b.element_at(7), Some(1));
        assert_eq!(b.element_at(8), None);
        assert_eq!(b.element_at(2), None);
        assert!(array_element_lines(text, "constraints").starts.is_empty());
    }
}

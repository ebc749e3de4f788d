//! Where each item of a model file starts: (top-level key, array index) → line (1-based).
//! Used to put line numbers on semantic (validation) errors.
use std::collections::BTreeMap;

/// Line numbers of the items of the top-level arrays and of the top-level keys.
#[derive(Debug, Default, Clone)]
pub(crate) struct SourceMap {
    items: BTreeMap<(String, usize), usize>,
    keys: BTreeMap<String, usize>,
}

/// 1-based line of byte offset `pos` in `text`.
pub fn line_of(text: &str, pos: usize) -> usize {
    let pos = pos.min(text.len());
    text.as_bytes()[..pos]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The byte offsets of the line breaks of a text: the line of any offset in O(log n), so
/// that mapping the n items of a large file costs n log n, not n² ([`line_of`] scans).
struct LineBreaks(Vec<usize>);

impl LineBreaks {
    fn new(text: &str) -> LineBreaks {
        LineBreaks(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i)
                .collect(),
        )
    }

    /// 1-based line of byte offset `pos`, as [`line_of`].
    fn line(&self, pos: usize) -> usize {
        self.0.partition_point(|&b| b < pos) + 1
    }
}

impl SourceMap {
    /// How many items top-level array `key` has.
    pub fn item_count(&self, key: &str) -> usize {
        self.items
            .range((key.to_string(), 0)..=(key.to_string(), usize::MAX))
            .count()
    }

    /// Line of item `index` of top-level array `key`.
    pub fn item_line(&self, key: &str, index: usize) -> Option<usize> {
        self.items.get(&(key.to_string(), index)).copied()
    }

    /// Line of top-level key `key`.
    pub fn key_line(&self, key: &str) -> Option<usize> {
        self.keys.get(key).copied()
    }

    /// The item (key, index) whose start is the last one at or before `line`.
    pub fn item_at(&self, line: usize) -> Option<(String, usize)> {
        self.items
            .iter()
            .filter(|(_, &l)| l <= line)
            .max_by_key(|(_, &l)| l)
            .map(|((k, i), _)| (k.clone(), *i))
    }

    /// Builds the map from TOML text (empty if the text does not parse).
    pub fn from_toml(text: &str) -> SourceMap {
        let mut map = SourceMap::default();
        let Ok(root) = toml::de::DeTable::parse(text) else {
            return map;
        };
        let lines = LineBreaks::new(text);
        for (key, value) in root.get_ref().iter() {
            let name = key.get_ref().to_string();
            map.keys.insert(name.clone(), lines.line(key.span().start));
            if let toml::de::DeValue::Array(items) = value.get_ref() {
                for (i, item) in items.iter().enumerate() {
                    map.items
                        .insert((name.clone(), i), lines.line(item.span().start));
                }
            }
        }
        map
    }

    /// Builds the map from JSON text by a small scan of the root object's arrays.
    pub fn from_json(text: &str) -> SourceMap {
        let mut map = SourceMap::default();
        let b = text.as_bytes();
        let (mut i, mut line, mut depth) = (0usize, 1usize, 0usize);
        let mut last_string = String::new();
        let mut key = String::new();
        let mut in_array = false; // inside an array that is a root member
        let mut expect_item = false;
        let mut index = 0usize;
        while i < b.len() {
            let c = b[i];
            if in_array && depth == 2 && expect_item && !c.is_ascii_whitespace() && c != b']' {
                map.items.insert((key.clone(), index), line);
                index += 1;
                expect_item = false;
            }
            match c {
                b'\n' => line += 1,
                b'"' => {
                    let start = i + 1;
                    i += 1;
                    while i < b.len() && b[i] != b'"' {
                        if b[i] == b'\\' {
                            i += 1;
                        }
                        i += 1;
                    }
                    last_string = String::from_utf8_lossy(&b[start..i.min(b.len())]).into_owned();
                }
                b':' if depth == 1 => {
                    key = last_string.clone();
                    map.keys.insert(key.clone(), line);
                }
                b'{' | b'[' => {
                    depth += 1;
                    if depth == 2 && c == b'[' {
                        in_array = true;
                        expect_item = true;
                        index = 0;
                    }
                }
                b'}' | b']' => {
                    if depth == 2 {
                        in_array = false;
                    }
                    depth = depth.saturating_sub(1);
                }
                b',' if in_array && depth == 2 => expect_item = true,
                _ => {}
            }
            i += 1;
        }
        map
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_and_json_items_get_their_lines() {
        let t = "name = \"a\"\nnode = [\n  { tag = 1, x = 0.0, y = 0.0, z = 0.0 },\n  { tag = 2, x = 1.0, y = 0.0, z = 0.0 },\n]\n\n[[element]]\ntag = 3\n";
        let m = SourceMap::from_toml(t);
        assert_eq!(m.item_line("node", 0), Some(3));
        assert_eq!(m.item_line("node", 1), Some(4));
        assert!(matches!(m.item_line("element", 0), Some(7) | Some(8)));
        let j = "{\n \"name\": \"a\",\n \"node\": [\n  {\"tag\": 1},\n  {\"tag\": 2,\n \"x\": [1, 2]}\n ]\n}";
        let m = SourceMap::from_json(j);
        assert_eq!(m.item_line("node", 0), Some(4));
        assert_eq!(m.item_line("node", 1), Some(5));
        assert_eq!(m.item_line("node", 2), None);
        assert_eq!(m.key_line("name"), Some(2));
    }
}

//! CSV fields as RFC 4180 writes them, for every table fem2rbd writes (`bodies.csv`,
//! `ruins.csv`, `keyframes.csv`, `connections.csv`, the mapping table, the scene poses).
//!
//! A field holding a comma, a double quote, a carriage return or a line feed is written
//! in double quotes with each quote doubled; any other field as it is (so tables of
//! ordinary names are byte-for-byte what they were). The run folder is read back with
//! the `csv` crate ([`crate::output::run_folder`]), which undoes exactly this quoting:
//! a body named `Col,umn` or `a "b"` round-trips.
use std::borrow::Cow;

/// The field `s` as written in a CSV row (module docs).
pub fn field(s: &str) -> Cow<'_, str> {
    if s.contains([',', '"', '\n', '\r']) {
        Cow::Owned(format!("\"{}\"", s.replace('"', "\"\"")))
    } else {
        Cow::Borrowed(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_fields_round_trip_through_the_csv_reader() {
        let names = [
            "plain",
            "Col,umn",
            "a \"b\"",
            "two\nlines",
            "cr\r",
            "",
            "\"",
            ",",
        ];
        let line: Vec<String> = names.iter().map(|n| field(n).into_owned()).collect();
        let text = line.join(",") + "\n";
        let mut r = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(text.as_bytes());
        let rec = r.records().next().unwrap().unwrap();
        let back: Vec<&str> = rec.iter().collect();
        assert_eq!(back, names);
        assert!(matches!(field("plain"), Cow::Borrowed("plain")));
    }
}

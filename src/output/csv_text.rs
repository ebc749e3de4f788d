//! CSV fields as RFC 4180 writes them, for every table fem2rbd writes (`bodies.csv`,
//! `ruins.csv`, `keyframes.csv`, `connections.csv`, the mapping table, the scene poses).
//!
//! A field holding a comma, a double quote, a carriage return or a line feed is written
//! in double quotes with each quote doubled; any other field as it is (so tables of
//! ordinary names are byte-for-byte what they were). The run folder is read back with
//! the `csv` crate ([`crate::output::run_folder`]), which undoes exactly this quoting:
//! a body named `Col,umn` or `a "b"` round-trips.
//!
//! The numbers of the structural tables (`nodes.csv` and `reactions.csv` of `fem2rbd fe`,
//! `capacity.csv` and `reactions.csv` of `fem2rbd pushover`) are written by [`number`] with
//! 17 significant digits: each reads back to the same f64, so no difference between two
//! runs or two programs is hidden by the output.
use std::borrow::Cow;

/// A number of the structural tables: 17 significant digits in scientific notation
/// (`-1.2345678901234567e-3`), which parses back to the same f64.
pub fn number(x: f64) -> String {
    format!("{x:.16e}")
}

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
    fn numbers_read_back_to_the_same_f64_and_one_ulp_shows() {
        for x in [
            0.1 + 0.2,
            -1.740_212_345_678_9e-3,
            1e-10 + 1e-25,
            f64::MIN_POSITIVE,
            f64::MAX,
            -0.0,
            2.0,
        ] {
            let text = number(x);
            assert_eq!(
                text.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{text}"
            );
        }
        // 1 + 2^-52 differs from 1 in the 17th significant digit
        let next = f64::from_bits(1.0f64.to_bits() + 1);
        assert_eq!(number(1.0), "1.0000000000000000e0");
        assert_eq!(number(next), "1.0000000000000002e0");
    }

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

//! The building model: file format (serde, TOML/JSON), validation, generator. (Issue 3.)

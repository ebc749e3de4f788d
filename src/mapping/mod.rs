//! Geometry mapping: FE elements → rigid boxes, overlap removal, mass mapping. (Issue 3.)

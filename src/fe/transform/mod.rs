//! Geometric transformations: linear, P-Delta, 3D corotational.

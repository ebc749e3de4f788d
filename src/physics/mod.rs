//! The one safe wrapper over `bullet-sys`: a `World` owning bodies and constraints in arenas addressed by typed handles. (Issue 2.)

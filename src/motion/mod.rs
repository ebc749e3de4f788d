//! Ground motions: PEER AT2 / two-column / BCB CSV readers, scaling, integration. (Issue 3.)

//! Exports of the model to other programs (openseespy). (Issue 3.)

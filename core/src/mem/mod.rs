//! Caller memory: the arena that carves typed slices out of one caller
//! block, and the exact size queries that replay it.
//!
//! Layer 1: imports only `error`.

pub mod arena;

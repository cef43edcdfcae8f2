//! Scenes that reproduce the test scenes of published shadow-mapping papers, generated from a
//! seed so that they can be rebuilt bit for bit.

pub mod island;

pub use island::*;

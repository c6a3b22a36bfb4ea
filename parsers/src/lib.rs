#![forbid(unsafe_code)]

pub mod deck;
pub mod uff;

pub mod deck;
pub mod uff;

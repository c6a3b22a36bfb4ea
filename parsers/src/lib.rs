pub mod uff;
pub mod deck;

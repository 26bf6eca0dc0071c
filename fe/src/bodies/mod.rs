//! Parametric FE models. So far the closed-form check decks; the tub, drum and cabinet follow.

pub mod balance;
pub mod drum;
pub mod geometry;
pub mod test_decks;
pub mod tub;

//! Parametric FE models. So far the closed-form check decks; the tub, drum and cabinet follow.

pub mod test_decks;

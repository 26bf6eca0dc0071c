//! The built-in FE models: parametric decks of the tub, the drum and the cabinet.

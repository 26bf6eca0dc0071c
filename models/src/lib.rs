//! Built-in machine models.

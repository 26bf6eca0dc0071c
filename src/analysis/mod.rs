//! Run-up analysis: order plots, cascades and speed plots from sensor signals.

//! Cross-method tests on the problems in `problems/`. Every expected value comes from a closed
//! form, a published reference, or theory (convergence orders); none from our own output.

//! The integration tests as one binary, each file a module: one link instead of one per
//! file, and every file's tests scheduled together on the machine's cores (cargo runs test
//! binaries one after the other, so a binary waiting on a single-threaded ccx left the other
//! core idle). The package sets `autotests = false`: a new file is added here, and
//! tests/tidy.rs fails when one is not.

mod common;

mod bodies;
mod cabinet;
mod closed_forms;
mod drum;
mod free_body;
mod modal_import;
mod rotating;
mod steady_state;

//! The integration tests as one binary, each file a module: one link instead of one per
//! file, and every file's tests scheduled together on the machine's cores (cargo runs test
//! binaries one after the other, so a binary waiting on a single-threaded ccx left the other
//! core idle). The package sets `autotests = false`: a new file is added here, and
//! tests/tidy.rs fails when one is not.
//! washdyn-fe's tests are here too (`fe_*.rs`): their ccx solves overlap the others'.
//! tests/no_alloc.rs stays a binary of its own: it counts allocations through its global
//! allocator, which other tests' threads would disturb.

mod common;

mod analysis_orders;
mod analysis_plots;
mod analysis_read;
mod backend_agreement;
mod bad_input;
mod bad_modal_input;
mod bare_tub;
mod characteristic_curves;
mod compare;
mod compare_speed;
mod contact;
mod counterweights;
mod damper_mass;
mod elastic_cabinet;
mod elastic_machine;
mod energy;
mod exit_codes;
mod failed_run;
mod fe_bodies;
mod fe_cabinet;
mod fe_closed_forms;
mod fe_correction_order;
mod fe_curves;
mod fe_drum;
mod fe_free_body;
mod fe_modal_import;
mod fe_rotating;
mod fe_steady_state;
mod fields;
mod free_parameters;
mod full_mesh;
mod gasket;
mod half_wave;
mod hard_cases;
mod installed_binary;
mod jacobians;
mod measured;
mod model_files;
mod parquet_roundtrip;
mod presliding;
mod rigid_physics;
mod run_dir;
mod simulation;
mod slurm;
mod starts_and_sensors;
mod study;
mod study_sobol;
mod suspension_modes;
mod sweep;
mod tidy;
mod truncation;
mod tutorial;
mod uff58;
mod unbalance_response;
mod user_deck;
mod user_spinning;
mod validation_e2e;
mod validity_watch;

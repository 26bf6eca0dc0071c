//! The bounds and tolerances of the modal data's rules (`rules.rs`): what any washing-machine
//! part's data must be, each constant with its reason.

/// Relative tolerance of the stored participation against the point's shapes (both come from
/// the same rigid fit, so they agree to round-off).
pub const PARTICIPATION_TOLERANCE: f64 = 1e-6;

/// Mass-normalisation tolerance of the checker: a sanity check (the consistent mass gives
/// ~1e-4 on the built-in bodies; HRZ lumping gave a few per cent and grew with the modes).
pub const MASS_NORMALISATION_TOLERANCE: f64 = 0.05;

/// How far a mode's support strain energy share may exceed 1: the shapes' print precision
/// (ccx's `.frd`, 6 digits) with margin.
pub const SUPPORT_ENERGY_TOLERANCE: f64 = 1e-3;

/// Plausible mass of one elastic part of a washing machine, kg: the parts weigh kilograms to
/// tens of kilograms (the committed drum 9.5 kg, cabinet 29 kg, tub 44 kg). A gram or ten
/// tonnes is a unit slip (g or t for kg) or a broken deck, and 1e308 kg overflows the sums.
pub const MASS_RANGE: (f64, f64) = (1e-3, 1e4);

/// Elastic eigenfrequencies, Hz. Below 0.1 Hz a "mode" is a rigid-body motion left in (the
/// multibody's own DOF; the committed data start at 26 Hz); above 1 MHz no structural mode of
/// an appliance (the committed correction modes reach 6.6 kHz), and (2 pi f)^2 of 1e308
/// overflows.
pub const FREQUENCY_RANGE: (f64, f64) = (0.1, 1e6);

/// Largest distance of a CoG, point or axis point from the machine frame's origin, m: a washing
/// machine is under 1 m in each direction (the committed points within 0.91 m); 10 m still
/// refuses a position in mm read as m.
pub const MAX_EXTENT: f64 = 10.0;

/// Largest translation of a point per unit modal coordinate, m kg^-1/2. A mass-normalised mode
/// moves a node of mass dm by at most 1/sqrt(dm) (its share of the unit modal mass), and a
/// point is a rigid fit of nodes; 1e3 is a node of 1 mg, far below any node of a sheet-metal
/// or plastic mesh (the committed data: 1.7 at most).
pub const MAX_W: f64 = 1e3;

/// Largest rotation of a point per unit modal coordinate, rad kg^-1/2: `MAX_W` across a node
/// set 1 mm wide (the committed data: 29 at most).
pub const MAX_PHI: f64 = 1e6;

/// Largest entry of K_G / Omega^2 (mass-normalised modes, so dimensionless): the stress
/// stiffening of a ring's mode with n waves is of the order n^2; 1e4 is n = 100, beyond any
/// mode a drum's data keep (the committed drum: 7.8; its spin softening at most 0.71).
pub const MAX_PER_OMEGA2: f64 = 1e4;

/// Stiffest support spring, N/m: a washing machine's feet are 1e5-1e6 N/m (the committed
/// cabinet's 4e5 and 2e6); 1e10 N/m is a rigid support, a body clamped rather than on springs.
pub const MAX_SUPPORT_STIFFNESS: f64 = 1e10;

/// How far a direction given as a unit vector may be from unit length.
pub const UNIT_TOLERANCE: f64 = 1e-9;

/// Relative round-off allowed in the identities of a Gram matrix (symmetry, Cauchy-Schwarz):
/// the committed data hold them to 1e-15.
pub const GRAM_TOLERANCE: f64 = 1e-6;

/// Margin on the Cauchy-Schwarz bounds of `c` and `s` against the mass properties (both are
/// formed with the one consistent mass matrix, so the bounds hold exactly; the committed data
/// reach 0.99 of them); the margin allows a user's data whose mass properties come from another
/// integration of the same body.
pub const MOMENT_BOUND_MARGIN: f64 = 1.1;

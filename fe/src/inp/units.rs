//! The deck's unit system (SI or mm-t-s) and the conversion of a mesh into it. Separate from
//! the reader (`mod.rs`) as the one place the factors to SI are stated, used both ways: read
//! into SI (`read`) and written out of it (`in_units`, for the tests and the tutorial).

use crate::mesh::{Material, Mesh, Section};

/// The deck's consistent unit system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
pub enum Units {
    /// m, kg, s, N, Pa.
    #[serde(rename = "SI")]
    Si,
    /// mm, t, s, N, MPa (density t/mm^3, springs N/mm).
    #[serde(rename = "mm-t-s")]
    MmTS,
}

impl Units {
    /// Factors to SI: (length, mass, stress, density, stiffness N/m).
    pub(super) fn factors(self) -> (f64, f64, f64, f64, f64) {
        match self {
            Units::Si => (1.0, 1.0, 1.0, 1.0, 1.0),
            Units::MmTS => (1e-3, 1e3, 1e6, 1e12, 1e3),
        }
    }
}

/// `mesh` (SI) with every number in `units`: what a deck in those units holds (a user's
/// deck in mm-t-s is written this way in the tests and the tutorial).
pub fn in_units(mesh: &Mesh, units: Units) -> Mesh {
    let (fl, fm, fs, frho, fk) = units.factors();
    let mut m = mesh.clone();
    for p in &mut m.nodes {
        *p = p.map(|c| c / fl);
    }
    let scale = |mat: &mut Material| {
        mat.e /= fs;
        mat.rho /= frho;
    };
    for part in &mut m.parts {
        match &mut part.section {
            Section::Shell {
                thickness,
                material,
            } => {
                *thickness /= fl;
                scale(material);
            }
            Section::Solid { material } | Section::ReducedSolid { material } => scale(material),
            Section::Beam {
                width,
                height,
                material,
                ..
            } => {
                *width /= fl;
                *height /= fl;
                scale(material);
            }
            Section::Mass { kg } => *kg /= fm,
            Section::Ground { k, .. } => *k /= fk,
        }
    }
    m
}

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
    /// Every unit system a spec may name, for the advice on a deck read in the wrong one.
    pub const ALL: [Units; 2] = [Units::Si, Units::MmTS];

    /// The name a spec writes (`units = "..."`).
    pub fn name(self) -> &'static str {
        match self {
            Units::Si => "SI",
            Units::MmTS => "mm-t-s",
        }
    }

    /// (length, mass) factors to SI: a deck's mass read in these units is its number times
    /// the mass factor (density times volume scales alike, `consistent_mass_scaling` below),
    /// its positions times the length factor.
    pub fn length_and_mass(self) -> (f64, f64) {
        let (fl, fm, ..) = self.factors();
        (fl, fm)
    }

    /// Factors to SI: (length, mass, stress, density, stiffness N/m).
    pub(super) fn factors(self) -> (f64, f64, f64, f64, f64) {
        match self {
            Units::Si => (1.0, 1.0, 1.0, 1.0, 1.0),
            Units::MmTS => (1e-3, 1e3, 1e6, 1e12, 1e3),
        }
    }
}

impl std::fmt::Display for Units {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
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

#[cfg(test)]
mod tests {
    use super::Units;

    /// An element's mass (density x length^3: solids, shells' area x thickness, beams'
    /// section x length) scales as a point mass does, so one factor converts a deck's whole
    /// mass from one unit system to another (`user::check`'s advice).
    #[test]
    fn consistent_mass_scaling() {
        for u in Units::ALL {
            let (fl, fm, _, frho, _) = u.factors();
            assert!((fl.powi(3) * frho / fm - 1.0).abs() < 1e-12, "{u}");
        }
    }
}

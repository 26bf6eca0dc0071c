//! ccx's committed answer for the full-mesh reference, tied to the deck it solved.

use crate::error::FileError;
use crate::error::fe::FullMeshError;
use nalgebra::Complex;
use serde::{Deserialize, Serialize};
use std::path::Path;
use washdyn_fe::assembly::Solution;
use washdyn_model::ir::files::content_hash;

/// ccx's answer for one assembled deck, as `washdyn fe reference` commits it: the 200-mode
/// solve takes 15 to 20 min on 2 cores, too long for every test run, and the deck's hash ties
/// the answer to what the code and the model write now (a changed mesh, model or deck writer
/// refuses it instead of comparing with a stale reference).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CcxReference {
    /// `ccx -v` of the solve.
    pub ccx_version: String,
    /// FNV-1a 64 of the deck's text (`ir::files::content_hash`).
    pub deck_fnv1a64: String,
    pub modes: usize,
    pub wall_s: f64,
    /// ccx's total mass (EMAS plus the point masses), kg.
    pub mass: Option<f64>,
    /// The assembled machine's eigenfrequencies, Hz.
    pub frequencies: Vec<f64>,
    pub rpm: Vec<f64>,
    /// Per speed, every channel's complex amplitude as [re, im] (`Solution::channels`).
    pub channels: Vec<Vec<[f64; 2]>>,
}

impl CcxReference {
    pub(super) fn of(s: &Solution, deck: &str, modes: usize) -> CcxReference {
        CcxReference {
            ccx_version: washdyn_fe::ccx::version().unwrap_or_default(),
            deck_fnv1a64: content_hash(deck.as_bytes()),
            modes,
            wall_s: s.wall_s,
            mass: s.mass,
            frequencies: s.frequencies.clone(),
            rpm: s.rpm.clone(),
            channels: s
                .channels
                .iter()
                .map(|c| c.iter().map(|z| [z.re, z.im]).collect())
                .collect(),
        }
    }

    /// The committed answer in `path` for this deck (`channels` per speed), or why it does
    /// not fit.
    pub fn read(
        path: &Path,
        deck: &str,
        modes: usize,
        rpm: &[f64],
        channels: usize,
    ) -> Result<Solution, FullMeshError> {
        let path_buf = || path.to_path_buf();
        let text = std::fs::read_to_string(path).map_err(FileError::at::<FullMeshError>(path))?;
        let r: CcxReference =
            serde_json::from_str(&text).map_err(|source| FullMeshError::Json {
                path: path_buf(),
                source,
            })?;
        let hash = content_hash(deck.as_bytes());
        if r.deck_fnv1a64 != hash {
            return Err(FullMeshError::OtherDeck {
                path: path_buf(),
                committed: r.deck_fnv1a64,
                now: hash,
                modes,
            });
        }
        if r.modes != modes || r.rpm != rpm {
            return Err(FullMeshError::OtherSettings {
                path: path_buf(),
                found_modes: r.modes,
                found_rpm: r.rpm,
                modes,
                rpm: rpm.to_vec(),
            });
        }
        // The hash fixes the sensors, so this fails only for an edited file; the study indexes
        // every channel.
        if r.channels.len() != rpm.len() || r.channels.iter().any(|c| c.len() != channels) {
            return Err(FullMeshError::Channels {
                path: path_buf(),
                speeds: rpm.len(),
                channels,
                modes,
            });
        }
        Ok(Solution {
            frequencies: r.frequencies,
            rpm: r.rpm,
            channels: r
                .channels
                .iter()
                .map(|c| c.iter().map(|z| Complex::new(z[0], z[1])).collect())
                .collect(),
            mass: r.mass,
            wall_s: r.wall_s,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::full_mesh::COMMITTED;

    /// The committed answer is refused for any other deck, mode count or speeds (the test
    /// suite's full-mesh comparison rests on this; the deck the code writes now is taken in
    /// tests/full_mesh.rs).
    #[test]
    fn committed_answer_is_refused_for_another_deck() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(COMMITTED);
        let r: CcxReference =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let nc = r.channels[0].len();
        let e = CcxReference::read(&path, "** another deck\n", r.modes, &r.rpm, nc).unwrap_err();
        assert!(
            matches!(&e, FullMeshError::OtherDeck { committed, .. } if *committed == r.deck_fnv1a64),
            "{e}"
        );
        let e = e.to_string();
        assert!(
            e.contains(&r.deck_fnv1a64) && e.contains("regenerate"),
            "{e}"
        );
        // The right hash, other settings: a deck whose text hashes equal is what the file
        // records (FNV-1a of the text), so fake it by editing a copy of the file.
        let dir = tempfile::tempdir().unwrap();
        let copy = dir.path().join("ccx.json");
        let mut r2 = r.clone();
        r2.deck_fnv1a64 = content_hash(b"deck");
        std::fs::write(&copy, serde_json::to_string(&r2).unwrap()).unwrap();
        assert!(CcxReference::read(&copy, "deck", r.modes, &r.rpm, nc).is_ok());
        assert!(matches!(
            CcxReference::read(&copy, "deck", r.modes - 1, &r.rpm, nc),
            Err(FullMeshError::OtherSettings { .. })
        ));
        assert!(matches!(
            CcxReference::read(&copy, "deck", r.modes, &r.rpm[1..], nc),
            Err(FullMeshError::OtherSettings { .. })
        ));
        // An edited file with a channel short at one speed: refused, not indexed past its end.
        r2.channels[3].pop();
        std::fs::write(&copy, serde_json::to_string(&r2).unwrap()).unwrap();
        let e = CcxReference::read(&copy, "deck", r.modes, &r.rpm, nc).unwrap_err();
        assert!(matches!(e, FullMeshError::Channels { .. }), "{e}");
        assert!(e.to_string().contains("channels"), "{e}");
    }
}

//! The sensors of the IR: measurement points on a body, three channels each.

use super::{BodyRef, V3};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SensorKind {
    Acceleration,
    Displacement,
}

/// A measurement point: three channels (x, y, z) in global axes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sensor {
    pub name: String,
    pub body: BodyRef,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub point: V3,
    pub kind: SensorKind,
}

impl Sensor {
    /// CSV column names of the three channels.
    pub fn channels(&self) -> [String; 3] {
        let p = match self.kind {
            SensorKind::Acceleration => "a",
            SensorKind::Displacement => "u",
        };
        ["x", "y", "z"].map(|c| format!("{}_{}{}", self.name, p, c))
    }
}

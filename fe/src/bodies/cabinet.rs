//! The cabinet's FE model: S8R panels (sides with a 2 mm outward bulge, top, back, front with
//! the door opening) on B32 frame beams along the edges and across the base; the feet are
//! SPRING1 elements to the ground. No rigid DOF: the feet hold it (seed paper: the floor
//! contact is part of the FE model, so the cabinet's modes are those on its feet).
//!
//! Numbers: reference-machine.md ("FE models"), engineering estimates; frame, rails and base
//! sheet are sized so the cabinet weighs about 16 kg.

use super::drum::steel;
use super::geometry::{beam_line, shell_grid, shell_grid_masked};
use crate::mesh::{Mesh, Section};
use std::f64::consts::PI;

/// The cabinet's parameters; `Default` is the reference machine.
#[derive(Clone, Debug)]
pub struct Cabinet {
    /// Half width (x and y) and height, m.
    pub half: f64,
    pub height: f64,
    pub sheet: f64,
    /// Outward bulge of the side panels at their centre, m.
    pub bulge: f64,
    /// Door opening: centre height and radius, m (front panel x = +half).
    pub door_z: f64,
    pub door_radius: f64,
    /// Frame members: square side, m.
    pub frame: f64,
    /// Rails (top cross members, base rails): section depth (vertical, ccx's 1-direction) and
    /// thickness, m.
    pub rail_depth: f64,
    pub rail_thickness: f64,
    /// Feet at (+-foot, +-foot, 0); stiffness vertical and horizontal, N/m.
    pub foot: f64,
    pub k_vertical: f64,
    pub k_horizontal: f64,
    /// Elements across (x, y) and up (z).
    pub n_across: usize,
    pub n_up: usize,
}

impl Default for Cabinet {
    fn default() -> Self {
        Cabinet {
            half: 0.30,
            height: 0.85,
            sheet: 0.0007,
            bulge: 0.002,
            door_z: 0.45,
            door_radius: 0.20,
            frame: 0.0040,
            rail_depth: 0.025,
            rail_thickness: 0.004,
            foot: 0.26,
            k_vertical: 2e5,
            k_horizontal: 5e4,
            // 15 across puts nodes every 20 mm: on the feet (0.26) and dampers (0.24).
            n_across: 15,
            n_up: 17,
        }
    }
}

impl Cabinet {
    pub fn mesh(&self) -> Mesh {
        let mut m = Mesh::new("washdyn cabinet: S8R panels, B32 frame, feet springs");
        let (a, h, na, nz) = (self.half, self.height, self.n_across, self.n_up);
        let sheet = Section::Shell {
            thickness: self.sheet,
            material: steel(),
        };
        let s = |u: f64| -a + 2.0 * a * u;
        // Sides y = +-a, bulging outwards (a sine-sine bump, 2 mm at the centre).
        for side in [-1.0, 1.0] {
            shell_grid(&mut m, "CAB_SIDE", &sheet, na, nz, false, |u, v| {
                let b = self.bulge * (PI * u).sin() * (PI * v).sin();
                [s(u), side * (a + b), h * v]
            });
        }
        shell_grid(&mut m, "CAB_TOP", &sheet, na, na, false, |u, v| {
            [s(u), s(v), h]
        });
        shell_grid(&mut m, "CAB_BACK", &sheet, na, nz, false, |u, v| {
            [-a, s(u), h * v]
        });
        // Front with the door opening: elements whose centre lies inside the circle go.
        let (dz, dr) = (self.door_z, self.door_radius);
        let keep = |ei: usize, ej: usize| {
            let (y, z) = (
                s((ei as f64 + 0.5) / na as f64),
                h * (ej as f64 + 0.5) / nz as f64,
            );
            y * y + (z - dz) * (z - dz) > dr * dr
        };
        let front = shell_grid_masked(&mut m, "CAB_FRONT", &sheet, na, nz, false, keep, |u, v| {
            [a, s(u), h * v]
        });
        // The opening's edge: front nodes next to a removed element.
        let edge: Vec<usize> = front
            .iter()
            .filter(|((i, j), _)| {
                let (i, j) = (*i as i64, *j as i64);
                [(-1, -1), (-1, 1), (1, -1), (1, 1)].iter().any(|(di, dj)| {
                    let (ei, ej) = ((i + di).div_euclid(2), (j + dj).div_euclid(2));
                    ei >= 0
                        && ej >= 0
                        && (ei as usize) < na
                        && (ej as usize) < nz
                        && !keep(ei as usize, ej as usize)
                })
            })
            .map(|(_, &id)| id)
            .collect();
        m.add_to_set("GASKET", &edge);
        // Frame: the 12 edges.
        let frame = Section::Beam {
            width: self.frame,
            height: self.frame,
            normal: [0.0, 0.0, 1.0],
            material: steel(),
        };
        let vertical = Section::Beam {
            width: self.frame,
            height: self.frame,
            normal: [1.0, 0.0, 0.0],
            material: steel(),
        };
        for (x, y) in [(-a, -a), (-a, a), (a, -a), (a, a)] {
            beam_line(&mut m, "CAB_POSTS", &vertical, [x, y, 0.0], [x, y, h], nz);
        }
        for z in [0.0, h] {
            for y in [-a, a] {
                beam_line(&mut m, "CAB_FRAME", &frame, [-a, y, z], [a, y, z], na);
            }
            for x in [-a, a] {
                beam_line(&mut m, "CAB_FRAME", &frame, [x, -a, z], [x, a, z], na);
            }
        }
        // Rails where the loads come in: across the top under the springs' cabinet ends
        // (x = -0.10 and 0.12), and along the base under the dampers (y = +-0.24) and the feet
        // (x = +-foot). A 0.7 mm sheet alone would sag 0.15 m under a spring's 245 N.
        let rail = Section::Beam {
            width: self.rail_depth,
            height: self.rail_thickness,
            normal: [0.0, 0.0, 1.0],
            material: steel(),
        };
        for x in [-0.10, 0.12] {
            beam_line(&mut m, "CAB_RAILS", &rail, [x, -a, h], [x, a, h], na);
        }
        for y in [-0.24, 0.24] {
            beam_line(&mut m, "CAB_RAILS", &rail, [-a, y, 0.0], [a, y, 0.0], na);
        }
        let f = self.foot;
        for x in [-f, f] {
            beam_line(&mut m, "CAB_RAILS", &rail, [x, -a, 0.0], [x, a, 0.0], na);
        }
        // Feet: springs to the ground in x, y and z at each foot node.
        let mut feet = Vec::new();
        for (k, (x, y)) in [(f, f), (f, -f), (-f, f), (-f, -f)].iter().enumerate() {
            let id = m.node([*x, *y, 0.0]);
            m.add_to_set(&format!("FOOT_{}", k + 1), &[id]);
            feet.push(id);
        }
        for (dof, k, name) in [
            (1, self.k_horizontal, "CAB_FOOT_X"),
            (2, self.k_horizontal, "CAB_FOOT_Y"),
            (3, self.k_vertical, "CAB_FOOT_Z"),
        ] {
            m.part(name, Section::Ground { dof, k }).elements =
                feet.iter().map(|&id| vec![id]).collect();
        }
        m
    }
}

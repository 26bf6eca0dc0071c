//! The drum's FE model (seed paper, fig. 5): S8R shell cylinder with front ring, back wall and
//! three lifters; the drum star (spider) as C3D20 bricks behind the back wall; the shaft as B32
//! beams, joined to the star and to the pulley hub by short beam spokes; the pulley as an
//! attached rigid part (point masses on a *RIGID BODY). Clamped at its bearing: the drum has no
//! DOF of its own relative to the tub (seed paper: same rigid-body DOF as the multibody model).
//!
//! Numbers: reference-machine.md ("FE models"); all engineering estimates. The rigid model's
//! polar inertia 0.49 kg m^2 assumes all 8.5 kg at the shell radius; with a star, a shaft and
//! a pulley near the axis the FE drum has less (reported by `washdyn fe modal`).

use super::geometry::{beam_line, brick_grid, on_circle, shell_grid};
use crate::mesh::{Material, Mesh, Rigid, Section};
use std::f64::consts::PI;

/// The drum's parameters; `Default` is the reference machine.
#[derive(Clone, Debug)]
pub struct Drum {
    /// Shell radius and thickness, m.
    pub radius: f64,
    pub thickness: f64,
    /// Front face and back wall, x, m.
    pub x_front: f64,
    pub x_back: f64,
    /// Front ring: door opening radius and sheet thickness, m (a folded, stiffened ring).
    pub door_radius: f64,
    pub ring_thickness: f64,
    /// Lifter height (radial), m.
    pub lifter_height: f64,
    /// Drum star: outer radius and axial thickness, m.
    pub star_radius: f64,
    pub star_thickness: f64,
    /// Bearing position (the clamp) and shaft end, x, m; shaft diameter m.
    pub x_bearing: f64,
    pub x_shaft_end: f64,
    pub shaft_diameter: f64,
    /// Pulley: mass kg and radius m of its rim masses.
    pub pulley_mass: f64,
    pub pulley_radius: f64,
    /// Axis height, m.
    pub axis_z: f64,
    /// Elements around and along.
    pub n_circ: usize,
    pub n_axial: usize,
}

impl Default for Drum {
    fn default() -> Self {
        Drum {
            radius: 0.24,
            thickness: 0.0005,
            x_front: 0.17,
            x_back: -0.13,
            door_radius: 0.17,
            ring_thickness: 0.0015,
            lifter_height: 0.04,
            star_radius: 0.12,
            star_thickness: 0.015,
            x_bearing: -0.25,
            x_shaft_end: -0.32,
            shaft_diameter: 0.03,
            pulley_mass: 1.2,
            pulley_radius: 0.08,
            axis_z: 0.45,
            // 5 degrees around: the HRZ lumping error of the kept shell modes stays below 5 %.
            n_circ: 72,
            n_axial: 10,
        }
    }
}

pub fn stainless() -> Material {
    Material {
        name: "STAINLESS".into(),
        e: 200e9,
        nu: 0.3,
        rho: 7900.0,
    }
}
pub fn aluminium() -> Material {
    Material {
        name: "ALUMINIUM".into(),
        e: 70e9,
        nu: 0.33,
        rho: 2700.0,
    }
}
pub fn steel() -> Material {
    Material {
        name: "STEEL".into(),
        e: 210e9,
        nu: 0.3,
        rho: 7850.0,
    }
}

impl Drum {
    pub fn mesh(&self) -> Mesh {
        let mut m = Mesh::new("washdyn drum: S8R shell, C3D20 star, B32 shaft, pulley mass");
        let (r, zc, nc) = (self.radius, self.axis_z, self.n_circ);
        let shell = Section::Shell {
            thickness: self.thickness,
            material: stainless(),
        };
        let ring = Section::Shell {
            thickness: self.ring_thickness,
            material: stainless(),
        };
        let (xf, xb) = (self.x_front, self.x_back);
        let cyl = shell_grid(
            &mut m,
            "DRUM_SHELL",
            &shell,
            self.n_axial,
            nc,
            true,
            |u, v| on_circle(xb + (xf - xb) * u, 0.0, zc, r, 2.0 * PI * v),
        );
        let all_shell: Vec<usize> = cyl.values().copied().collect();
        m.add_to_set("ALL_SHELL", &all_shell);
        // Front ring: door opening to the shell (normal along +x).
        // Radially 4 and 5 elements: the annuli's own bending modes lump badly on fewer.
        shell_grid(&mut m, "DRUM_RING", &ring, 4, nc, true, |u, v| {
            on_circle(
                xf,
                0.0,
                zc,
                self.door_radius + (r - self.door_radius) * u,
                -2.0 * PI * v,
            )
        });
        // Back wall: outer part, and inner part over the star (sharing its front face).
        let rs = self.star_radius;
        let r_in = 0.02;
        shell_grid(&mut m, "DRUM_BACK", &shell, 5, nc, true, |u, v| {
            on_circle(xb, 0.0, zc, rs + (r - rs) * u, 2.0 * PI * v)
        });
        shell_grid(&mut m, "DRUM_BACK", &shell, 2, nc, true, |u, v| {
            on_circle(xb, 0.0, zc, r_in + (rs - r_in) * u, 2.0 * PI * v)
        });
        // Lifters: radial strips at 0, 120, 240 degrees.
        for k in 0..3 {
            let a = 2.0 * PI * k as f64 / 3.0;
            shell_grid(
                &mut m,
                "DRUM_LIFTER",
                &shell,
                self.n_axial,
                1,
                false,
                |u, v| on_circle(xb + (xf - xb) * u, 0.0, zc, r - self.lifter_height * v, a),
            );
        }
        // Drum star: an annular C3D20 plate behind the back wall.
        let alu = Section::Solid {
            material: aluminium(),
        };
        let ts = self.star_thickness;
        let star = brick_grid(&mut m, "DRUM_STAR", &alu, [2, nc, 1], true, |u, v, w| {
            on_circle(xb - ts * w, 0.0, zc, r_in + (rs - r_in) * u, 2.0 * PI * v)
        });
        // Three arms from the hub ring to the rim (a spider): without them the 0.5 mm back wall
        // alone carries the shell, and the drum rocks on it at 6 Hz.
        let half = 2.0 * PI / nc as f64;
        for k in 0..3 {
            let a = 2.0 * PI * k as f64 / 3.0;
            brick_grid(&mut m, "DRUM_STAR", &alu, [2, 2, 1], false, |u, v, w| {
                on_circle(
                    xb - ts * w,
                    0.0,
                    zc,
                    rs + (r - rs) * u,
                    a - half + 2.0 * half * v,
                )
            });
        }
        // Shaft: square steel section of the round shaft's area, from the star's back face
        // through the bearing to the pulley hub; spokes join its ends to the bricks (a beam
        // end on one solid node would be a hinge).
        let a = self.shaft_diameter * (PI / 4.0f64).sqrt();
        let shaft_sec = Section::Beam {
            width: a,
            height: a,
            normal: [0.0, 1.0, 0.0],
            material: steel(),
        };
        let x0 = xb - ts;
        let shaft = beam_line(
            &mut m,
            "DRUM_SHAFT",
            &shaft_sec,
            [x0, 0.0, zc],
            [self.x_bearing, 0.0, zc],
            4,
        );
        beam_line(
            &mut m,
            "DRUM_SHAFT",
            &shaft_sec,
            [self.x_bearing, 0.0, zc],
            [self.x_shaft_end, 0.0, zc],
            2,
        );
        let spoke = Section::Beam {
            width: 0.012,
            height: 0.012,
            normal: [1.0, 0.0, 0.0],
            material: steel(),
        };
        // Star end: to the star's back face inner ring, four directions.
        let back_ring: Vec<usize> = (0..4).map(|q| star[&(0, q * nc / 2, 2)]).collect();
        for &id in &back_ring {
            let p = m.nodes[id - 1];
            beam_line(&mut m, "DRUM_SPOKE", &spoke, [x0, 0.0, zc], p, 1);
        }
        // Pulley hub: one C3D20 block behind the shaft end, spokes to its front corners.
        let (h, xe) = (0.02, self.x_shaft_end);
        let hub = brick_grid(&mut m, "DRUM_HUB", &alu, [1, 1, 1], false, |u, v, w| {
            [xe - 0.01 - 0.02 * w, -h + 2.0 * h * u, zc - h + 2.0 * h * v]
        });
        for (i, j) in [(0, 0), (2, 0), (2, 2), (0, 2)] {
            let p = m.nodes[hub[&(i, j, 0)] - 1];
            beam_line(&mut m, "DRUM_SPOKE", &spoke, [xe, 0.0, zc], p, 1);
        }
        // The pulley: four rim masses and the hub's back face, one rigid part.
        let xp = xe - 0.02;
        let rim: Vec<usize> = (0..4)
            .map(|q| {
                m.node(on_circle(
                    xp,
                    0.0,
                    zc,
                    self.pulley_radius,
                    PI / 4.0 + PI / 2.0 * q as f64,
                ))
            })
            .collect();
        m.part(
            "PULLEY",
            Section::Mass {
                kg: self.pulley_mass / 4.0,
            },
        )
        .elements = rim.iter().map(|&i| vec![i]).collect();
        let back: Vec<usize> = hub
            .iter()
            .filter(|((_, _, k), _)| *k == 2)
            .map(|(_, &id)| id)
            .collect();
        let mut set = rim.clone();
        set.extend(back);
        m.add_to_set("PULLEY", &set);
        let ref_node = m.fresh_node([xp, 0.0, zc]);
        let rot_node = m.fresh_node([xp, 0.0, zc]);
        m.rigid.push(Rigid {
            nset: "PULLEY".into(),
            ref_node,
            rot_node,
        });
        // The bearing: the shaft node there, all six DOF held.
        let bearing = m.nearest([self.x_bearing, 0.0, zc], Some(&shaft));
        m.add_to_set("BEARING", &[bearing]);
        m.fixed.push(("BEARING".into(), 1, 6));
        m
    }
}

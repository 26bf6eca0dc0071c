//! The drum's FE model (seed paper, fig. 5, as a production drum is built): S8R shell cylinder
//! with front ring, back wall and three lifters; a cast aluminium three-arm spider behind the
//! back wall (sharing its nodes) with its solid hub; the steel shaft cast into the hub, stepped
//! from 35 mm (front bearing) to 25 mm (rear bearing); the pulley as an attached rigid part
//! (point masses on a *RIGID BODY with the shaft's end) behind the rear bearing. Shaft, hub and
//! spider are one polar C3D20 mesh sharing nodes: no beam ends, no point connections. Its modes
//! are those on rigid bearings, both seats' surface nodes held (seed paper: same rigid-body DOF
//! as the multibody model, where the drum turns on the tub's bearing housing).
//!
//! The spider's arms are solid tapered aluminium (38 mm deep at the hub, 15 mm at the tips at
//! r 0.23, 20 degrees wide) on a full disc round the hub (to r 0.07): a polar mesh cannot carry
//! a thin rib, and a solid arm of the same depth is the stiffer, heavier bound of a ribbed one.
//! The shaft has the front bearing's abutment shoulder (42 mm) from the seat into the hub:
//! without it the 11.5 mm of 35 mm shaft between the hub and the seat carries 290 MPa at
//! 1400 rpm with the reference unbalance (beam theory 247 MPa), above the 250.
//!
//! Measured (`tests/fe_drum.rs`, ccx 2.20): 9.52 kg, polar inertia 0.232 kg m^2; first
//! rocking pair 107.5 Hz on rigid bearings; at 1400 rpm with 0.6 kg at the front, front edge
//! 2.39 mm, spider 58 MPa, shaft 150 MPa just outside the front seat.
//!
//! Numbers: reference-machine.md ("FE models"), the plan of issue 19; engineering estimates.
//! `Drum::brick_mesh` is the same drum with its sheets as single-layer bricks (no shell knots,
//! no MPCs) for CalculiX's Coriolis reference (`tests/fe_drum.rs`).

use super::geometry::{brick_grid, on_circle, piecewise, polar_bricks, shell_grid};
use crate::mesh::{Material, Mesh, Rigid, Section};
use std::f64::consts::PI;

/// A bearing seat on the shaft: centre and width along x, m.
#[derive(Clone, Copy, Debug)]
pub struct Seat {
    pub x: f64,
    pub width: f64,
}

impl Seat {
    /// The seat's ends (front, rear) along x.
    pub fn ends(&self) -> (f64, f64) {
        (self.x + 0.5 * self.width, self.x - 0.5 * self.width)
    }
}

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
    /// Back wall sheet thickness, m.
    pub back_thickness: f64,
    /// Lifter height (radial), m.
    pub lifter_height: f64,
    /// Hub: radius, and its rear face x (its front face is the back wall), m.
    pub hub_radius: f64,
    pub x_hub_back: f64,
    /// Spider: full disc out to `disc_radius`, three arms out to `spider_radius`; axial depth
    /// at the hub and at the arms' tips (linear in between), m; arm width in elements round.
    pub disc_radius: f64,
    pub spider_radius: f64,
    pub depth_hub: f64,
    pub depth_rim: f64,
    /// Shape of the arms' taper: depth = rim + (hub - rim) s^p, s = 1 at the hub, 0 at the
    /// tip. p = 1.5 thins the arms quickly outboard: at 1400 rpm their stress stays far below
    /// the bound while the front edge deflects as a production drum does (`tests/fe_drum.rs`).
    pub depth_exponent: f64,
    pub arm_elements: usize,
    /// Shaft: bore of the polar mesh (no degenerate bricks on the axis), diameters in front of
    /// and behind the step at `x_step`, and its end, m.
    pub bore_radius: f64,
    pub shaft_front_diameter: f64,
    pub shaft_rear_diameter: f64,
    /// The front bearing's abutment shoulder, from the seat into the hub: the bearing's
    /// catalogue abutment diameter (SKF 6207: d_a min 42 mm), m.
    pub shoulder_diameter: f64,
    pub x_step: f64,
    pub x_shaft_end: f64,
    pub front_bearing: Seat,
    pub rear_bearing: Seat,
    /// The drum's mount point in the multibody model (between the bearings), x, m.
    pub x_mount: f64,
    /// Pulley: mass kg, rim radius of its point masses m, and the length of shaft end it is
    /// pressed on, m.
    pub pulley_mass: f64,
    pub pulley_radius: f64,
    pub pulley_length: f64,
    /// Axis height, m.
    pub axis_z: f64,
    /// Elements around (every part: the mesh conforms) and along the shell.
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
            back_thickness: 0.0007,
            lifter_height: 0.04,
            hub_radius: 0.04,
            x_hub_back: -0.18,
            disc_radius: 0.07,
            spider_radius: 0.23,
            depth_hub: 0.038,
            depth_rim: 0.015,
            depth_exponent: 1.5,
            arm_elements: 2,
            bore_radius: 0.003,
            shaft_front_diameter: 0.035,
            shaft_rear_diameter: 0.025,
            shoulder_diameter: 0.042,
            // The step sits near the rear bearing: between the bearings the overhung drum's
            // moment falls from the front bearing's to nothing at the rear one.
            x_step: -0.28,
            x_shaft_end: -0.33,
            front_bearing: Seat {
                x: -0.20,
                width: 0.017,
            },
            rear_bearing: Seat {
                x: -0.30,
                width: 0.012,
            },
            x_mount: -0.25,
            pulley_mass: 1.2,
            pulley_radius: 0.08,
            pulley_length: 0.012,
            axis_z: 0.45,
            n_circ: 36,
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

/// `n` equal steps from `a` to `b` (n + 1 stations).
fn steps(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
}

/// Append `n` equal steps from the last station to `b`.
fn extend(v: &mut Vec<f64>, b: f64, n: usize) {
    let a = *v.last().expect("a first station");
    v.extend(steps(a, b, n).into_iter().skip(1));
}

impl Drum {
    /// The pulley's plane, x (the middle of the shaft end it sits on).
    pub fn x_pulley(&self) -> f64 {
        self.x_shaft_end + 0.5 * self.pulley_length
    }

    /// The spider's axial depth at radius r.
    fn depth(&self, r: f64) -> f64 {
        let s = (self.spider_radius - r) / (self.spider_radius - self.hub_radius);
        self.depth_rim + (self.depth_hub - self.depth_rim) * s.max(0.0).powf(self.depth_exponent)
    }

    /// The shaft's axial stations from the back wall to its end (descending x): the hub (two
    /// elements over the spider's depth at the hub, one behind), then the free length, the
    /// seats (two elements each), the step and the pulley's seat.
    pub fn shaft_stations(&self) -> Vec<f64> {
        let xb = self.x_back;
        let (f0, f1) = self.front_bearing.ends();
        let (r0, r1) = self.rear_bearing.ends();
        let mut x = vec![
            xb,
            xb - 0.5 * self.depth_hub,
            xb - self.depth_hub,
            self.x_hub_back,
        ];
        extend(&mut x, f0, 2);
        extend(&mut x, f1, 2);
        extend(&mut x, self.x_step, 3);
        extend(&mut x, r0, 1);
        extend(&mut x, r1, 2);
        let pulley = self.x_shaft_end + self.pulley_length;
        if r1 - pulley > 1e-6 {
            extend(&mut x, pulley, 1);
        }
        extend(&mut x, self.x_shaft_end, 2);
        x
    }

    /// Radial stations of the back wall (and of the spider's front face): the hub's rim, the
    /// disc, the arms in 4 elements, and the shell's radius `outer`.
    fn wall_stations(&self, outer: f64) -> Vec<f64> {
        let mut r = vec![self.hub_radius, self.disc_radius];
        extend(&mut r, self.spider_radius, 4);
        if outer - self.spider_radius > 1e-6 {
            r.push(outer);
        } else {
            *r.last_mut().expect("stations") = outer;
        }
        r
    }

    /// Shaft, hub and spider: polar C3D20 blocks sharing nodes. The element sets are
    /// DRUM_SHAFT (steel), DRUM_HUB and DRUM_SPIDER (aluminium).
    fn solid_core(&self, m: &mut Mesh) {
        let (zc, nc) = (self.axis_z, self.n_circ);
        let full = (0.0, 2.0 * PI, nc);
        let shaft = Section::Solid { material: steel() };
        let alu = Section::Solid {
            material: aluminium(),
        };
        let (rf, rr) = (
            0.5 * self.shaft_front_diameter,
            0.5 * self.shaft_rear_diameter,
        );
        let xs = self.shaft_stations();
        polar_bricks(
            m,
            "DRUM_SHAFT",
            &shaft,
            zc,
            &[self.bore_radius, rr],
            &xs,
            full,
        );
        let front: Vec<f64> = xs
            .iter()
            .copied()
            .filter(|&x| x >= self.x_step - 1e-9)
            .collect();
        polar_bricks(m, "DRUM_SHAFT", &shaft, zc, &[rr, rf], &front, full);
        let rs = 0.5 * self.shoulder_diameter;
        let r_in = if rs > rf + 1e-6 {
            let seat = self.front_bearing.ends().0;
            let shoulder: Vec<f64> = xs.iter().copied().filter(|&x| x >= seat - 1e-9).collect();
            polar_bricks(m, "DRUM_SHAFT", &shaft, zc, &[rf, rs], &shoulder, full);
            rs
        } else {
            rf
        };
        let rh = self.hub_radius;
        polar_bricks(
            m,
            "DRUM_HUB",
            &alu,
            zc,
            &[r_in, 0.5 * (r_in + rh), rh],
            &xs[..4],
            full,
        );
        // The spider: a disc round the hub, then the three arms; front face on the back wall.
        let xb = self.x_back;
        let rd = self.disc_radius;
        brick_grid(m, "DRUM_SPIDER", &alu, [1, nc, 2], true, |u, v, w| {
            let r = rh + (rd - rh) * u;
            on_circle(xb - w * self.depth(r), 0.0, zc, r, 2.0 * PI * v)
        });
        let arm = steps(rd, self.spider_radius, 4);
        let half = PI * self.arm_elements as f64 / nc as f64;
        for k in 0..3 {
            let a = 2.0 * PI * k as f64 / 3.0;
            brick_grid(
                m,
                "DRUM_SPIDER",
                &alu,
                [4, self.arm_elements, 2],
                false,
                |u, v, w| {
                    let r = piecewise(&arm, u);
                    on_circle(
                        xb - w * self.depth(r),
                        0.0,
                        zc,
                        r,
                        a - half + 2.0 * half * v,
                    )
                },
            );
        }
    }

    /// The nodes of the shaft's surface inside a seat.
    fn seat_nodes(&self, m: &Mesh, seat: Seat, radius: f64) -> Vec<usize> {
        let (x0, x1) = seat.ends();
        let part = m
            .parts
            .iter()
            .find(|p| p.name == "DRUM_SHAFT")
            .expect("the shaft");
        let mut ids: Vec<usize> = part
            .elements
            .iter()
            .flatten()
            .copied()
            .filter(|&id| {
                let p = m.nodes[id - 1];
                let r = (p[1].powi(2) + (p[2] - self.axis_z).powi(2)).sqrt();
                (r - radius).abs() < 1e-7 && p[0] <= x0 + 1e-7 && p[0] >= x1 - 1e-7
            })
            .collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    }

    /// The shaft nodes the pulley is pressed on (its last `pulley_length`).
    fn pulley_seat(&self, m: &Mesh) -> Vec<usize> {
        let limit = self.x_shaft_end + self.pulley_length + 1e-7;
        let mut ids: Vec<usize> = m
            .parts
            .iter()
            .filter(|p| p.name == "DRUM_SHAFT")
            .flat_map(|p| p.elements.iter().flatten().copied())
            .filter(|&id| m.nodes[id - 1][0] <= limit)
            .collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    }

    /// BEARING (both seats), BEARING_FRONT and BEARING_REAR, held in translation (rigid
    /// bearings: solid nodes carry no rotations).
    fn bearings(&self, m: &mut Mesh) {
        let front = self.seat_nodes(m, self.front_bearing, 0.5 * self.shaft_front_diameter);
        let rear = self.seat_nodes(m, self.rear_bearing, 0.5 * self.shaft_rear_diameter);
        m.add_to_set("BEARING_FRONT", &front);
        m.add_to_set("BEARING_REAR", &rear);
        m.add_to_set("BEARING", &front);
        m.add_to_set("BEARING", &rear);
        m.fixed.push(("BEARING".into(), 1, 3));
    }

    /// The production drum: S8R sheets, polar C3D20 core, rigid pulley.
    pub fn mesh(&self) -> Mesh {
        let mut m = Mesh::new(
            "washdyn drum: S8R shell, C3D20 spider, hub and shaft, pulley mass, rigid bearings",
        );
        let (r, zc, nc) = (self.radius, self.axis_z, self.n_circ);
        let sheet = |t: f64| Section::Shell {
            thickness: t,
            material: stainless(),
        };
        let (xf, xb) = (self.x_front, self.x_back);
        let cyl = shell_grid(
            &mut m,
            "DRUM_SHELL",
            &sheet(self.thickness),
            self.n_axial,
            nc,
            true,
            |u, v| on_circle(xb + (xf - xb) * u, 0.0, zc, r, 2.0 * PI * v),
        );
        let all_shell: Vec<usize> = cyl.values().copied().collect();
        m.add_to_set("ALL_SHELL", &all_shell);
        // Front ring: door opening to the shell (normal along +x).
        shell_grid(
            &mut m,
            "DRUM_RING",
            &sheet(self.ring_thickness),
            4,
            nc,
            true,
            |u, v| {
                on_circle(
                    xf,
                    0.0,
                    zc,
                    self.door_radius + (r - self.door_radius) * u,
                    -2.0 * PI * v,
                )
            },
        );
        // Back wall from the hub's rim, on the spider's front face.
        let rw = self.wall_stations(r);
        shell_grid(
            &mut m,
            "DRUM_BACK",
            &sheet(self.back_thickness),
            rw.len() - 1,
            nc,
            true,
            |u, v| on_circle(xb, 0.0, zc, piecewise(&rw, u), 2.0 * PI * v),
        );
        // Lifters: radial strips at 0, 120, 240 degrees.
        for k in 0..3 {
            let a = 2.0 * PI * k as f64 / 3.0;
            shell_grid(
                &mut m,
                "DRUM_LIFTER",
                &sheet(self.thickness),
                self.n_axial,
                1,
                false,
                |u, v| on_circle(xb + (xf - xb) * u, 0.0, zc, r - self.lifter_height * v, a),
            );
        }
        self.solid_core(&mut m);
        // The pulley: four rim masses and the shaft's end, one rigid part.
        let xp = self.x_pulley();
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
        let mut set = rim.clone();
        set.extend(self.pulley_seat(&m));
        m.add_to_set("PULLEY", &set);
        let ref_node = m.fresh_node([xp, 0.0, zc]);
        let rot_node = m.fresh_node([xp, 0.0, zc]);
        m.rigid.push(Rigid {
            nset: "PULLEY".into(),
            ref_node,
            rot_node,
        });
        self.bearings(&mut m);
        m
    }

    /// The knot-free variant: every sheet a single layer of C3D20R bricks whose faces meet
    /// (the shell's inner face carries the back wall's and the ring's edges: its first and last
    /// axial elements are as long as those sheets are thick), the pulley as point masses on the
    /// shaft end's nodes, no lifters (a thin radial strip does not fit the polar grid), no
    /// *RIGID BODY: ccx builds no MPC. Only for checking CalculiX's Coriolis matrix.
    pub fn brick_mesh(&self) -> Mesh {
        let mut m = Mesh::new("washdyn drum, knot-free brick variant (Coriolis reference)");
        let (r, zc, nc) = (self.radius, self.axis_z, self.n_circ);
        let full = (0.0, 2.0 * PI, nc);
        let sheet = Section::ReducedSolid {
            material: stainless(),
        };
        let (xf, xb) = (self.x_front, self.x_back);
        let (t, tb, tr) = (self.thickness, self.back_thickness, self.ring_thickness);
        let mut xs = vec![xb, xb + tb];
        extend(&mut xs, xf - tr, self.n_axial - 2);
        xs.push(xf);
        polar_bricks(&mut m, "DRUM_SHELL", &sheet, zc, &[r - t, r], &xs, full);
        let ring = steps(self.door_radius, r - t, 4);
        polar_bricks(&mut m, "DRUM_RING", &sheet, zc, &ring, &[xf - tr, xf], full);
        let rw = self.wall_stations(r - t);
        polar_bricks(&mut m, "DRUM_BACK", &sheet, zc, &rw, &[xb, xb + tb], full);
        self.solid_core(&mut m);
        let end = self.pulley_seat(&m);
        m.part(
            "PULLEY",
            Section::Mass {
                kg: self.pulley_mass / end.len() as f64,
            },
        )
        .elements = end.iter().map(|&i| vec![i]).collect();
        self.bearings(&mut m);
        m
    }
}
